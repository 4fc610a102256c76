//! Scripts in XML trees: `Script` nodes against the blackboard, syntax errors at load time,
//! run-time errors as tick errors, and enum names in scripts and number ports.

use neurotree::{LoadError, ManualClock, Status, TickError, Tree, XmlLoader};

use crate::shared;
use shared::{error, load, registry};

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
