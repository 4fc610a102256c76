//! PersistentSequence: a sequence whose place is kept in a blackboard entry.

use neurotree_core::nodes::semantics::{union, Order, Semantics, Statuses};
use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeStatus};

/// PersistentSequence's semantics: it starts at the child its entry names, so no order
/// between its children holds; SUCCESS past the last, FAILURE with a child's.
pub const SEMANTICS: Semantics = Semantics::new(Order::AllAtOnce, |_, c| {
    let all = union(c);
    Statuses::SUCCESS
        .or(Statuses::FAILURE.when(all.can_fail()))
        .or(Statuses::RUNNING.when(all.can_run()))
});

/// PersistentSequence: a sequence whose current child is kept in the blackboard, through
/// the in/out port `current_child_idx`, as Nav2's `persistent_sequence.cpp` does.
///
/// Every tick: read `current_child_idx` (a tick error when it cannot be read, as Nav2
/// throws: set it first, e.g. `<Script code="current_child_idx := 0"/>`), then tick the
/// children from that index:
///
/// - Running: Running.
/// - Failure: reset all, write 0, Failure.
/// - Success or Skipped: write the next index, go on.
/// - Past the last child: reset all, write 0, Success.
///
/// The node keeps nothing itself, so the place survives halts, resets and even another
/// tree: whoever writes the entry moves the sequence. An index past the last child gives
/// Success at once; a negative one starts at the first child. The index is written as the
/// type the entry holds (`i32`, or the `i64` or `f64` that a Script or `--set` writes).
#[derive(Debug, Default)]
pub struct PersistentSequence;

impl PersistentSequence {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder); bind
    /// `current_child_idx` to an entry with `.ports(..)`.
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "PersistentSequence",
            Arity::AtLeast(1),
            Box::new(|| Box::new(PersistentSequence)),
        )
    }
}

/// Writes `index` to `current_child_idx`, as the type its entry already holds.
fn write_index<C>(node: &mut NodeCtx<'_, '_, C>, index: i32) -> Result<(), String> {
    let written = super::write_output(node, "current_child_idx", index)
        .or_else(|_| super::write_output(node, "current_child_idx", i64::from(index)))
        .or_else(|_| super::write_output(node, "current_child_idx", f64::from(index)));
    written.or_else(|_| super::write_output(node, "current_child_idx", index.to_string()))
}

impl<C> CustomNode<C> for PersistentSequence {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(Vec::new())
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let index = match super::port_value::<C, i32>(node, "current_child_idx") {
            Ok(Some(index)) => index,
            Ok(None) => {
                node.fail(
                    "missing input `current_child_idx`; set it first, e.g. \
                     <Script code=\"current_child_idx := 0\"/>",
                );
                return NodeStatus::Failure;
            }
            Err(e) => {
                node.fail(e);
                return NodeStatus::Failure;
            }
        };
        node.set_running();
        let count = node.child_count();
        let mut current = usize::try_from(index).unwrap_or(0);
        while current < count {
            let status = node.tick_child(current);
            let result = match status {
                NodeStatus::Running => return NodeStatus::Running,
                NodeStatus::Success | NodeStatus::Skipped => {
                    current += 1;
                    write_index(node, current as i32)
                }
                _ => {
                    node.reset_children();
                    if let Err(e) = write_index(node, 0) {
                        node.fail(e);
                    }
                    return NodeStatus::Failure;
                }
            };
            if let Err(e) = result {
                node.fail(e);
                return NodeStatus::Failure;
            }
        }
        node.reset_children();
        if let Err(e) = write_index(node, 0) {
            node.fail(e);
            return NodeStatus::Failure;
        }
        NodeStatus::Success
    }
}
