//! Loading BehaviorTree.CPP XML: what loads, how it runs, and how bad files are reported.

use neurotree::{
    LoadError, ManualClock, NodeId, PortSpec, Registry, Status, TickError, Tree, XmlLoader,
};

#[path = "../../neurotree/tests/support/corpus.rs"]
mod corpus_dir;
use corpus_dir::corpus;

/// The registry of these tests: a counter context and a few leaves.
fn registry() -> Registry<Vec<String>> {
    let mut r = Registry::<Vec<String>>::new();
    r.register_condition("Succ", vec![], |_| true).unwrap();
    r.register_condition("Fail", vec![], |_| false).unwrap();
    r.register_action(
        "Say",
        vec![PortSpec::input::<String>("message")],
        |h| match h.input::<String>("message") {
            Ok(m) => {
                h.ctx_mut().push(m);
                Status::Success
            }
            Err(e) => {
                h.ctx_mut().push(e.to_string());
                Status::Failure
            }
        },
    )
    .unwrap();
    r.register_action(
        "Produce",
        vec![
            PortSpec::input::<i64>("value").default_value("7"),
            PortSpec::output::<i64>("out"),
        ],
        |h| {
            let v: i64 = h.input("value").unwrap_or(-1);
            h.output("out", v)
                .map_or(Status::Failure, |_| Status::Success)
        },
    )
    .unwrap();
    r
}

fn load(text: &str) -> Result<neurotree::Blueprint<Vec<String>>, LoadError> {
    let r = registry();
    let mut loader = XmlLoader::new(&r);
    loader.load_str(text, "test.xml")?;
    loader.build_main()
}

fn error(text: &str) -> LoadError {
    match load(text) {
        Err(e) => e,
        Ok(_) => panic!("expected a load error"),
    }
}

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
fn preconditions_skip_succeed_and_fail_nodes() {
    let bp = load(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T">
             <Sequence>
               <Script code="x := 1"/>
               <Say message="skipped" _skipIf="x == 1"/>
               <Fail _successIf="x == 1"/>
               <Say message="said" _failureIf="y == 2"/>
               <Say message="not while" _while="x > 5"/>
             </Sequence>
           </BehaviorTree></root>"#,
    )
    .unwrap();
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    let mut said = Vec::new();
    // `y` is missing: as in BehaviorTree.CPP, a script that cannot run is an error of the
    // tick, and the node it guards does not run.
    let err = tree.tick_once(&mut said).unwrap_err();
    assert!(
        matches!(&err, TickError::Node { path, message, .. }
            if path == "Sequence/Say" && message.contains("no blackboard entry `y`")),
        "{err}"
    );
    assert!(said.is_empty());
    tree.blackboard_mut().set("y", 0_i64).unwrap();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["said"]);
    // Now `_failureIf` holds, and the Sequence fails at that node without ticking it.
    tree.blackboard_mut().set("y", 2_i64).unwrap();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Failure));
    assert_eq!(said, ["said"]);
}

#[test]
fn postconditions_run_after_completion_and_halt() {
    let mut r = registry();
    r.register_stateful("Wait3", vec![], || Wait3(0)).unwrap();
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            r#"<root main_tree_to_execute="T"><BehaviorTree ID="T">
                 <Sequence>
                   <Succ _onSuccess="ok := 1" _onFailure="ok := 0" _post="posts := 1"/>
                   <Wait3 _while="go" _onHalted="halted := true"/>
                 </Sequence>
               </BehaviorTree></root>"#,
            "t.xml",
        )
        .unwrap();
    let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
    tree.blackboard_mut().set("go", true).unwrap();
    let mut ctx = Vec::new();
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Running));
    assert_eq!(tree.blackboard().get::<i64>("ok"), Ok(1));
    assert_eq!(tree.blackboard().get::<i64>("posts"), Ok(1));
    assert!(!tree.blackboard().contains("halted"));
    // `_while` turns false while Wait3 runs: it is halted and skipped, and the Sequence,
    // whose other child succeeded on the first tick, succeeds.
    tree.blackboard_mut().set("go", false).unwrap();
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Success));
    assert_eq!(tree.blackboard().get::<bool>("halted"), Ok(true));
    assert_eq!(ctx, ["Wait3 halted"]);
}

/// Runs for three ticks; records its halts in the context.
struct Wait3(u8);

