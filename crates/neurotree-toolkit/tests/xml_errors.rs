//! How bad BehaviorTree.CPP files are reported: unknown names and ports, literals, child
//! counts, malformed XML, every error of a tree at once, and names that load with a warning.

use neurotree::{ManualClock, NodeId, Status, Tree, XmlLoader};

use crate::shared;
use shared::{error, registry};

#[test]
fn unknown_node_suggests_the_closest_name() {
    let e = error(
        "<root main_tree_to_execute=\"T\">\n<BehaviorTree ID=\"T\">\n  <Sequense/>\n</BehaviorTree>\n</root>",
    );
    assert_eq!((e.file.as_str(), e.line, e.col), ("test.xml", 3, 3));
    assert!(e.message.contains("unknown node type `Sequense`"), "{e}");
    assert!(e.message.contains("did you mean `Sequence`?"), "{e}");
    assert!(e.to_string().starts_with("test.xml:3:3: error: "), "{e}");
}

#[test]
fn unknown_port_lists_the_valid_ones() {
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Produce valu="3"/></BehaviorTree></root>"#,
    );
    assert!(
        e.message.contains("unknown port `valu` on `Produce`"),
        "{e}"
    );
    assert!(e.message.contains("its ports are: value, out"), "{e}");
}

#[test]
fn mistyped_ports_trees_and_remappings_get_the_nearest_declared_name() {
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Produce valeu="3"/></BehaviorTree></root>"#,
    );
    assert!(
        e.message.starts_with(
            "unknown port `valeu` on `Produce` (did you mean `value`?); its ports are: value, out"
        ),
        "{e}"
    );
    // Nothing near: no guess.
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Produce speed="3"/></BehaviorTree></root>"#,
    );
    assert!(!e.message.contains("did you mean"), "{e}");
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><SubTree ID="Dock"/></BehaviorTree>
           <BehaviorTree ID="Docking"><Succ/></BehaviorTree></root>"#,
    );
    assert!(
        e.message.starts_with(
            "no tree with ID `Dock` is loaded or registered (did you mean `Docking`?)"
        ),
        "{e}"
    );
    // A SubTree's model declares `goal`; `gaol` is remapped instead.
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><SubTree ID="Go" gaol="{g}"/></BehaviorTree>
           <BehaviorTree ID="Go"><Succ/></BehaviorTree>
           <TreeNodesModel><SubTree ID="Go"><input_port name="goal"/></SubTree></TreeNodesModel></root>"#,
    );
    assert!(
        e.message
            .contains("mandatory (`gaol` is no port of it: did you mean `goal`?); remap it here"),
        "{e}"
    );
}

#[test]
fn literals_are_converted_at_load_time() {
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Repeat num_cycles="many"><Succ/></Repeat></BehaviorTree></root>"#,
    );
    assert!(e.message.contains("cannot read `many` as i32"), "{e}");
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Produce value="x"/></BehaviorTree></root>"#,
    );
    assert!(e.message.contains("port `value` of `Produce`"), "{e}");
}

#[test]
fn child_counts_are_checked_where_they_are_written() {
    let e = error(
        "<root main_tree_to_execute=\"T\">\n<BehaviorTree ID=\"T\">\n<Inverter>\n<Succ/><Succ/>\n</Inverter>\n</BehaviorTree></root>",
    );
    assert_eq!(e.line, 3);
    assert!(
        e.message
            .contains("`Inverter` takes exactly 1 child, found 2"),
        "{e}"
    );
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Succ><Fail/></Succ></BehaviorTree></root>"#,
    );
    assert!(e.message.contains("is a leaf and takes no children"), "{e}");
}

