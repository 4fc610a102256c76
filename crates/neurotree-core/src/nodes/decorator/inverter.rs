//! Inverter: swap Success and Failure.
//!
//! Swap Success/Failure; Running passes.
//!
//! A completed child is reset; Running and Skipped pass through unchanged.

use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::nodes::decl::NodeDecl;
use crate::{Arity, Category};

/// Inverter's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const INVERTER: NodeDecl = NodeDecl {
    name: "Inverter",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[],
    summary: "Swaps Success and Failure; Running passes.",
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
