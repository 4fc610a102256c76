//! ReactiveSequence and ReactiveFallback: re-check every child from the first, every tick.
//!
//! - **ReactiveSequence**: restart at child 0 every tick.
//!   - A child Running: halt (and reset) every other child, return Running.
//!   - Failure: halt/reset all, Failure.
//!   - All succeeded: reset, Success.
//! - **ReactiveFallback**: mirror of ReactiveSequence: Success ends it, Failure moves on, all
//!   failed → Failure.
//!
//! This is what makes a tree reactive: a condition placed before a long action is checked on
//! every tick, and when it flips, the running action is halted in the same tick. A skipped
//! child is reset so that it can be skipped (or run) afresh next tick; all skipped → Skipped.
//!
//! Only one child should run: the node remembers the first child that returned Running since
//! it started from Idle (or was halted). If another child returns Running later in the run,
//! BehaviorTree.CPP 4.10 by default lets it (the earlier one is halted, as above); after its
//! `EnableException(true)` it throws "only a single child can return RUNNING". Here
//! [`Tree::reject_multiple_running`](crate::Tree::reject_multiple_running) is that switch:
//! on, the tick ends with a [`TickError::Node`](crate::TickError::Node) naming the control,
//! after the other children were halted, and the tree is halted.
//!
//! A halt that takes ticks ([`slow_halt`](crate::tree::slow_halt)): when a child this node
//! halts answers Halting, the node returns Running (whatever it was about to return) and,
//! on later ticks, continues the halt and returns Running without ticking any child; on the
//! tick the halt is done it ticks as usual, from child 0.

use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus, Status};

use crate::blueprint::{Builder, NodeKind, PortBinding, PortBindingError};
use crate::nodes::built_in::{BuiltIn, Family, Tick};
use crate::nodes::decl::NodeDecl;
use crate::nodes::semantics::{chain, Order, Semantics, Statuses};
use crate::{Arity, Category};

/// ReactiveSequence's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const REACTIVE_SEQUENCE: NodeDecl = NodeDecl {
    name: "ReactiveSequence",
    category: Category::Control,
    arity: Arity::AtLeast(1),
    ports: &[],
    summary: "Restarts at child 0 every tick; a Running child halts the other Running children.",
    semantics: Semantics::new(
        Order::again(Statuses::SUCCESS.or(Statuses::SKIPPED), Statuses::ANY),
        |_, c| chain(c, Statuses::SUCCESS),
    ),
};

/// ReactiveFallback's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const REACTIVE_FALLBACK: NodeDecl = NodeDecl {
    name: "ReactiveFallback",
    category: Category::Control,
    arity: Arity::AtLeast(1),
    ports: &[],
    summary: "Mirror of ReactiveSequence.",
    semantics: Semantics::new(
        Order::again(Statuses::FAILURE.or(Statuses::SKIPPED), Statuses::ANY),
        |_, c| chain(c, Statuses::FAILURE),
    ),
};

