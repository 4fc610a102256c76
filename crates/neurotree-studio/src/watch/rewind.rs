//! Going back in a watched run: a state kept after every tick, in a bounded window, so that
//! a paused run can be shown as it was at an earlier tick, and forked from there.
//!
//! The tree's own state is saved with [`Tree::save_state_with`] into a [`Snapshots`]; what
//! the tree acts on (a simulated robot, a game level, the run's clock and counters) is
//! saved beside it by the run's [`World`]. Going back restores both; stepping or
//! continuing from a past tick drops the later ones, and the run goes on from there.

use std::any::Any;
use std::collections::VecDeque;

use neurotree_core::state::{SaveError, Snapshots, StateCodecs};
use neurotree_core::{NodeStatus, Tree};
use neurotree_toolkit::scene::Scene;
use serde_json::{json, Value};

/// The ticks a watched run keeps unless told otherwise ([`Watch::rewind_window`]).
///
/// [`Watch::rewind_window`]: crate::Watch::rewind_window
pub const DEFAULT_REWIND_WINDOW: usize = 300;

/// What a watched run keeps of each tick beside its tree's state, and what it draws beside
/// the tree: the world the tree acts on.
///
/// Going back to a tick restores the world ([`restore`](Self::restore)) and then the tree,
/// so a world that owns the tree's clock sets it there, and the tree's timers resume with
/// what they had left. `()` is the world of a run whose leaves act on nothing kept.
///
/// ```
/// use neurotree_studio::World;
/// use neurotree_toolkit::scene::{Scene, Style};
/// use neurotree_toolkit::Tree;
///
/// /// A robot on a line.
/// struct Line { x: f64 }
///
/// impl<C> World<C> for Line {
///     type Saved = f64;
///     fn save(&self, _: &Tree<C>) -> Result<f64, String> {
///         Ok(self.x)
///     }
///     fn restore(&mut self, saved: &f64) {
///         self.x = *saved;
///     }
///     fn scene(&self, _: &Tree<C>) -> Option<Scene> {
///         let mut scene = Scene::new([0.0, -1.0], [10.0, 1.0]);
///         scene.circle("robot", [self.x, 0.0], 0.5, Style::fill("#36c"));
///         Some(scene)
///     }
/// }
/// ```
pub trait World<C> {
    /// The world as of one tick.
    type Saved: Send + 'static;

    /// The world now, after a tick; `Err` with the reason when it cannot be kept now (the
    /// run's pages then cannot go back from this tick).
    fn save(&self, tree: &Tree<C>) -> Result<Self::Saved, String>;

    /// Puts the world back as `saved` has it (before the tree is restored).
    fn restore(&mut self, saved: &Self::Saved);

    /// The codecs the tree's blackboard values are saved with: add the types the leaves
    /// write ([`StateCodecs::with`]). Asked once.
    fn codecs(&self) -> StateCodecs {
        StateCodecs::new()
    }

    /// The scene to show beside the tree, as of now; `None` shows none.
    fn scene(&self, _tree: &Tree<C>) -> Option<Scene> {
        None
    }
}

impl<C> World<C> for () {
    type Saved = ();
    fn save(&self, _: &Tree<C>) -> Result<(), String> {
        Ok(())
    }
    fn restore(&mut self, _: &()) {}
}

/// Why a tick could not be kept, for the title of the page's back control. A stateful
/// node that saves no state while it runs (a ROS 2 action whose goal is on its server) is
/// said to be running, as a running async action is: the run can go back from the ticks
/// where it is not.
fn why_unsaved<C>(tree: &Tree<C>, e: &SaveError) -> String {
    match e {
        SaveError::Unsaveable { node, path, kind } if tree.status(*node) == NodeStatus::Running => {
            format!(
                "{path}: this {kind} is running, and keeps no state that can be saved while \
                 it runs; the run can go back from a tick where it is not running"
            )
        }
        other => other.to_string(),
    }
}

/// A way through the kept ticks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Travel {
    Back,
    Forward,
}

