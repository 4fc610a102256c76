//! AlwaysSuccess and AlwaysFailure: leaves with a fixed outcome, for stubs and tests.
//!
//! - **AlwaysSuccess**: Success, every tick.
//! - **AlwaysFailure**: Failure, every tick.

use crate::blueprint::NodeDef;
use crate::blueprint::{Builder, NodeKind, PortBinding, PortBindingError};
use crate::nodes::built_in::{BuiltIn, Tick};
use crate::nodes::decl::NodeDecl;
use crate::nodes::semantics::{Order, Semantics, Statuses};
use crate::tree::Ticker;
use crate::{Arity, Category};
use crate::{NodeId, NodeStatus};

/// AlwaysSuccess's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const ALWAYS_SUCCESS: NodeDecl = NodeDecl {
    name: "AlwaysSuccess",
    category: Category::Action,
    arity: Arity::Leaf,
    ports: &[],
    summary: "Success, every tick.",
    semantics: Semantics::new(Order::AllAtOnce, |_, _| Statuses::SUCCESS),
};

/// AlwaysFailure's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const ALWAYS_FAILURE: NodeDecl = NodeDecl {
    name: "AlwaysFailure",
    category: Category::Action,
    arity: Arity::Leaf,
    ports: &[],
    summary: "Failure, every tick.",
    semantics: Semantics::new(Order::AllAtOnce, |_, _| Statuses::FAILURE),
};

/// The AlwaysSuccess leaf. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AlwaysSuccess;

impl BuiltIn for AlwaysSuccess {}

impl Tick for AlwaysSuccess {
    const DECL: &'static NodeDecl = &ALWAYS_SUCCESS;

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(AlwaysSuccess)
    }

    #[inline]
    fn tick<C>(&self, _: &mut Ticker<'_, C>, _: NodeId, _: &NodeDef<C>) -> NodeStatus {
        NodeStatus::Success
    }
}

impl<C> Builder<C> {
    /// An [AlwaysSuccess](self) leaf.
    pub fn always_success(self, name: &str) -> Self {
        self.leaf(NodeKind::AlwaysSuccess(AlwaysSuccess), name)
    }
}
/// The AlwaysFailure leaf. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AlwaysFailure;

impl BuiltIn for AlwaysFailure {}

impl Tick for AlwaysFailure {
    const DECL: &'static NodeDecl = &ALWAYS_FAILURE;

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(AlwaysFailure)
    }

    #[inline]
    fn tick<C>(&self, _: &mut Ticker<'_, C>, _: NodeId, _: &NodeDef<C>) -> NodeStatus {
        NodeStatus::Failure
    }
}

impl<C> Builder<C> {
    /// An [AlwaysFailure](self) leaf.
    pub fn always_failure(self, name: &str) -> Self {
        self.leaf(NodeKind::AlwaysFailure(AlwaysFailure), name)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn fixed_outcomes() {
        let (mut tree, _) = build(|b| b.always_success("s"));
        assert_eq!(tick(&mut tree), Ok(Status::Success));
        let (mut tree, _) = build(|b| b.always_failure("f"));
        assert_eq!(tick(&mut tree), Ok(Status::Failure));
    }
}
