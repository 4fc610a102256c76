//! Loading BehaviorTree.CPP XML: what loads and how it runs, which tree is the main one,
//! and how includes are followed.

use neurotree::{ManualClock, NodeId, PortSpec, Registry, Status, Tree, XmlLoader};

use crate::corpus_dir;
use corpus_dir::corpus;

use crate::shared;
use shared::{error, load, registry};

#[test]
fn tree1111_loads_and_ticks() {
    let r = registry();
    let mut loader = XmlLoader::new(&r);
    loader.load_file(corpus("bench/tree1111.xml")).unwrap();
    let bp = loader.build_main().unwrap();
    assert_eq!(bp.len(), 1111);
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    assert_eq!(tree.tick_once(&mut Vec::new()), Ok(Status::Success));
}

#[test]
fn built_ins_ports_and_subtree_remapping_run() {
    let bp = load(
        r#"<root BTCPP_format="4" main_tree_to_execute="Main">
          <BehaviorTree ID="Main">
            <Sequence name="main_seq">
              <Produce out="{x}"/>
              <Repeat num_cycles="2"><Say message="tick"/></Repeat>
              <SubTree ID="Child" num="{x}" greeting="hello" result="{child_out}"/>
            </Sequence>
          </BehaviorTree>
          <BehaviorTree ID="Child">
            <Sequence>
              <Say message="{greeting}"/>
              <Produce value="{num}" out="{result}"/>
              <Produce value="{missing}" out="{local}"/>
            </Sequence>
          </BehaviorTree>
        </root>"#,
    )
    .unwrap();
    assert_eq!(bp.name(NodeId(0)), "main_seq");
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    let mut said = Vec::new();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    // A literal subtree port arrives as text; the remapped `num` is the parent's i64 `x`
    // (7, Produce's default), written back through `result` to the parent's `child_out`.
    assert_eq!(said, ["tick", "tick", "hello"]);
    let bb = tree.blackboard();
    assert_eq!(bb.get::<i64>("x"), Ok(7));
    assert_eq!(bb.get::<i64>("child_out"), Ok(7));
    // `missing` is read from nowhere (-1) and `local` stays in the child's scope.
    assert!(!bb.contains("local"));
}

#[test]
fn explicit_form_and_names() {
    let bp = load(
        r#"<root main_tree_to_execute="T">
          <BehaviorTree ID="T">
            <Control ID="Fallback" name="choose">
              <Condition ID="Fail" name="never"/>
              <Action ID="Say" message="ok"/>
            </Control>
          </BehaviorTree>
        </root>"#,
    )
    .unwrap();
    assert_eq!(bp.path(NodeId(1)), "choose/never");
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    let mut said = Vec::new();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["ok"]);
}

#[test]
fn a_single_unnamed_tree_is_the_main_tree() {
    let bp = load(r#"<root><BehaviorTree><Say message="hi"/></BehaviorTree></root>"#).unwrap();
    assert_eq!(bp.len(), 1);
    let r = registry();
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            r#"<root><BehaviorTree><Succ/></BehaviorTree></root>"#,
            "a.xml",
        )
        .unwrap();
    assert_eq!(loader.main_tree(), Some("BehaviorTree_0"));
}

#[test]
fn bare_ampersands_in_attributes_load() {
    let bp = load(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Say message="a && b"/></BehaviorTree></root>"#,
    )
    .unwrap();
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    let mut said = Vec::new();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["a && b"]);
}

#[test]
fn includes_follow_relative_paths_and_stay_in_the_base_directory() {
    let trees = corpus("btcpp/files/tests/trees");
    let r = registry();
    let mut loader = XmlLoader::new(&r).mock_unknown(true);
    loader
        .load_file(trees.join("parent_include_child_include_child.xml"))
        .unwrap();
    assert!(loader.tree_ids().count() >= 2, "{loader:?}");
    // child/child_include_parent.xml includes ../ : outside its own directory.
    let mut confined = XmlLoader::new(&r).mock_unknown(true);
    let e = confined
        .load_file(trees.join("child/child_include_parent.xml"))
        .unwrap_err();
    assert!(e.message.contains("outside the base directory"), "{e}");
    // With the base widened it loads.
    let mut widened = XmlLoader::new(&r).mock_unknown(true).base_dir(&trees);
    widened
        .load_file(trees.join("child/child_include_parent.xml"))
        .unwrap();
}