/// What a page is shown of a kept tick besides what the restored tree says.
#[derive(Clone)]
pub(crate) struct Shown {
    pub tick: u64,
    pub statuses: Box<[u8]>,
    /// The nodes scored then, `(id, bits of the score)` (none for most trees).
    pub scores: Box<[(usize, u64)]>,
    pub failure: Value,
}

/// One tick's state beside the tree's: the world's, and what pages were shown.
struct Kept {
    world: Box<dyn Any + Send>,
    shown: Shown,
}

/// The kept ticks of a run, oldest first, and where in them the run stands.
pub(crate) struct Window {
    keep: usize,
    snapshots: Snapshots,
    kept: VecDeque<Kept>,
    /// The past tick the run stands at, when it went back.
    at: Option<u64>,
    /// Why the latest tick could not be kept: going back from it would lose it.
    blocked: Option<String>,
}

impl Window {
    /// A window of `keep` ticks (none when 0), saving blackboard values with `codecs`.
    pub fn new(keep: usize, codecs: StateCodecs) -> Self {
        Self {
            keep,
            snapshots: Snapshots::new(1, keep).with_codecs(codecs),
            kept: VecDeque::new(),
            at: None,
            blocked: None,
        }
    }

    /// Keeps the state after tick `shown.tick` (replacing one kept for that tick or later).
    pub fn keep<C, W: World<C>>(&mut self, tree: &Tree<C>, world: &W, shown: Shown) {
        if self.keep == 0 {
            return;
        }
        let tick = shown.tick;
        let world = match world.save(tree) {
            Ok(world) => world,
            Err(why) => {
                self.blocked = Some(why);
                return;
            }
        };
        match tick.checked_sub(1) {
            Some(before) => self.forget_after(before),
            None => {
                self.snapshots.clear();
                self.kept.clear();
            }
        }
        if let Err(e) = self.snapshots.after_tick(tree, tick) {
            self.blocked = Some(why_unsaved(tree, &e));
            return;
        }
        self.blocked = None;
        self.kept.push_back(Kept {
            world: Box::new(world),
            shown,
        });
        // The snapshots dropped their oldest past the window: so do these.
        while self.kept.len() > self.snapshots.len() {
            self.kept.pop_front();
        }
    }

    fn forget_after(&mut self, tick: u64) {
        self.snapshots.forget_after(tick);
        while self.kept.back().is_some_and(|k| k.shown.tick > tick) {
            self.kept.pop_back();
        }
    }

    /// The tick to go to from `now` (the latest tick, unless the run went back), or why
    /// there is none.
    pub fn target(&self, travel: Travel, now: u64) -> Result<u64, String> {
        if self.keep == 0 {
            return Err("this run keeps no ticks to go back to (its rewind window is 0)".into());
        }
        if let (Some(why), None) = (&self.blocked, self.at) {
            return Err(format!("the run cannot go back from this tick: {why}"));
        }
        let from = self.at.unwrap_or(now);
        let mut ticks = self.kept.iter().map(|k| k.shown.tick);
        let found = match travel {
            Travel::Back => ticks.rev().find(|t| *t < from),
            Travel::Forward => ticks.find(|t| *t > from),
        };
        found.ok_or_else(|| match travel {
            Travel::Back => format!(
                "tick {from} is the oldest kept: the run keeps its last {} ticks \
                 (--rewind-window)",
                self.keep
            ),
            Travel::Forward => format!("tick {from} is the latest"),
        })
    }

    /// Restores tick `tick` (one [`target`](Self::target) gave) into `world` and `tree`;
    /// what pages are to be shown of it. Leaving the latest tick keeps it again first
    /// (`latest` says what pages are shown of it), with the edits made since it was kept.
    pub fn go<C, W: World<C>>(
        &mut self,
        tick: u64,
        tree: &mut Tree<C>,
        world: &mut W,
        latest: impl FnOnce() -> Shown,
    ) -> Result<&Shown, String> {
        if self.at.is_none() {
            self.keep(tree, world, latest());
        }
        let not_kept = || format!("tick {tick} is not kept");
        let index = self
            .kept
            .iter()
            .position(|k| k.shown.tick == tick)
            .ok_or_else(not_kept)?;
        let (_, bytes) = self
            .snapshots
            .at_or_before(tick)
            .filter(|(t, _)| *t == tick)
            .ok_or_else(not_kept)?;
        let saved = self.kept[index]
            .world
            .downcast_ref::<W::Saved>()
            .ok_or("the run's world is not the one it kept")?;
        // The world first: it may own the tree's clock, which the tree's timers are
        // restored against. A state this window saved from this tree is not refused.
        world.restore(saved);
        tree.restore_state_with(bytes, self.snapshots.codecs())
            .map_err(|e| e.to_string())?;
        self.at = (Some(tick) != self.newest()).then_some(tick);
        Ok(&self.kept[index].shown)
    }

