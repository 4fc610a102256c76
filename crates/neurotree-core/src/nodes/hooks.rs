//! Pre- and post-conditions: scripts BehaviorTree.CPP attaches to any node with the
//! `_failureIf`, `_successIf`, `_skipIf`, `_while`, `_onSuccess`, `_onFailure`, `_post` and
//! `_onHalted` attributes.
//!
//! - **Before the tick**: checked only while the node is Idle, in this order:
//!   `_failureIf` true → Failure, `_successIf` true → Success, `_skipIf` true → Skipped,
//!   `_while` false → Skipped; the node's own tick is then not called. While the node is
//!   Running, only `_while` is checked: false halts the node and returns Skipped. A node
//!   re-ticked after completing, before its parent reset it, is ticked with no check
//!   (BehaviorTree.CPP's `checkPreConditions` looks only at Idle, Skipped and Running).
//! - **After the tick**: on Success `_onSuccess`, on Failure `_onFailure`, then `_post` on
//!   either (also when a precondition decided the status).
//! - **After a halt**: `_onHalted`, when a Running node is halted.
//!
//! The engine calls a [`NodeHooks`] object at these points; the `neurotree` crate implements
//! it with its script language. A node without hooks pays nothing.

use crate::nodes::leaf::Handle;
use crate::NodeStatus;

/// What runs around a node's tick (see the [module docs](self)).
pub trait NodeHooks<C>: Send + Sync {
    /// Before the tick. `stored` is the node's stored status: Idle, Running, or Success or
    /// Failure when the parent re-ticks a completed child it has not reset (BehaviorTree.CPP
    /// checks no precondition then). Return the status that replaces the tick, or `None` to
    /// tick the node. Returning Skipped while
    /// `stored` is Running halts the node; so does returning Success or Failure then (a
    /// result forced on a running node by hand), so that no leaf is left running under a
    /// completed status.
    fn before(&self, h: &mut Handle<'_, C>, stored: NodeStatus) -> Option<NodeStatus>;

    /// After a tick (or a precondition) that completed with `status` (Success or Failure).
    fn after(&self, _h: &mut Handle<'_, C>, _status: NodeStatus) {}

    /// After the node was halted while Running.
    fn halted(&self, _h: &mut Handle<'_, C>) {}

    /// Calls `f` with each hook as the attribute a file writes it as (`_skipIf`, its
    /// script), so a saved tree keeps its hooks. Hooks with no textual form write nothing.
    fn attributes(&self, _f: &mut dyn FnMut(&str, &str)) {}

    /// `true` if the hooks' checks read the blackboard alone (scripts do): a node re-checked
    /// every tick with such hooks lets the tree sleep (see [`sleep`](crate::tree::sleep)).
    /// `false` keeps a tree awake while a node with these hooks is re-checked.
    fn reads_only_blackboard(&self) -> bool {
        false
    }
}