#[test]
fn missing_include_is_reported_at_the_include() {
    let dir = std::env::temp_dir().join(format!("neurotree-include-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("main.xml");
    std::fs::write(&file, "<root>\n  <include path=\"nope.xml\"/>\n</root>\n").unwrap();
    let r = registry();
    let e = XmlLoader::new(&r).load_file(&file).unwrap_err();
    assert_eq!(e.line, 2);
    assert!(e.message.contains("not found"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn includes_can_be_served_from_texts_read_elsewhere() {
    let main = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
      <include path="../parts/say.xml"/>
      <BehaviorTree ID="Main"><SubTree ID="Speech"/></BehaviorTree>
    </root>"#;
    let say = r#"<root BTCPP_format="4">
      <include path="./more/./hi.xml"/>
      <BehaviorTree ID="Speech"><Sequence><Say message="one"/><SubTree ID="Hi"/></Sequence></BehaviorTree>
    </root>"#;
    let hi = r#"<root BTCPP_format="4"><BehaviorTree ID="Hi"><Say message="two"/></BehaviorTree></root>"#;
    // What to read, in turn, with `.` and `..` resolved against each includer's directory.
    assert_eq!(
        XmlLoader::<Vec<String>>::includes_of(main, "trees/main.xml").unwrap(),
        ["parts/say.xml"]
    );
    assert_eq!(
        XmlLoader::<Vec<String>>::includes_of(say, "parts/say.xml").unwrap(),
        ["parts/more/hi.xml"]
    );
    let r = registry();
    let texts = [("parts/say.xml", say), ("parts/more/hi.xml", hi)]
        .map(|(path, text)| (path.to_string(), text.to_string()));
    let mut loader = XmlLoader::new(&r);
    loader.include_texts(texts.into_iter().collect());
    loader.load_str(main, "trees/main.xml").unwrap();
    let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
    let mut said = Vec::new();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["one", "two"]);
    // A text not given is an error at its include.
    let mut loader = XmlLoader::new(&r);
    loader.include_texts(Default::default());
    let e = loader.load_str(main, "trees/main.xml").unwrap_err();
    assert_eq!(e.line, 2);
    assert!(e.message.contains("`parts/say.xml` was not read"), "{e}");
}

#[test]
fn the_subtree_remapping_tutorial_runs() {
    // BehaviorTree.CPP's tutorial 06 as shipped, with its two leaves registered. Its scripts
    // assign with `=`, which works because every entry a port names exists from the start.
    let file = corpus("btcpp/examples/examples__t06_subtree_port_remapping__01.xml");
    let mut r = Registry::<Vec<String>>::new();
    r.register_action(
        "SaySomething",
        vec![PortSpec::input::<String>("message")],
        |h| {
            let m = h
                .input::<String>("message")
                .unwrap_or_else(|e| e.to_string());
            h.ctx_mut().push(m);
            Status::Success
        },
    )
    .unwrap();
    r.register_action(
        "MoveBase",
        vec![PortSpec::input::<Vec<f64>>("goal")],
        |h| match h.input::<Vec<f64>>("goal") {
            Ok(goal) if goal == [1.0, 2.0, 3.0] => Status::Success,
            _ => Status::Failure,
        },
    )
    .unwrap();
    let mut loader = XmlLoader::new(&r);
    loader.load_file(&file).unwrap();
    let bp = loader.build("MainTree").unwrap();
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    let mut said = Vec::new();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["goal reached"]);
    assert_eq!(
        tree.blackboard().get::<String>("move_result"),
        Ok("goal reached".to_string())
    );
}

#[test]
fn subtrees_made_with_the_builder_are_used_by_id_with_remapping() {
    let mut r = registry();
    r.register_subtree("Announce", |b| {
        b.action("say", |log: &mut Vec<String>| {
            log.push("announced".into());
            Status::Success
        })
    })
    .unwrap();
    r.register_subtree("Echo", |b| b.sequence("echo", |s| s.always_success("ok")))
        .unwrap();
    assert!(r.register_subtree("Echo", |b| b).is_err());
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            r#"<root main_tree_to_execute="T">
                 <BehaviorTree ID="T">
                   <Sequence>
                     <SubTree ID="Announce" message="{msg}"/>
                     <SubTree ID="Echo"/>
                   </Sequence>
                 </BehaviorTree>
                 <BehaviorTree ID="Echo"><Say message="from the file"/></BehaviorTree>
               </root>"#,
            "test.xml",
        )
        .unwrap();
    let bp = loader.build_main().unwrap();
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    let mut said = Vec::new();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    // The registered one where no file defines the ID; the file's tree where one does.
    assert_eq!(said, ["announced", "from the file"]);
    let saved = neurotree::xml::write_xml(
        tree.blueprint(),
        &r,
        &neurotree::xml::SaveOptions::default(),
    );
    assert!(
        saved.contains(r#"<SubTree ID="Announce" message="{msg}"/>"#),
        "{saved}"
    );
    assert!(
        !saved.contains(r#"<BehaviorTree ID="Announce">"#),
        "{saved}"
    );
    assert!(saved.contains(r#"<BehaviorTree ID="Echo">"#), "{saved}");
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><SubTree ID="Nope"/></BehaviorTree></root>"#,
    );
    assert!(
        e.message
            .contains("no tree with ID `Nope` is loaded or registered"),
        "{e}"
    );
}

#[test]
fn the_main_tree_is_the_first_files_and_a_later_file_does_not_change_it() {
    let r = registry();
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            r#"<root main_tree_to_execute="Main"><BehaviorTree ID="Main"><SubTree ID="Sub"/></BehaviorTree></root>"#,
            "main.xml",
        )
        .unwrap();
    loader
        .load_str(
            r#"<root main_tree_to_execute="Sub"><BehaviorTree ID="Sub"><Succ/></BehaviorTree></root>"#,
            "sub.xml",
        )
        .unwrap();
    assert_eq!(loader.main_tree(), Some("Main"));
    // Nor does a later file name one when the first did not.
    let mut loader = XmlLoader::new(&r);
    let trees = r#"<root><BehaviorTree ID="A"><Succ/></BehaviorTree><BehaviorTree ID="B"><Succ/></BehaviorTree></root>"#;
    loader.load_str(trees, "first.xml").unwrap();
    loader
        .load_str(
            r#"<root main_tree_to_execute="C"><BehaviorTree ID="C"><Succ/></BehaviorTree></root>"#,
            "second.xml",
        )
        .unwrap();
    assert_eq!(loader.main_tree(), None);
}

#[test]
fn the_trees_no_subtree_names_are_the_candidates_to_start_from() {
    let r = registry();
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            r#"<root>
                 <BehaviorTree ID="Leaf"><Succ/></BehaviorTree>
                 <BehaviorTree ID="Mid"><Sequence><SubTree ID="Leaf"/><SubTree ID="Elsewhere"/></Sequence></BehaviorTree>
                 <BehaviorTree ID="Top"><SubTree ID="Mid"/></BehaviorTree>
               </root>"#,
            "trees.xml",
        )
        .unwrap();
    assert_eq!(loader.main_tree(), None);
    assert_eq!(loader.unreferenced_trees(), ["Top"]);
    assert_eq!(loader.unresolved_subtrees(), ["Elsewhere"]);
}