/// `goal` is the outcome that lets the node move on: Success for the sequence, Failure for
/// the fallback.
#[inline(never)]
pub(crate) fn tick<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
    goal: Status,
) -> NodeStatus {
    let bp = t.bp;
    let children = bp.children_of(def);
    let hot = bp.hot_children_of(def);
    let go_on = NodeStatus::from(goal);
    let mut all_skipped = true;
    // The first child that returned Running in this run, plus one (0: none yet), as
    // BehaviorTree.CPP's `running_child_`, forgotten when a run starts and on halt.
    let slot = bp.slot(id);
    if t.waits_for_halts(id) {
        return NodeStatus::Running;
    }
    if t.status(id) == NodeStatus::Idle {
        t.aux[slot] = 0;
    }
    t.set_status(id, NodeStatus::Running);
    for (index, hot_child) in hot.iter().enumerate() {
        let child = hot_child.id;
        // Whether a child ticked before this one may read more than the blackboard: if
        // this one runs, they are re-checked next tick.
        let rechecks_opaque = t.waits.opaque;
        let status = t.tick_child::<true>(hot_child);
        all_skipped &= status == NodeStatus::Skipped;
        if status == NodeStatus::Running {
            t.halting_for(id, |t| {
                for (other, &c) in children.iter().enumerate() {
                    if other != index {
                        t.halt_child(c);
                    }
                }
            });
            if rechecks_opaque {
                let node = t.waits.opaque_node;
                t.stay_awake(crate::AwakeReason::ReactiveCondition, node);
            }
            let running = index as u32 + 1;
            if t.aux[slot] == 0 {
                t.aux[slot] = running;
            } else if t.reject_multiple_running && t.aux[slot] != running {
                multiple_running(t, id, goal);
            }
            return NodeStatus::Running;
        }
        if status == NodeStatus::Skipped {
            // Skipped is stored Idle: nothing to halt (a precondition that skipped a
            // Running child halted it already, on the tree's behalf).
            t.halt_child(child);
        } else if status != go_on {
            if t.halting_for(id, |t| t.reset_children(id)) {
                return NodeStatus::Running;
            }
            return status;
        }
    }
    t.reset_children(id);
    if all_skipped {
        NodeStatus::Skipped
    } else {
        go_on
    }
}

/// BehaviorTree.CPP's LogicError for a second Running child, as the tick's error.
#[cold]
#[inline(never)]
fn multiple_running<C>(t: &mut Ticker<'_, C>, id: NodeId, goal: Status) {
    let kind = if goal == Status::Success {
        "ReactiveSequence"
    } else {
        "ReactiveFallback"
    };
    t.fault_node(
        id,
        alloc::format!(
            "[{kind}]: only a single child can return Running (Tree::reject_multiple_running(false) allows it)"
        ),
    );
}

/// Runs `tick`, a node's that re-checks children every tick, telling it (through
/// `Waits::opaque`) only about the leaves ticked under it; the leaves ticked before it are
/// remembered again after. A tree sleeps under such a node when every child it re-checks
/// reads only what wakes the tree (see [`sleep`](crate::tree::sleep)).
#[inline(always)]
pub(crate) fn rechecking<C>(
    t: &mut Ticker<'_, C>,
    tick: impl FnOnce(&mut Ticker<'_, C>) -> NodeStatus,
) -> NodeStatus {
    let outer = (t.waits.opaque, t.waits.opaque_node);
    t.waits.opaque = false;
    let status = tick(t);
    if outer.0 {
        t.waits.opaque = true;
        t.waits.opaque_node = outer.1;
    }
    status
}

/// The ReactiveSequence node. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReactiveSequence;

impl BuiltIn for ReactiveSequence {
    fn family(&self) -> Option<Family> {
        Some(Family::Sequential)
    }
}

impl Tick for ReactiveSequence {
    const DECL: &'static NodeDecl = &REACTIVE_SEQUENCE;
    const RECHECKS: bool = true;
    const AUX_SLOTS: u32 = 1;

    /// The running child a saved state names (its index plus one, 0 for none), one the node
    /// has.
    fn restored_aux(saved: u64, children: u32) -> Option<u64> {
        (saved <= u64::from(children)).then_some(saved)
    }

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(ReactiveSequence)
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        rechecking(t, |t| tick(t, id, def, Status::Success))
    }

    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, _: &NodeDef<C>) {
        t.halt_afresh(id);
    }
}

impl<C> Builder<C> {
    /// A [ReactiveSequence](self).
    pub fn reactive_sequence(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::ReactiveSequence(ReactiveSequence), name, children)
    }
}
/// The ReactiveFallback node. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReactiveFallback;

impl BuiltIn for ReactiveFallback {
    fn family(&self) -> Option<Family> {
        Some(Family::Alternative)
    }
}

impl Tick for ReactiveFallback {
    const DECL: &'static NodeDecl = &REACTIVE_FALLBACK;
    const RECHECKS: bool = true;
    const AUX_SLOTS: u32 = 1;