impl neurotree::StatefulAction<Vec<String>> for Wait3 {
    fn on_start(&mut self, _h: &mut neurotree::Handle<'_, Vec<String>>) -> Status {
        self.0 = 0;
        Status::Running
    }
    fn on_running(&mut self, _h: &mut neurotree::Handle<'_, Vec<String>>) -> Status {
        self.0 += 1;
        if self.0 >= 3 {
            Status::Success
        } else {
            Status::Running
        }
    }
    fn on_halted(&mut self, h: &mut neurotree::Handle<'_, Vec<String>>) {
        h.ctx_mut().push("Wait3 halted".into());
    }
}

#[test]
fn bad_condition_attributes_are_load_errors() {
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Succ _skipIf="x =="/></BehaviorTree></root>"#,
    );
    assert!(e.message.contains("in `_skipIf` script `x ==`"), "{e}");
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Succ _skip="x"/></BehaviorTree></root>"#,
    );
    assert!(e.message.contains("unknown attribute `_skip`"), "{e}");
}

#[test]
fn a_long_condition_script_is_quoted_by_a_window_around_its_error() {
    // 10,000 characters of assignments, the last of which lacks its value.
    let script = format!("  {}y := )", "x := 1; ".repeat(1_249));
    assert_eq!(script.len(), 10_000);
    let e = error(&format!(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Succ _skipIf="{script}"/></BehaviorTree></root>"#
    ));
    assert!(e.message.starts_with("in `_skipIf` script `…"), "{e}");
    assert!(e.message.contains("x := 1; y := )`"), "{e}");
    assert!(
        e.message.chars().count() < 200,
        "{} characters: {e}",
        e.message.len()
    );
}

#[test]
fn nav2_trees_validate_against_their_model() {
    let nav2 = corpus("nav2");
    let mut r = Registry::<()>::new();
    let model = std::fs::read_to_string(nav2.join("nav2_tree_nodes.xml")).unwrap();
    let added = r.add_model_str(&model, "nav2_tree_nodes.xml").unwrap();
    assert!(added > 70, "{added} node types from the model");
    let mut checked = 0;
    let mut files: Vec<_> = std::fs::read_dir(&nav2)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "xml"))
        .filter(|p| p.file_name().unwrap() != "nav2_tree_nodes.xml")
        .collect();
    files.sort();
    for file in files {
        let mut loader = XmlLoader::new(&r);
        loader.load_file(&file).unwrap();
        let ids: Vec<String> = loader.tree_ids().map(String::from).collect();
        for id in ids {
            // The docking example writes `<inverter>`: a built-in spelt in another case
            // is read as that built-in.
            match loader.validate(&id) {
                Ok(()) => checked += 1,
                Err(e) => panic!("{}: {e}", file.display()),
            }
        }
        // A model describes; it does not run.
        if let Some(main) = loader.main_tree() {
            let e = loader.build(main).unwrap_err();
            assert!(e.message.contains("only described by a model"), "{e}");
        }
    }
    assert_eq!(checked, 16, "trees validated");
}

#[test]
fn model_ports_are_checked_too() {
    let mut r = Registry::<()>::new();
    r.add_model_str(
        r#"<root><TreeNodesModel>
             <Action ID="Spin"><input_port name="spin_dist" type="double" default="1.57"/></Action>
           </TreeNodesModel></root>"#,
        "model.xml",
    )
    .unwrap();
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Spin spin_dist="far"/></BehaviorTree></root>"#,
            "t.xml",
        )
        .unwrap();
    let e = loader.validate("T").unwrap_err();
    assert!(e.message.contains("cannot read `far` as f64"), "{e}");
}

#[test]
fn script_nodes_run_against_the_blackboard() {
    let bp = load(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T">
             <Sequence>
               <Script code="count := 0; label := 'start'"/>
               <Repeat num_cycles="3"><Script code="count += 1"/></Repeat>
               <ScriptCondition code="count == 3 && label == 'start'"/>
               <SetBlackboard value="42" output_key="answer"/>
               <UnsetBlackboard key="label"/>
               <Fallback>
                 <ScriptCondition code="count > 5"/>
                 <Say message="{answer}"/>
               </Fallback>
             </Sequence>
           </BehaviorTree></root>"#,
    )
    .unwrap();
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    let mut said = Vec::new();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["42"]);
    let bb = tree.blackboard();
    assert_eq!(bb.get::<i64>("count"), Ok(3));
    assert!(!bb.contains("label"));
}