#[test]
fn tree_level_errors() {
    let e = error(
        r#"<root><BehaviorTree ID="A"><Succ/></BehaviorTree><BehaviorTree ID="A"><Succ/></BehaviorTree></root>"#,
    );
    assert!(e.message.contains("`A` is already loaded"), "{e}");
    let e = error(
        r#"<root><BehaviorTree ID="A"><Succ/></BehaviorTree><BehaviorTree ID="B"><Succ/></BehaviorTree></root>"#,
    );
    assert!(e.message.contains("no main tree"), "{e}");
    let e = error(
        r#"<root main_tree_to_execute="A">
             <BehaviorTree ID="A"><SubTree ID="B"/></BehaviorTree>
             <BehaviorTree ID="B"><Sequence><SubTree ID="A"/></Sequence></BehaviorTree>
           </root>"#,
    );
    assert!(e.message.contains("subtree cycle: A -> B -> A"), "{e}");
    let e = error(
        r#"<root main_tree_to_execute="A"><BehaviorTree ID="A"><SubTree ID="Nope"/></BehaviorTree></root>"#,
    );
    assert!(e.message.contains("no tree with ID `Nope`"), "{e}");
    let e = error(r#"<tree/>"#);
    assert!(e.message.contains("starts with <root"), "{e}");
}

#[test]
fn malformed_xml_is_an_error_with_a_position() {
    let e = error("<root>\n<BehaviorTree ID=\"T\">\n<Succ>\n</BehaviorTree>\n</root>");
    assert_eq!(e.line, 4);
    assert!(e.message.starts_with("malformed XML"), "{e}");
}

#[test]
fn a_threshold_error_points_at_the_node_and_names_it_once() {
    let e = error(
        "<root main_tree_to_execute=\"T\">\n  <BehaviorTree ID=\"T\">\n    <Sequence>\n      <Parallel success_count=\"3\">\n        <Succ/>\n        <Succ/>\n      </Parallel>\n    </Sequence>\n  </BehaviorTree>\n</root>",
    );
    assert_eq!(
        e.to_string(),
        "test.xml:4:7: error: Parallel: success threshold 3 needs at least 3 children, found 2"
    );
}

#[test]
fn validate_all_reports_every_error_of_a_tree_in_document_order() {
    let r = registry();
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            "<root>\n<BehaviorTree ID=\"T\">\n<Sequence>\n  <Sequense/>\n  <Fallback>\n    <Produce valu=\"3\"/>\n    <Parallel success_count=\"2\"><Succ/></Parallel>\n  </Fallback>\n  <Inverter><Succ/><Succ/></Inverter>\n  <Jump/>\n</Sequence>\n</BehaviorTree>\n</root>",
            "many.xml",
        )
        .unwrap();
    let errors: Vec<String> = loader
        .validate_all("T", 20)
        .iter()
        .map(ToString::to_string)
        .collect();
    assert_eq!(
        errors,
        [
            "many.xml:4:3: error: unknown node type `Sequense`; did you mean `Sequence`? register it in the Registry before loading",
            "many.xml:6:5: error: unknown port `valu` on `Produce` (did you mean `value`?); its ports are: value, out",
            "many.xml:9:3: error: `Inverter` takes exactly 1 child, found 2",
            "many.xml:10:3: error: unknown node type `Jump`; register it in the Registry before loading",
            "many.xml:7:5: error: Parallel: success threshold 2 needs at least 2 children, found 1",
        ]
    );
    // The limit is kept; `validate` still stops at the first.
    assert_eq!(loader.validate_all("T", 2).len(), 2);
    assert_eq!(loader.validate("T").unwrap_err().to_string(), errors[0]);
}

#[test]
fn built_in_names_are_case_sensitive_but_for_a_documented_alias() {
    // `<inverter>` (Nav2's docking example writes it) is in the alias list: it loads as
    // Inverter, with a warning saying BehaviorTree.CPP would refuse it.
    let r = registry();
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            "<root main_tree_to_execute=\"T\"><BehaviorTree ID=\"T\">\n  <inverter><Fail/></inverter>\n</BehaviorTree></root>",
            "test.xml",
        )
        .unwrap();
    let bp = loader.build_main().unwrap();
    assert_eq!(format!("{:?}", bp.kind(NodeId(0))), "Inverter");
    let warnings: Vec<String> = loader.warnings().iter().map(|w| w.to_string()).collect();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].starts_with("test.xml:2:3: warning: `inverter` is not a BehaviorTree.CPP name"),
        "{warnings:?}"
    );
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    assert_eq!(tree.tick_once(&mut Vec::new()), Ok(Status::Success));
    // Any other spelling in another case is unknown, as in BehaviorTree.CPP.
    for (written, meant) in [("forceSuccess", "ForceSuccess"), ("INVERTER", "Inverter")] {
        let e = error(&format!(
            r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><{written}><Fail/></{written}></BehaviorTree></root>"#
        ));
        assert!(
            e.message.contains(&format!(
                "unknown node type `{written}`; did you mean `{meant}`?"
            )),
            "{e}"
        );
    }
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><say message="x"/></BehaviorTree></root>"#,
    );
    assert!(
        e.message
            .contains("unknown node type `say`; did you mean `Say`?"),
        "{e}"
    );
}

#[test]
fn sequence_star_loads_as_sequence_with_memory_with_a_deprecation_warning() {
    let r = registry();
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            "<root main_tree_to_execute=\"T\">\n<BehaviorTree ID=\"T\">\n  <SequenceStar><Succ/><Fail/></SequenceStar>\n</BehaviorTree></root>",
            "old.xml",
        )
        .unwrap();
    let bp = loader.build_main().unwrap();
    assert_eq!(format!("{:?}", bp.kind(NodeId(0))), "SequenceWithMemory");
    let warnings: Vec<String> = loader.warnings().iter().map(|w| w.to_string()).collect();
    assert_eq!(
        warnings,
        ["old.xml:3:3: warning: `SequenceStar` is deprecated (BehaviorTree.CPP 3's name); it loads as `SequenceWithMemory`, write that"]
    );
    // SequenceWithMemory keeps its place: the failed child is retried, the first is not.
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    assert_eq!(tree.tick_once(&mut Vec::new()), Ok(Status::Failure));
    // A misspelling of it points to the v4 name.
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><SequenceStr><Succ/></SequenceStr></BehaviorTree></root>"#,
    );
    assert!(
        e.message
            .contains("unknown node type `SequenceStr`; did you mean `SequenceWithMemory`?"),
        "{e}"
    );
}
