//! The one hook through which loggers, statistics and live views watch a tree.
//!
//! An [`Observer`] attached to a [`Tree`](crate::Tree) is told when a tick starts and ends and
//! every time a node's stored status changes, including the changes to `Idle` that halts and
//! resets cause. With no observer attached, the engine pays one branch per status write.

use core::time::Duration;

use crate::{NodeId, NodeStatus, Reason};

/// One change of a node's stored status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StatusChange {
    /// The node whose status changed.
    pub node: NodeId,
    /// Its status before.
    pub from: NodeStatus,
    /// Its status now.
    pub to: NodeStatus,
    /// The tree's clock at the change.
    pub at: Duration,
}

/// Receives what a tree does, as it happens.
///
/// All methods have empty defaults, so an observer implements only what it needs.
pub trait Observer: Send {
    /// A root tick is about to start (called once per pass of the root, so `tick_once` may
    /// call it several times when a node asks to be woken).
    fn on_tick_start(&mut self, _now: Duration) {}

    /// A node's stored status changed.
    fn on_status_change(&mut self, _change: StatusChange) {}

    /// A node's own tick is about to run (not called when a precondition decides instead).
    fn on_node_tick(&mut self, _node: NodeId) {}

    /// A node returned Skipped: a precondition (`_skipIf`, a false `_while`) or the node
    /// itself (RunOnce after its run, a control whose children were all skipped) chose not
    /// to run. A skipped node keeps, or returns to, Idle, so no status change tells of it;
    /// this is called after its status was stored.
    fn on_node_skipped(&mut self, _node: NodeId) {}

    /// A root tick ended with `status`.
    fn on_tick_end(&mut self, _status: NodeStatus, _now: Duration) {}

    /// `node` failed for `reason`: called just before the status change of `node` to
    /// Failure, and only when the node gave a reason ([`Handle::fail_with`]) or is a
    /// built-in that gives its own (a Timeout that fired, a Retry that ran out, a
    /// `_failureIf` precondition). Never called in a tick where no reason is given.
    ///
    /// [`Handle::fail_with`]: crate::Handle::fail_with
    fn on_failure_reason(&mut self, _node: NodeId, _reason: &Reason) {}

    /// `node` was given the score `score` in this tick: the number a control chose by (a
    /// UtilitySelector tells each of its Utility children's, as it evaluates them), which a
    /// live view shows on the node. Called only where a node reports one
    /// ([`NodeCtx::report_child_score`](crate::NodeCtx::report_child_score)).
    fn on_node_score(&mut self, _node: NodeId, _score: f64) {}

    /// `false` (the default): the tree it watches never [sleeps](crate::tree::sleep), so
    /// that it sees every tick. `true` for an observer content to see the passes alone,
    /// and the tree as it stands between them (a live view of one agent of a crowd): the
    /// tree then sleeps as it would unobserved.
    fn lets_tree_sleep(&self) -> bool {
        false
    }
}

/// Two observers side by side: both see every event, the first one first.
impl<A: Observer, B: Observer> Observer for (A, B) {
    fn on_tick_start(&mut self, now: Duration) {
        self.0.on_tick_start(now);
        self.1.on_tick_start(now);
    }
    fn on_status_change(&mut self, change: StatusChange) {
        self.0.on_status_change(change);
        self.1.on_status_change(change);
    }
    fn on_node_tick(&mut self, node: NodeId) {
        self.0.on_node_tick(node);
        self.1.on_node_tick(node);
    }
    fn on_node_skipped(&mut self, node: NodeId) {
        self.0.on_node_skipped(node);
        self.1.on_node_skipped(node);
    }
    fn on_tick_end(&mut self, status: NodeStatus, now: Duration) {
        self.0.on_tick_end(status, now);
        self.1.on_tick_end(status, now);
    }
    fn on_failure_reason(&mut self, node: NodeId, reason: &Reason) {
        self.0.on_failure_reason(node, reason);
        self.1.on_failure_reason(node, reason);
    }
    fn on_node_score(&mut self, node: NodeId, score: f64) {
        self.0.on_node_score(node, score);
        self.1.on_node_score(node, score);
    }
    fn lets_tree_sleep(&self) -> bool {
        self.0.lets_tree_sleep() && self.1.lets_tree_sleep()
    }
}

/// Any number of boxed observers, in order.
impl Observer for alloc::vec::Vec<alloc::boxed::Box<dyn Observer>> {
    fn on_tick_start(&mut self, now: Duration) {
        for o in self.iter_mut() {
            o.on_tick_start(now);
        }
    }
    fn on_status_change(&mut self, change: StatusChange) {
        for o in self.iter_mut() {
            o.on_status_change(change);
        }
    }
    fn on_node_tick(&mut self, node: NodeId) {
        for o in self.iter_mut() {
            o.on_node_tick(node);
        }
    }
    fn on_node_skipped(&mut self, node: NodeId) {
        for o in self.iter_mut() {
            o.on_node_skipped(node);
        }
    }
    fn on_tick_end(&mut self, status: NodeStatus, now: Duration) {
        for o in self.iter_mut() {
            o.on_tick_end(status, now);
        }
    }
    fn on_failure_reason(&mut self, node: NodeId, reason: &Reason) {
        for o in self.iter_mut() {
            o.on_failure_reason(node, reason);
        }
    }
    fn on_node_score(&mut self, node: NodeId, score: f64) {
        for o in self.iter_mut() {
            o.on_node_score(node, score);
        }
    }
    fn lets_tree_sleep(&self) -> bool {
        self.iter().all(|o| o.lets_tree_sleep())
    }
}
