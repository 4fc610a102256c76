//! Per-node statistics: how often each node ran, what it returned, how long it was Running.

use std::fmt;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree_core::{Blueprint, NodeId, NodeStatus, Observer, StatusChange};

use super::lock;

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
    /// See [`Blueprint::subtree_ends`].
    subtree_ends: Vec<u32>,
    nodes: Vec<NodeStats>,
    /// The tree's stored statuses, as the changes told them.
    stored: Vec<NodeStatus>,
    running_since: Vec<Option<Duration>>,
    /// Nodes whose own tick began and whose result is not counted yet, each the parent
    /// (or an ancestor) of the next. A result that equals the stored status changes
    /// nothing, so it is read from `stored` when the next event shows the tick is over.
    pending: Vec<NodeId>,
    /// A pending node just went from Running to Idle: a skip if its skip event follows at
    /// once, a halt otherwise.
    running_to_idle: Option<NodeId>,
    last_seen: Duration,
}

impl Statistics {
    /// Statistics for the nodes of `blueprint`, all zero.
    pub fn new<C>(blueprint: &Blueprint<C>) -> Self {
        let n = blueprint.len();
        Self {
            state: Arc::new(Mutex::new(Stats {
                paths: blueprint.paths(),
                subtree_ends: blueprint.subtree_ends(),
                nodes: vec![NodeStats::default(); n],
                stored: vec![NodeStatus::Idle; n],
                running_since: vec![None; n],
                pending: Vec::new(),
                running_to_idle: None,
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

    fn is_in_subtree(&self, node: NodeId, of: NodeId) -> bool {
        of.0 <= node.0 && node.0 < self.subtree_ends[of.index()]
    }

    /// Counts the result of a node whose tick is over, read from its stored status.
    fn count_result(&mut self, id: NodeId) {
        let status = self.stored[id.index()];
        self.count(id, status);
    }

    fn count(&mut self, id: NodeId, status: NodeStatus) {
        let stats = &mut self.nodes[id.index()];
        match status {
            NodeStatus::Success => stats.successes += 1,
            NodeStatus::Failure => stats.failures += 1,
            NodeStatus::Idle | NodeStatus::Running | NodeStatus::Skipped => {}
        }
    }

    /// Ends the ticks of the pending nodes for which `keep` is false, innermost first.
    fn end_ticks_until(&mut self, keep: impl Fn(&Self, NodeId) -> bool) {
        while let Some(&top) = self.pending.last() {
            if keep(self, top) {
                break;
            }
            self.pending.pop();
            self.count_result(top);
        }
    }

    /// Settles a Running-to-Idle change that was not followed by its skip: a halt.
    fn settle(&mut self) {
        if let Some(id) = self.running_to_idle.take() {
            self.nodes[id.index()].halts += 1;
        }
    }

    fn knows(&self, id: NodeId) -> bool {
        id.index() < self.nodes.len()
    }
}

impl Observer for Statistics {
    fn on_tick_start(&mut self, now: Duration) {
        let mut state = lock(&self.state);
        state.settle();
        state.end_ticks_until(|_, _| false);
        state.last_seen = now;
    }

    fn on_node_tick(&mut self, node: NodeId) {
        let mut state = lock(&self.state);
        if !state.knows(node) {
            return;
        }
        state.settle();
        // A node ticked again within the same pass (a retry) ended its previous tick.
        state.end_ticks_until(|s, p| p != node && s.is_in_subtree(node, p));
        state.nodes[node.index()].ticks += 1;
        state.pending.push(node);
    }

    fn on_status_change(&mut self, c: StatusChange) {
        let mut state = lock(&self.state);
        if !state.knows(c.node) {
            return;
        }
        state.settle();
        state.end_ticks_until(|s, p| s.is_in_subtree(c.node, p));
        let i = c.node.index();
        let pending = state.pending.last() == Some(&c.node);
        match (c.from, c.to) {
            // Its own result: counted when its tick is over, in case it changes again
            // (a control marks itself Running before it ticks its children).
            (_, NodeStatus::Running | NodeStatus::Success | NodeStatus::Failure) if pending => {}
            (NodeStatus::Running, NodeStatus::Idle) if pending => {
                state.pending.pop();
                state.running_to_idle = Some(c.node);
            }
            // Returned its result and was reset at once (the root, by the tree).
            (from, NodeStatus::Idle) if pending => {
                state.pending.pop();
                state.count(c.node, from);
            }
            (NodeStatus::Running, NodeStatus::Idle) => state.nodes[i].halts += 1,
            // Decided by a precondition, without a tick.
            (_, to) => state.count(c.node, to),
        }
        if c.to == NodeStatus::Running && c.from != NodeStatus::Running {
            state.running_since[i] = Some(c.at);
        } else if c.from == NodeStatus::Running && c.to != NodeStatus::Running {
            if let Some(since) = state.running_since[i].take() {
                state.nodes[i].running += c.at.saturating_sub(since);
            }
        }
        state.stored[i] = c.to;
        state.last_seen = c.at;
    }

    fn on_node_skipped(&mut self, node: NodeId) {
        let mut state = lock(&self.state);
        if !state.knows(node) {
            return;
        }
        if state.running_to_idle != Some(node) {
            state.settle();
        }
        // Its Running-to-Idle change just before was the skip, not a halt.
        state.running_to_idle = None;
        state.end_ticks_until(|s, p| s.is_in_subtree(node, p));
        if state.pending.last() == Some(&node) {
            state.pending.pop();
        }
        state.nodes[node.index()].skips += 1;
    }

    fn on_tick_end(&mut self, _status: NodeStatus, now: Duration) {
        let mut state = lock(&self.state);
        state.settle();
        state.end_ticks_until(|_, _| false);
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
