//! Watching a run: the observer the engine calls, the shared state the pages read, and the
//! controls (pause, step, continue, breakpoints, blackboard edits) the pages send.
//!
//! The tick thread never waits on the network. The observer writes each status into an
//! atomic byte and, at the end of a tick, bumps a version number; each page's task wakes
//! on the bump and sends what changed since it last sent, so a slow page skips
//! intermediate states instead of falling behind. The run waits only where a page asked it
//! to (a pause, a step, a breakpoint) and only while a page is attached.
//!
//! A run keeps its state after every tick in a bounded window ([`rewind`]): a paused page
//! goes back and forth through the kept ticks, and a step or continue from a past tick
//! forks the run there. What the tree acts on is kept and drawn by the run's [`World`].

mod agents;
mod force;
mod hub;
mod page;
mod rewind;
mod standing;
mod travel;
mod values;

use std::sync::Arc;

use neurotree_core::{NodeId, Status, Tree};
use neurotree_toolkit::scene::Scene;

pub(crate) use agents::{
    agents as agents_page, choose as choose_agent, together as agents_together,
};
pub use agents::{AgentEntry, Agents, CrowdWatch, MAX_AGENTS_PAGE};
pub use force::Forced;
pub(crate) use hub::Hub;
pub use hub::StudioObserver;
pub(crate) use page::serve_page;
pub use page::MAX_SCENE_BYTES;
use rewind::{Travel, Window};
pub use rewind::{World, DEFAULT_REWIND_WINDOW};

/// The run's side of a watched tree: call [`between_ticks`](Self::between_ticks) after
/// each tick (or tick through [`tick_once`](Self::tick_once)), so that pages see the
/// blackboards and the failure chain, their edits are applied, and a pause holds the run
/// where the tree can be read.
pub struct Watch {
    hub: Arc<Hub>,
    /// The ticks to keep.
    keep: usize,
    /// Made at the first tick, with the world's codecs.
    window: Option<Window>,
}

impl std::fmt::Debug for Watch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Watch").finish_non_exhaustive()
    }
}

impl Watch {
    pub(crate) fn new(hub: Arc<Hub>) -> Self {
        Self {
            hub,
            keep: DEFAULT_REWIND_WINDOW,
            window: None,
        }
    }

    /// Keeps the state of the last `ticks` ticks for pages to go back to (0: none);
    /// [`DEFAULT_REWIND_WINDOW`] unless set. Set it before the first tick.
    pub fn rewind_window(mut self, ticks: usize) -> Self {
        self.keep = ticks;
        self.window = None;
        self
    }

    /// Applies the pages' blackboard edits, publishes the blackboards and the failure chain
    /// to the pages attached, and waits while a page has paused the run (applying edits
    /// made meanwhile). Returns at once when no page is attached.
    ///
    /// The tree's state is kept for pages to go back to; a run whose leaves act on a world
    /// (a simulator, a game) calls [`between_ticks_with`](Self::between_ticks_with) instead.
    /// Returns the tick the run goes on from when a page went back to it and stepped or
    /// continued from there (see [`between_ticks_with`](Self::between_ticks_with)).
    /// The scene is left as [`show_scene`](Self::show_scene) last set it.
    pub fn between_ticks<C>(&mut self, tree: &mut Tree<C>) -> Option<u64> {
        self.between(tree, &mut (), false)
    }

    /// [`between_ticks`](Self::between_ticks) for a run whose tree acts on `world`: the
    /// world is kept with the tree after each tick, restored with it when a page goes
    /// back, and its [scene](World::scene) shown beside the tree.
    ///
    /// When a page went back to tick T and then stepped or continued, the run forks: the
    /// ticks after T are forgotten, tree and world are as they were after T (with the
    /// edits made there), and `Some(T)` is returned: the caller's own tick count goes on
    /// from T.
    pub fn between_ticks_with<C, W: World<C>>(
        &mut self,
        tree: &mut Tree<C>,
        world: &mut W,
    ) -> Option<u64> {
        self.between(tree, world, true)
    }

    /// Both of the above: `scenes` says whether the world's scene is shown, so that a run
    /// without a world keeps the scene it shows by hand rather than blanking it each tick.
    fn between<C, W: World<C>>(
        &mut self,
        tree: &mut Tree<C>,
        world: &mut W,
        scenes: bool,
    ) -> Option<u64> {
        let keep = self.keep;
        let window = self
            .window
            .get_or_insert_with(|| Window::new(keep, world.codecs()));
        if let Some(shown) = self.hub.shown_now() {
            window.keep(tree, world, shown);
        }
        if scenes && self.hub.pages() > 0 {
            show_scene(&self.hub, world.scene(tree).as_ref());
        }
        let hub = Arc::clone(&self.hub);
        self.hub
            .between_ticks(tree, window.describe(), &mut |tree, travel: Travel| {
                let Some(now) = hub.shown_now() else {
                    return;
                };
                let gone = window
                    .target(travel, now.tick)
                    .and_then(|tick| window.go(tick, tree, world, || now));
                let shown = match gone {
                    Ok(shown) => shown.clone(),
                    Err(why) => {
                        hub.refuse(why);
                        return;
                    }
                };
                // The tick first: the scene goes out tagged with the tick shown.
                hub.show_kept(tree, shown);
                hub.set_rewind(window.describe());
                if scenes {
                    show_scene(&hub, world.scene(tree).as_ref());
                }
            });
        let fork = window.go_on(tree, world);
        if let Some(tick) = fork {
            self.hub.forces.fork(tick);
        }
        fork
    }

    /// The results forced by hand that applied since the last call, in order (a run
    /// logs them, as `neurotree run` prints `{"force":…}`), the last 4,096 of them; a
    /// fork forgets those after the tick it went back to.
    pub fn forced(&mut self) -> Vec<Forced> {
        self.hub.forces.take_log()
    }

    /// Shows `scene` beside the tree, in place of the last one (`None`: none). A run with
    /// a [`World`] has its scene shown by [`between_ticks_with`](Self::between_ticks_with).
    pub fn show_scene(&mut self, scene: Option<&Scene>) {
        if self.hub.pages() > 0 {
            show_scene(&self.hub, scene);
        }
    }

    /// The bytes the kept tree states take (the worlds' not counted): what the rewind
    /// window costs in memory, beside the worlds it keeps.
    pub fn rewind_bytes(&self) -> usize {
        self.window.as_ref().map_or(0, Window::bytes)
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
        // The kept states are of the tree before.
        if let Some(window) = &mut self.window {
            window.clear();
        }
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

/// Tells pages `scene`, or why it is not drawn (over the bounds of a scene or a message).
fn show_scene(hub: &Hub, scene: Option<&Scene>) {
    let text = match scene {
        None => Err(String::new()),
        Some(scene) => match scene.check() {
            Err(e) => Err(e.to_string()),
            Ok(()) => match serde_json::to_string(scene) {
                Ok(t) if t.len() <= MAX_SCENE_BYTES => Ok(t),
                Ok(t) => Err(format!(
                    "the scene is {} bytes of JSON; at most {MAX_SCENE_BYTES} are sent",
                    t.len()
                )),
                Err(e) => Err(e.to_string()),
            },
        },
    };
    hub.set_scene(text);
}

/// The id of a node by its index, for messages from pages (which may name any number).
fn node_in(index: u64, len: usize) -> Option<NodeId> {
    (index < len as u64).then_some(NodeId(index as u32))
}
