//! Why the root failed: the chain `Tree::last_failure` builds from the reasons nodes gave,
//! through Sequences, Fallbacks, Retries and Timeouts; the observer's view of reasons; and
//! the promise that a static reason allocates nothing.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree_core::{
    Action, Blueprint, Builder, Failure, Handle, ManualClock, NodeId, NodeStatus, Observer, Reason,
    StatefulAction, Status, StatusChange, Tree,
};

use crate::counting_alloc;
use counting_alloc::allocations;

/// Fails with a static reason.
struct FailWith(u32, &'static str);
impl<C> Action<C> for FailWith {
    fn tick(&self, h: &mut Handle<'_, C>) -> Status {
        h.fail_with(self.0, self.1)
    }
}

/// Runs until halted.
struct Forever;
impl<C> StatefulAction<C> for Forever {
    fn on_start(&mut self, _h: &mut Handle<'_, C>) -> Status {
        Status::Running
    }
    fn on_running(&mut self, _h: &mut Handle<'_, C>) -> Status {
        Status::Running
    }
}

fn tree(b: Builder<()>) -> (Tree<()>, ManualClock) {
    let clock = ManualClock::new();
    (
        Tree::with_clock(b.build_shared().unwrap(), clock.clone()),
        clock,
    )
}

/// A chain as `path: reason` per link, and `tried path: reason` per Fallback try.
fn lines(f: &Failure) -> Vec<String> {
    let mut out = Vec::new();
    for link in &f.links {
        out.push(match &link.reason {
            Some(r) => format!("{}: {r}", link.path),
            None => link.path.clone(),
        });
        for t in &link.tried {
            out.push(match &t.reason {
                Some(r) => format!("  tried {}: {r}", t.path),
                None => format!("  tried {}", t.path),
            });
        }
    }
    out
}

#[test]
fn a_leaf_failing_under_a_sequence() {
    let (mut t, _) = tree(Blueprint::builder().sequence("go", |s| {
        s.condition("ready", |_: &()| true)
            .action_node("follow_path", FailWith(106, "blocked"))
            .condition("never", |_: &()| true)
    }));
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
    let f = t.last_failure().unwrap();
    assert_eq!(lines(&f), ["go", "go/follow_path: blocked (error 106)"]);
    assert_eq!(f.leaf().node, NodeId(2));
    assert_eq!(f.reason(), Some(&Reason::new(106, "blocked")));
    assert_eq!(f.to_string(), "go\n  go/follow_path: blocked (error 106)");
}

#[test]
fn a_fallback_whose_children_all_failed_lists_each_reason() {
    let (mut t, _) = tree(Blueprint::builder().sequence("root", |s| {
        s.fallback("fb", |f| {
            f.action_node("a", FailWith(1, "a broke"))
                .condition("b", |_: &()| false)
                .sequence("c", |c| c.action_node("c1", FailWith(3, "c1 broke")))
        })
    }));
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
    assert_eq!(
        lines(&t.last_failure().unwrap()),
        [
            "root",
            "root/fb",
            "  tried root/fb/a: a broke (error 1)",
            "  tried root/fb/b",
            "  tried root/fb/c: c1 broke (error 3)",
            "root/fb/c",
            "root/fb/c/c1: c1 broke (error 3)",
        ]
    );
}

#[test]
fn the_last_child_of_a_failed_fallback_decides_even_without_a_reason() {
    let (mut t, _) = tree(Blueprint::builder().fallback("fb", |f| {
        f.action_node("a", FailWith(1, "a broke"))
            .condition("b", |_: &()| false)
    }));
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
    let f = t.last_failure().unwrap();
    assert_eq!(
        lines(&f),
        [
            "fb",
            "  tried fb/a: a broke (error 1)",
            "  tried fb/b",
            "fb/b"
        ]
    );
    // The deepest reason is the one a Fallback alternative gave: the chain's own links
    // carry none, so `reason` says nothing rather than blame `a`.
    assert_eq!(f.reason(), None);
}

#[test]
fn a_retry_that_ran_out_counts_its_attempts() {
    let mut t = docking(3);
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
    assert_eq!(lines(&t.last_failure().unwrap()), docking_chain(3));
    // One attempt per call: the attempts span calls, the count is the Retry's.
    for _ in 0..2 {
        assert_eq!(t.tick_exactly_once(&mut ()), Ok(Status::Running));
        assert_eq!(t.last_failure(), None);
    }
    assert_eq!(t.tick_exactly_once(&mut ()), Ok(Status::Failure));
    assert_eq!(
        t.last_failure().unwrap().links[1].reason,
        Some(Reason::owned(0, "gave up after 3 attempts"))
    );
}

#[test]
fn a_timeout_gives_its_own_reason() {
    let (mut t, clock) = tree(Blueprint::builder().sequence("root", |s| {
        s.timeout("limit", Duration::from_millis(100), |t| {
            t.stateful("drive", || Forever)
        })
    }));
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Running));
    assert_eq!(t.last_failure(), None);
    clock.advance(Duration::from_millis(100));
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
    assert_eq!(
        lines(&t.last_failure().unwrap()),
        ["root", "root/limit: timed out after 100 ms"]
    );

    let (mut t, clock) = tree(
        Blueprint::builder().timeout("limit", Duration::from_secs(2), |t| {
            t.stateful("drive", || Forever)
        }),
    );
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Running));
    clock.advance(Duration::from_secs(2));
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
    assert_eq!(
        lines(&t.last_failure().unwrap()),
        ["limit: timed out after 2 s"]
    );
}

