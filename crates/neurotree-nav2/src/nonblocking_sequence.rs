//! NonblockingSequence: a sequence that ticks every child on every tick.

use neurotree_core::nodes::semantics::{Order, Semantics, Statuses};
use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeStatus};

/// NonblockingSequence's semantics: every child on every tick, until one fails.
pub const SEMANTICS: Semantics = Semantics::new(
    Order::again(Statuses::ANY.without(Statuses::FAILURE), Statuses::ANY),
    |_, c| {
        let mut out = Statuses::NONE;
        for s in c {
            out = out.or(s.without(Statuses::SUCCESS.or(Statuses::SKIPPED)));
            if !s.meets(Statuses::ANY.without(Statuses::FAILURE)) {
                return out;
            }
        }
        let ends = c
            .iter()
            .all(|s| s.meets(Statuses::SUCCESS.or(Statuses::SKIPPED)));
        let all_skipped = c.iter().all(|s| s.can_skip());
        out.or(Statuses::SUCCESS.when(ends))
            .or(Statuses::SKIPPED.when(all_skipped))
            .or(Statuses::RUNNING.when(
                c.iter()
                    .any(|s| s.meets(Statuses::RUNNING.or(Statuses::SKIPPED))),
            ))
    },
);

/// NonblockingSequence: a sequence that ticks every child on every tick, as Nav2's
/// `nonblocking_sequence.cpp` does.
///
/// Every tick, tick all children from the first:
///
/// - Failure: halt all, Failure (the children after it are not ticked).
/// - Success, Running: go on to the next child.
/// - All ticked and all Success: halt all, Success; else Running.
///
/// Unlike a Sequence, a Running child does not stop the children after it from being
/// ticked, and unlike a PipelineSequence, every child (earlier ones too) is ticked every
/// tick. Children that succeeded are ticked again on later ticks while another runs.
/// Nav2 throws on a Skipped child; here a Skipped child counts as a Success, and when every
/// child was skipped the node is Skipped (a difference kept so that a tree with `_skipIf`
/// does not stop with an error).
#[derive(Debug, Default)]
pub struct NonblockingSequence;

impl NonblockingSequence {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder).
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "NonblockingSequence",
            Arity::AtLeast(1),
            Box::new(|| Box::new(NonblockingSequence)),
        )
    }
}

impl<C> CustomNode<C> for NonblockingSequence {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(Vec::new())
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let count = node.child_count();
        let (mut all_success, mut skipped) = (true, 0);
        for i in 0..count {
            match node.tick_child(i) {
                NodeStatus::Running => all_success = false,
                NodeStatus::Skipped => skipped += 1,
                NodeStatus::Success => {}
                // Failure (a child never returns Idle: the engine reports it as Failure).
                _ => {
                    node.reset_children();
                    return NodeStatus::Failure;
                }
            }
        }
        if !all_success {
            return NodeStatus::Running;
        }
        node.reset_children();
        if skipped == count {
            NodeStatus::Skipped
        } else {
            NodeStatus::Success
        }
    }
}
