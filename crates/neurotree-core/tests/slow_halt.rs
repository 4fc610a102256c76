//! Halts that take several ticks (`tree::slow_halt`): an arm that decelerates over a set
//! number of ticks, under each node that waits for it, with every call counted.

use std::time::Duration;

use neurotree_core::{
    Blueprint, Builder, HaltProgress, Handle, ManualClock, NodeStatus, StatefulAction, Status, Tree,
};

/// The world the trees act on: switches the conditions read, and what the leaves did, in
/// order.
#[derive(Default)]
struct World {
    /// What the `go` condition answers.
    go: bool,
    /// What the `other_go` condition answers (a second arm's).
    other_go: bool,
    /// Every call of a leaf, as "arm start", "arm halt requested", "alt", ...
    log: Vec<String>,
}

impl World {
    fn count(&self, entry: &str) -> usize {
        self.log.iter().filter(|e| *e == entry).count()
    }
}

/// Runs until halted; a halt takes `halt_ticks` ticks: the one of the request, and
/// `halt_ticks - 1` calls of `on_halting`.
struct Arm {
    name: &'static str,
    halt_ticks: u32,
    left: u32,
}

impl Arm {
    fn new(name: &'static str, halt_ticks: u32) -> Self {
        Self {
            name,
            halt_ticks,
            left: 0,
        }
    }
    fn note(&self, h: &mut Handle<'_, World>, what: &str) {
        let line = format!("{} {what}", self.name);
        h.ctx_mut().log.push(line);
    }
}

impl StatefulAction<World> for Arm {
    fn on_start(&mut self, h: &mut Handle<'_, World>) -> Status {
        self.note(h, "start");
        Status::Running
    }
    fn on_running(&mut self, h: &mut Handle<'_, World>) -> Status {
        self.note(h, "running");
        Status::Running
    }
    fn on_halted(&mut self, h: &mut Handle<'_, World>) {
        self.note(h, "halted");
    }
    fn on_halt_requested(&mut self, h: &mut Handle<'_, World>) -> HaltProgress {
        self.note(h, "halt requested");
        self.left = self.halt_ticks - 1;
        if self.left == 0 {
            self.note(h, "halted");
            return HaltProgress::Done;
        }
        HaltProgress::Halting
    }
    fn on_halting(&mut self, h: &mut Handle<'_, World>) -> HaltProgress {
        self.left -= 1;
        if self.left == 0 {
            self.note(h, "halted");
            HaltProgress::Done
        } else {
            self.note(h, "halting");
            HaltProgress::Halting
        }
    }
}

fn alt(w: &mut World) -> Status {
    w.log.push("alt".into());
    Status::Success
}

fn tree(build: impl FnOnce(Builder<World>) -> Builder<World>) -> (Tree<World>, ManualClock) {
    let bp = build(Blueprint::builder()).build_shared().unwrap();
    let clock = ManualClock::new();
    (Tree::with_clock(bp, clock.clone()), clock)
}

/// Fallback(ReactiveSequence(go, arm), alt): the arm runs while `go` holds.
fn guarded_arm(halt_ticks: u32) -> (Tree<World>, ManualClock) {
    tree(|b| {
        b.fallback("root", |f| {
            f.reactive_sequence("guarded", |r| {
                r.condition("go", |w: &World| w.go)
                    .stateful("arm", move || Arm::new("arm", halt_ticks))
            })
            .action("alt", alt)
        })
    })
}

#[test]
fn a_reactive_sequence_starts_nothing_else_until_its_arm_has_stopped() {
    let (mut tree, _) = guarded_arm(3);
    let mut w = World {
        go: true,
        ..World::default()
    };
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    // The condition fails: the halt is requested, and the sequence stays Running.
    w.go = false;
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert!(tree.is_halting());
    // The arm is Idle (its run is over), the controls above it Running.
    let statuses: Vec<NodeStatus> = tree.statuses().to_vec();
    use NodeStatus::{Idle, Running};
    assert_eq!(statuses, [Running, Running, Idle, Idle, Idle]);
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(w.log, ["arm start", "arm halt requested", "arm halting"]);
    // The third tick of the halt ends it; in the same tick the sequence fails and the
    // fallback starts its alternative.
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Success));
    assert_eq!(
        w.log,
        [
            "arm start",
            "arm halt requested",
            "arm halting",
            "arm halted",
            "alt"
        ]
    );
    assert!(!tree.is_halting());
    assert!(tree.statuses().iter().all(|s| *s == Idle));
}