#[test]
fn a_failure_without_a_reason_reaches_its_leaf_and_a_stale_reason_is_not_blamed() {
    // `a` fails with a reason, but its Fallback recovers; `c`, which gives none, fails
    // the root.
    let (mut t, _) = tree(Blueprint::builder().sequence("root", |s| {
        s.fallback("fb", |f| {
            f.action_node("a", FailWith(1, "a broke"))
                .condition("ok", |_: &()| true)
        })
        .condition("c", |_: &()| false)
    }));
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
    assert_eq!(lines(&t.last_failure().unwrap()), ["root", "root/c"]);

    let (mut t, _) = tree(Blueprint::builder().condition("c", |_: &()| false));
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
    assert_eq!(lines(&t.last_failure().unwrap()), ["c"]);
    // A success clears it.
    let (mut t, _) = tree(Blueprint::builder().always_success("ok"));
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Success));
    assert_eq!(t.last_failure(), None);
}

/// Notes reasons and status changes, in order.
#[derive(Clone, Default)]
struct Seen(Arc<Mutex<Vec<String>>>);
impl Observer for Seen {
    fn on_status_change(&mut self, c: StatusChange) {
        let line = format!("{} {}->{}", c.node, c.from, c.to);
        self.0.lock().unwrap().push(line);
    }
    fn on_failure_reason(&mut self, node: NodeId, reason: &Reason) {
        self.0
            .lock()
            .unwrap()
            .push(format!("{node} because {reason}"));
    }
}

#[test]
fn the_observer_hears_the_reason_just_before_the_failure() {
    let (mut t, _) =
        tree(Blueprint::builder().sequence("root", |s| s.action_node("a", FailWith(5, "jammed"))));
    let seen = Seen::default();
    t.set_observer(seen.clone());
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
    assert_eq!(
        *seen.0.lock().unwrap(),
        [
            "#0 IDLE->RUNNING",
            "#1 because jammed (error 5)",
            "#1 IDLE->FAILURE",
            "#1 FAILURE->IDLE",
            "#0 RUNNING->FAILURE",
            "#0 FAILURE->IDLE",
        ]
    );
    assert_eq!(
        lines(&t.last_failure().unwrap()),
        ["root", "root/a: jammed (error 5)"]
    );
}

#[test]
fn a_static_reason_allocates_nothing() {
    let (mut t, _) = tree(Builder::new().fallback("root", |f| {
        f.action_node("a", FailWith(1, "a"))
            .sequence("s", |s| s.action_node("b", FailWith(2, "b")))
            .retry("r", 2, |r| r.action_node("c", FailWith(3, "c")))
    }));
    // The first tick grows the record to the size a tick needs.
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
    let n = allocations(|| {
        for _ in 0..100 {
            assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
            assert_eq!(t.tick_exactly_once(&mut ()), Ok(Status::Running));
            assert_eq!(t.tick_exactly_once(&mut ()), Ok(Status::Failure));
        }
    });
    // The Retry's own reason is recorded as a count, formatted only when asked for.
    assert_eq!(n, 0);
    assert_eq!(t.status(NodeId::ROOT), NodeStatus::Idle);
    assert_eq!(t.last_failure().unwrap().leaf().path, "root/r/c");
}

/// A Retry of `attempts` around a leaf that fails with a reason each time: each tick of the
/// tree notes two entries an attempt, and a few more above.
fn docking(attempts: i32) -> Tree<()> {
    tree(Blueprint::builder().sequence("root", |s| {
        s.retry("retry", attempts, |r| {
            r.action_node("dock", FailWith(7, "no dock"))
        })
    }))
    .0
}

