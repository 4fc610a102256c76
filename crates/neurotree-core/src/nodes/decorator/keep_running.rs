//! KeepRunningUntilFailure: keep a succeeding child going.
//!
//! Success → Running; Failure → Failure.
//!
//! The child is reset after each completion, so it starts afresh on the next tick. A skipped
//! child leaves the node Running, as in BehaviorTree.CPP.

use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::blueprint::{Builder, NodeKind, PortBinding, PortBindingError};
use crate::nodes::built_in::{BuiltIn, Tick};
use crate::nodes::decl::NodeDecl;
use crate::nodes::semantics::{first, Order, Semantics, Statuses};
use crate::{Arity, Category};

/// KeepRunningUntilFailure's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const KEEP_RUNNING_UNTIL_FAILURE: NodeDecl = NodeDecl {
    name: "KeepRunningUntilFailure",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[],
    summary: "Child Success becomes Running; Failure ends it.",
    semantics: Semantics::new(
        Order::again(Statuses::ANY, Statuses::SUCCESS.or(Statuses::SKIPPED)),
        |_, c| {
            let c = first(c);
            // A success or a skip of the child leaves the node Running.
            Statuses::FAILURE
                .when(c.can_fail())
                .or(Statuses::RUNNING.when(c.meets(Statuses::ANY.without(Statuses::FAILURE))))
        },
    ),
};

#[inline(never)]
pub(crate) fn tick<C>(t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
    t.set_status(id, NodeStatus::Running);
    let child = t.child(def, 0);
    match t.tick(child) {
        NodeStatus::Success => {
            t.halt_child(child);
            // Running with nothing under it waiting: the next tick starts the child again.
            t.stay_awake(crate::AwakeReason::RestartsChild, id);
            NodeStatus::Running
        }
        NodeStatus::Failure | NodeStatus::Idle => {
            t.halt_child(child);
            NodeStatus::Failure
        }
        NodeStatus::Running => NodeStatus::Running,
        NodeStatus::Skipped => {
            t.stay_awake(crate::AwakeReason::RestartsChild, id);
            NodeStatus::Running
        }
    }
}

/// The KeepRunningUntilFailure node. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KeepRunningUntilFailure;

impl BuiltIn for KeepRunningUntilFailure {}

impl Tick for KeepRunningUntilFailure {
    const DECL: &'static NodeDecl = &KEEP_RUNNING_UNTIL_FAILURE;

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(KeepRunningUntilFailure)
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        tick(t, id, def)
    }
}

impl<C> Builder<C> {
    /// A [KeepRunningUntilFailure](self): Success becomes Running.
    pub fn keep_running_until_failure(
        self,
        name: &str,
        children: impl FnOnce(Self) -> Self,
    ) -> Self {
        self.node(
            NodeKind::KeepRunningUntilFailure(KeepRunningUntilFailure),
            name,
            children,
        )
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn runs_until_the_child_fails() {
        let mut lab = Lab::new(&[&[S, R, S, F]]);
        let mut tree = lab.tree(|b| b.keep_running_until_failure("k", |k| k.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [4]);
        assert_eq!(lab.log_of(0), ["start", "start", "running", "start"]);
    }

    #[test]
    fn a_skipped_child_keeps_it_running() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| {
            b.keep_running_until_failure("k", |k| k.run_once("once", true, |o| o.scripted(0)))
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [1]);
    }
}
