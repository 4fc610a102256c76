//! Text pictures of a tree with its statuses, in the manner of py_trees' ascii display.
//!
//! One line per node in pre-order, indented by depth with tree-drawing characters, each
//! line a status marker, the node's name, and its kind's type name when that differs from
//! the name:
//!
//! ```text
//! [R] robot (ReactiveSequence)
//! ├── [✓] battery_ok (Condition)
//! └── [R] patrol (Sequence)
//!     ├── [✓] Inverter
//!     │   └── [✗] stuck (Condition)
//!     └── [R] move (StatefulAction)
//! ```
//!
//! | status | ascii | unicode |
//! |---|---|---|
//! | Idle | `[ ]` | `[ ]` |
//! | Running | `[R]` | `[R]` |
//! | Success | `[S]` | `[✓]` |
//! | Failure | `[F]` | `[✗]` |
//! | Skipped | `[-]` | `[-]` |
//!
//! The ascii form draws branches with `+--`, `\--` and `|`; the unicode form with `├──`,
//! `└──` and `│`.
//!
//! A tree's *stored* statuses ([`render_ascii`], [`render_unicode`]) show where a run
//! stands between ticks, but a root that completes resets every node to Idle, so after a
//! tick that finished the tree they are all blank. To see what happened *during* a tick,
//! attach a [`LastTickStatuses`] observer and draw what it recorded with
//! [`render_statuses`]:
//!
//! ```
//! use neurotree::render::{render_statuses, LastTickStatuses};
//! use neurotree::{Blueprint, ManualClock, Status, Tree};
//!
//! let blueprint = Blueprint::<u32>::builder()
//!     .fallback("find", |f| {
//!         f.condition("is_zero", |n: &u32| *n == 0)
//!             .action("decrement", |n: &mut u32| { *n -= 1; Status::Success })
//!     })
//!     .build_shared()
//!     .unwrap();
//! let mut tree = Tree::with_clock(blueprint, ManualClock::new());
//! let seen = LastTickStatuses::new();
//! tree.set_observer(seen.clone());
//!
//! assert_eq!(tree.tick_once(&mut 3), Ok(Status::Success));
//! // Completed, so every stored status is Idle again...
//! assert!(neurotree::render::render_ascii(&tree).starts_with("[ ] find"));
//! // ...but the observer kept what each node did.
//! assert_eq!(
//!     render_statuses(tree.blueprint(), &seen.statuses(), false),
//!     "[S] find (Fallback)\n\
//!      +-- [F] is_zero (Condition)\n\
//!      \\-- [S] decrement (Action)\n"
//! );
//! ```

use std::fmt::Write as _;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use neurotree_core::{Blueprint, NodeId, NodeStatus, Observer, StatusChange, Tree};

/// Draws `tree`'s stored statuses with ascii characters (`+--`, `\--`, `|`, `[S]`, `[F]`).
pub fn render_ascii<C>(tree: &Tree<C>) -> String {
    render_statuses(tree.blueprint(), tree.statuses(), false)
}

/// Draws `tree`'s stored statuses with unicode characters (`├──`, `└──`, `│`, `[✓]`, `[✗]`).
pub fn render_unicode<C>(tree: &Tree<C>) -> String {
    render_statuses(tree.blueprint(), tree.statuses(), true)
}

/// Draws the nodes of `bp` with the given statuses, indexed by [`NodeId`] (nodes beyond the
/// end of `statuses` are drawn Idle). `unicode` picks the character set; every line, the
/// last included, ends with `\n`.
pub fn render_statuses<C>(bp: &Blueprint<C>, statuses: &[NodeStatus], unicode: bool) -> String {
    let glyphs = if unicode { &UNICODE } else { &ASCII };
    let mut out = String::new();
    // For each ancestor below the root, on the path to the current node: whether it has a
    // later sibling, so that its column carries on with a vertical bar.
    let mut open_columns: Vec<bool> = Vec::new();
    // Ids are in pre-order, so a node's ancestors have all been visited just before it.
    for id in bp.ids() {
        let depth = bp.depth(id) as usize;
        if let Some(parent) = bp.parent(id) {
            open_columns.truncate(depth - 2);
            for &open in &open_columns {
                out.push_str(if open { glyphs.pipe } else { glyphs.blank });
            }
            let is_last = bp.children(parent).last() == Some(&id);
            out.push_str(if is_last { glyphs.last } else { glyphs.branch });
            open_columns.push(!is_last);
        }
        let status = statuses.get(id.index()).copied().unwrap_or_default();
        out.push_str(glyphs.marker(status));
        out.push(' ');
        let name = bp.name(id);
        out.push_str(name);
        let type_name = bp.kind(id).type_name();
        if type_name != name {
            // Writing into a String cannot fail.
            let _ = write!(out, " ({type_name})");
        }
        out.push('\n');
    }
    out
}

