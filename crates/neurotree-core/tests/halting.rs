//! Halting and resetting, as properties of random trees under random ticks and halts:
//!
//! (a) a StatefulAction that returned Running ends that run exactly once, by a completion
//!     (a later Success or Failure) or by one `on_halted`, before it is started again; it is
//!     stored Running exactly while such a run is open; after `tree.halt()` every node is
//!     Idle (BT.CPP's `haltTree` resets every node);
//! (b) halts go children first: when a node goes from Running to Idle, none of its
//!     descendants is still Running (checked on the observer's own copy of the statuses,
//!     which must equal the tree's after every step);
//! (c) after a tick that returns Success or Failure every stored status is Idle, except
//!     where BehaviorTree.CPP itself leaves a completed status behind.
//!
//! Each property runs twice: with every halt immediate (BehaviorTree.CPP's), and with each
//! stateful action's halt taking a random 0 to 3 more ticks (`StatefulAction::on_halting`).
//! There (a) reads: a run ends by one completion or by one halt, which may be in progress
//! over several ticks, during which the action is stored Idle, not started again and
//! asked nothing but `on_halting`; and after the final halt, `tick_halt` is called until the
//! tree is fully halted, and then no halt is in progress. That takes at most 3 calls per
//! halt; a TryCatch with `catch_on_halt` runs its catch once the halts below it are done,
//! and the catch's own halt may take ticks, so every TryCatch above a leaf may add a
//! halt's ticks (16 calls cover the generated trees' depth).
//!
//! The same three properties hold with async actions among the leaves, their runs ended
//! by completion or by a halt whose future takes 0 to 3 more ticks
//! (`AsyncAction::on_halt_requested`), under the same rules: (a) reads the same for them.
//!
//! The trees are those of `reference_model.rs` without Repeat/Retry(-1), so every
//! `tick_once` ends.

use crate::common;

use std::sync::{Arc, Mutex};

use common::{Ctx, Event, FlatKind, Kind, LeafKind, Op, Spec, What};
use neurotree_core::{
    ManualClock, NodeId, NodeKind, NodeStatus, Observer, Status, StatusChange, TickError, Tree,
};
use proptest::prelude::*;

use NodeStatus::{Failure, Idle, Running, Success};

/// Passes of one `tick_once` after which the run counts as endless (the tree's own bound,
/// `Tree::set_max_passes`). Some trees yield on every pass, in BT.CPP too: a node that
/// yields under a Parallel that then completes, inside a KeepRunningUntilFailure or before
/// a Running sibling in a ReactiveSequence. Such cases are discarded.
const MAX_PASSES: usize = 1000;

/// What the observer saw.
#[derive(Default)]
struct Seen {
    /// Passes since the step began.
    passes: usize,
    /// The statuses, from the reported changes alone.
    mirror: Vec<NodeStatus>,
    /// Node `i`'s descendants are `i + 1 .. end[i]` (pre-order numbering).
    end: Vec<usize>,
    /// Broken rules, as text.
    violations: Vec<String>,
    /// Running → Idle changes seen.
    stops: usize,
}

#[derive(Clone)]
struct Watch(Arc<Mutex<Seen>>);

impl Observer for Watch {
    fn on_tick_start(&mut self, _now: std::time::Duration) {
        self.0.lock().unwrap().passes += 1;
    }

    fn on_status_change(&mut self, c: StatusChange) {
        let mut seen = self.0.lock().unwrap();
        let id = c.node.index();
        if seen.mirror[id] != c.from {
            let msg = format!(
                "node {id}: change reported from {} but it was {}",
                c.from, seen.mirror[id]
            );
            seen.violations.push(msg);
        }
        if c.from == Running && c.to == Idle {
            seen.stops += 1;
            for d in id + 1..seen.end[id] {
                if seen.mirror[d] == Running {
                    let msg = format!("node {id} went Running -> Idle before its descendant {d}");
                    seen.violations.push(msg);
                }
            }
        }
        seen.mirror[id] = c.to;
    }
}

