//! Test helpers: scripted leaves whose outcomes, ticks, halts and calls are recorded in the
//! context, so each test reads as "given these child outcomes, after these ticks, these
//! statuses, these tick and halt counts".

pub(crate) use crate::{
    Builder, ManualClock, NodeId, NodeStatus, ParallelPolicy, Status, TickError, Tree,
};
pub(crate) use alloc::format;
pub(crate) use alloc::string::{String, ToString};
pub(crate) use alloc::sync::Arc;
pub(crate) use alloc::vec;
pub(crate) use alloc::vec::Vec;
pub(crate) use core::time::Duration;

use crate::{Action, Handle, StatefulAction};

pub(crate) const S: Status = Status::Success;
pub(crate) const F: Status = Status::Failure;
pub(crate) const R: Status = Status::Running;

pub(crate) fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

/// A tree over the unit context, with its manual clock.
pub(crate) fn build(f: impl FnOnce(Builder<()>) -> Builder<()>) -> (Tree<()>, ManualClock) {
    let clock = ManualClock::new();
    let bp = f(Builder::new())
        .build_shared()
        .expect("test tree is valid");
    (Tree::with_clock(bp, clock.clone()), clock)
}

/// `tick_once` over the unit context.
pub(crate) fn tick(tree: &mut Tree<()>) -> Result<Status, TickError> {
    tree.tick_once(&mut ())
}

/// The context of scripted leaves.
pub(crate) struct Lab {
    /// Outcomes per leaf; the last repeats forever.
    pub scripts: Vec<Vec<Status>>,
    /// Calls of `on_start` or `on_running` per leaf.
    pub ticks: Vec<u32>,
    /// Calls of `on_halted` per leaf.
    pub halts: Vec<u32>,
    /// Every call per leaf, in order: "start", "running", "halted".
    pub logs: Vec<Vec<&'static str>>,
    pub clock: ManualClock,
}

impl Lab {
    pub(crate) fn new(scripts: &[&[Status]]) -> Self {
        Self {
            scripts: scripts.iter().map(|s| s.to_vec()).collect(),
            ticks: vec![0; scripts.len()],
            halts: vec![0; scripts.len()],
            logs: vec![Vec::new(); scripts.len()],
            clock: ManualClock::new(),
        }
    }

    pub(crate) fn tree(&self, f: impl FnOnce(Builder<Lab>) -> Builder<Lab>) -> Tree<Lab> {
        let bp = f(Builder::new())
            .build_shared()
            .expect("test tree is valid");
        Tree::with_clock(bp, self.clock.clone())
    }

    pub(crate) fn tick(&mut self, tree: &mut Tree<Lab>) -> Result<Status, TickError> {
        tree.tick_once(self)
    }

    pub(crate) fn tick_exactly_once(&mut self, tree: &mut Tree<Lab>) -> Result<Status, TickError> {
        tree.tick_exactly_once(self)
    }

    pub(crate) fn halt(&mut self, tree: &mut Tree<Lab>) -> bool {
        tree.halt(self)
    }

    pub(crate) fn log_of(&self, leaf: usize) -> &[&'static str] {
        &self.logs[leaf]
    }

    fn next(&mut self, leaf: usize, call: &'static str) -> Status {
        self.ticks[leaf] += 1;
        self.logs[leaf].push(call);
        let script = &self.scripts[leaf];
        let at = (self.ticks[leaf] as usize - 1).min(script.len() - 1);
        script[at]
    }
}

/// A stateful leaf that plays its script from the [`Lab`].
struct Scripted(usize);

impl StatefulAction<Lab> for Scripted {
    fn on_start(&mut self, h: &mut Handle<'_, Lab>) -> Status {
        h.ctx_mut().next(self.0, "start")
    }
    fn on_running(&mut self, h: &mut Handle<'_, Lab>) -> Status {
        h.ctx_mut().next(self.0, "running")
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Lab>) {
        let lab = h.ctx_mut();
        lab.halts[self.0] += 1;
        lab.logs[self.0].push("halted");
    }
}

/// A sync leaf that plays its script from the [`Lab`]: re-ticked whatever its stored status,
/// as conditions are. Its script must not hold Running.
struct Check(usize);

impl Action<Lab> for Check {
    fn tick(&self, h: &mut Handle<'_, Lab>) -> Status {
        h.ctx_mut().next(self.0, "tick")
    }
}

pub(crate) trait ScriptedExt {
    /// Adds stateful leaf `i` of the lab, named `L{i}`.
    fn scripted(self, i: usize) -> Self;
    /// Adds sync leaf `i` of the lab (a condition-like check), named `L{i}`.
    fn check(self, i: usize) -> Self;
}

impl ScriptedExt for Builder<Lab> {
    fn scripted(self, i: usize) -> Self {
        self.stateful(&format!("L{i}"), move || Scripted(i))
    }
    fn check(self, i: usize) -> Self {
        self.action_node(&format!("L{i}"), Check(i))
    }
}
