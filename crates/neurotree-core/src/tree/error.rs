//! Why a tick produced no status.

use alloc::string::String;

use crate::NodeId;

/// A tick that did not produce a status. The tree has been halted when this is returned, so
/// it can be ticked again from a clean state.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TickError {
    /// The root's precondition skipped it: nothing ran.
    #[error("the root node was skipped by its precondition; nothing ran")]
    RootSkipped,
    /// A leaf that must complete in one tick returned Running.
    #[error("{path} ({node}) is a {kind} and must not return RUNNING; use a StatefulAction for work that spans ticks")]
    LeafRunning {
        /// The leaf.
        node: NodeId,
        /// Its path in the tree.
        path: String,
        /// `Condition` or `Action`.
        kind: &'static str,
    },
    /// A node returned Idle, which only the engine may set.
    #[error(
        "{path} ({node}) returned IDLE; a tick must return RUNNING, SUCCESS, FAILURE or SKIPPED"
    )]
    ReturnedIdle {
        /// The node.
        node: NodeId,
        /// Its path in the tree.
        path: String,
    },
    /// A node reported an error of its own.
    #[error("{path} ({node}): {message}")]
    Node {
        /// The node.
        node: NodeId,
        /// Its path in the tree.
        path: String,
        /// What went wrong.
        message: String,
    },
}
