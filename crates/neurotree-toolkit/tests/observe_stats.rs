//! Per-node statistics: exact counts and Running times for scripted runs on a manual clock.

use crate::patrol;

use std::time::Duration;

use neurotree::observe::{NodeStats, Statistics};
use neurotree::{
    Blueprint, Handle, ManualClock, NodeId, Registry, StatefulAction, Status, Tree, XmlLoader,
};

fn stats(ticks: u64, successes: u64, failures: u64, skips: u64, halts: u64, ms: u64) -> NodeStats {
    NodeStats {
        ticks,
        successes,
        failures,
        skips,
        halts,
        running: Duration::from_millis(ms),
    }
}

#[test]
fn patrol_counts_and_table() {
    let (mut tree, clock) = patrol::start();
    let stats_ = Statistics::new(tree.blueprint());
    tree.set_observer(stats_.clone());
    patrol::run(&mut tree, &clock);

    let s = &stats_;
    // Ticks 1-5 return Running, Failure, Running, Running, Success.
    assert_eq!(s.by_path("patrol"), Some(stats(5, 1, 1, 0, 0, 300)));
    // Ticked every tick; it failed on tick 2 only.
    assert_eq!(
        s.by_path("patrol/battery_ok"),
        Some(stats(5, 4, 1, 0, 0, 0))
    );
    // Not ticked on tick 2, halted there instead.
    assert_eq!(s.by_path("patrol/route"), Some(stats(4, 1, 0, 0, 1, 300)));
    // Ran on tick 1, skipped on tick 3; the route resumes past it on ticks 4 and 5.
    assert_eq!(
        s.by_path("patrol/route/once"),
        Some(stats(2, 1, 0, 1, 0, 0))
    );
    assert_eq!(
        s.by_path("patrol/route/once/wave"),
        Some(stats(1, 1, 0, 0, 0, 0))
    );
    // Running 0.1-0.2 s (halted), then 0.3-0.5 s.
    assert_eq!(
        s.by_path("patrol/route/move"),
        Some(stats(4, 1, 0, 0, 1, 300))
    );
    assert_eq!(s.node(NodeId(6)), Some(stats(1, 1, 0, 0, 0, 0)));
    assert_eq!(s.node(NodeId(7)), None);
    assert_eq!(s.by_path("patrol/nowhere"), None);
    assert_eq!(s.nodes().len(), 7);

    assert_eq!(
        s.to_string(),
        "node                    ticks  successes  failures  skips  halts  running\n\
         patrol                      5          1         1      0      0   0.300s\n\
         patrol/battery_ok           5          4         1      0      0   0.000s\n\
         patrol/route                4          1         0      0      1   0.300s\n\
         patrol/route/once           2          1         0      1      0   0.000s\n\
         patrol/route/once/wave      1          1         0      0      0   0.000s\n\
         patrol/route/move           4          1         0      0      1   0.300s\n\
         patrol/route/scan           1          1         0      0      0   0.000s\n"
    );
}

/// Running for `ticks` ticks, then Success (forever Running with `u32::MAX`).
struct Work {
    ticks: u32,
    left: u32,
}

impl<C> StatefulAction<C> for Work {
    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.left = self.ticks;
        self.on_running(h)
    }
    fn on_running(&mut self, _h: &mut Handle<'_, C>) -> Status {
        if self.left == 0 {
            return Status::Success;
        }
        self.left -= 1;
        Status::Running
    }
}

#[test]
fn results_are_counted_per_return_not_per_change() {
    // The condition is re-ticked every tick while the body runs, and is not reset in
    // between: it succeeds three times, but its stored status changes once.
    let blueprint = Blueprint::<()>::builder()
        .while_do_else("guard", |w| {
            w.condition("ok", |_: &()| true)
                .stateful("body", || Work { ticks: 2, left: 0 })
        })
        .build_shared()
        .unwrap();
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(blueprint.clone(), clock.clone());
    let s = Statistics::new(&blueprint);
    tree.set_observer(s.clone());
    for expected in [Status::Running, Status::Running, Status::Success] {
        assert_eq!(tree.tick_once(&mut ()), Ok(expected));
        clock.advance(Duration::from_millis(50));
    }
    assert_eq!(s.by_path("guard/ok"), Some(stats(3, 3, 0, 0, 0, 0)));
    assert_eq!(s.by_path("guard/body"), Some(stats(3, 1, 0, 0, 0, 100)));
    assert_eq!(s.by_path("guard"), Some(stats(3, 1, 0, 0, 0, 100)));
}

#[test]
fn preconditions_decide_without_a_tick() {
    let mut registry = Registry::<()>::new();
    registry
        .register_stateful("Work", vec![], || Work {
            ticks: u32::MAX,
            left: 0,
        })
        .unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
                 <Sequence name="root">
                   <AlwaysFailure name="forced" _successIf="true"/>
                   <AlwaysSuccess name="skipped" _skipIf="true"/>
                   <Sequence name="empty"><AlwaysSuccess name="inner" _skipIf="true"/></Sequence>
                   <Work name="work" _while="go"/>
                 </Sequence>
               </BehaviorTree></root>"#,
            "preconditions.xml",
        )
        .unwrap();
    let blueprint = std::sync::Arc::new(loader.build_main().unwrap());
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(blueprint.clone(), clock.clone());
    let s = Statistics::new(&blueprint);
    tree.set_observer(s.clone());

    tree.blackboard_mut().set("go", true).unwrap();
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    clock.advance(Duration::from_millis(250));
    // A node still Running counts its time up to the latest moment the statistics saw
    // (the end of the tick, at 0 s), not up to the clock.
    assert_eq!(s.by_path("root/work").unwrap().running, Duration::ZERO);
    tree.blackboard_mut().set("go", false).unwrap();
    // The false `_while` halts the work and skips it; the sequence is done.
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));

    assert_eq!(s.by_path("root"), Some(stats(2, 1, 0, 0, 0, 250)));
    assert_eq!(s.by_path("root/forced"), Some(stats(0, 1, 0, 0, 0, 0)));
    assert_eq!(s.by_path("root/skipped"), Some(stats(0, 0, 0, 1, 0, 0)));
    // It marked itself Running, then found its only child skipped: a skip, not a halt.
    assert_eq!(s.by_path("root/empty"), Some(stats(1, 0, 0, 1, 0, 0)));
    assert_eq!(s.by_path("root/empty/inner"), Some(stats(0, 0, 0, 1, 0, 0)));
    assert_eq!(s.by_path("root/work"), Some(stats(1, 0, 0, 1, 1, 250)));
}

#[test]
fn a_node_still_running_counts_its_time_so_far() {
    let blueprint = Blueprint::<()>::builder()
        .stateful("work", || Work {
            ticks: u32::MAX,
            left: 0,
        })
        .build_shared()
        .unwrap();
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(blueprint.clone(), clock.clone());
    let s = Statistics::new(&blueprint);
    tree.set_observer(s.clone());
    for _ in 0..4 {
        assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
        clock.advance(Duration::from_millis(100));
    }
    // Seen last at the fourth tick, 0.3 s after the first.
    assert_eq!(s.node(NodeId::ROOT), Some(stats(4, 0, 0, 0, 0, 300)));
    tree.halt(&mut ());
    assert_eq!(s.node(NodeId::ROOT), Some(stats(4, 0, 0, 0, 1, 400)));
}
