//! WhileDoElse: re-check a condition every tick and run the matching branch.
//!
//! The condition is re-ticked every tick; Success halts "else" and ticks "do"; Failure halts
//! "do" and ticks "else" (2 children → Failure).
//!
//! A branch that completes resets the node, so the next tick checks the condition afresh.
//!
//! A halt that takes ticks ([`slow_halt`](crate::tree::slow_halt)): when the branch this
//! node halts answers Halting, the node returns Running without ticking the other branch
//! and, on later ticks, continues the halt and returns Running without ticking any child;
//! on the tick the halt is done it ticks as usual, condition first.

use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::blueprint::{Builder, NodeKind, PortBinding, PortBindingError};
use crate::nodes::built_in::{BuiltIn, Tick};
use crate::nodes::decl::NodeDecl;
use crate::nodes::semantics::{Order, Semantics, Statuses};
use crate::{Arity, Category};

/// WhileDoElse's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const WHILE_DO_ELSE: NodeDecl = NodeDecl {
    name: "WhileDoElse",
    category: Category::Control,
    arity: Arity::Range { min: 2, max: 3 },
    ports: &[],
    summary: "Re-ticks the condition every tick; switching branch halts the other one.",
    semantics: Semantics::new(Order::again(Statuses::ANY, Statuses::ANY), |_, c| {
        let branch = |i: usize| c.get(i).copied().unwrap_or(Statuses::FAILURE);
        let cond = c.first().copied().unwrap_or(Statuses::ANY);
        // RUNNING too while a branch it switches from takes ticks to halt.
        Statuses::RUNNING
            .or(Statuses::SKIPPED.when(cond.can_skip()))
            .or(branch(1).when(cond.can_succeed()))
            .or(branch(2).when(cond.can_fail()))
    }),
};

#[inline(never)]
pub(crate) fn tick<C>(t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
    let three = def.child_count == 3;
    if t.waits_for_halts(id) {
        return NodeStatus::Running;
    }
    t.set_status(id, NodeStatus::Running);
    let condition = t.child(def, 0);
    let status = match t.tick(condition) {
        NodeStatus::Running => return NodeStatus::Running,
        NodeStatus::Success => {
            if three {
                let otherwise = t.child(def, 2);
                if t.halting_for(id, |t| t.halt_child(otherwise)) {
                    return NodeStatus::Running;
                }
            }
            let body = t.child(def, 1);
            t.tick(body)
        }
        NodeStatus::Failure | NodeStatus::Idle => {
            if three {
                let body = t.child(def, 1);
                if t.halting_for(id, |t| t.halt_child(body)) {
                    return NodeStatus::Running;
                }
                let otherwise = t.child(def, 2);
                t.tick(otherwise)
            } else {
                NodeStatus::Failure
            }
        }
        NodeStatus::Skipped => NodeStatus::Skipped,
    };
    if status != NodeStatus::Running && t.halting_for(id, |t| t.reset_children(id)) {
        return NodeStatus::Running;
    }
    status
}

/// The WhileDoElse node. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WhileDoElse;

impl BuiltIn for WhileDoElse {}

impl Tick for WhileDoElse {
    const DECL: &'static NodeDecl = &WHILE_DO_ELSE;
    const RECHECKS: bool = true;

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(WhileDoElse)
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        // The condition is re-checked every tick: the tree sleeps under a Running branch
        // only if nothing ticked here may read more than the blackboard (the branch's
        // leaves too, as a margin: they are not re-checked, but telling them apart would
        // cost every tick).
        super::reactive::rechecking(t, |t| {
            let status = tick(t, id, def);
            if status == NodeStatus::Running && t.waits.opaque {
                let node = t.waits.opaque_node;
                t.stay_awake(crate::AwakeReason::ReactiveCondition, node);
            }
            status
        })
    }
}

impl<C> Builder<C> {
    /// A [WhileDoElse](self): a branch by a condition re-checked every tick.
    pub fn while_do_else(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::WhileDoElse(WhileDoElse), name, children)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn condition_flip_halts_the_running_branch() {
        let mut lab = Lab::new(&[&[S, F], &[R], &[R]]);
        let mut tree = lab.tree(|b| b.while_do_else("wde", |w| w.check(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [2, 1, 1]);
        assert_eq!(lab.halts, [0, 1, 0]);
    }

    #[test]
    fn two_children_fail_with_the_condition() {
        let mut lab = Lab::new(&[&[S, F], &[R]]);
        let mut tree = lab.tree(|b| b.while_do_else("wde", |w| w.check(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.halts, [0, 1]);
    }

    #[test]
    fn completion_resets() {
        let mut lab = Lab::new(&[&[S], &[S], &[S]]);
        let mut tree = lab.tree(|b| b.while_do_else("wde", |w| w.check(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }
}