#[test]
fn a_reactive_sequence_does_not_recheck_its_condition_while_its_arm_stops() {
    /// Counts the condition's ticks in the world.
    fn go(w: &World) -> bool {
        w.go
    }
    let checks = std::sync::Arc::new(std::sync::atomic::AtomicU32::new(0));
    let seen = std::sync::Arc::clone(&checks);
    let (mut tree, _) = tree(move |b| {
        b.fallback("root", |f| {
            f.reactive_sequence("guarded", |r| {
                r.condition("go", move |w: &World| {
                    seen.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    go(w)
                })
                .stateful("arm", || Arm::new("arm", 3))
            })
            .action("alt", alt)
        })
    });
    let mut w = World {
        go: true,
        ..World::default()
    };
    let checks_now = || checks.load(std::sync::atomic::Ordering::Relaxed);
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    w.go = false;
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(checks_now(), 2);
    // The condition holds again, but nothing is checked before the arm has stopped.
    w.go = true;
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(checks_now(), 2);
    // Stopped: the sequence ticks afresh in the same tick, and the arm starts again.
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(checks_now(), 3);
    assert_eq!(
        w.log,
        [
            "arm start",
            "arm halt requested",
            "arm halting",
            "arm halted",
            "arm start"
        ]
    );
    assert_eq!(w.count("alt"), 0);
}

#[test]
fn an_arm_that_halts_at_once_behaves_as_before() {
    let (mut tree, _) = guarded_arm(1);
    let mut w = World {
        go: true,
        ..World::default()
    };
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    w.go = false;
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Success));
    assert_eq!(
        w.log,
        ["arm start", "arm halt requested", "arm halted", "alt"]
    );
    assert!(!tree.is_halting());
}

#[test]
fn a_timeout_is_running_while_its_child_stops_then_fails() {
    let (mut tree, clock) = tree(|b| {
        b.timeout("limit", ms(100), |t| {
            t.stateful("arm", || Arm::new("arm", 3))
        })
    });
    let mut w = World::default();
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    clock.advance(ms(100));
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(w.log, ["arm start", "arm halt requested", "arm halting"]);
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Failure));
    assert_eq!(w.count("arm halted"), 1);
    assert_eq!(w.count("arm running"), 0);
    let failure = tree.last_failure().unwrap();
    assert_eq!(
        failure.reason().unwrap().to_string(),
        "timed out after 100 ms"
    );
    // The next run is timed afresh.
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(w.count("arm start"), 2);
}

#[test]
fn while_do_else_ticks_the_other_branch_only_once_the_first_has_stopped() {
    let (mut tree, _) = tree(|b| {
        b.while_do_else("wde", |x| {
            x.condition("go", |w: &World| w.go)
                .stateful("arm", || Arm::new("arm", 2))
                .action("alt", alt)
        })
    });
    let mut w = World {
        go: true,
        ..World::default()
    };
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    w.go = false;
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(w.log, ["arm start", "arm halt requested"]);
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Success));
    assert_eq!(
        w.log,
        ["arm start", "arm halt requested", "arm halted", "alt"]
    );
}

#[test]
fn a_parallel_returns_its_outcome_once_its_halted_children_have_stopped() {
    // One success is enough; the arm still runs and takes 3 ticks to stop.
    let (mut tree, _) = tree(|b| {
        b.sequence("root", |s| {
            s.parallel("p", 1, -1, |p| {
                p.stateful("arm", || Arm::new("arm", 3)).action("alt", alt)
            })
            .action("after", |w: &mut World| {
                w.log.push("after".into());
                Status::Success
            })
        })
    });
    let mut w = World::default();
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(
        w.log,
        ["arm start", "alt", "arm halt requested", "arm halting"]
    );
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Success));
    assert_eq!(
        w.log,
        [
            "arm start",
            "alt",
            "arm halt requested",
            "arm halting",
            "arm halted",
            "after"
        ]
    );
}