    /// The running child a saved state names (its index plus one, 0 for none), one the node
    /// has.
    fn restored_aux(saved: u64, children: u32) -> Option<u64> {
        (saved <= u64::from(children)).then_some(saved)
    }

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(ReactiveFallback)
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        rechecking(t, |t| tick(t, id, def, Status::Failure))
    }

    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, _: &NodeDef<C>) {
        t.halt_afresh(id);
    }
}

impl<C> Builder<C> {
    /// A [ReactiveFallback](self).
    pub fn reactive_fallback(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::ReactiveFallback(ReactiveFallback), name, children)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn rechecks_conditions_every_tick() {
        let mut lab = Lab::new(&[&[S], &[R, R, S]]);
        let mut tree = lab.tree(|b| b.reactive_sequence("rs", |s| s.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [3, 3]);
        assert_eq!(lab.halts, [0, 0]);
    }

    #[test]
    fn failing_condition_halts_the_running_action() {
        let mut lab = Lab::new(&[&[S, S, F], &[R]]);
        let mut tree = lab.tree(|b| b.reactive_sequence("rs", |s| s.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [3, 2]);
        assert_eq!(lab.halts, [0, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn fallback_halts_its_running_action_when_a_condition_flips() {
        // BehaviorTree.CPP's case: ReactiveFallback(condition, action); the condition turns
        // true while the action runs, so the action is halted and the node succeeds.
        let mut lab = Lab::new(&[&[F, F, S], &[R]]);
        let mut tree = lab.tree(|b| b.reactive_fallback("rf", |f| f.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [3, 2]);
        assert_eq!(lab.halts, [0, 1]);
        assert_eq!(lab.log_of(1), ["start", "running", "halted"]);
    }

    #[test]
    fn a_later_running_child_halts_an_earlier_one() {
        // Child 0 runs, then succeeds; child 1 starts running in the same tick and child 0,
        // completed, is reset to Idle without a halt.
        let mut lab = Lab::new(&[&[R, S], &[R]]);
        let mut tree = lab.tree(|b| b.reactive_sequence("rs", |s| s.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [1, 0]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [2, 1]);
        // Child 0 succeeded this tick, and was reset to Idle when child 1 ran.
        assert_eq!(lab.halts, [0, 0]);
        assert_eq!(tree.status(NodeId(1)), NodeStatus::Idle);
        assert_eq!(tree.status(NodeId(2)), NodeStatus::Running);
    }

    #[test]
    fn refusing_a_second_running_child_is_an_error_naming_the_node() {
        // BehaviorTree.CPP with ReactiveSequence::EnableException(true): child 0 ran, then a
        // tick later succeeded and child 1 returned Running: "only a single child can return
        // RUNNING". The tick ends with the error and the tree is halted.
        let mut lab = Lab::new(&[&[R, S], &[R]]);
        let mut tree = lab.tree(|b| b.reactive_sequence("rs", |s| s.scripted(0).scripted(1)));
        tree.reject_multiple_running(true);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        match lab.tick(&mut tree) {
            Err(TickError::Node { path, message, .. }) => {
                assert_eq!(path, "rs");
                assert!(
                    message.contains("only a single child can return Running"),
                    "{message}"
                );
            }
            other => panic!("expected a node error, got {other:?}"),
        }
        assert_eq!(lab.ticks, [2, 1]);
        assert_eq!(lab.halts, [0, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn refusing_still_lets_the_same_child_run_on_and_a_new_run_pick_another() {
        let mut lab = Lab::new(&[&[R, R, F, S], &[R]]);
        let mut tree = lab.tree(|b| b.reactive_fallback("rf", |f| f.scripted(0).scripted(1)));
        tree.reject_multiple_running(true);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        // Halted, the node forgets its running child: child 1 may run in the new run.
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [1, 0]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [3, 1]);
        // The same child Running again is fine; then child 0 succeeds: Success.
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [4, 1]);
        assert_eq!(lab.halts, [1, 1]);
    }
}