/// The characters of one style of drawing.
struct Glyphs {
    branch: &'static str,
    last: &'static str,
    pipe: &'static str,
    blank: &'static str,
    markers: [&'static str; 5],
}

impl Glyphs {
    fn marker(&self, status: NodeStatus) -> &'static str {
        self.markers[match status {
            NodeStatus::Idle => 0,
            NodeStatus::Running => 1,
            NodeStatus::Success => 2,
            NodeStatus::Failure => 3,
            NodeStatus::Skipped => 4,
        }]
    }
}

const ASCII: Glyphs = Glyphs {
    branch: "+-- ",
    last: "\\-- ",
    pipe: "|   ",
    blank: "    ",
    markers: ["[ ]", "[R]", "[S]", "[F]", "[-]"],
};

const UNICODE: Glyphs = Glyphs {
    branch: "├── ",
    last: "└── ",
    pipe: "│   ",
    blank: "    ",
    markers: ["[ ]", "[R]", "[✓]", "[✗]", "[-]"],
};

/// An [`Observer`] that records, for each node, the last status other than Idle it had
/// during the latest tick: what a live view should show once the tick is over, since a
/// root that completes resets every stored status to Idle.
///
/// The rules, per pass of the root:
/// - when the pass starts, the record is reset to the stored statuses (a node that was
///   Running, or a completed child a Sequence will not re-tick, keeps showing that status
///   even if the pass does not change it);
/// - each change to Running, Success or Failure is recorded;
/// - a reset (a completed node back to Idle) keeps the completed status in the record;
/// - a halt (a Running node back to Idle) clears it, so a halted node shows Idle rather
///   than a run it did not finish.
///
/// [`Tree::tick_once`] may make several passes when a node asks to be woken (Repeat,
/// RetryUntilSuccessful, the Async composites); the record is then that of the last pass.
///
/// The observer is a handle: clones share one record, so keep a clone to read it while the
/// tree owns the other. Attach it to a fresh tree, or build it with
/// [`LastTickStatuses::for_tree`] for a tree that has already run. Recording allocates
/// only the first time it sees a node.
#[derive(Clone, Debug, Default)]
pub struct LastTickStatuses {
    record: Arc<Mutex<Record>>,
}

#[derive(Debug, Default)]
struct Record {
    /// A mirror of the tree's stored statuses, kept by the change events.
    stored: Vec<NodeStatus>,
    /// What the latest pass showed of each node.
    last_tick: Vec<NodeStatus>,
}

impl LastTickStatuses {
    /// A record for a tree that has not been ticked yet (every node Idle).
    pub fn new() -> Self {
        Self::default()
    }

    /// A record for `tree` as it stands now, for an observer attached after it ran.
    pub fn for_tree<C>(tree: &Tree<C>) -> Self {
        let record = Record {
            stored: tree.statuses().to_vec(),
            last_tick: tree.statuses().to_vec(),
        };
        Self {
            record: Arc::new(Mutex::new(record)),
        }
    }

    /// The recorded status of every node, indexed by [`NodeId`]; nodes never seen are
    /// left out of the end and read as Idle by [`render_statuses`].
    pub fn statuses(&self) -> Vec<NodeStatus> {
        self.lock().last_tick.clone()
    }

    /// The recorded status of one node.
    pub fn status(&self, id: NodeId) -> NodeStatus {
        self.lock()
            .last_tick
            .get(id.index())
            .copied()
            .unwrap_or_default()
    }