#[test]
fn script_syntax_errors_are_load_errors() {
    let e = error(
        "<root main_tree_to_execute=\"T\"><BehaviorTree ID=\"T\">\n  <Script code=\"a := (1 + 2\"/>\n</BehaviorTree></root>",
    );
    assert_eq!(e.line, 2);
    assert!(e.message.contains("in script `a := (1 + 2`"), "{e}");
}

#[test]
fn subtrees_take_conditions_too() {
    let bp = load(
        r#"<root main_tree_to_execute="Main">
             <BehaviorTree ID="Main">
               <Sequence>
                 <SubTree ID="Talk" _skipIf="quiet" _onSuccess="talked := true"/>
                 <Say message="after"/>
               </Sequence>
             </BehaviorTree>
             <BehaviorTree ID="Talk"><Say message="hello"/></BehaviorTree>
           </root>"#,
    )
    .unwrap();
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    let mut said = Vec::new();
    tree.blackboard_mut().set("quiet", false).unwrap();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(tree.blackboard().get::<bool>("talked"), Ok(true));
    tree.blackboard_mut().set("quiet", true).unwrap();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["hello", "after", "after"]);
}

#[test]
fn precondition_checks_its_script_only_before_the_child_runs() {
    let mut r = registry();
    r.register_stateful("Wait3", vec![], || Wait3(0)).unwrap();
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            r#"<root main_tree_to_execute="T"><BehaviorTree ID="T">
                 <Precondition if="door == 'open'" else="SKIPPED"><Wait3/></Precondition>
               </BehaviorTree></root>"#,
            "t.xml",
        )
        .unwrap();
    let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
    let mut ctx = Vec::new();
    tree.blackboard_mut()
        .set("door", String::from("closed"))
        .unwrap();
    assert_eq!(
        tree.tick_once(&mut ctx),
        Err(neurotree::TickError::RootSkipped)
    );
    tree.blackboard_mut()
        .set("door", String::from("open"))
        .unwrap();
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Running));
    // Closing the door does not stop a child that already runs.
    tree.blackboard_mut()
        .set("door", String::from("closed"))
        .unwrap();
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Success));
    assert_eq!(
        tree.tick_once(&mut ctx),
        Err(neurotree::TickError::RootSkipped)
    );
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Precondition if="1" else="MAYBE"><Succ/></Precondition></BehaviorTree></root>"#,
    );
    assert!(e.message.contains("`MAYBE` is not a status"), "{e}");
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
fn loops_run_the_child_once_per_element() {
    let bp = load(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T">
             <Sequence>
               <LoopInt queue="1;2;3" value="{n}">
                 <Script code="sum := sum + n"/>
               </LoopInt>
               <LoopString queue="{words}" value="{w}">
                 <Say message="{w}"/>
               </LoopString>
             </Sequence>
           </BehaviorTree></root>"#,
    )
    .unwrap();
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    tree.blackboard_mut().set("sum", 0_i64).unwrap();
    tree.blackboard_mut()
        .set("words", vec!["a".to_string(), "b".to_string()])
        .unwrap();
    let mut said = Vec::new();
    // One element per tick: 3 ints, then 2 words, then both queues are empty.
    let mut ticks = 0;
    while tree.tick_once(&mut said) == Ok(Status::Running) {
        ticks += 1;
        assert!(ticks < 20);
    }
    assert_eq!(ticks, 5);
    assert_eq!(tree.blackboard().get::<i64>("sum"), Ok(6));
    assert_eq!(said, ["a", "b"]);
    // A Vec entry is copied for the run and left as it was; the literal one starts over.
    assert_eq!(
        tree.blackboard().get::<Vec<String>>("words"),
        Ok(vec!["a".to_string(), "b".to_string()])
    );
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Running));
    assert_eq!(tree.blackboard().get::<i64>("sum"), Ok(7));
}