#[test]
fn tree_halt_says_whether_it_is_done_and_tick_halt_finishes_it() {
    let (mut tree, _) = guarded_arm(3);
    let mut w = World {
        go: true,
        ..World::default()
    };
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert!(!tree.halt(&mut w));
    assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    assert!(!tree.tick_halt(&mut w));
    assert!(tree.tick_halt(&mut w));
    assert!(tree.tick_halt(&mut w), "done stays done");
    assert_eq!(
        w.log,
        [
            "arm start",
            "arm halt requested",
            "arm halting",
            "arm halted"
        ]
    );
    // A halt of a tree that halts at once is done at once.
    let (mut quick, _) = guarded_arm(1);
    assert_eq!(quick.tick_once(&mut w), Ok(Status::Running));
    assert!(quick.halt(&mut w));
}

#[test]
fn ticks_after_tree_halt_finish_the_halt_before_the_root_runs_again() {
    let (mut tree, _) = guarded_arm(3);
    let mut w = World {
        go: true,
        ..World::default()
    };
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert!(!tree.halt(&mut w));
    // The root is not ticked while the halt goes on: no condition, no start.
    assert_eq!(tree.tick_exactly_once(&mut w), Ok(Status::Running));
    assert_eq!(w.log.last().unwrap(), "arm halting");
    // The halt ends, and the same call ticks the root: the arm starts again.
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(
        w.log,
        [
            "arm start",
            "arm halt requested",
            "arm halting",
            "arm halted",
            "arm start"
        ]
    );
}

#[test]
fn a_halt_in_progress_waits_for_whoever_halts_the_node_that_waited() {
    // The sequence waits for its arm; then the whole tree is halted: the arm now waits for
    // the tree, and still gets one on_halting per call, never a second request.
    let (mut tree, _) = guarded_arm(4);
    let mut w = World {
        go: true,
        ..World::default()
    };
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    w.go = false;
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert!(!tree.halt(&mut w));
    assert!(!tree.tick_halt(&mut w));
    assert!(tree.tick_halt(&mut w));
    assert_eq!(
        w.log,
        [
            "arm start",
            "arm halt requested",
            "arm halting",
            "arm halting",
            "arm halted"
        ]
    );
    assert_eq!(w.count("arm halt requested"), 1);
    assert_eq!(w.count("alt"), 0);
}

#[test]
fn two_arms_under_one_reactive_fallback_each_wait_for_their_own_halter() {
    // ReactiveFallback(Sequence(other_go, arm_a), arm_b): when other_go holds, arm_a runs
    // and arm_b is halted; arm_b takes 2 ticks to stop, during which arm_a is not ticked.
    let (mut tree, _) = tree(|b| {
        b.reactive_fallback("rf", |r| {
            r.reactive_sequence("first", |s| {
                s.condition("other_go", |w: &World| w.other_go)
                    .stateful("a", || Arm::new("a", 1))
            })
            .stateful("b", || Arm::new("b", 3))
        })
    });
    let mut w = World::default();
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    w.other_go = true;
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    // As in BehaviorTree.CPP, "a" started before "b" was halted, in the same tick.
    assert_eq!(w.log, ["b start", "a start", "b halt requested"]);
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(
        w.log,
        [
            "b start",
            "a start",
            "b halt requested",
            "b halting",
            "b halted",
            "a running"
        ]
    );
}

fn catch(w: &mut World) -> Status {
    w.log.push("catch".into());
    Status::Success
}