/// `end[i]`: one past node `i`'s last descendant.
fn subtree_ends(spec: &Spec) -> Vec<usize> {
    let flat = spec.flatten();
    let mut end = vec![0; flat.len()];
    for id in (0..flat.len()).rev() {
        end[id] = flat[id].children.last().map_or(id + 1, |&c| end[c]);
    }
    end
}

/// A tree of `spec` with a [`Watch`] attached; every halt immediate.
fn start(spec: &Spec) -> (Tree<Ctx>, Ctx, Arc<Mutex<Seen>>) {
    start_with(spec, &[])
}

/// As [`start`], leaf `i`'s halts taking `halt_ticks[i]` more ticks.
fn start_with(spec: &Spec, halt_ticks: &[usize]) -> (Tree<Ctx>, Ctx, Arc<Mutex<Seen>>) {
    let mut tree = Tree::with_clock(common::blueprint(spec), ManualClock::new());
    tree.set_max_passes(MAX_PASSES as u32);
    let seen = Arc::new(Mutex::new(Seen {
        mirror: vec![Idle; spec.len()],
        end: subtree_ends(spec),
        ..Seen::default()
    }));
    tree.set_observer(Watch(Arc::clone(&seen)));
    (tree, Ctx::new(spec).with_halt_ticks(halt_ticks), seen)
}

/// Runs one step: `None` for a halt, else the tick's result. `Err` (the case is discarded)
/// when a `tick_once` does not end.
fn step(
    tree: &mut Tree<Ctx>,
    ctx: &mut Ctx,
    seen: &Mutex<Seen>,
    op: Op,
) -> Result<Option<Result<Status, TickError>>, TestCaseError> {
    seen.lock().unwrap().passes = 0;
    let result = match op {
        Op::TickOnce => Some(tree.tick_once(ctx)),
        Op::TickExactlyOnce => Some(tree.tick_exactly_once(ctx)),
        Op::Halt => {
            tree.halt(ctx);
            None
        }
    };
    match &result {
        Some(Err(TickError::TooManyPasses { .. })) => {
            Err(TestCaseError::reject("endless tick_once"))
        }
        // Scripted leaves never break a contract; a RunOnce root may be Skipped.
        Some(Err(e)) => {
            prop_assert_eq!(e, &TickError::RootSkipped);
            Ok(result)
        }
        _ => Ok(result),
    }
}

/// Where a stateful leaf's run stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Run {
    Closed,
    Open,
    /// Its halt is in progress.
    Halting,
}

/// Follows each stateful leaf's runs through its calls.
fn follow(runs: &mut [Run], events: &[Event]) -> Result<(), String> {
    for e in events {
        let l = e.leaf;
        let expected = match e.what {
            What::Start(_) => Run::Closed,
            What::Running(_) | What::HaltRequested => Run::Open,
            What::StillHalting => Run::Halting,
            // Halted at once, or at the end of a halt in progress.
            What::Halted if runs[l] == Run::Halting => Run::Halting,
            What::Halted => Run::Open,
            What::Tick(_) => continue,
        };
        if runs[l] != expected {
            return Err(format!("{e}: the run was {:?}", runs[l]));
        }
        runs[l] = match e.what {
            What::Start(s) | What::Running(s) if s == Status::Running => Run::Open,
            What::HaltRequested | What::StillHalting => Run::Halting,
            _ => Run::Closed,
        };
    }
    Ok(())
}

fn stateful_leaves(spec: &Spec) -> Vec<usize> {
    spec.flatten()
        .iter()
        .enumerate()
        .filter(|(_, f)| {
            matches!(
                f.node,
                FlatKind::Leaf(LeafKind::Stateful) | FlatKind::Leaf(LeafKind::Async)
            )
        })
        .map(|(i, _)| i)
        .collect()
}