#[test]
fn entry_watchers_see_writes() {
    let bp = load(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T">
             <Sequence>
               <Fallback>
                 <WasEntryUpdated entry="goal"/>
                 <Say message="no new goal"/>
               </Fallback>
               <SkipUnlessUpdated entry="{goal}"><Say message="new goal"/></SkipUnlessUpdated>
             </Sequence>
           </BehaviorTree></root>"#,
    )
    .unwrap();
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    let mut said = Vec::new();
    tree.blackboard_mut().set("goal", 1_i64).unwrap();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["new goal"]);
    said.clear();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["no new goal"]);
    said.clear();
    // The same value written again is a write.
    tree.blackboard_mut().set("goal", 1_i64).unwrap();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["new goal"]);
}

#[test]
fn wait_value_update_runs_until_a_write() {
    let bp = load(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T">
             <WaitValueUpdate entry="ping"><Say message="pong"/></WaitValueUpdate>
           </BehaviorTree></root>"#,
    )
    .unwrap();
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    let mut said = Vec::new();
    tree.blackboard_mut().set("ping", true).unwrap();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Running));
    tree.blackboard_mut().set("ping", true).unwrap();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["pong", "pong"]);
}

#[test]
fn switch_picks_a_branch_and_halts_the_previous_one() {
    let mut r = registry();
    r.register_stateful("Wait3", vec![], || Wait3(0)).unwrap();
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            r#"<root main_tree_to_execute="T"><BehaviorTree ID="T">
                 <Switch3 variable="{mode}" case_1="walk" case_2="2" case_3="{fly}">
                   <Wait3/>
                   <Say message="two"/>
                   <Say message="flying"/>
                   <Say message="default"/>
                 </Switch3>
               </BehaviorTree></root>"#,
            "t.xml",
        )
        .unwrap();
    let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
    let mut said = Vec::new();
    let bb = tree.blackboard_mut();
    bb.set("mode", String::from("walk")).unwrap();
    bb.set("fly", 7.0_f64).unwrap();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Running));
    // An integer entry matches the text case "2"; the running Wait3 is halted.
    tree.blackboard_mut().replace_in(
        neurotree::ScopeId::ROOT,
        "mode",
        2_i64,
        std::time::Duration::ZERO,
    );
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["Wait3 halted", "two"]);
    // Text "7" matches the real entry 7.0; then nothing matches: the default.
    tree.blackboard_mut().replace_in(
        neurotree::ScopeId::ROOT,
        "mode",
        String::from("7"),
        std::time::Duration::ZERO,
    );
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    tree.blackboard_mut().replace_in(
        neurotree::ScopeId::ROOT,
        "mode",
        String::from("swim"),
        std::time::Duration::ZERO,
    );
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["Wait3 halted", "two", "flying", "default"]);
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Switch2 variable="a" case_1="a"><Succ/></Switch2></BehaviorTree></root>"#,
    );
    assert!(
        e.message
            .contains("`Switch2` takes exactly 3 children, found 1"),
        "{e}"
    );
}

/// Loads `text` with the test registry plus the enums `IDLE = 0`, `DOCKING = 2`.
fn load_with_enums(text: &str) -> Result<neurotree::Blueprint<Vec<String>>, LoadError> {
    let mut r = registry();
    r.register_enums([("IDLE", 0), ("DOCKING", 2)]).unwrap();
    let mut loader = XmlLoader::new(&r);
    loader.load_str(text, "test.xml")?;
    loader.build_main()
}

#[test]
fn enum_names_work_in_scripts_and_in_numeric_ports() {
    let bp = load_with_enums(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T">
             <Sequence>
               <Script code="state := DOCKING"/>
               <Say message="DOCKING" _skipIf="state == IDLE"/>
               <Produce value="DOCKING" out="{n}"/>
               <Precondition if="state != IDLE"><Say message="docking"/></Precondition>
             </Sequence>
           </BehaviorTree></root>"#,
    )
    .unwrap();
    let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
    let mut said = Vec::new();
    assert_eq!(tree.tick_once(&mut said), Ok(Status::Success));
    // A text port keeps the name; a number port reads the value.
    assert_eq!(said, ["DOCKING", "docking"]);
    assert_eq!(tree.blackboard().get::<i64>("state"), Ok(2));
    assert_eq!(tree.blackboard().get::<i64>("n"), Ok(2));
}

