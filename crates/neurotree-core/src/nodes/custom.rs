//! User-defined controls and decorators.
//!
//! A [`CustomNode`] decides which children to tick, like the built-in controls do, through a
//! [`NodeCtx`]. One object is made per tree instance, so it may keep state in `self`. The
//! engine marks the node Running before calling [`CustomNode::tick`], and after
//! [`CustomNode::halt`] it halts any child still Running, so the halting rules hold for user
//! nodes too.

use alloc::string::String;
use core::time::Duration;

use crate::blackboard::Blackboard;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

/// A control or decorator written by the user.
///
/// ```
/// use neurotree_core::{Arity, Blueprint, CustomNode, CustomSpec, ManualClock, NodeCtx, NodeStatus, Status, Tree};
///
/// /// Ticks its children in reverse order, as a Sequence would.
/// struct ReverseSequence;
/// impl<C> CustomNode<C> for ReverseSequence {
///     fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
///         for i in (0..node.child_count()).rev() {
///             match node.tick_child(i) {
///                 NodeStatus::Success | NodeStatus::Skipped => {}
///                 other => return other,
///             }
///         }
///         node.reset_children();
///         NodeStatus::Success
///     }
/// }
///
/// let spec = CustomSpec::<Vec<&str>> {
///     type_name: "ReverseSequence".into(),
///     arity: Arity::AtLeast(1),
///     factory: Box::new(|| Box::new(ReverseSequence)),
/// };
/// let bp = Blueprint::builder()
///     .custom("rev", spec, |c| {
///         c.action("a", |log: &mut Vec<&str>| { log.push("a"); Status::Success })
///             .action("b", |log: &mut Vec<&str>| { log.push("b"); Status::Success })
///     })
///     .build_shared()
///     .unwrap();
/// let mut tree = Tree::with_clock(bp, ManualClock::new());
/// let mut log = Vec::new();
/// assert_eq!(tree.tick_once(&mut log), Ok(Status::Success));
/// assert_eq!(log, ["b", "a"]);
/// ```
pub trait CustomNode<C>: Send {
    /// Ticks the node; return Running, Success, Failure or Skipped (never Idle).
    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus;

    /// Called when the node is halted while Running, before the engine halts its running
    /// children. Reset the node's own state here.
    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {}
}

/// What a [`CustomNode`] sees: its children, the context, the blackboard and the clock.
pub struct NodeCtx<'a, 't, C> {
    pub(crate) t: &'a mut Ticker<'t, C>,
    pub(crate) id: NodeId,
}

impl<C> NodeCtx<'_, '_, C> {
    /// The node's id.
    pub fn id(&self) -> NodeId {
        self.id
    }

    /// Number of children.
    pub fn child_count(&self) -> usize {
        self.t.bp.children(self.id).len()
    }

    /// Ticks child `i` and returns what it returned.
    ///
    /// # Panics
    /// If `i` is not below [`child_count`](Self::child_count).
    pub fn tick_child(&mut self, i: usize) -> NodeStatus {
        let child = self.t.bp.children(self.id)[i];
        self.t.tick(child)
    }

    /// The stored status of child `i`.
    pub fn child_status(&self, i: usize) -> NodeStatus {
        let child = self.t.bp.children(self.id)[i];
        self.t.status(child)
    }

    /// Halts child `i` if it is Running and resets it to Idle.
    pub fn halt_child(&mut self, i: usize) {
        let child = self.t.bp.children(self.id)[i];
        self.t.halt_child(child);
    }

    /// Halts every Running child and resets all of them to Idle; call it when completing.
    pub fn reset_children(&mut self) {
        self.t.reset_children(self.id);
    }

    /// Asks `tick_once` to tick the tree again at once (after yielding Running).
    pub fn request_wake_up(&mut self) {
        self.t.wake = true;
    }

    /// The user's context.
    pub fn ctx(&mut self) -> &mut C {
        self.t.ctx
    }

    /// The tree's blackboard.
    pub fn blackboard(&mut self) -> &mut Blackboard {
        self.t.bb
    }

    /// The blackboard scope the node reads and writes (its subtree's).
    pub fn scope(&self) -> crate::ScopeId {
        self.t.bp.scope(self.id)
    }

    /// The node's ports and their bindings.
    pub fn ports(&self) -> &[crate::Port] {
        self.t.bp.ports(self.id)
    }

    /// The tree's clock reading.
    pub fn now(&self) -> Duration {
        self.t.clock.now()
    }

    /// Reports a runtime error: the tick ends with [`TickError::Node`](crate::TickError::Node)
    /// after the tree is halted. Return Failure after calling it.
    pub fn fail(&mut self, message: impl Into<String>) {
        let id = self.id;
        self.t.fault_node(id, message.into());
    }
}

/// Stands in for a custom node while it is being ticked, so the node can borrow the engine.
pub(crate) struct Vacant;

impl<C> CustomNode<C> for Vacant {
    fn tick(&mut self, _node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        // Only reachable if a custom node's tick re-enters itself, which the tree's shape
        // forbids; failing is the safe answer.
        NodeStatus::Failure
    }
}
