//! Trees checked against `TreeNodesModel`s, and mocks standing in for the leaves a model
//! only describes.

use neurotree::{ManualClock, Registry, Status, Tree, XmlLoader};

use crate::corpus_dir;
use corpus_dir::corpus;

use crate::shared;
use shared::registry;

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