#[test]
fn an_enum_name_cannot_change_its_value() {
    let mut r = registry();
    r.register_enum("DOCKING", 2).unwrap();
    r.register_enum("DOCKING", 2).unwrap();
    assert_eq!(
        r.register_enum("DOCKING", 3).unwrap_err().to_string(),
        "the enum name `DOCKING` is already 2; it cannot also be 3"
    );
    // Unregistered, the name is just text that a number port cannot read.
    let e = error(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T">
             <Produce value="DOCKING"/>
           </BehaviorTree></root>"#,
    );
    assert!(e.message.contains("cannot read `DOCKING`"), "{e}");
}

#[test]
fn scripts_that_fail_at_run_time_are_tick_errors() {
    for (node, path) in [
        (r#"<Script code="x := missing + 1"/>"#, "Sequence/Script"),
        (
            r#"<ScriptCondition code="missing > 1"/>"#,
            "Sequence/ScriptCondition",
        ),
        (
            r#"<Precondition if="missing"><Say message="no"/></Precondition>"#,
            "Sequence/Precondition",
        ),
    ] {
        let bp = load(&format!(
            r#"<root main_tree_to_execute="T"><BehaviorTree ID="T">
                 <Sequence><Say message="first"/>{node}<Say message="never"/></Sequence>
               </BehaviorTree></root>"#
        ))
        .unwrap();
        let mut tree = Tree::with_clock(bp.into(), ManualClock::new());
        let mut said = Vec::new();
        let err = tree.tick_once(&mut said).unwrap_err();
        match &err {
            TickError::Node {
                path: at, message, ..
            } => {
                assert_eq!(at, path);
                assert!(message.contains("no blackboard entry `missing`"), "{err}");
            }
            other => panic!("{other:?}"),
        }
        // The tick stopped at the error and the tree was halted, ready to tick again.
        assert_eq!(said, ["first"], "{node}");
        assert!(tree
            .statuses()
            .iter()
            .all(|s| *s == neurotree::NodeStatus::Idle));
    }
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
            "many.xml:6:5: error: unknown port `valu` on `Produce`; its ports are: value, out",
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
fn mock_unknown_mocks_leaves_only_a_model_describes() {
    let mut r = Registry::<()>::new();
    r.add_model_str(
        r#"<root><TreeNodesModel>
             <Action ID="Dock"/>
             <Control ID="Pick"/>
           </TreeNodesModel></root>"#,
        "model.xml",
    )
    .unwrap();
    let tree = r#"<root><BehaviorTree ID="T"><Sequence><Dock/></Sequence></BehaviorTree></root>"#;
    let mut loader = XmlLoader::new(&r).mock_unknown(true);
    loader.load_str(tree, "t.xml").unwrap();
    let mut run = Tree::with_clock(loader.build("T").unwrap().into(), ManualClock::new());
    assert_eq!(run.tick_once(&mut ()), Ok(Status::Success));
    // A control only a model describes is not a leaf: it still cannot run.
    let tree = r#"<root><BehaviorTree ID="T"><Pick><Dock/></Pick></BehaviorTree></root>"#;
    let mut loader = XmlLoader::new(&r).mock_unknown(true);
    loader.load_str(tree, "t.xml").unwrap();
    let e = loader.build("T").unwrap_err();
    assert_eq!(
        e.message,
        "`Pick` is only described by a model; register an implementation to run it; mocks replace only leaves"
    );
}

#[test]
fn a_mock_of_a_control_or_decorator_is_an_error() {
    let r = registry();
    let tree = r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Sequence name="steps"><Inverter><Succ/></Inverter></Sequence></BehaviorTree></root>"#;
    for (name, expected) in [
        ("steps", "`steps` is a Control (`Sequence`) and no leaf is named so; a mock replaces only a leaf (an Action or a Condition)"),
        ("Inverter", "`Inverter` is a Decorator (`Inverter`) and no leaf is named so; a mock replaces only a leaf (an Action or a Condition)"),
    ] {
        let mut loader = XmlLoader::new(&r).mock(name, vec![Status::Success]);
        loader.load_str(tree, "t.xml").unwrap();
        assert_eq!(loader.build_main().unwrap_err().message, expected);
    }
    let mut loader = XmlLoader::new(&r).mock("Succ", vec![Status::Failure]);
    loader.load_str(tree, "t.xml").unwrap();
    let mut run = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
    assert_eq!(run.tick_once(&mut Vec::new()), Ok(Status::Success));
    // A name that a control and a leaf share (Nav2's RecoveryNode `FollowPath` around the
    // action FollowPath) mocks the leaf and keeps the control.
    let shared = r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Sequence name="Succ"><Succ/></Sequence></BehaviorTree></root>"#;
    let mut loader = XmlLoader::new(&r).mock("Succ", vec![Status::Failure]);
    loader.load_str(shared, "t.xml").unwrap();
    let bp = loader.build_main().unwrap();
    assert_eq!(bp.len(), 2);
    let mut run = Tree::with_clock(bp.into(), ManualClock::new());
    assert_eq!(run.tick_once(&mut Vec::new()), Ok(Status::Failure));
}

/// A file of `levels` trees `T0`..`T{levels-1}`, one a line after `<root>`, each using the
/// next one twice, and a leaf `T{levels}`: 2 KB that would expand to 2^(levels+2) nodes.
fn doubling_subtrees(levels: usize) -> String {
    let mut xml = String::from("<root BTCPP_format=\"4\" main_tree_to_execute=\"T0\">\n");
    for i in 0..levels {
        let next = i + 1;
        xml.push_str(&format!(
            "<BehaviorTree ID=\"T{i}\"><Sequence><SubTree ID=\"T{next}\"/><SubTree ID=\"T{next}\"/></Sequence></BehaviorTree>\n"
        ));
    }
    xml.push_str(&format!(
        "<BehaviorTree ID=\"T{levels}\"><AlwaysSuccess/></BehaviorTree>\n</root>\n"
    ));
    xml
}

/// The nodes tree `T1` of [`doubling_subtrees`] expands to: each level is a Sequence and two
/// SubTree nodes over two copies of the next, so `3 + 2 * next`, from 1 for the leaf.
fn doubling_size(levels: u32) -> u64 {
    (1u64 << (levels + 1)) - 3
}

#[test]
fn subtrees_using_each_other_twice_over_are_refused_at_the_first_subtree() {
    let r = registry();
    for levels in [24, 30] {
        let xml = doubling_subtrees(levels);
        assert!(xml.len() < 3_200, "{} bytes", xml.len());
        let mut loader = XmlLoader::new(&r);
        loader.load_str(&xml, "doubling.xml").unwrap();
        let expected = format!(
            "doubling.xml:2:33: error: the tree expands past the limit of 2000000 nodes here: \
             SubTree `T1` adds {} nodes to the 2 counted so far (each use of a subtree is a \
             copy of it); raise the limit with XmlLoader::max_nodes if the tree is meant to be \
             this big",
            doubling_size(levels as u32)
        );
        let built = loader.build_main().unwrap_err();
        assert_eq!(built.to_string(), expected);
        assert_eq!(loader.validate("T0").unwrap_err().to_string(), expected);
        // Validating every error goes past the first SubTree to the second, and expands
        // neither.
        let all = loader.validate_all("T0", 20);
        assert_eq!(all.len(), 2, "{all:?}");
        assert_eq!(all[0].to_string(), expected);
        assert_eq!((all[1].line, all[1].col), (2, 51));
    }
}

#[test]
fn the_node_budget_counts_expanded_subtrees_exactly() {
    let r = registry();
    let xml = doubling_subtrees(4);
    // T0 is a Sequence and two SubTree nodes over two copies of T1.
    let size = 3 + 2 * doubling_size(4) as usize;
    assert_eq!(size, 61);
    let mut loader = XmlLoader::new(&r).max_nodes(size);
    loader.load_str(&xml, "doubling.xml").unwrap();
    assert_eq!(loader.build_main().unwrap().len(), size);
    let mut loader = XmlLoader::new(&r).max_nodes(size - 1);
    loader.load_str(&xml, "doubling.xml").unwrap();
    let e = loader.build_main().unwrap_err();
    assert_eq!((e.line, e.col), (2, 51));
    assert!(
        e.message.starts_with(&format!(
            "the tree expands past the limit of {} nodes here: SubTree `T1` adds 29 nodes to the 32 counted so far",
            size - 1
        )),
        "{e}"
    );
    // A tree's own elements count too: the sixth node of five is refused where it is.
    let mut loader = XmlLoader::new(&r).max_nodes(5);
    loader
        .load_str(
            "<root main_tree_to_execute=\"T\"><BehaviorTree ID=\"T\"><Sequence>\n<Succ/><Succ/><Succ/><Succ/><Succ/></Sequence></BehaviorTree></root>",
            "wide.xml",
        )
        .unwrap();
    assert_eq!(
        loader.build_main().unwrap_err().to_string(),
        "wide.xml:2:29: error: the tree expands past the limit of 5 nodes here; raise the limit with XmlLoader::max_nodes if the tree is meant to be this big"
    );
}

/// Loads `path` on another thread: the result, or `None` if it took more than ten
/// seconds (a load blocked on a FIFO), so that a regression fails instead of hanging.
fn load_on_a_thread(path: &std::path::Path, base: &str) -> Option<Result<(), LoadError>> {
    let (send, receive) = std::sync::mpsc::channel();
    let path = path.to_path_buf();
    let base = base.to_string();
    std::thread::spawn(move || {
        let r = registry();
        let mut loader = XmlLoader::new(&r).base_dir(base);
        let _ = send.send(loader.load_file(&path));
    });
    receive
        .recv_timeout(std::time::Duration::from_secs(10))
        .ok()
}

#[test]
fn a_device_is_refused_as_a_file_and_as_an_include() {
    if !std::path::Path::new("/dev/zero").exists() {
        println!("note: no /dev/zero here; skipped");
        return;
    }
    let e = load_on_a_thread("/dev/zero".as_ref(), "/")
        .expect("loading /dev/zero returns")
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "/dev/zero:1:1: error: not a regular file but a character device; give the path of a tree file"
    );
    let dir = tempfile::tempdir().unwrap();
    let main = dir.path().join("main.xml");
    std::fs::write(&main, "<root>\n  <include path=\"/dev/zero\"/>\n</root>\n").unwrap();
    let e = load_on_a_thread(&main, "/")
        .expect("including /dev/zero returns")
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}:2:3: error: in included file `/dev/zero`: not a regular file but a character device; give the path of a tree file",
            main.display()
        )
    );
}

