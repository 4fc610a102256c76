//! Nav2's gtest fixtures without ROS: a `DummyNode` whose status the test sets, and a holder
//! that ticks the node under test as the gtests' `bt_node_->executeTick()` does, without a
//! parent that resets it after it completes.

#![allow(dead_code, unused_imports)]

use std::collections::VecDeque;

pub use neurotree::{
    Arity, Builder, CustomNode, CustomSpec, ManualClock, NodeCtx, NodeId, NodeStatus, Port,
    TickError, Tree,
};

pub const S: NodeStatus = NodeStatus::Success;
pub const F: NodeStatus = NodeStatus::Failure;
pub const R: NodeStatus = NodeStatus::Running;
pub const K: NodeStatus = NodeStatus::Skipped;
pub const I: NodeStatus = NodeStatus::Idle;

/// The context: the status each dummy is asked to return, and what happened.
#[derive(Default)]
pub struct Bench {
    /// `changeStatus`: what dummy `i` returns.
    pub requested: Vec<NodeStatus>,
    /// Outcomes dummy `i` returns first, one per tick, before `requested`.
    pub queued: Vec<VecDeque<NodeStatus>>,
    pub ticks: Vec<u32>,
    pub halts: Vec<u32>,
    /// What the node under test returned on the last tick.
    pub last: Option<NodeStatus>,
}

impl Bench {
    pub fn new(dummies: usize) -> Self {
        Self {
            requested: vec![I; dummies],
            queued: vec![VecDeque::new(); dummies],
            ticks: vec![0; dummies],
            halts: vec![0; dummies],
            last: None,
        }
    }

    /// `dummy->changeStatus(status)`.
    pub fn set(&mut self, dummy: usize, status: NodeStatus) {
        self.requested[dummy] = status;
    }

    /// `bt_node_->executeTick()`: what the node under test returned, or the tick's error.
    pub fn tick(&mut self, tree: &mut Tree<Bench>) -> Result<NodeStatus, TickError> {
        self.last = None;
        tree.tick_once(self)?;
        Ok(self.last.expect("the holder ticked the node"))
    }

    /// [`tick`](Self::tick), for a tick that must not fail.
    pub fn ok(&mut self, tree: &mut Tree<Bench>) -> NodeStatus {
        self.tick(tree).expect("the tick has no error")
    }
}

/// Nav2's `DummyNode`: returns the status the test asked for; asked for Idle, it is an error
/// of the tick, as Nav2's nodes throw on an Idle child.
struct Dummy(usize);

impl CustomNode<Bench> for Dummy {
    fn tick(&mut self, node: &mut NodeCtx<'_, '_, Bench>) -> NodeStatus {
        let bench = node.ctx();
        bench.ticks[self.0] += 1;
        let status = bench.queued[self.0]
            .pop_front()
            .unwrap_or(bench.requested[self.0]);
        if status == I {
            node.fail("A child node must never return IDLE");
            return F;
        }
        status
    }

    fn halt(&mut self, node: &mut NodeCtx<'_, '_, Bench>) {
        node.ctx().halts[self.0] += 1;
    }
}

/// Ticks its one child and notes its result in [`Bench::last`]; always Running itself, so
/// the child is never reset by its parent between ticks.
struct Holder;

impl CustomNode<Bench> for Holder {
    fn tick(&mut self, node: &mut NodeCtx<'_, '_, Bench>) -> NodeStatus {
        let status = node.tick_child(0);
        node.ctx().last = Some(status);
        R
    }
}

pub trait DummyExt {
    /// Adds dummy `i`, named `dummy{i}`.
    fn dummy(self, i: usize) -> Self;
}

impl DummyExt for Builder<Bench> {
    fn dummy(self, i: usize) -> Self {
        let spec = CustomSpec::new(
            "DummyNode",
            Arity::Leaf,
            Box::new(move || Box::new(Dummy(i))),
        );
        self.custom(&format!("dummy{i}"), spec, |c| c)
    }
}

/// A tree: the holder (id 0), the node under test (id 1) built by `node`, its children from
/// id 2 on.
pub fn tree(
    clock: &ManualClock,
    node: impl FnOnce(Builder<Bench>) -> Builder<Bench>,
) -> Tree<Bench> {
    let holder = CustomSpec::new("Holder", Arity::One, Box::new(|| Box::new(Holder)));
    let bp = Builder::new()
        .custom("holder", holder, node)
        .build_shared()
        .expect("test tree is valid");
    Tree::with_clock(bp, clock.clone())
}

/// The stored statuses of the node under test's children (ids 2..2+n).
pub fn children(tree: &Tree<Bench>, n: usize) -> Vec<NodeStatus> {
    (2..2 + n as u32).map(|i| tree.status(NodeId(i))).collect()
}