    /// The latest kept tick.
    fn newest(&self) -> Option<u64> {
        self.kept.back().map(|k| k.shown.tick)
    }

    /// The run goes on from where it stands: when that is a past tick, the ticks after it
    /// are dropped, it is kept again as the fork has it (with the edits made there), and
    /// it is returned.
    pub fn go_on<C, W: World<C>>(&mut self, tree: &Tree<C>, world: &W) -> Option<u64> {
        let at = self.at.take()?;
        self.forget_after(at);
        if let Some(kept) = self.kept.back() {
            let shown = kept.shown.clone();
            self.keep(tree, world, shown);
        }
        Some(at)
    }

    /// Forgets every kept tick (the tree was replaced).
    pub fn clear(&mut self) {
        self.snapshots.clear();
        self.kept.clear();
        self.at = None;
        self.blocked = None;
    }

    /// The window as pages are told it (PROTOCOL.md, "Rewind").
    pub fn describe(&self) -> Value {
        json!({
            "window": self.keep,
            "oldest": self.kept.front().map(|k| k.shown.tick),
            "newest": self.newest(),
            "at": self.at,
            "blocked": self.blocked,
        })
    }

    /// The bytes the kept tree states and shown statuses take (not the worlds').
    pub fn bytes(&self) -> usize {
        self.snapshots.bytes()
            + self
                .kept
                .iter()
                .map(|k| k.shown.statuses.len() + 16 * k.shown.scores.len())
                .sum::<usize>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_toolkit::{Registry, Status, XmlLoader};
    use std::sync::Arc;

    /// A world that moves 10 a tick.
    struct Odometer(u64);

    impl<C> World<C> for Odometer {
        type Saved = u64;
        fn save(&self, _: &Tree<C>) -> Result<u64, String> {
            Ok(self.0)
        }
        fn restore(&mut self, saved: &u64) {
            self.0 = *saved;
        }
    }

    fn tree(xml_leaf: &str, registry: &Registry<()>) -> Tree<()> {
        let mut loader = XmlLoader::new(registry);
        let xml = format!(
            r#"<root BTCPP_format="4"><BehaviorTree ID="M">
                 <Sequence><Script code="count += 1"/>{xml_leaf}</Sequence>
               </BehaviorTree></root>"#
        );
        loader.load_str(&xml, "m.xml").unwrap();
        let mut tree = Tree::new(Arc::new(loader.build_main().unwrap()));
        tree.blackboard_mut().set("count", 0i64).unwrap();
        tree
    }

    fn shown(tick: u64) -> Shown {
        Shown {
            tick,
            statuses: vec![tick as u8].into(),
            scores: Box::new([]),
            failure: Value::Null,
        }
    }

    fn count(tree: &Tree<()>) -> i64 {
        tree.blackboard().get_exact::<i64>("count").unwrap()
    }

    /// Ticks 1 to `to`, keeping each (and tick 0).
    fn run(tree: &mut Tree<()>, world: &mut Odometer, window: &mut Window, to: u64) {
        window.keep(tree, world, shown(0));
        for tick in 1..=to {
            assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
            world.0 += 10;
            window.keep(tree, world, shown(tick));
        }
    }

    #[test]
    fn back_and_forth_restores_tree_and_world_and_a_step_from_the_past_forks() {
        let registry = Registry::new();
        let mut tree = tree("<AlwaysSuccess/>", &registry);
        let mut world = Odometer(0);
        let mut window = Window::new(3, StateCodecs::new());
        run(&mut tree, &mut world, &mut window, 5);
        let d = window.describe();
        assert_eq!(
            (d["oldest"].clone(), d["newest"].clone()),
            (json!(3), json!(5))
        );
        assert_eq!(d["at"], Value::Null);

        assert_eq!(
            window.target(Travel::Forward, 5),
            Err("tick 5 is the latest".into())
        );
        assert_eq!(window.target(Travel::Back, 5), Ok(4));
        let at = window.go(4, &mut tree, &mut world, || shown(5)).unwrap();
        assert_eq!((at.tick, &*at.statuses), (4, &[4u8][..]));
        assert_eq!((count(&tree), world.0), (4, 40));
        assert_eq!(window.target(Travel::Back, 5), Ok(3));
        window.go(3, &mut tree, &mut world, || shown(5)).unwrap();
        assert_eq!((count(&tree), world.0), (3, 30));
        let refused = window.target(Travel::Back, 5).unwrap_err();
        assert_eq!(
            refused,
            "tick 3 is the oldest kept: the run keeps its last 3 ticks (--rewind-window)"
        );
        // Forward to 4, an edit there, and a step: the fork.
        assert_eq!(window.target(Travel::Forward, 5), Ok(4));
        window.go(4, &mut tree, &mut world, || shown(5)).unwrap();
        assert_eq!(window.describe()["at"], 4);
        tree.blackboard_mut().set("count", 100i64).unwrap();
        assert_eq!(window.go_on(&tree, &world), Some(4));
        assert_eq!(window.describe()["newest"], 4);
        assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
        world.0 += 10;
        window.keep(&tree, &world, shown(5));
        assert_eq!((count(&tree), world.0), (101, 50));
        // The fork's tick 5 is the one kept: back to 4 and forward again shows it.
        window.go(4, &mut tree, &mut world, || shown(5)).unwrap();
        assert_eq!(count(&tree), 100);
        window.go(5, &mut tree, &mut world, || shown(5)).unwrap();
        assert_eq!((count(&tree), world.0), (101, 50));
        assert_eq!(
            window.go_on(&tree, &world),
            None,
            "back at the newest tick: no fork"
        );
        assert!(window.bytes() > 0);
    }

    #[test]
    fn leaving_the_newest_tick_keeps_the_edits_made_there() {
        let registry = Registry::new();
        let mut tree = tree("<AlwaysSuccess/>", &registry);
        let mut world = Odometer(0);
        let mut window = Window::new(10, StateCodecs::new());
        run(&mut tree, &mut world, &mut window, 2);
        tree.blackboard_mut().set("count", 50i64).unwrap();
        window.go(1, &mut tree, &mut world, || shown(2)).unwrap();
        assert_eq!(count(&tree), 1);
        window.go(2, &mut tree, &mut world, || shown(2)).unwrap();
        assert_eq!(count(&tree), 50);
        assert_eq!(window.go_on(&tree, &world), None);
    }

    #[test]
    fn a_running_async_action_blocks_going_back_and_says_so() {
        let mut registry = Registry::new();
        registry
            .register_async("Forever", vec![], |_| std::future::pending::<Status>())
            .unwrap();
        let mut tree = tree("<Forever/>", &registry);
        let world = Odometer(0);
        let mut window = Window::new(10, StateCodecs::new());
        window.keep(&tree, &world, shown(0));
        assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
        window.keep(&tree, &world, shown(1));
        let why = window.target(Travel::Back, 1).unwrap_err();
        assert!(
            why.starts_with("the run cannot go back from this tick: ") && why.contains("Forever"),
            "{why}"
        );
        assert_eq!(window.describe()["newest"], 0);
        assert!(window.describe()["blocked"].is_string());
    }

    #[test]
    fn a_window_of_zero_keeps_nothing() {
        let registry = Registry::new();
        let mut tree = tree("<AlwaysSuccess/>", &registry);
        let mut world = Odometer(0);
        let mut window = Window::new(0, StateCodecs::new());
        run(&mut tree, &mut world, &mut window, 3);
        assert_eq!(window.bytes(), 0);
        assert!(window
            .target(Travel::Back, 3)
            .unwrap_err()
            .contains("rewind window is 0"));
    }
}
