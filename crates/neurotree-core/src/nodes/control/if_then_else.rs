//! IfThenElse: pick a branch by a condition, and stay on it until it completes.
//!
//! IfThenElse takes 2 or 3 children. Condition ticked once; the chosen branch is kept until it
//! completes. Condition Failure with 2 children → Failure.
//!
//! The condition is ticked only when no branch is in progress; a Running condition makes the
//! node Running. Unlike [WhileDoElse](super::while_do_else), a branch in progress is not
//! interrupted when the condition would change.

use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::blueprint::{Builder, NodeKind, PortBinding, PortBindingError};
use crate::nodes::built_in::{BuiltIn, Tick};
use crate::nodes::decl::NodeDecl;
use crate::nodes::semantics::{Order, Semantics, Statuses};
use crate::{Arity, Category};

/// IfThenElse's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const IF_THEN_ELSE: NodeDecl = NodeDecl {
    name: "IfThenElse",
    category: Category::Control,
    arity: Arity::Range { min: 2, max: 3 },
    ports: &[],
    summary: "Ticks the condition once, then keeps the chosen branch until it completes; no else branch: Failure.",
    semantics: Semantics::new(Order::in_turn(Statuses::ANY), |_, c| {
        let branch = |i: usize| c.get(i).copied().unwrap_or(Statuses::FAILURE);
        let cond = c.first().copied().unwrap_or(Statuses::ANY);
        cond.without(Statuses::DONE)
            .or(branch(1).when(cond.can_succeed()))
            .or(branch(2).when(cond.can_fail()))
    }),
};

#[inline(never)]
pub(crate) fn tick<C>(t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
    let slot = t.bp.slot(id);
    t.set_status(id, NodeStatus::Running);
    if t.aux[slot] == 0 {
        let condition = t.child(def, 0);
        match t.tick(condition) {
            NodeStatus::Running => return NodeStatus::Running,
            NodeStatus::Success => t.aux[slot] = 1,
            NodeStatus::Failure | NodeStatus::Idle => {
                if def.child_count == 3 {
                    t.aux[slot] = 2;
                } else {
                    // BehaviorTree.CPP returns here without resetting the condition.
                    return NodeStatus::Failure;
                }
            }
            NodeStatus::Skipped => return NodeStatus::Skipped,
        }
    }
    let branch = t.child(def, t.aux[slot]);
    let status = t.tick(branch);
    if status != NodeStatus::Running {
        t.reset_children(id);
        t.aux[slot] = 0;
    }
    status
}

/// The IfThenElse node. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IfThenElse;

impl BuiltIn for IfThenElse {}

impl Tick for IfThenElse {
    const DECL: &'static NodeDecl = &IF_THEN_ELSE;
    const AUX_SLOTS: u32 = 1;

    /// The branch a saved state names: the condition (0), then (1) or else (2), one the
    /// node has.
    fn restored_aux(saved: u64, children: u32) -> Option<u64> {
        (saved <= 2 && saved < u64::from(children)).then_some(saved)
    }

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(IfThenElse)
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        tick(t, id, def)
    }

    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, _: &NodeDef<C>) {
        t.halt_afresh(id);
    }
}

impl<C> Builder<C> {
    /// An [IfThenElse](self): pick a branch by a condition.
    pub fn if_then_else(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::IfThenElse(IfThenElse), name, children)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn then_branch_is_kept_until_it_completes() {
        let mut lab = Lab::new(&[&[S, F], &[R, S], &[S]]);
        let mut tree =
            lab.tree(|b| b.if_then_else("ite", |i| i.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        // The condition was not re-checked while "then" ran.
        assert_eq!(lab.ticks, [1, 2, 0]);
    }

    #[test]
    fn else_branch_on_failure() {
        let mut lab = Lab::new(&[&[F], &[S], &[F]]);
        let mut tree =
            lab.tree(|b| b.if_then_else("ite", |i| i.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1, 0, 1]);
    }

    #[test]
    fn two_children_fail_with_the_condition() {
        let mut lab = Lab::new(&[&[F], &[S]]);
        let mut tree = lab.tree(|b| b.if_then_else("ite", |i| i.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1, 0]);
    }

    #[test]
    fn halt_returns_to_the_condition() {
        let mut lab = Lab::new(&[&[S], &[R], &[S]]);
        let mut tree =
            lab.tree(|b| b.if_then_else("ite", |i| i.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [0, 1, 0]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [2, 2, 0]);
    }
}