    /// Draws `bp` with the recorded statuses; see [`render_statuses`].
    pub fn render<C>(&self, bp: &Blueprint<C>, unicode: bool) -> String {
        render_statuses(bp, &self.lock().last_tick, unicode)
    }

    fn lock(&self) -> MutexGuard<'_, Record> {
        // A panic while holding the lock cannot leave the record half-written in a way
        // that matters for display, so a poisoned lock is still read.
        self.record.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl Observer for LastTickStatuses {
    fn on_tick_start(&mut self, _now: Duration) {
        let mut record = self.lock();
        let Record { stored, last_tick } = &mut *record;
        last_tick.clear();
        last_tick.extend_from_slice(stored);
    }

    fn on_status_change(&mut self, change: StatusChange) {
        let mut record = self.lock();
        let i = change.node.index();
        if record.stored.len() <= i {
            record.stored.resize(i + 1, NodeStatus::Idle);
            record.last_tick.resize(i + 1, NodeStatus::Idle);
        }
        record.stored[i] = change.to;
        match (change.from, change.to) {
            (NodeStatus::Running, NodeStatus::Idle) => record.last_tick[i] = NodeStatus::Idle,
            (_, NodeStatus::Idle | NodeStatus::Skipped) => {}
            (_, to) => record.last_tick[i] = to,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_core::{Builder, ManualClock, StatefulAction, Status};

    fn sample() -> std::sync::Arc<Blueprint<u32>> {
        Builder::<u32>::new()
            .sequence("root", |s| {
                s.fallback("choose", |f| {
                    f.condition("big", |n: &u32| *n > 10)
                        .inverter("", |i| i.condition("odd", |n: &u32| n % 2 == 1))
                })
                .always_success("")
                .action("done", |_: &mut u32| Status::Success)
            })
            .build_shared()
            .unwrap()
    }

    /// Running for `n` ticks, then Success; counts halts in the context.
    struct Work {
        left: u32,
        n: u32,
    }
    impl StatefulAction<u32> for Work {
        fn on_start(&mut self, h: &mut neurotree_core::Handle<'_, u32>) -> Status {
            self.left = self.n;
            self.on_running(h)
        }
        fn on_running(&mut self, _h: &mut neurotree_core::Handle<'_, u32>) -> Status {
            if self.left == 0 {
                return Status::Success;
            }
            self.left -= 1;
            Status::Running
        }
        fn on_halted(&mut self, h: &mut neurotree_core::Handle<'_, u32>) {
            *h.ctx_mut() += 100;
        }
    }

    #[test]
    fn ascii_drawing_of_stored_statuses() {
        let bp = sample();
        let statuses = [
            NodeStatus::Running,
            NodeStatus::Success,
            NodeStatus::Failure,
            NodeStatus::Success,
            NodeStatus::Failure,
            NodeStatus::Skipped,
        ];
        assert_eq!(
            render_statuses(&bp, &statuses, false),
            "[R] root (Sequence)\n\
             +-- [S] choose (Fallback)\n\
             |   +-- [F] big (Condition)\n\
             |   \\-- [S] Inverter\n\
             |       \\-- [F] odd (Condition)\n\
             +-- [-] AlwaysSuccess\n\
             \\-- [ ] done (Action)\n"
        );
    }

    #[test]
    fn unicode_drawing_of_stored_statuses() {
        let bp = sample();
        let statuses = [
            NodeStatus::Running,
            NodeStatus::Success,
            NodeStatus::Failure,
            NodeStatus::Success,
            NodeStatus::Failure,
        ];
        assert_eq!(
            render_statuses(&bp, &statuses, true),
            "[R] root (Sequence)\n\
             ├── [✓] choose (Fallback)\n\
             │   ├── [✗] big (Condition)\n\
             │   └── [✓] Inverter\n\
             │       └── [✗] odd (Condition)\n\
             ├── [ ] AlwaysSuccess\n\
             └── [ ] done (Action)\n"
        );
    }

    #[test]
    fn single_node_and_last_branch_columns_stay_blank() {
        let bp = Builder::<()>::new().always_failure("only").build().unwrap();
        assert_eq!(
            render_statuses(&bp, &[NodeStatus::Failure], true),
            "[✗] only (AlwaysFailure)\n"
        );
        let bp = Builder::<()>::new()
            .sequence("a", |s| {
                s.sequence("b", |s| s.sequence("c", |s| s.always_success("d")))
                    .always_success("e")
            })
            .build()
            .unwrap();
        assert_eq!(
            render_statuses(&bp, &[], false),
            "[ ] a (Sequence)\n\
             +-- [ ] b (Sequence)\n\
             |   \\-- [ ] c (Sequence)\n\
             |       \\-- [ ] d (AlwaysSuccess)\n\
             \\-- [ ] e (AlwaysSuccess)\n"
        );
    }

    #[test]
    fn tree_renderers_show_what_is_stored() {
        let bp = Builder::<u32>::new()
            .sequence("job", |s| {
                s.always_success("prepare")
                    .stateful("work", || Work { left: 0, n: 1 })
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut n = 0;
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        assert_eq!(
            render_unicode(&tree),
            "[R] job (Sequence)\n\
             ├── [✓] prepare (AlwaysSuccess)\n\
             └── [R] work (StatefulAction)\n"
        );
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Success));
        assert_eq!(
            render_ascii(&tree),
            "[ ] job (Sequence)\n\
             +-- [ ] prepare (AlwaysSuccess)\n\
             \\-- [ ] work (StatefulAction)\n"
        );
    }

    #[test]
    fn last_tick_keeps_completed_statuses_and_unchanged_ones() {
        let bp = Builder::<u32>::new()
            .sequence("job", |s| {
                s.always_success("prepare")
                    .stateful("work", || Work { left: 0, n: 2 })
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let seen = LastTickStatuses::new();
        tree.set_observer(seen.clone());
        let mut n = 0;
        let (r, s) = (NodeStatus::Running, NodeStatus::Success);
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        assert_eq!(seen.statuses(), [r, s, r]);
        // Nothing changes in the second tick: every status is carried over from the first.
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        assert_eq!(seen.statuses(), [r, s, r]);
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Success));
        assert_eq!(tree.statuses(), [NodeStatus::Idle; 3]);
        assert_eq!(seen.statuses(), [s, s, s]);
        assert_eq!(seen.status(NodeId(2)), s);
        assert_eq!(
            seen.render(tree.blueprint(), false),
            "[S] job (Sequence)\n\
             +-- [S] prepare (AlwaysSuccess)\n\
             \\-- [S] work (StatefulAction)\n"
        );
    }

    #[test]
    fn last_tick_clears_halted_nodes_and_resets_each_tick() {
        // The work runs while the guard holds; a failing guard halts it.
        let bp = Builder::<u32>::new()
            .reactive_sequence("guarded", |s| {
                s.condition("allowed", |n: &u32| *n == 0)
                    .stateful("work", || Work { left: 0, n: 5 })
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let seen = LastTickStatuses::new();
        tree.set_observer(seen.clone());
        let (i, r, s, f) = (
            NodeStatus::Idle,
            NodeStatus::Running,
            NodeStatus::Success,
            NodeStatus::Failure,
        );
        let mut n = 0;
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        assert_eq!(seen.statuses(), [r, s, r]);
        n = 1;
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Failure));
        assert_eq!(n, 101, "the work was halted");
        assert_eq!(seen.statuses(), [f, f, i]);
        // A new tick starts from the stored statuses (all Idle), not from the last record.
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Failure));
        assert_eq!(seen.statuses(), [f, f, i]);
    }

    #[test]
    fn attached_late_it_starts_from_the_stored_statuses() {
        let bp = Builder::<u32>::new()
            .sequence("job", |s| {
                s.always_success("prepare")
                    .stateful("work", || Work { left: 0, n: 3 })
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut n = 0;
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        let seen = LastTickStatuses::for_tree(&tree);
        tree.set_observer(seen.clone());
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        let (r, s) = (NodeStatus::Running, NodeStatus::Success);
        assert_eq!(seen.statuses(), [r, s, r]);
    }
}
