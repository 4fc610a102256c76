//! Why a tick produced no status.

use alloc::string::String;

use crate::NodeId;

/// A tick that did not produce a status. The tree has been halted when this is returned, so
/// it can be ticked again from a clean state.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
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
    /// [`Tree::tick_once`](crate::Tree::tick_once) made its most passes and a node still
    /// asked for another; the tree was halted.
    #[error("{path} asked for another pass of the tree {passes} times in one tick; the tree was halted (a Repeat of -1 over a child that completes at once never stops; raise the limit with Tree::set_max_passes if the loop is meant)")]
    TooManyPasses {
        /// The node that asked last, or `None` for the future of an async action.
        node: Option<NodeId>,
        /// Its path in the tree.
        path: String,
        /// The passes made.
        passes: u32,
    },
    /// User code in a node panicked (a leaf, a custom node, a hook, or an `on_halted`). The
    /// tree caught it, halted every Running node and is ready for the next tick.
    #[error("{path} ({node}) panicked: {message}")]
    Panicked {
        /// The node the panic came from.
        node: NodeId,
        /// Its path in the tree.
        path: String,
        /// The panic's message.
        message: String,
    },
    /// A [`HaltHandle`](crate::HaltHandle) asked for a halt, and this call served it at a
    /// tick boundary: the tree was halted (each Running stateful action got its one
    /// `on_halted`) and nothing more was ticked. The next tick starts afresh.
    #[error("a halt was requested through a HaltHandle; the tree was halted")]
    HaltRequested,
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

crate::debug_shows_message!(enum TickError {
    RootSkipped,
    LeafRunning { node, path, kind },
    ReturnedIdle { node, path },
    TooManyPasses { node, path, passes },
    Panicked { node, path, message },
    HaltRequested,
    Node { node, path, message },
});
