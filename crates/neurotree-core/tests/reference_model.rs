//! The engine against a reference interpreter, on random trees and random tick sequences.
//!
//! The interpreter below is written plainly from the semantics tables of the node catalog
//! (`neurotree_core::nodes`) and BehaviorTree.CPP 4.10's node sources: a recursive walk over a tree of nodes, each with its stored status and its
//! own state (cursor, skipped count, counters, completed lists, ...), as BT.CPP keeps them.
//! It shares nothing with the engine but the scripted leaves' descriptions.
//!
//! Rules it mirrors:
//! - `execute` stores what a node returned; a Skipped node is stored as Idle.
//! - `halt_child` (BT.CPP `haltChild`): halt the child if Running, then reset it to Idle; a
//!   halt resets a node's children (children first) before the node itself. `Tree::halt` is
//!   BT.CPP's `haltTree`: the root's halt, then `haltNode` on every node.
//! - A StatefulAction ticks `on_start` from Idle, `on_running` from Running, and returns its
//!   stored status, calling nothing, when that is Success or Failure (not yet reset).
//! - Yields (Running + wake-up) only after a child that went from Idle to completed within
//!   the pass, and only while work remains; `tick_once` repeats the pass while the root is
//!   Running and a node asked to be woken during that pass.
//! - Where BT.CPP throws (a Skipped condition in IfThenElse / WhileDoElse), the node returns
//!   Skipped, as a node whose children were all skipped does.
//!
//! Each step compares the root's result, every leaf call in order and every stored status.

use crate::common;

use std::sync::{Arc, Mutex};

use common::{Event, Kind, LeafKind, Op, Spec};
use neurotree_core::{ManualClock, NodeStatus, Observer, Status, StatusChange, Tree};
use proptest::prelude::*;

#[path = "reference_model/model.rs"]
mod model;
use model::{to_result, Model};

use NodeStatus::{Failure, Idle, Running, Success};

/// Passes after which the reference gives up on a `tick_once`. Some trees yield on every pass,
/// in BT.CPP as here: Repeat(-1) over a child that always succeeds at once, or a node that
/// yields under a Parallel that then completes inside a KeepRunningUntilFailure or before a
/// Running sibling in a ReactiveSequence. The step then becomes a `tick_exactly_once` for
/// both.
const MAX_PASSES: usize = 1000;

/// Keeps a copy of the stored statuses from the observer's reports alone.
#[derive(Clone)]
struct Mirror(Arc<Mutex<Vec<NodeStatus>>>);

impl Observer for Mirror {
    fn on_status_change(&mut self, c: StatusChange) {
        let mut m = self.0.lock().unwrap();
        assert_eq!(
            m[c.node.index()],
            c.from,
            "observer saw a change from a wrong status"
        );
        m[c.node.index()] = c.to;
    }
}

fn text(events: &[Event]) -> Vec<String> {
    events.iter().map(ToString::to_string).collect()
}