fn check_lifecycle(spec: &Spec, ops: &[Op], halt_ticks: &[usize]) -> Result<(), TestCaseError> {
    let (mut tree, mut ctx, seen) = start_with(spec, halt_ticks);
    let leaves = stateful_leaves(spec);
    let mut runs = vec![Run::Closed; spec.len()];
    let all = ops.iter().copied().chain([Op::Halt]);
    let last = ops.len();
    for (i, op) in all.enumerate() {
        step(&mut tree, &mut ctx, &seen, op)?;
        if i == last {
            let mut calls = 0;
            while !tree.tick_halt(&mut ctx) {
                calls += 1;
                prop_assert!(calls < 16, "a halt is in progress after 16 tick_halt");
            }
            prop_assert!(!tree.is_halting());
        }
        let events = ctx.take_events();
        if let Err(e) = follow(&mut runs, &events) {
            return Err(TestCaseError::fail(format!("step {i} ({op:?}): {e}")));
        }
        let halting = runs.contains(&Run::Halting);
        prop_assert_eq!(tree.is_halting(), halting, "step {} ({:?})", i, op);
        for &l in &leaves {
            let open = runs[l] == Run::Open;
            prop_assert_eq!(
                tree.status(NodeId(l as u32)) == Running,
                open,
                "step {} ({:?}): leaf L{} stored {} with its run {:?}",
                i,
                op,
                l,
                tree.status(NodeId(l as u32)),
                runs[l]
            );
        }
        if op == Op::Halt {
            prop_assert!(
                tree.statuses().iter().all(|s| *s == Idle),
                "step {} (halt): not all Idle: {:?}",
                i,
                tree.statuses()
            );
        }
    }
    prop_assert!(
        runs.iter().all(|r| *r == Run::Closed),
        "a run is open or halting after the final halt"
    );
    Ok(())
}

fn check_halt_order(spec: &Spec, ops: &[Op], halt_ticks: &[usize]) -> Result<(), TestCaseError> {
    let (mut tree, mut ctx, seen) = start_with(spec, halt_ticks);
    let all = ops.iter().copied().chain([Op::Halt]);
    for (i, op) in all.enumerate() {
        step(&mut tree, &mut ctx, &seen, op)?;
        let seen = seen.lock().unwrap();
        prop_assert!(
            seen.violations.is_empty(),
            "step {} ({:?}): {:?}",
            i,
            op,
            seen.violations
        );
        prop_assert_eq!(
            &seen.mirror[..],
            tree.statuses(),
            "step {} ({:?}): the observer missed a change",
            i,
            op
        );
    }
    Ok(())
}

/// Where BehaviorTree.CPP leaves a completed status when the root completes: the earlier
/// children of a SequenceWithMemory that failed (it keeps its place: Success), and the
/// condition of a two-child IfThenElse that failed (returned without a reset: Failure).
fn may_stay(tree: &Tree<Ctx>, id: NodeId) -> Option<NodeStatus> {
    let bp = tree.blueprint();
    let parent = bp.parent(id)?;
    match bp.kind(parent) {
        NodeKind::SequenceWithMemory(_) => Some(Success),
        NodeKind::IfThenElse(_)
            if bp.children(parent).len() == 2 && bp.children(parent)[0] == id =>
        {
            Some(Failure)
        }
        _ => None,
    }
}