#[test]
fn a_try_catch_halted_while_trying_runs_its_catch_only_once_its_arm_has_stopped() {
    // Fallback(ReactiveSequence(go, TryCatch[catch_on_halt](arm, catch)), alt).
    let (mut tree, _) = tree(|b| {
        b.fallback("root", |f| {
            f.reactive_sequence("guarded", |r| {
                r.condition("go", |w: &World| w.go)
                    .try_catch("tc", true, |t| {
                        t.stateful("arm", || Arm::new("arm", 3))
                            .action("catch", catch)
                    })
            })
            .action("alt", alt)
        })
    });
    let mut w = World {
        go: true,
        ..World::default()
    };
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    w.go = false;
    // The sequence halts the TryCatch, which halts the arm: the catch waits for it.
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert!(tree.is_halting());
    use NodeStatus::{Idle, Running};
    assert_eq!(
        tree.statuses(),
        [Running, Running, Idle, Idle, Idle, Idle, Idle]
    );
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(w.log, ["arm start", "arm halt requested", "arm halting"]);
    // The arm stops; in the same tick the catch runs, once, then the sequence ticks as
    // usual: `go` fails, and the fallback's alternative runs.
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Success));
    assert_eq!(
        w.log,
        [
            "arm start",
            "arm halt requested",
            "arm halting",
            "arm halted",
            "catch",
            "alt"
        ]
    );
    assert!(!tree.is_halting());
    assert!(tree.statuses().iter().all(|s| *s == Idle));
}

#[test]
fn after_tree_halt_a_try_catch_runs_its_catch_before_the_root_is_ticked_again() {
    let (mut tree, _) = tree(|b| {
        b.try_catch("tc", true, |t| {
            t.stateful("arm", || Arm::new("arm", 3))
                .action("catch", catch)
        })
    });
    let mut w = World::default();
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert!(!tree.halt(&mut w));
    assert_eq!(w.log, ["arm start", "arm halt requested"]);
    assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    // Halted again while the catch waits: the catch still runs once, later.
    assert!(!tree.halt(&mut w));
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(w.log.last().unwrap(), "arm halting");
    // The halt ends with the catch; the same call then ticks the root afresh.
    assert_eq!(tree.tick_once(&mut w), Ok(Status::Running));
    assert_eq!(
        w.log,
        [
            "arm start",
            "arm halt requested",
            "arm halting",
            "arm halted",
            "catch",
            "arm start"
        ]
    );
    assert_eq!(w.count("catch"), 1);
}

#[test]
fn a_catch_run_after_a_halt_is_halted_once_and_its_own_halt_may_take_ticks() {
    // The catch is an action that runs, and takes 2 ticks to halt.
    let (mut slow, _) = tree(|b| {
        b.try_catch("tc", true, |t| {
            t.stateful("arm", || Arm::new("arm", 2))
                .stateful("cleanup", || Arm::new("cleanup", 2))
        })
    });
    let mut w = World::default();
    assert_eq!(slow.tick_once(&mut w), Ok(Status::Running));
    assert!(!slow.halt(&mut w));
    assert!(!slow.tick_halt(&mut w));
    assert_eq!(
        w.log,
        [
            "arm start",
            "arm halt requested",
            "arm halted",
            "cleanup start",
            "cleanup halt requested"
        ]
    );
    assert!(slow.tick_halt(&mut w));
    assert_eq!(w.log.last().unwrap(), "cleanup halted");
    assert_eq!(
        (w.count("cleanup start"), w.count("cleanup halted")),
        (1, 1)
    );
    assert!(slow.statuses().iter().all(|s| *s == NodeStatus::Idle));
    // A halt that is done at once runs the catch in the halt itself, as before.
    let (mut quick, _) = tree(|b| {
        b.try_catch("tc", true, |t| {
            t.stateful("arm", || Arm::new("arm", 1))
                .action("catch", catch)
        })
    });
    let mut w = World::default();
    assert_eq!(quick.tick_once(&mut w), Ok(Status::Running));
    assert!(quick.halt(&mut w));
    assert_eq!(
        w.log,
        ["arm start", "arm halt requested", "arm halted", "catch"]
    );
}

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}
