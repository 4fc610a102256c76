//! SingleTrigger: tick the child to completion once per run of the node.

use neurotree_core::nodes::semantics::{first, Order, Semantics, Statuses};
use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeStatus};

/// SingleTrigger's semantics: its child's statuses, then FAILURE once used up.
pub const SEMANTICS: Semantics = Semantics::new(Order::in_turn(Statuses::ANY), |_, c| {
    first(c).or(Statuses::FAILURE)
});

/// SingleTrigger: tick the child to completion once per run, then fail, as Nav2's
/// `single_trigger_node.cpp` does.
///
/// - On the tick from Idle (or Skipped), the child may be ticked.
/// - While it may: tick it; Running or Skipped passes through; Success or Failure passes
///   through and uses up the trigger.
/// - Once used up: Failure without ticking the child, until the node starts a new run.
///
/// "Once used up" needs a parent that keeps the completed node as it is (a
/// PipelineSequence, a ReactiveSequence's earlier child is reset instead): a parent that
/// resets it to Idle starts a new run, which may tick the child again. The completed child
/// is reset after the tick, as BehaviorTree.CPP's decorators do.
#[derive(Debug, Default)]
pub struct SingleTrigger {
    /// The child has completed in this run.
    used: bool,
}

impl SingleTrigger {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder).
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "SingleTrigger",
            Arity::One,
            Box::new(|| Box::new(SingleTrigger::default())),
        )
    }
}

impl<C> CustomNode<C> for SingleTrigger {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(self.used,)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(used,)| self.used = used)
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        if !node.previous_status().is_active() {
            self.used = false;
        }
        node.set_running();
        if self.used {
            return NodeStatus::Failure;
        }
        let status = node.tick_child(0);
        if status.is_completed() {
            self.used = true;
            node.reset_completed_children_after_tick();
        }
        status
    }
}
