//! BehaviorTree.CPP's substitution rules (`xml::Substitutions`) and mocks that match by type
//! and write outputs, as a user loading a tree applies them.

use std::time::Duration;

use neurotree::xml::{parse_outcomes, Substitute, Substitutions};
use neurotree::{LoadErrorKind, ManualClock, Registry, Status, Tree, XmlLoader};

/// The tree of `xml` built with `rules`, on a manual clock.
fn tree_with(xml: &str, rules: Substitutions) -> (Tree<()>, ManualClock) {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry).substitute(rules);
    loader.load_str(xml, "t.xml").unwrap();
    let clock = ManualClock::new();
    let bp = loader.build_main().unwrap_or_else(|e| panic!("{e}"));
    (Tree::with_clock(bp.into(), clock.clone()), clock)
}

const RULES: &str = r#"{
  "TestNodeConfigs": {
    "Slow": { "async_delay": 300, "return_status": "SUCCESS", "post_script": "done := true" },
    "Judge": { "return_status_script": "battery > 20 ? SUCCESS : FAILURE",
               "failure_script": "why := 'low'", "success_script": "why := 'ok'" }
  },
  "SubstitutionRules": {
    "Drive": "Slow",
    "nav/Check*": "Judge",
    "Beep": "AlwaysSuccess"
  }
}"#;

const TREE: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Beep volume="3"/>
      <SubTree ID="Nav" name="nav" _autoremap="true"/>
      <Drive/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Nav"><CheckBattery/></BehaviorTree>
</root>"#;

#[test]
fn rules_replace_unregistered_nodes_by_test_nodes_and_registered_types() {
    let rules = Substitutions::from_json(RULES, "rules.json").unwrap();
    let (mut tree, clock) = tree_with(TREE, rules.clone());
    tree.blackboard_mut().set("battery", 80_i64).unwrap();
    // Drive waits 300 ms of the tree's clock, then succeeds and runs its post script.
    for _ in 0..3 {
        assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
        clock.advance(Duration::from_millis(100));
    }
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    assert_eq!(tree.blackboard().get::<bool>("done"), Ok(true));
    assert_eq!(tree.blackboard().get::<String>("why").as_deref(), Ok("ok"));

    let (mut low, _) = tree_with(TREE, rules);
    low.blackboard_mut().set("battery", 5_i64).unwrap();
    assert_eq!(low.tick_once(&mut ()), Ok(Status::Failure));
    assert_eq!(low.blackboard().get::<String>("why").as_deref(), Ok("low"));
    assert!(!low.blackboard().contains("done"));
}

#[test]
fn a_pattern_matches_the_path_through_subtrees_only() {
    let rules = Substitutions::from_json(RULES, "rules.json").unwrap();
    // The pattern is `nav/Check*`: the same node outside the SubTree named `nav` stays
    // unknown.
    let outside = r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
        <Sequence><CheckBattery/></Sequence></BehaviorTree></root>"#;
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry).substitute(rules);
    loader.load_str(outside, "t.xml").unwrap();
    assert_eq!(
        loader.build_main().unwrap_err().kind(),
        LoadErrorKind::UnknownNode
    );
}

#[test]
fn bad_rules_files_are_errors_naming_the_file_and_place() {
    let e = Substitutions::from_json("{\n  \"SubstitutionRules\": [1,\n", "r.json").unwrap_err();
    assert_eq!(e.kind(), LoadErrorKind::Substitution);
    assert_eq!((e.file.as_str(), e.line), ("r.json", 2));
    let e = Substitutions::from_json(
        r#"{"TestNodeConfigs": {"X": {"async_delay": 5}}, "SubstitutionRules": {}}"#,
        "r.json",
    )
    .unwrap_err();
    assert!(e
        .message
        .contains("`X` must contain return_status or return_status_script"));
    let e = Substitutions::from_json(
        r#"{"TestNodeConfigs": {"X": {"return_status": "MAYBE"}}, "SubstitutionRules": {}}"#,
        "r.json",
    )
    .unwrap_err();
    assert!(e.message.contains("`MAYBE`"), "{}", e.message);
    let e = Substitutions::from_json(
        r#"{"TestNodeConfigs": {"X": {"return_status": "SUCCESS", "post_script": "a :="}}, "SubstitutionRules": {}}"#,
        "r.json",
    )
    .unwrap_err();
    assert!(e.message.contains("post_script"), "{}", e.message);
    assert!(Substitutions::read("/no/such/rules.json").is_err());
}

#[test]
fn a_rule_to_an_unknown_type_is_an_error_at_the_node() {
    let mut rules = Substitutions::new();
    rules.add_rule("Beep", Substitute::Node("Nothing".into()));
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry).substitute(rules);
    loader
        .load_str(
            r#"<root BTCPP_format="4"><BehaviorTree ID="Main"><Beep/></BehaviorTree></root>"#,
            "t.xml",
        )
        .unwrap();
    let e = loader.build_main().unwrap_err();
    assert_eq!(e.kind(), LoadErrorKind::Substitution);
    assert!(e.message.contains("`Nothing`"), "{}", e.message);
}

#[test]
fn mocks_match_by_type_write_outputs_and_must_match_something() {
    let registry = Registry::<()>::new();
    let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
        <Sequence><BatteryOK name="b" level="{charge}"/><Plan/></Sequence>
        </BehaviorTree></root>"#;
    let mock = parse_outcomes("SUCCESS;level:i32=42;mode=dock").unwrap();
    let mut loader = XmlLoader::new(&registry)
        .mock("BatteryOK", mock)
        .mock("Plan", vec![Status::Failure]);
    loader.load_str(xml, "t.xml").unwrap();
    let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Failure));
    // The port `level` is bound to `{charge}`; `mode` has no attribute: its own name.
    assert_eq!(tree.blackboard().get_exact::<i32>("charge"), Ok(42));
    assert_eq!(tree.blackboard().get::<i64>("mode").ok(), None);
    assert_eq!(
        tree.blackboard().get::<String>("mode").as_deref(),
        Ok("dock")
    );

    let mut loader = XmlLoader::new(&registry)
        .mock("BatteryOK", vec![Status::Success])
        .mock("Plan", vec![Status::Success])
        .mock("Plna", vec![Status::Success]);
    loader.load_str(xml, "t.xml").unwrap();
    let e = loader.build_main().unwrap_err();
    assert_eq!(e.kind(), LoadErrorKind::UnmatchedMock);
    assert!(e.message.contains("`Plna`"), "{}", e.message);
}
