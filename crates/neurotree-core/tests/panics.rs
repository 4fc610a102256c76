//! A panic in user code ends the tick with `TickError::Panicked`, naming the node; the tree
//! halts every Running node (each Running stateful action gets exactly one `on_halted`),
//! ends the tick for the observer, and ticks normally afterwards. A panic inside
//! `on_halted` skips only that node.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree_core::{
    Arity, Blueprint, CustomNode, CustomSpec, Handle, ManualClock, NodeCtx, NodeStatus, Observer,
    StatefulAction, Status, TickError, Tree,
};

/// What the leaves of these tests did, by name.
#[derive(Default)]
struct Log {
    calls: Vec<String>,
    /// The tick on which `boom` panics (1-based), and `halt_boom` panics in `on_halted`.
    panic_on: u32,
    ticks: u32,
}

/// A stateful action that runs until halted, logging each call.
struct Walk(&'static str);

impl StatefulAction<Log> for Walk {
    fn on_start(&mut self, h: &mut Handle<'_, Log>) -> Status {
        h.ctx_mut().calls.push(format!("{} start", self.0));
        Status::Running
    }
    fn on_running(&mut self, h: &mut Handle<'_, Log>) -> Status {
        h.ctx_mut().calls.push(format!("{} running", self.0));
        Status::Running
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Log>) {
        h.ctx_mut().calls.push(format!("{} halted", self.0));
        if self.0 == "halt_boom" {
            panic!("cannot stop");
        }
    }
}

fn boom(log: &mut Log) -> Status {
    log.ticks += 1;
    if log.ticks == log.panic_on {
        panic!("kaboom at tick {}", log.ticks);
    }
    Status::Success
}

/// Counts ticks that ended, and with which status.
#[derive(Clone, Default)]
struct Ends(Arc<Mutex<Vec<NodeStatus>>>);

impl Observer for Ends {
    fn on_tick_end(&mut self, status: NodeStatus, _now: Duration) {
        self.0.lock().unwrap().push(status);
    }
}

#[test]
fn a_panicking_leaf_ends_the_tick_with_its_path_and_the_tree_ticks_on() {
    let bp = Blueprint::<Log>::builder()
        .parallel("both", -1, 1, |p| {
            p.stateful("walk", || Walk("walk"))
                .sequence("seq", |s| s.action("boom", boom))
        })
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(bp, ManualClock::new());
    let ends = Ends::default();
    tree.set_observer(ends.clone());
    // `walk` starts, then `boom` panics in the same tick.
    let mut log = Log {
        panic_on: 1,
        ..Log::default()
    };
    assert_eq!(
        tree.tick_once(&mut log),
        Err(TickError::Panicked {
            node: tree.blueprint().find("both/seq/boom").unwrap(),
            path: "both/seq/boom".into(),
            message: "kaboom at tick 1".into(),
        })
    );
    // The Running action was halted exactly once, and every node is Idle again.
    assert_eq!(log.calls, ["walk start", "walk halted"]);
    assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    // The observer saw the tick end.
    assert_eq!(*ends.0.lock().unwrap(), [NodeStatus::Idle]);
    // The next tick starts afresh.
    log.calls.clear();
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Running));
    assert_eq!(log.calls, ["walk start"]);
}

#[test]
fn a_panic_in_on_halted_skips_only_that_node() {
    let bp = Blueprint::<Log>::builder()
        .parallel("three", -1, 1, |p| {
            p.stateful("a", || Walk("halt_boom"))
                .stateful("b", || Walk("b"))
                .action("boom", boom)
        })
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(bp, ManualClock::new());
    let mut log = Log {
        panic_on: 1,
        ..Log::default()
    };
    let err = tree.tick_once(&mut log).unwrap_err();
    assert!(
        matches!(&err, TickError::Panicked { path, .. } if path == "three/boom"),
        "{err}"
    );
    // `a` panicked while halting; `b` was halted all the same, each exactly once.
    assert_eq!(
        log.calls,
        ["halt_boom start", "b start", "halt_boom halted", "b halted"]
    );
    // `a` is Idle, so the next tick starts it rather than running it on.
    log.calls.clear();
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Running));
    assert_eq!(log.calls, ["halt_boom start", "b start"]);
    // A user halt whose on_halted panics still halts the rest.
    log.calls.clear();
    tree.halt(&mut log);
    assert_eq!(log.calls, ["halt_boom halted", "b halted"]);
    assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
}

#[test]
fn a_panic_in_on_halted_during_a_tick_is_that_ticks_error() {
    // The Timeout halts its Running child on the second tick; the child panics in
    // on_halted.
    let bp = Blueprint::<Log>::builder()
        .timeout("limit", Duration::from_millis(100), |t| {
            t.stateful("a", || Walk("halt_boom"))
        })
        .build_shared()
        .unwrap();
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(bp, clock.clone());
    let mut log = Log::default();
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Running));
    clock.advance(Duration::from_millis(100));
    assert_eq!(
        tree.tick_once(&mut log),
        Err(TickError::Panicked {
            node: tree.blueprint().find("limit/a").unwrap(),
            path: "limit/a".into(),
            message: "cannot stop".into(),
        })
    );
    assert_eq!(log.calls, ["halt_boom start", "halt_boom halted"]);
    assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
}

/// A custom decorator that counts its ticks, and panics on the tick `panic_on` says.
struct Counting {
    ticks: u32,
}

impl CustomNode<Log> for Counting {
    fn tick(&mut self, node: &mut NodeCtx<'_, '_, Log>) -> NodeStatus {
        self.ticks += 1;
        node.ctx().calls.push(format!("custom tick {}", self.ticks));
        if node.ctx().panic_on == self.ticks {
            panic!("custom node gave up");
        }
        node.tick_child(0)
    }
}