/// The chain of every failing tick of [`docking`].
fn docking_chain(attempts: i32) -> [String; 3] {
    [
        "root".to_string(),
        format!("root/retry: gave up after {attempts} attempts"),
        "root/retry/dock: no dock (error 7)".to_string(),
    ]
}

/// Bytes of a record with room for `words` words of 4 bytes (a failure takes one, a reason
/// two), and, beside it, room for `kept` reasons of 32 bytes kept apart (a static or owned
/// one): a `ThinVec` head of 16 bytes each, and the box holding the pass's error, the last
/// call's and the reasons kept apart.
fn record_bytes(words: usize, kept: usize) -> usize {
    let apart = match kept {
        0 => 0,
        kept => box_bytes() + 16 + kept * 32,
    };
    16 + words * 4 + apart
}

/// Bytes of the box that keeps a tree's errors and the reasons kept apart: the pass's
/// error, the last call's, and the reasons' pointer.
fn box_bytes() -> usize {
    2 * core::mem::size_of::<Option<neurotree_core::TickError>>() + 8
}

#[test]
fn a_full_record_drops_its_older_half_and_keeps_the_chain() {
    let mut t = docking(40);
    // The tree has no record until its first reason: that tick makes it with room for 16
    // words and doubles it once; 40 attempts note 80 entries (120 words), more than it
    // holds, and it grows no further. The leaf's static reasons are kept apart: room for 4,
    // then 16, as many as 32 words hold.
    let fresh = t.state_bytes();
    let n = allocations(|| assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure)));
    assert_eq!(n, 5);
    let with_record = t.state_bytes();
    assert_eq!(with_record, fresh + record_bytes(32, 16));
    for _ in 0..3 {
        let n = allocations(|| assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure)));
        assert_eq!(n, 0);
        assert_eq!(t.state_bytes(), with_record);
        assert_eq!(lines(&t.last_failure().unwrap()), docking_chain(40));
    }
}

#[test]
fn a_record_keeps_room_for_16_until_a_tick_notes_more() {
    // Three attempts note 13 words (the leaf's reason and failure each time, the Retry's
    // and the root's): the record made by the first tick keeps its room for 16, the three
    // static reasons their room for 4, and no tick after allocates.
    let mut t = docking(3);
    let fresh = t.state_bytes();
    let n = allocations(|| assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure)));
    assert_eq!(n, 3);
    assert_eq!(t.state_bytes(), fresh + record_bytes(16, 4));
    for _ in 0..3 {
        let n = allocations(|| assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure)));
        assert_eq!(n, 0);
        assert_eq!(t.state_bytes(), fresh + record_bytes(16, 4));
        assert_eq!(lines(&t.last_failure().unwrap()), docking_chain(3));
    }
}

#[test]
fn a_record_of_built_in_reasons_is_entries_alone() {
    // A Retry that gives up and a Timeout that fires give reasons that fit an entry: the
    // first tick makes the record (one allocation, 80 bytes), and no tick allocates after.
    let (mut t, clock) = tree(Blueprint::builder().fallback("root", |f| {
        f.retry("retry", 3, |r| r.condition("seen", |_: &()| false))
            .timeout("limit", Duration::from_millis(100), |d| {
                d.stateful("wait", || Forever)
            })
    }));
    let fresh = t.state_bytes();
    // The Retry gives up in the first tick, which makes the record.
    let n = allocations(|| assert_eq!(t.tick_once(&mut ()), Ok(Status::Running)));
    assert_eq!(n, 1);
    clock.advance(Duration::from_millis(100));
    let n = allocations(|| assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure)));
    assert_eq!(n, 0);
    assert_eq!(t.state_bytes(), fresh + record_bytes(16, 0));
    assert_eq!(
        lines(&t.last_failure().unwrap()),
        [
            // The Fallback resumed at its Running child: the Retry ran in the first tick.
            "root",
            "  tried root/limit: timed out after 100 ms",
            "root/limit: timed out after 100 ms",
        ]
    );
}

