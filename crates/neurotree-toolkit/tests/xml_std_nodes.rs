//! The std built-in nodes loaded from XML: loops, entry watchers, `WaitValueUpdate` and
//! `Switch`.

use neurotree::{ManualClock, Status, Tree, XmlLoader};

use crate::shared;
use shared::{error, load, registry, Wait3};

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

/// A Service loaded from XML: its script refreshes `seen` at the start and every 100 ms
/// while the Sleep runs; the tree sleeps between the intervals; a write to it round-trips.
#[test]
fn a_service_refreshes_the_blackboard_at_its_interval() {
    let xml = r#"<root main_tree_to_execute="T"><BehaviorTree ID="T">
             <Service interval_msec="100">
               <Script code="seen := seen + 1"/>
               <Sleep msec="350"/>
             </Service>
           </BehaviorTree></root>"#;
    let bp = load(xml).unwrap();
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(bp.into(), clock.clone());
    tree.blackboard_mut().set("seen", 0_i64).unwrap();
    let mut said = Vec::new();
    let mut seen = Vec::new();
    let mut passes = 0;
    for _ in 0..25 {
        let status = tree.tick_once(&mut said).unwrap();
        passes += u32::from(tree.last_passes() > 0);
        seen.push(tree.blackboard().get::<i64>("seen").unwrap());
        if status != Status::Running {
            break;
        }
        clock.advance(std::time::Duration::from_millis(20));
    }
    // 0, 100, 200, 300 ms: four services; the Sleep succeeds at 360 ms, the 19th tick.
    assert_eq!(seen.len(), 19);
    assert_eq!(*seen.last().unwrap(), 4);
    assert_eq!(seen[4], 1);
    assert_eq!(seen[5], 2);
    // Passes: each service's tick (its write keeps the tree awake one more tick), and the
    // last: 4 * 2 + 1, not 19.
    assert_eq!(passes, 9);
}
