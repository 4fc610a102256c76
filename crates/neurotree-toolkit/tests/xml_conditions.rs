//! The pre- and postcondition attributes of XML nodes (`_skipIf`, `_while`, `_onHalted`, ...)
//! and the `Precondition` node: when their scripts run and what they do to the node.

use neurotree::{ManualClock, Status, TickError, Tree, XmlLoader};

use crate::shared;
use shared::{error, load, registry, Wait3};

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