#[test]
fn a_tree_whose_nodes_give_no_reason_carries_no_record() {
    // Actions, a Retry and a Timeout could give reasons; these never do.
    let (mut t, _) = tree(Blueprint::builder().sequence("root", |s| {
        s.retry("retry", 2, |r| r.action("ok", |_: &mut ()| Status::Success))
            .timeout("limit", core::time::Duration::from_secs(1), |d| {
                d.action("ok2", |_: &mut ()| Status::Success)
            })
    }));
    let fresh = t.state_bytes();
    let n = allocations(|| {
        for _ in 0..3 {
            assert_eq!(t.tick_once(&mut ()), Ok(Status::Success));
        }
    });
    assert_eq!(n, 0);
    assert_eq!(t.state_bytes(), fresh);
}

#[test]
fn a_reserved_record_makes_even_the_first_reason_allocate_nothing() {
    let mut t = docking(3);
    let fresh = t.state_bytes();
    t.reserve_failure_record();
    assert_eq!(t.state_bytes(), fresh + record_bytes(32, 16));
    // What `Tree::reserve_failure_record` says it costs.
    assert_eq!(record_bytes(32, 16), 792);
    let n = allocations(|| assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure)));
    assert_eq!(n, 0);
    assert_eq!(lines(&t.last_failure().unwrap()), docking_chain(3));
}

#[test]
fn a_fallback_of_sequences_whose_first_conditions_fail_lists_each_down_to_its_leaf() {
    // Closure conditions, called straight from the child lists (their statuses never
    // stored), and a Sequence of conditions alone, run as one guard.
    let (mut t, _) = tree(Blueprint::builder().fallback("root", |f| {
        f.sequence("dock", |s| {
            s.condition("battery_low", |_: &()| false)
                .action("go_dock", |_: &mut ()| Status::Success)
        })
        .sequence("patrol", |s| {
            s.condition("battery_ok", |_: &()| false)
                .condition("map_ready", |_: &()| true)
        })
    }));
    for _ in 0..2 {
        assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
        let f = t.last_failure().unwrap();
        assert_eq!(
            lines(&f),
            [
                "root",
                "  tried root/dock",
                "  tried root/patrol",
                "root/patrol",
                "root/patrol/battery_ok",
            ]
        );
        assert_eq!(
            f.links[0].tried[0]
                .chain
                .iter()
                .map(|l| l.path.as_str())
                .collect::<Vec<_>>(),
            ["root/dock", "root/dock/battery_low"]
        );
        assert_eq!(
            f.to_string(),
            "root\n  tried root/dock: no reason given\n    root/dock/battery_low\n  \
             tried root/patrol: no reason given\n  root/patrol\n    root/patrol/battery_ok"
        );
    }
}

#[test]
fn an_inverter_whose_child_succeeded_says_so() {
    let (mut t, _) = tree(
        Blueprint::builder().sequence("root", |s| s.inverter("not", |i| i.always_success("ok"))),
    );
    assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
    assert_eq!(
        lines(&t.last_failure().unwrap()),
        ["root", "root/not: its child succeeded"]
    );
}

#[test]
fn marking_failures_allocates_nothing() {
    let (mut t, _) = tree(Blueprint::builder().fallback("root", |f| {
        f.sequence("a", |s| s.condition("c", |_: &()| false))
            .condition("d", |_: &()| false)
    }));
    let bytes = t.state_bytes();
    let n = allocations(|| {
        for _ in 0..100 {
            assert_eq!(t.tick_once(&mut ()), Ok(Status::Failure));
        }
    });
    assert_eq!(n, 0);
    assert_eq!(t.state_bytes(), bytes);
}

/// Errs on the first tick (a runtime error), fails with a static reason on the second,
/// succeeds on the third, then again: the context counts the ticks.
struct Moody;
impl Action<u32> for Moody {
    fn tick(&self, h: &mut Handle<'_, u32>) -> Status {
        let step = *h.ctx();
        *h.ctx_mut() += 1;
        match step % 3 {
            0 => {
                h.fail("broken");
                Status::Failure
            }
            1 => h.fail_with(3, "no"),
            _ => Status::Success,
        }
    }
}