#[test]
fn a_custom_node_that_panics_is_made_anew() {
    let bp = Blueprint::<Log>::builder()
        .custom(
            "count",
            CustomSpec::new(
                "Counting",
                Arity::One,
                Box::new(|| Box::new(Counting { ticks: 0 })),
            ),
            |c| c.always_success("ok"),
        )
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(bp, ManualClock::new());
    let mut log = Log {
        panic_on: 2,
        ..Log::default()
    };
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Success));
    let err = tree.tick_once(&mut log).unwrap_err();
    assert!(
        matches!(&err, TickError::Panicked { path, message, .. }
            if path == "count" && message == "custom node gave up"),
        "{err}"
    );
    // Its object was lost in the unwinding: a new one counts from 1 again.
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Success));
    assert_eq!(
        log.calls,
        ["custom tick 1", "custom tick 2", "custom tick 1"]
    );
}

#[test]
fn a_repeat_interrupted_by_a_panic_counts_afresh() {
    let bp = Blueprint::<Log>::builder()
        .repeat("thrice", 3, |r| r.action("boom", boom))
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(bp, ManualClock::new());
    let mut log = Log {
        panic_on: 2,
        ..Log::default()
    };
    assert!(matches!(
        tree.tick_once(&mut log),
        Err(TickError::Panicked { .. })
    ));
    // Three fresh cycles, not the one left over.
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Success));
    assert_eq!(log.ticks, 5);
}

#[test]
fn a_panicking_condition_is_named_in_an_unobserved_sequence_and_fallback() {
    // Closure conditions of a plain Sequence or Fallback are called straight from the child
    // list with no status stored; a panic in one still names it, not its parent or the
    // condition ticked before it.
    let bp = Blueprint::<Log>::builder()
        .sequence("root", |s| {
            s.condition("fine", |_: &Log| true)
                .fallback("fb", |f| {
                    f.condition("no", |_: &Log| false)
                        .condition("bad", |log: &Log| {
                            if log.panic_on == 1 {
                                panic!("bad condition");
                            }
                            true
                        })
                })
                .condition("after", |_: &Log| true)
        })
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(bp, ManualClock::new());
    let mut log = Log {
        panic_on: 1,
        ..Log::default()
    };
    assert_eq!(
        tree.tick_once(&mut log),
        Err(TickError::Panicked {
            node: tree.blueprint().find("root/fb/bad").unwrap(),
            path: "root/fb/bad".into(),
            message: "bad condition".into(),
        })
    );
    assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    log.panic_on = 0;
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Success));
}

/// A condition object (as the registry makes for XML) that panics when told to.
struct Explodes;

impl neurotree_core::Condition<Log> for Explodes {
    fn check(&self, h: &Handle<'_, Log>) -> bool {
        if h.ctx().panic_on == 1 {
            panic!("object condition");
        }
        false
    }
}

#[test]
fn a_panicking_condition_object_is_named_too() {
    let bp = Blueprint::<Log>::builder()
        .fallback("root", |f| {
            f.condition("first", |_: &Log| false)
                .condition_node("object", Explodes)
                .condition("last", |_: &Log| true)
        })
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(bp, ManualClock::new());
    let mut log = Log {
        panic_on: 1,
        ..Log::default()
    };
    let err = tree.tick_once(&mut log).unwrap_err();
    assert!(
        matches!(&err, TickError::Panicked { path, message, .. }
            if path == "root/object" && message == "object condition"),
        "{err}"
    );
    log.panic_on = 0;
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Success));
}

/// A condition object that holds unless its node is the one named in the context's
/// `panic_on` (its id), where it panics; it checks that the handle it gets is its own.
struct Named(&'static str);

impl neurotree_core::Condition<Log> for Named {
    fn check(&self, h: &Handle<'_, Log>) -> bool {
        assert_eq!(h.name(), self.0, "a condition gets its own node's handle");
        if h.ctx().panic_on == h.node().0 {
            panic!("{} panicked", self.0);
        }
        true
    }
}

#[test]
fn a_panicking_condition_object_in_a_guard_is_named_at_every_place() {
    // Guards of condition objects, alone at the root and under a plain Sequence: each
    // object gets its own handle, and the one that panics is blamed, wherever it stands.
    const NAMES: [&str; 7] = ["a", "b", "c", "d", "e", "f", "g"];
    for nested in [false, true] {
        for len in 1..=NAMES.len() {
            let guard = |b: neurotree_core::Builder<Log>| {
                b.sequence("guard", |mut g| {
                    for name in &NAMES[..len] {
                        g = g.condition_node(name, Named(name));
                    }
                    g
                })
            };
            let bp = if nested {
                Blueprint::<Log>::builder()
                    .sequence("root", |s| guard(s.condition("first", |_: &Log| true)))
            } else {
                guard(Blueprint::<Log>::builder())
            }
            .build_shared()
            .unwrap();
            let mut tree = Tree::with_clock(Arc::clone(&bp), ManualClock::new());
            for name in &NAMES[..len] {
                let path = if nested {
                    format!("root/guard/{name}")
                } else {
                    format!("guard/{name}")
                };
                let node = bp.find(&path).unwrap();
                let mut log = Log {
                    panic_on: node.0,
                    ..Log::default()
                };
                assert_eq!(
                    tree.tick_once(&mut log),
                    Err(TickError::Panicked {
                        node,
                        path,
                        message: format!("{name} panicked"),
                    })
                );
                log.panic_on = u32::MAX;
                assert_eq!(tree.tick_once(&mut log), Ok(Status::Success));
            }
        }
    }
}