fn check(spec: &Spec, ops: &[Op], observe: bool) -> Result<(), TestCaseError> {
    let bp = common::blueprint(spec);
    let mut tree = Tree::with_clock(bp, ManualClock::new());
    let mirror = Mirror(Arc::new(Mutex::new(vec![Idle; spec.len()])));
    if observe {
        tree.set_observer(mirror.clone());
    }
    let mut ctx = common::Ctx::new(spec);
    let mut model = Model::new(spec);
    for (step, &op) in ops.iter().enumerate() {
        let (want, got, done) = match op {
            Op::TickOnce => {
                let before = model.clone();
                match model.tick_once() {
                    Some(s) => (Some(s), Some(tree.tick_once(&mut ctx)), "tick_once"),
                    None => {
                        model = before;
                        let s = model.tick_exactly_once();
                        let got = tree.tick_exactly_once(&mut ctx);
                        (
                            Some(s),
                            Some(got),
                            "tick_exactly_once (tick_once never ends)",
                        )
                    }
                }
            }
            Op::TickExactlyOnce => (
                Some(model.tick_exactly_once()),
                Some(tree.tick_exactly_once(&mut ctx)),
                "tick_exactly_once",
            ),
            Op::Halt => {
                model.halt_tree();
                tree.halt(&mut ctx);
                (None, None, "halt")
            }
        };
        prop_assert_eq!(
            got,
            want.map(to_result),
            "step {} ({}): root result",
            step,
            done
        );
        prop_assert_eq!(
            text(&ctx.take_events()),
            text(&std::mem::take(&mut model.events)),
            "step {} ({}): leaf calls",
            step,
            done
        );
        prop_assert_eq!(
            tree.statuses(),
            &model.statuses()[..],
            "step {} ({}): stored statuses",
            step,
            done
        );
        if observe {
            prop_assert_eq!(
                &mirror.0.lock().unwrap()[..],
                tree.statuses(),
                "step {} ({}): statuses as the observer saw them",
                step,
                done
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 1024,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn engine_matches_the_reference(
        spec in common::tree(true),
        ops in common::ops(),
        observe in any::<bool>(),
    ) {
        check(&spec, &ops, observe)?;
    }

    /// Unobserved trees whose Running path is made of pass-through nodes start their ticks
    /// at the stateful action they rest in: the same calls, results and statuses.
    #[test]
    fn resting_trees_match_the_reference(
        spec in common::pass_through_tree(),
        ops in common::ops(),
    ) {
        check(&spec, &ops, false)?;
    }
}

// ---- fixed cases: the interpreter itself, on behaviours the semantics spell out ----

fn leaf(script: &[Status]) -> Spec {
    Spec::Leaf(LeafKind::Stateful, script.to_vec())
}

fn node(kind: Kind, children: Vec<Spec>) -> Spec {
    Spec::Node(kind, children)
}

const S: Status = Status::Success;
const F: Status = Status::Failure;
const R: Status = Status::Running;

/// Runs `ops` on the reference alone, returning each result and the leaf calls as text.
fn model_run(spec: &Spec, ops: &[Op]) -> (Vec<Option<NodeStatus>>, Vec<String>, Model) {
    let mut m = Model::new(spec);
    let results = ops
        .iter()
        .map(|op| match op {
            Op::TickOnce => m.tick_once(),
            Op::TickExactlyOnce => Some(m.tick_exactly_once()),
            Op::Halt => {
                m.halt_tree();
                None
            }
        })
        .collect();
    let events = text(&std::mem::take(&mut m.events));
    (results, events, m)
}

#[test]
fn reference_yields_async_sequence_and_tick_once_rewakes() {
    let spec = node(
        Kind::AsyncSequence,
        vec![leaf(&[S]), leaf(&[S]), leaf(&[S])],
    );
    let (results, events, _) = model_run(&spec, &[Op::TickExactlyOnce, Op::TickOnce]);
    assert_eq!(results, [Some(Running), Some(Success)]);
    assert_eq!(
        events,
        [
            "L1 start -> SUCCESS",
            "L2 start -> SUCCESS",
            "L3 start -> SUCCESS"
        ]
    );
}

#[test]
fn reference_halts_children_first_and_keeps_memory() {
    // SequenceWithMemory(L1, Inverter(L3)): L1 succeeds, L3 runs; a halt keeps the place.
    let spec = node(
        Kind::SequenceWithMemory,
        vec![leaf(&[S]), node(Kind::Inverter, vec![leaf(&[R, R, F])])],
    );
    let (results, events, m) =
        model_run(&spec, &[Op::TickOnce, Op::Halt, Op::TickOnce, Op::TickOnce]);
    assert_eq!(results, [Some(Running), None, Some(Running), Some(Success)]);
    assert_eq!(
        events,
        [
            "L1 start -> SUCCESS",
            "L3 start -> RUNNING",
            "L3 halted",
            "L3 start -> RUNNING",
            "L3 running -> FAILURE"
        ]
    );
    assert!(m.statuses().iter().all(|s| *s == Idle));
}

#[test]
fn reference_repeats_a_stale_stateful_condition() {
    // Sequence(IfThenElse(L2, L3), L4): the failed condition of a two-child IfThenElse is not
    // reset, so next time it returns its stored Failure without being called.
    let spec = node(
        Kind::Sequence,
        vec![
            node(Kind::IfThenElse, vec![leaf(&[F, S]), leaf(&[S])]),
            leaf(&[S]),
        ],
    );
    let (results, events, m) = model_run(&spec, &[Op::TickOnce, Op::TickOnce]);
    assert_eq!(results, [Some(Failure), Some(Failure)]);
    assert_eq!(events, ["L2 start -> FAILURE"]);
    assert_eq!(m.statuses(), [Idle, Idle, Failure, Idle, Idle]);
}

#[test]
fn reference_parallel_thresholds() {
    // Parallel(3, -2) over 4 children: the third success ends it and halts the fourth.
    let spec = node(
        Kind::Parallel {
            success: 3,
            failure: -2,
        },
        vec![leaf(&[S]), leaf(&[R, S]), leaf(&[S]), leaf(&[R])],
    );
    let (results, events, _) = model_run(&spec, &[Op::TickOnce, Op::TickOnce]);
    assert_eq!(results, [Some(Running), Some(Success)]);
    assert_eq!(
        events,
        [
            "L1 start -> SUCCESS",
            "L2 start -> RUNNING",
            "L3 start -> SUCCESS",
            "L4 start -> RUNNING",
            "L2 running -> SUCCESS",
            "L4 halted"
        ]
    );
}

#[test]
fn reference_detects_endless_tick_once() {
    let spec = node(
        Kind::Repeat(-1),
        vec![Spec::Leaf(LeafKind::Sync, vec![Status::Success])],
    );
    let (results, _, _) = model_run(&spec, &[Op::TickOnce]);
    assert_eq!(results, [None]);
}