#[test]
fn the_last_tick_calls_error_is_kept_until_the_next_tick_call_and_a_halt_leaves_it() {
    let bp = Blueprint::<u32>::builder()
        .sequence("root", |s| s.action_node("moody", Moody))
        .build_shared()
        .unwrap();
    let mut t = Tree::with_clock(bp, ManualClock::new());
    let mut step = 0;
    let fresh = t.state_bytes();
    assert_eq!(t.last_error(), None);
    for tick_once in [true, false] {
        let tick = |t: &mut Tree<u32>, step: &mut u32| match tick_once {
            true => t.tick_once(step),
            false => t.tick_exactly_once(step),
        };
        let error = tick(&mut t, &mut step).unwrap_err();
        assert!(
            matches!(&error, neurotree_core::TickError::Node { message, .. } if message == "broken")
        );
        assert_eq!(t.last_error(), Some(&error));
        // A halt is not a tick call: the error stays.
        t.halt(&mut step);
        assert_eq!(t.last_error(), Some(&error));
        assert_eq!(tick(&mut t, &mut step), Ok(Status::Failure));
        assert_eq!(t.last_error(), None);
        assert_eq!(
            lines(&t.last_failure().unwrap())[1],
            "root/moody: no (error 3)"
        );
        // The box that kept the error also keeps the static reason, with room for 4.
        assert_eq!(t.state_bytes(), fresh + record_bytes(16, 4));
        assert_eq!(tick(&mut t, &mut step), Ok(Status::Success));
        assert_eq!(t.last_error(), None);
    }
}

/// Runs in its first tick and panics in its next.
struct PanicsWhenResumed;
impl<C> StatefulAction<C> for PanicsWhenResumed {
    fn on_start(&mut self, _h: &mut Handle<'_, C>) -> Status {
        Status::Running
    }
    fn on_running(&mut self, _h: &mut Handle<'_, C>) -> Status {
        panic!("lost the map")
    }
}

#[test]
fn the_error_of_a_resumed_action_and_of_a_halt_request_is_kept_and_the_first_makes_its_box() {
    let (mut t, _) =
        tree(Blueprint::builder().sequence("root", |s| s.stateful("drive", || PanicsWhenResumed)));
    let fresh = t.state_bytes();
    assert_eq!(t.tick_exactly_once(&mut ()), Ok(Status::Running));
    // Resumed where it rested, without a pass from the root, it panics.
    let error = t.tick_exactly_once(&mut ()).unwrap_err();
    assert!(
        matches!(&error, neurotree_core::TickError::Panicked { message, .. } if message == "lost the map")
    );
    assert_eq!(t.last_error(), Some(&error));
    // The box that keeps the tree's errors: made by its first, kept.
    let kept = t.state_bytes() - fresh;
    assert_eq!(kept, box_bytes());
    assert_eq!(t.tick_exactly_once(&mut ()), Ok(Status::Running));
    assert_eq!(t.last_error(), None);
    // A halt request served: its error is kept too, and allocates nothing now.
    let handle = t.halt_handle();
    handle.request();
    let n = allocations(|| {
        assert_eq!(
            t.tick_exactly_once(&mut ()),
            Err(neurotree_core::TickError::HaltRequested)
        )
    });
    assert_eq!(n, 0);
    assert_eq!(
        t.last_error(),
        Some(&neurotree_core::TickError::HaltRequested)
    );
    assert_eq!(t.state_bytes() - fresh, kept);
}

#[test]
fn a_trees_first_error_allocates_its_box_once() {
    let (mut t, _) =
        tree(Blueprint::builder().sequence("root", |s| s.stateful("drive", || Forever)));
    let handle = t.halt_handle();
    for first in [true, false] {
        assert_eq!(t.tick_once(&mut ()), Ok(Status::Running));
        handle.request();
        // A halt request's error has no text: only the box is made, by the first.
        let n = allocations(|| {
            assert_eq!(
                t.tick_once(&mut ()),
                Err(neurotree_core::TickError::HaltRequested)
            )
        });
        assert_eq!(n, usize::from(first));
    }
}

/// Runs in its first tick and fails with a reason in its next.
struct GivesUpWhenResumed;
impl<C> StatefulAction<C> for GivesUpWhenResumed {
    fn on_start(&mut self, _h: &mut Handle<'_, C>) -> Status {
        Status::Running
    }
    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        h.fail_with(7, "no dock")
    }
}

#[test]
fn a_resumed_action_s_reason_is_in_the_chain_whichever_tick_call_resumed_it() {
    for exactly_once in [false, true] {
        let (mut t, _) = tree(
            Blueprint::builder().sequence("root", |s| s.stateful("dock", || GivesUpWhenResumed)),
        );
        let tick = |t: &mut Tree<()>| match exactly_once {
            true => t.tick_exactly_once(&mut ()),
            false => t.tick_once(&mut ()),
        };
        assert_eq!(tick(&mut t), Ok(Status::Running));
        assert_eq!(tick(&mut t), Ok(Status::Failure));
        assert_eq!(
            lines(&t.last_failure().unwrap()),
            ["root", "root/dock: no dock (error 7)"],
            "exactly once: {exactly_once}"
        );
    }
}
