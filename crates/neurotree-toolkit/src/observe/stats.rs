//! Per-node statistics: how often each node ran, what it returned, how long it was Running.

use std::fmt;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree_core::{Blueprint, NodeId, NodeStatus, Observer, StatusChange};

use super::lock;
use super::outcome::{Outcome, OutcomeReader};

/// What one node did, as [`Statistics`] counted it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NodeStats {
    /// Its own tick ran (a precondition that decided instead does not count).
    pub ticks: u64,
    /// It returned Success (from its tick, or from `_successIf`).
    pub successes: u64,
    /// It returned Failure (from its tick, or from `_failureIf`).
    pub failures: u64,
    /// It returned Skipped.
    pub skips: u64,
    /// It was halted while Running.
    pub halts: u64,
    /// Time spent Running, on the tree's clock; a node still Running counts up to the
    /// latest moment the observer saw.
    pub running: Duration,
}

/// Counts, per node, ticks, successes, failures, skips, halts and time spent Running.
///
/// Results are counted per return, not per status change: a condition that a
/// ReactiveSequence re-ticks and that succeeds on each of five ticks counts five
/// successes, although its stored status changed once. Running time is measured on the
/// tree's clock, from the change to Running to the change away from it (so with a
/// [`ManualClock`](crate::ManualClock) it is exact and repeatable).
///
/// A handle: keep a clone to query it by [`NodeId`] or by path while the tree owns the
/// other, or print it as a table:
///
/// ```
/// use std::time::Duration;
/// use neurotree::observe::Statistics;
/// use neurotree::{Blueprint, ManualClock, Status, Tree};
///
/// let blueprint = Blueprint::<()>::builder()
///     .sequence("job", |s| s.always_success("prepare").sleep("wait", Duration::from_millis(200)))
///     .build_shared()
///     .unwrap();
/// let clock = ManualClock::new();
/// let mut tree = Tree::with_clock(blueprint.clone(), clock.clone());
/// let stats = Statistics::new(&blueprint);
/// tree.set_observer(stats.clone());
/// while tree.tick_once(&mut ()) == Ok(Status::Running) {
///     clock.advance(Duration::from_millis(100));
/// }
/// let wait = stats.by_path("job/wait").unwrap();
/// assert_eq!((wait.ticks, wait.successes), (3, 1));
/// assert_eq!(wait.running, Duration::from_millis(200));
/// assert_eq!(
///     stats.to_string(),
///     "node         ticks  successes  failures  skips  halts  running\n\
///      job              3          1         0      0      0   0.200s\n\
///      job/prepare      1          1         0      0      0   0.000s\n\
///      job/wait         3          1         0      0      0   0.200s\n"
/// );
/// ```
#[derive(Clone)]
pub struct Statistics {
    state: Arc<Mutex<Stats>>,
}

struct Stats {
    paths: Vec<String>,
    nodes: Vec<NodeStats>,
    outcomes: OutcomeReader,
    running_since: Vec<Option<Duration>>,
    last_seen: Duration,
}

impl Statistics {
    /// Statistics for the nodes of `blueprint`, all zero.
    pub fn new<C>(blueprint: &Blueprint<C>) -> Self {
        let n = blueprint.len();
        Self {
            state: Arc::new(Mutex::new(Stats {
                paths: blueprint.paths(),
                nodes: vec![NodeStats::default(); n],
                outcomes: OutcomeReader::new(blueprint),
                running_since: vec![None; n],
                last_seen: Duration::ZERO,
            })),
        }
    }

    /// The statistics of one node, or `None` if the blueprint has no such node.
    pub fn node(&self, id: NodeId) -> Option<NodeStats> {
        let state = lock(&self.state);
        (id.index() < state.nodes.len()).then(|| state.with_open_time(id.index()))
    }

    /// The statistics of the first node (in pre-order) whose path is `path`.
    pub fn by_path(&self, path: &str) -> Option<NodeStats> {
        let state = lock(&self.state);
        let i = state.paths.iter().position(|p| p == path)?;
        Some(state.with_open_time(i))
    }

