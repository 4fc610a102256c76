//! Inverter: swap Success and Failure.
//!
//! Swap Success/Failure; Running passes.
//!
//! A completed child is reset; Running and Skipped pass through unchanged.

use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::blueprint::{Builder, NodeKind, PortBinding, PortBindingError};
use crate::nodes::built_in::{BuiltIn, Tick};
use crate::nodes::decl::NodeDecl;
use crate::nodes::semantics::{first, pass, Order, Semantics, Statuses};
use crate::{Arity, Category};

/// Inverter's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const INVERTER: NodeDecl = NodeDecl {
    name: "Inverter",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[],
    summary: "Swaps Success and Failure; Running passes.",
    semantics: Semantics::new(Order::in_turn(Statuses::ANY), |_, c| {
        pass(first(c), Statuses::FAILURE, Statuses::SUCCESS)
    }),
};

#[inline(never)]
pub(crate) fn tick<C>(t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
    t.set_status(id, NodeStatus::Running);
    let child = t.child(def, 0);
    let status = t.tick(child);
    let inverted = match status {
        NodeStatus::Success => NodeStatus::Failure,
        NodeStatus::Failure => NodeStatus::Success,
        other => return other,
    };
    t.halt_child(child);
    inverted
}

/// The Inverter node. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Inverter;

impl BuiltIn for Inverter {
    fn failed_alone(&self) -> Option<&'static str> {
        Some("its child succeeded")
    }
}

impl Tick for Inverter {
    /// Running is not inverted.
    fn passes_through(&self) -> bool {
        true
    }

    const DECL: &'static NodeDecl = &INVERTER;

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(Inverter)
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        tick(t, id, def)
    }
}

impl<C> Builder<C> {
    /// An [Inverter](self): Success ↔ Failure.
    pub fn inverter(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::Inverter(Inverter), name, children)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn swaps_completed_outcomes_and_passes_running() {
        let mut lab = Lab::new(&[&[S, F, R]]);
        let mut tree = lab.tree(|b| b.inverter("not", |i| i.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [3]);
    }
}