#[test]
fn a_fifo_is_refused_as_a_file_and_as_an_include_without_blocking() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.xml");
    match std::process::Command::new("mkfifo").arg(&fifo).status() {
        Ok(status) if status.success() => {}
        other => {
            println!("note: mkfifo did not make a FIFO ({other:?}); skipped");
            return;
        }
    }
    let base = dir.path().display().to_string();
    let main = dir.path().join("main.xml");
    std::fs::write(&main, "<root>\n  <include path=\"pipe.xml\"/>\n</root>\n").unwrap();
    let loaded = [
        load_on_a_thread(&fifo, &base),
        load_on_a_thread(&main, &base),
    ];
    if loaded.iter().any(Option::is_none) {
        // Unblock the loads left waiting for a writer before failing.
        drop(std::fs::OpenOptions::new().write(true).open(&fifo));
        drop(std::fs::OpenOptions::new().write(true).open(&fifo));
        panic!("loading a FIFO blocked");
    }
    let [Some(Err(direct)), Some(Err(included))] = loaded else {
        panic!("a FIFO loaded: {loaded:?}");
    };
    assert_eq!(
        direct.to_string(),
        format!(
            "{}:1:1: error: not a regular file but a FIFO; give the path of a tree file",
            fifo.display()
        )
    );
    assert_eq!(
        included.to_string(),
        format!(
            "{}:2:3: error: in included file `{}`: not a regular file but a FIFO; give the path of a tree file",
            main.display(),
            fifo.display()
        )
    );
}

#[test]
fn a_file_over_the_size_limit_is_refused_and_one_at_it_loads() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("tree.xml");
    let xml =
        "<root main_tree_to_execute=\"T\"><BehaviorTree ID=\"T\"><Succ/></BehaviorTree></root>";
    std::fs::write(&file, xml).unwrap();
    let size = xml.len() as u64;
    let r = registry();
    let e = XmlLoader::new(&r)
        .max_file_bytes(size - 1)
        .load_file(&file)
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}:1:1: error: the file is {size} bytes, more than the limit of {}; raise the limit (XmlLoader::max_file_bytes) if the file is meant to be this big",
            file.display(),
            size - 1
        )
    );
    let mut loader = XmlLoader::new(&r).max_file_bytes(size);
    loader.load_file(&file).unwrap();
    assert_eq!(loader.build_main().unwrap().len(), 1);
}
