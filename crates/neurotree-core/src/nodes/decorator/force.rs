//! ForceSuccess and ForceFailure: a completed child becomes a fixed outcome.
//!
//! A completed child becomes the forced status (Success for ForceSuccess, Failure for
//! ForceFailure); Running passes.

use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::blueprint::{Builder, NodeKind, PortBinding, PortBindingError};
use crate::nodes::built_in::{BuiltIn, Tick};
use crate::nodes::decl::NodeDecl;
use crate::nodes::semantics::{first, pass, Order, Semantics, Statuses};
use crate::{Arity, Category};

/// ForceSuccess's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const FORCE_SUCCESS: NodeDecl = NodeDecl {
    name: "ForceSuccess",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[],
    summary: "A completed child becomes Success; Running passes.",
    semantics: Semantics::new(Order::in_turn(Statuses::ANY), |_, c| {
        pass(first(c), Statuses::SUCCESS, Statuses::SUCCESS)
    }),
};

/// ForceFailure's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const FORCE_FAILURE: NodeDecl = NodeDecl {
    name: "ForceFailure",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[],
    summary: "A completed child becomes Failure; Running passes.",
    semantics: Semantics::new(Order::in_turn(Statuses::ANY), |_, c| {
        pass(first(c), Statuses::FAILURE, Statuses::FAILURE)
    }),
};

#[inline(never)]
pub(crate) fn tick<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
    forced: NodeStatus,
) -> NodeStatus {
    t.set_status(id, NodeStatus::Running);
    let child = t.child(def, 0);
    let status = t.tick(child);
    if status.is_completed() {
        t.halt_child(child);
        forced
    } else {
        status
    }
}

/// The ForceSuccess node. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ForceSuccess;

impl BuiltIn for ForceSuccess {}

impl Tick for ForceSuccess {
    /// Running is not forced.
    fn passes_through(&self) -> bool {
        true
    }

    const DECL: &'static NodeDecl = &FORCE_SUCCESS;

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(ForceSuccess)
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        tick(t, id, def, NodeStatus::Success)
    }
}

impl<C> Builder<C> {
    /// A [ForceSuccess](self): a completed child becomes Success.
    pub fn force_success(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::ForceSuccess(ForceSuccess), name, children)
    }
}
/// The ForceFailure node. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ForceFailure;

impl BuiltIn for ForceFailure {
    fn failed_alone(&self) -> Option<&'static str> {
        Some("forced to fail")
    }
}

impl Tick for ForceFailure {
    /// Running is not forced.
    fn passes_through(&self) -> bool {
        true
    }

    const DECL: &'static NodeDecl = &FORCE_FAILURE;

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(ForceFailure)
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        tick(t, id, def, NodeStatus::Failure)
    }
}

impl<C> Builder<C> {
    /// A [ForceFailure](self): a completed child becomes Failure.
    pub fn force_failure(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::ForceFailure(ForceFailure), name, children)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn forces_completed_outcomes() {
        let mut lab = Lab::new(&[&[F, R, S]]);
        let mut tree = lab.tree(|b| b.force_success("ok", |i| i.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));

        let mut lab = Lab::new(&[&[S, R, F]]);
        let mut tree = lab.tree(|b| b.force_failure("no", |i| i.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [3]);
    }
}