    /// Every node's statistics, indexed by [`NodeId`].
    pub fn nodes(&self) -> Vec<NodeStats> {
        let state = lock(&self.state);
        (0..state.nodes.len())
            .map(|i| state.with_open_time(i))
            .collect()
    }
}

impl Stats {
    fn with_open_time(&self, i: usize) -> NodeStats {
        let mut stats = self.nodes[i];
        if let Some(since) = self.running_since[i] {
            stats.running += self.last_seen.saturating_sub(since);
        }
        stats
    }

    /// Runs `read` on the outcome reader, counting each outcome it tells of.
    fn read(&mut self, read: impl FnOnce(&mut OutcomeReader, &mut dyn FnMut(NodeId, Outcome))) {
        let Stats {
            outcomes, nodes, ..
        } = self;
        read(outcomes, &mut |id, outcome| {
            let stats = &mut nodes[id.index()];
            match outcome {
                Outcome::Success => stats.successes += 1,
                Outcome::Failure => stats.failures += 1,
                Outcome::Halted => stats.halts += 1,
                Outcome::Skipped => stats.skips += 1,
                Outcome::Running => {}
            }
        });
    }
}

impl Observer for Statistics {
    fn on_tick_start(&mut self, now: Duration) {
        let mut state = lock(&self.state);
        state.read(|r, seen| r.pass_boundary(seen));
        state.last_seen = now;
    }

    fn on_node_tick(&mut self, node: NodeId) {
        let mut state = lock(&self.state);
        if !state.outcomes.knows(node) {
            return;
        }
        state.read(|r, seen| r.node_tick(node, seen));
        state.nodes[node.index()].ticks += 1;
    }

    fn on_status_change(&mut self, c: StatusChange) {
        let mut state = lock(&self.state);
        if !state.outcomes.knows(c.node) {
            return;
        }
        state.read(|r, seen| r.status_change(c, seen));
        let i = c.node.index();
        if c.to == NodeStatus::Running && c.from != NodeStatus::Running {
            state.running_since[i] = Some(c.at);
        } else if c.from == NodeStatus::Running
            && c.to != NodeStatus::Running
            && let Some(since) = state.running_since[i].take()
        {
            state.nodes[i].running += c.at.saturating_sub(since);
        }
        state.last_seen = c.at;
    }

    fn on_node_skipped(&mut self, node: NodeId) {
        let mut state = lock(&self.state);
        if !state.outcomes.knows(node) {
            return;
        }
        state.read(|r, seen| r.node_skipped(node, seen));
    }

    fn on_tick_end(&mut self, _status: NodeStatus, now: Duration) {
        let mut state = lock(&self.state);
        state.read(|r, seen| r.pass_boundary(seen));
        state.last_seen = now;
    }
}

/// An aligned table, one line per node in pre-order: path, ticks, successes, failures,
/// skips, halts, and the time Running in seconds.
impl fmt::Display for Statistics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        const HEADERS: [&str; 7] = [
            "node",
            "ticks",
            "successes",
            "failures",
            "skips",
            "halts",
            "running",
        ];
        let state = lock(&self.state);
        let rows: Vec<[String; 7]> = (0..state.nodes.len())
            .map(|i| {
                let s = state.with_open_time(i);
                [
                    state.paths[i].clone(),
                    s.ticks.to_string(),
                    s.successes.to_string(),
                    s.failures.to_string(),
                    s.skips.to_string(),
                    s.halts.to_string(),
                    format!("{}.{:03}s", s.running.as_secs(), s.running.subsec_millis()),
                ]
            })
            .collect();
        let mut widths = HEADERS.map(str::len);
        for row in &rows {
            for (w, cell) in widths.iter_mut().zip(row) {
                *w = (*w).max(cell.chars().count());
            }
        }
        let header = HEADERS.map(String::from);
        for row in std::iter::once(&header).chain(&rows) {
            write!(f, "{:<w$}", row[0], w = widths[0])?;
            for (cell, w) in row.iter().zip(widths).skip(1) {
                write!(f, "  {cell:>w$}")?;
            }
            writeln!(f)?;
        }
        Ok(())
    }
}
