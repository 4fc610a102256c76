//! Watching a run: the observer the engine calls, the shared state the pages read, and the
//! controls (pause, step, continue, breakpoints, blackboard edits) the pages send.
//!
//! The tick thread never waits on the network. The observer writes each status into an
//! atomic byte and, at the end of a tick, bumps a version number; each page's task wakes
//! on the bump and sends what changed since it last sent, so a slow page skips
//! intermediate states instead of falling behind. The run waits only where a page asked it
//! to (a pause, a step, a breakpoint) and only while a page is attached.

mod hub;
mod page;
mod values;

use std::sync::Arc;

use neurotree_core::{NodeId, Status, Tree};

pub(crate) use hub::Hub;
pub use hub::StudioObserver;
pub(crate) use page::serve_page;

/// The run's side of a watched tree: call [`between_ticks`](Self::between_ticks) after
/// each tick (or tick through [`tick_once`](Self::tick_once)), so that pages see the
/// blackboards and the failure chain, their edits are applied, and a pause holds the run
/// where the tree can be read.
pub struct Watch {
    hub: Arc<Hub>,
}

impl std::fmt::Debug for Watch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Watch").finish_non_exhaustive()
    }
}

impl Watch {
    pub(crate) fn new(hub: Arc<Hub>) -> Self {
        Self { hub }
    }

    /// Applies the pages' blackboard edits, publishes the blackboards and the failure chain
    /// to the pages attached, and waits while a page has paused the run (applying edits
    /// made meanwhile). Returns at once when no page is attached.
    pub fn between_ticks<C>(&mut self, tree: &mut Tree<C>) {
        self.hub.between_ticks(tree);
    }

    /// One [`Tree::tick_once`] with [`between_ticks`](Self::between_ticks) before it, and
    /// the run marked ended when the root is no longer Running.
    pub fn tick_once<C>(
        &mut self,
        tree: &mut Tree<C>,
        ctx: &mut C,
    ) -> Result<Status, neurotree_core::TickError> {
        self.between_ticks(tree);
        let status = tree.tick_once(ctx)?;
        if status != Status::Running {
            self.finish(tree, status);
        }
        Ok(status)
    }

    /// Shows `tree`, reloaded ([`Tree::reload`]), to the pages in place of the one
    /// watched: they get it whole, with the breakpoints of nodes whose paths it still has.
    /// The observer already set follows it from the next tick.
    pub fn reattach<C>(&mut self, tree: &Tree<C>, name: &str) {
        drop(self.hub.attach(tree, name));
    }

    /// Marks the run ended with `status` and publishes the tree's last blackboards.
    pub fn finish<C>(&mut self, tree: &mut Tree<C>, status: Status) {
        self.hub.publish(tree);
        self.hub.finish(status);
    }

    /// The number of pages attached now.
    pub fn pages(&self) -> usize {
        self.hub.pages()
    }
}

/// The id of a node by its index, for messages from pages (which may name any number).
fn node_in(index: u64, len: usize) -> Option<NodeId> {
    (index < len as u64).then_some(NodeId(index as u32))
}
