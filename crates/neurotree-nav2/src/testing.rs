//! Scripted leaves for the Nav2 node tests, in the manner of the core's: each leaf plays its
//! outcomes from the [`Lab`] and counts its ticks and halts there, so that a test reads as
//! "given these child outcomes, after these ticks, these statuses, these tick and halt
//! counts".

pub(crate) use std::time::Duration;

pub(crate) use neurotree_core::{
    Arity, Builder, CustomNode, CustomSpec, ManualClock, NodeCtx, NodeId, NodeStatus, Port, Status,
    Tree,
};

use neurotree_core::{Action, Handle, StatefulAction};

pub(crate) const S: NodeStatus = NodeStatus::Success;
pub(crate) const F: NodeStatus = NodeStatus::Failure;
pub(crate) const R: NodeStatus = NodeStatus::Running;
/// Skipped: only a [`ScriptedExt::skippable`] leaf may play it.
pub(crate) const K: NodeStatus = NodeStatus::Skipped;

pub(crate) fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

/// The context of scripted leaves.
pub(crate) struct Lab {
    /// Outcomes per leaf; the last repeats forever.
    pub scripts: Vec<Vec<NodeStatus>>,
    /// Calls per leaf (`on_start`, `on_running`, or a tick of a sync or skippable leaf).
    pub ticks: Vec<u32>,
    /// Halts per leaf (of a Running leaf).
    pub halts: Vec<u32>,
    pub clock: ManualClock,
}

impl Lab {
    pub(crate) fn new(scripts: &[&[NodeStatus]]) -> Self {
        Self {
            scripts: scripts.iter().map(|s| s.to_vec()).collect(),
            ticks: vec![0; scripts.len()],
            halts: vec![0; scripts.len()],
            clock: ManualClock::new(),
        }
    }

    pub(crate) fn tree(&self, f: impl FnOnce(Builder<Lab>) -> Builder<Lab>) -> Tree<Lab> {
        let bp = f(Builder::new())
            .build_shared()
            .expect("test tree is valid");
        Tree::with_clock(bp, self.clock.clone())
    }

    /// `tick_once`, with the outcome as a stored-status value so that Skipped shows too.
    pub(crate) fn tick(&mut self, tree: &mut Tree<Lab>) -> NodeStatus {
        match tree.tick_once(self) {
            Ok(status) => status.into(),
            Err(neurotree_core::TickError::RootSkipped) => NodeStatus::Skipped,
            Err(e) => panic!("tick failed: {e}"),
        }
    }

    pub(crate) fn halt(&mut self, tree: &mut Tree<Lab>) {
        tree.halt(self);
    }

    pub(crate) fn advance(&self, by: Duration) {
        self.clock.advance(by);
    }

    fn next(&mut self, leaf: usize) -> NodeStatus {
        self.ticks[leaf] += 1;
        let script = &self.scripts[leaf];
        let at = (self.ticks[leaf] as usize - 1).min(script.len() - 1);
        script[at]
    }
}

fn status(s: NodeStatus) -> Status {
    s.to_status()
        .expect("only a skippable leaf may play Skipped")
}

/// A stateful leaf: `on_start` / `on_running` play the script, `on_halted` counts.
struct Scripted(usize);

impl StatefulAction<Lab> for Scripted {
    fn on_start(&mut self, h: &mut Handle<'_, Lab>) -> Status {
        status(h.ctx_mut().next(self.0))
    }
    fn on_running(&mut self, h: &mut Handle<'_, Lab>) -> Status {
        status(h.ctx_mut().next(self.0))
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Lab>) {
        h.ctx_mut().halts[self.0] += 1;
    }
}

/// A sync leaf, re-ticked whatever its stored status, as conditions are.
struct Check(usize);

impl Action<Lab> for Check {
    fn tick(&self, h: &mut Handle<'_, Lab>) -> Status {
        status(h.ctx_mut().next(self.0))
    }
}

/// A leaf that may also be skipped: a custom node, re-ticked whatever its stored status.
struct Skippable(usize);

impl CustomNode<Lab> for Skippable {
    fn tick(&mut self, node: &mut NodeCtx<'_, '_, Lab>) -> NodeStatus {
        node.ctx().next(self.0)
    }
    fn halt(&mut self, node: &mut NodeCtx<'_, '_, Lab>) {
        node.ctx().halts[self.0] += 1;
    }
}

pub(crate) trait ScriptedExt {
    /// Adds stateful leaf `i` of the lab, named `L{i}`.
    fn scripted(self, i: usize) -> Self;
    /// Adds sync leaf `i` of the lab (a condition-like check), named `L{i}`.
    fn check(self, i: usize) -> Self;
    /// Adds leaf `i` of the lab that may play Skipped, named `L{i}`.
    fn skippable(self, i: usize) -> Self;
}

impl ScriptedExt for Builder<Lab> {
    fn scripted(self, i: usize) -> Self {
        self.stateful(&format!("L{i}"), move || Scripted(i))
    }
    fn check(self, i: usize) -> Self {
        self.action_node(&format!("L{i}"), Check(i))
    }
    fn skippable(self, i: usize) -> Self {
        let spec = CustomSpec::new(
            "Skippable",
            Arity::Leaf,
            Box::new(move || Box::new(Skippable(i))),
        );
        self.custom(&format!("L{i}"), spec, |c| c)
    }
}