fn check_reset(spec: &Spec, ops: &[Op], halt_ticks: &[usize]) -> Result<(), TestCaseError> {
    let (mut tree, mut ctx, seen) = start_with(spec, halt_ticks);
    for (i, &op) in ops.iter().enumerate() {
        let result = step(&mut tree, &mut ctx, &seen, op)?;
        if !matches!(result, Some(Ok(Status::Success | Status::Failure))) {
            continue;
        }
        for id in tree.blueprint().ids() {
            let s = tree.status(id);
            let allowed = may_stay(&tree, id);
            prop_assert!(
                s == Idle || Some(s) == allowed,
                "step {} ({:?}) returned {:?}: node {} is {}",
                i,
                op,
                result,
                id.0,
                s
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 384,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn a_running_stateful_action_completes_or_is_halted_once(
        spec in common::tree(false),
        ops in common::ops(),
    ) {
        check_lifecycle(&spec, &ops, &[])?;
    }

    #[test]
    fn halts_go_children_first(spec in common::tree(false), ops in common::ops()) {
        check_halt_order(&spec, &ops, &[])?;
    }

    #[test]
    fn a_completed_tick_leaves_every_node_idle(
        spec in common::tree(false),
        ops in common::ops(),
    ) {
        check_reset(&spec, &ops, &[])?;
    }

    #[test]
    fn with_halts_over_ticks_a_running_stateful_action_completes_or_is_halted_once(
        spec in common::tree(false),
        ops in common::ops(),
        halt_ticks in proptest::collection::vec(0..4usize, 64),
    ) {
        check_lifecycle(&spec, &ops, &halt_ticks)?;
    }

    #[test]
    fn with_halts_over_ticks_halts_go_children_first(
        spec in common::tree(false),
        ops in common::ops(),
        halt_ticks in proptest::collection::vec(0..4usize, 64),
    ) {
        check_halt_order(&spec, &ops, &halt_ticks)?;
    }

    #[test]
    fn with_async_actions_and_halts_over_ticks_a_run_completes_or_is_halted_once(
        spec in common::tree_with(false, true),
        ops in common::ops(),
        halt_ticks in proptest::collection::vec(0..4usize, 64),
    ) {
        check_lifecycle(&spec, &ops, &halt_ticks)?;
    }

    #[test]
    fn with_async_actions_and_halts_over_ticks_halts_go_children_first(
        spec in common::tree_with(false, true),
        ops in common::ops(),
        halt_ticks in proptest::collection::vec(0..4usize, 64),
    ) {
        check_halt_order(&spec, &ops, &halt_ticks)?;
    }

    #[test]
    fn with_async_actions_and_halts_over_ticks_a_completed_tick_leaves_every_node_idle(
        spec in common::tree_with(false, true),
        ops in common::ops(),
        halt_ticks in proptest::collection::vec(0..4usize, 64),
    ) {
        check_reset(&spec, &ops, &halt_ticks)?;
    }

    #[test]
    fn with_halts_over_ticks_a_completed_tick_leaves_every_node_idle(
        spec in common::tree(false),
        ops in common::ops(),
        halt_ticks in proptest::collection::vec(0..4usize, 64),
    ) {
        check_reset(&spec, &ops, &halt_ticks)?;
    }
}

// ---- fixed cases ----

const S: Status = Status::Success;
const F: Status = Status::Failure;
const R: Status = Status::Running;

fn leaf(script: &[Status]) -> Spec {
    Spec::Leaf(LeafKind::Stateful, script.to_vec())
}

/// The checks are not vacuous: a halt through four levels is seen children first.
#[test]
fn a_deep_halt_is_seen_children_first() {
    // Parallel(Sequence(Inverter(L3)), ForceSuccess(L5)), both leaves running.
    let spec = Spec::Node(
        Kind::Parallel {
            success: -1,
            failure: 1,
        },
        vec![
            Spec::Node(
                Kind::Sequence,
                vec![Spec::Node(Kind::Inverter, vec![leaf(&[R])])],
            ),
            Spec::Node(Kind::ForceSuccess, vec![leaf(&[R])]),
        ],
    );
    let (mut tree, mut ctx, seen) = start(&spec);
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Running));
    tree.halt(&mut ctx);
    let seen = seen.lock().unwrap();
    assert!(seen.violations.is_empty(), "{:?}", seen.violations);
    assert_eq!(seen.stops, 6);
    assert!(tree.statuses().iter().all(|s| *s == Idle));
    let events: Vec<String> = ctx.take_events().iter().map(ToString::to_string).collect();
    assert_eq!(
        events,
        [
            "L3 start -> RUNNING",
            "L5 start -> RUNNING",
            "L3 halted",
            "L5 halted"
        ]
    );
}

/// The guard against endless runs works, on a tree that yields on every pass in BT.CPP too:
/// the AsyncSequence yields, the Parallel then succeeds (halting it) and
/// KeepRunningUntilFailure turns that success into Running, so the wake-up never ends.
#[test]
fn an_endless_tick_once_is_recognised() {
    let spec = Spec::Node(
        Kind::KeepRunningUntilFailure,
        vec![Spec::Node(
            Kind::Parallel {
                success: 1,
                failure: -1,
            },
            vec![
                Spec::Node(Kind::AsyncSequence, vec![leaf(&[S]), leaf(&[S])]),
                Spec::Leaf(LeafKind::Sync, vec![S]),
            ],
        )],
    );
    let (mut tree, mut ctx, seen) = start(&spec);
    assert!(step(&mut tree, &mut ctx, &seen, Op::TickOnce).is_err());
    assert_eq!(seen.lock().unwrap().passes, MAX_PASSES);
    // One pass at a time, it is an ordinary Running tree.
    let (mut tree, mut ctx, seen) = start(&spec);
    let r = step(&mut tree, &mut ctx, &seen, Op::TickExactlyOnce).unwrap();
    assert_eq!(r, Some(Ok(Status::Running)));
    let events: Vec<String> = ctx.take_events().iter().map(ToString::to_string).collect();
    assert_eq!(events, ["L3 start -> SUCCESS", "L5 tick -> SUCCESS"]);
}

#[test]
fn lifecycle_checker_rejects_a_restart_and_a_double_halt() {
    let fresh = || vec![Run::Closed; 2];
    let ev = |what| Event { leaf: 1, what };
    assert!(follow(&mut fresh(), &[ev(What::Start(R)), ev(What::Start(R))]).is_err());
    assert!(follow(
        &mut fresh(),
        &[ev(What::Start(R)), ev(What::Halted), ev(What::Halted)]
    )
    .is_err());
    assert!(follow(&mut fresh(), &[ev(What::Start(S)), ev(What::Running(F))]).is_err());
    let mut runs = fresh();
    follow(
        &mut runs,
        &[
            ev(What::Start(R)),
            ev(What::Running(S)),
            ev(What::Start(R)),
            ev(What::Halted),
        ],
    )
    .unwrap();
    assert_eq!(runs[1], Run::Closed);
}

#[test]
fn lifecycle_checker_follows_a_halt_over_ticks() {
    let fresh = || vec![Run::Closed; 2];
    let ev = |what| Event { leaf: 1, what };
    let mut runs = fresh();
    let halting = [ev(What::Start(R)), ev(What::HaltRequested)];
    follow(&mut runs, &halting).unwrap();
    assert_eq!(runs[1], Run::Halting);
    // Neither started nor ticked while halting; halted once, at the end.
    assert!(follow(&mut runs.clone(), &[ev(What::Start(R))]).is_err());
    assert!(follow(&mut runs.clone(), &[ev(What::Running(R))]).is_err());
    assert!(follow(&mut runs.clone(), &[ev(What::HaltRequested)]).is_err());
    follow(&mut runs, &[ev(What::StillHalting), ev(What::Halted)]).unwrap();
    assert_eq!(runs[1], Run::Closed);
    assert!(follow(&mut runs, &[ev(What::StillHalting)]).is_err());
}

/// BehaviorTree.CPP's `Tree::haltTree()` halts the root and then calls `haltNode()` on every
/// node ("just in case"), so every stored status is Idle afterwards, including completed
/// statuses that a control left behind; a StatefulAction reset that way is started afresh on
/// the next tick.
#[test]
fn tree_halt_resets_every_node_as_bt_cpp_halt_tree_does() {
    // Sequence(IfThenElse(L2, L3), L4). The two-child IfThenElse fails with its condition
    // and, as in BT.CPP, does not reset it; the Sequence then resets only the IfThenElse.
    let spec = Spec::Node(
        Kind::Sequence,
        vec![
            Spec::Node(Kind::IfThenElse, vec![leaf(&[F, S]), leaf(&[S])]),
            leaf(&[S]),
        ],
    );
    let (mut tree, mut ctx, _) = start(&spec);
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Failure));
    assert_eq!(tree.statuses(), [Idle, Idle, Failure, Idle, Idle]);
    // Without a halt the condition's stored Failure is returned again, uncalled (BT.CPP too).
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Failure));
    let events: Vec<String> = ctx.take_events().iter().map(ToString::to_string).collect();
    assert_eq!(events, ["L2 start -> FAILURE"]);

    tree.halt(&mut ctx);
    assert_eq!(
        tree.statuses(),
        [Idle, Idle, Idle, Idle, Idle],
        "Tree::halt left a completed status behind"
    );
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Success));
    let events: Vec<String> = ctx.take_events().iter().map(ToString::to_string).collect();
    assert_eq!(
        events,
        [
            "L2 start -> SUCCESS",
            "L3 start -> SUCCESS",
            "L4 start -> SUCCESS"
        ]
    );
}
