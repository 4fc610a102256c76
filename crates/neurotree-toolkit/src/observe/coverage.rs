//! Coverage of a tree under test: which nodes a run reached and which of their possible
//! outcomes it saw.

use std::fmt;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree_core::nodes::built_in::Outcomes;
use neurotree_core::{Blueprint, NodeId, NodeKind, NodeStatus, Observer, StatusChange};

use super::lock;
use super::outcome::{Outcome, OutcomeReader, OutcomeSet};

/// Records, per node, whether it was ticked and which [`Outcome`]s it was seen with:
/// Success, Failure, Running (its tick returned Running), Halted (it went from Running back
/// to Idle without completing) and Skipped. [`report`](Coverage::report) compares them with
/// the outcomes each node could have ([`possible_outcomes`]).
///
/// Outcomes are read as [`Statistics`](super::Statistics) reads them, so a node counted
/// with a halt there is Halted here. A handle: clones share one record, so keep a clone
/// while the tree owns the other. Attach it to a fresh tree; it costs nothing when not
/// attached.
///
/// ```
/// use neurotree::observe::{Coverage, Outcome, OutcomeSet};
/// use neurotree::{Blueprint, ManualClock, Status, Tree};
///
/// let blueprint = Blueprint::<bool>::builder()
///     .fallback("find", |f| {
///         f.condition("near", |near: &bool| *near)
///             .action("walk", |_: &mut bool| Status::Success)
///     })
///     .build_shared()
///     .unwrap();
/// let mut tree = Tree::with_clock(blueprint.clone(), ManualClock::new());
/// let coverage = Coverage::new(&blueprint);
/// tree.set_observer(coverage.clone());
/// assert_eq!(tree.tick_once(&mut true), Ok(Status::Success));
///
/// let report = coverage.report(&blueprint);
/// assert_eq!(report.node_by_path("find/near").unwrap().seen, OutcomeSet::of(&[Outcome::Success]));
/// assert!(!report.node_by_path("find/walk").unwrap().reached);
/// assert_eq!(
///     report.to_string(),
///     "coverage: 2 of 6 outcomes (33.3%), 2 of 3 nodes reached\n\
///      node       type       seen     not seen\n\
///      find       Fallback   success  failure\n\
///      find/near  Condition  success  failure\n\
///      find/walk  Action     -        never reached\n"
/// );
/// ```
#[derive(Clone)]
pub struct Coverage {
    state: Arc<Mutex<Record>>,
}

struct Record {
    outcomes: OutcomeReader,
    seen: Vec<OutcomeSet>,
    ticked: Vec<bool>,
}

impl Coverage {
    /// A record for the nodes of `blueprint`, none reached.
    pub fn new<C>(blueprint: &Blueprint<C>) -> Self {
        Self {
            state: Arc::new(Mutex::new(Record {
                outcomes: OutcomeReader::new(blueprint),
                seen: vec![OutcomeSet::NONE; blueprint.len()],
                ticked: vec![false; blueprint.len()],
            })),
        }
    }

    /// The outcomes seen so far of every node, indexed by [`NodeId`].
    pub fn seen(&self) -> Vec<OutcomeSet> {
        lock(&self.state).seen.clone()
    }

    /// What the run covered of `blueprint`, the blueprint this record was made for.
    pub fn report<C>(&self, blueprint: &Blueprint<C>) -> CoverageReport {
        let state = lock(&self.state);
        let reached: Vec<bool> = state
            .ticked
            .iter()
            .zip(&state.seen)
            .map(|(&ticked, seen)| ticked || !seen.is_empty())
            .collect();
        CoverageReport::new(blueprint, &state.seen, &reached)
    }
}

impl Record {
    fn read(&mut self, read: impl FnOnce(&mut OutcomeReader, &mut dyn FnMut(NodeId, Outcome))) {
        let Record { outcomes, seen, .. } = self;
        read(outcomes, &mut |id, outcome| {
            seen[id.index()] = seen[id.index()].with(outcome);
        });
    }
}

impl Observer for Coverage {
    fn on_tick_start(&mut self, _now: Duration) {
        lock(&self.state).read(|r, seen| r.pass_boundary(seen));
    }

    fn on_node_tick(&mut self, node: NodeId) {
        let mut state = lock(&self.state);
        if state.outcomes.knows(node) {
            state.read(|r, seen| r.node_tick(node, seen));
            state.ticked[node.index()] = true;
        }
    }

    fn on_status_change(&mut self, c: StatusChange) {
        let mut state = lock(&self.state);
        if state.outcomes.knows(c.node) {
            state.read(|r, seen| r.status_change(c, seen));
        }
    }

    fn on_node_skipped(&mut self, node: NodeId) {
        let mut state = lock(&self.state);
        if state.outcomes.knows(node) {
            state.read(|r, seen| r.node_skipped(node, seen));
        }
    }

    fn on_tick_end(&mut self, _status: NodeStatus, _now: Duration) {
        lock(&self.state).read(|r, seen| r.pass_boundary(seen));
    }
}

/// The outcomes node `id` of `blueprint` can have, by its kind and its preconditions; what
/// a [`CoverageReport`] counts as possible:
///
/// - Success and Failure for every node, except that AlwaysSuccess, ForceSuccess, Script,
///   SetBlackboard and UnsetBlackboard cannot fail and AlwaysFailure, ForceFailure,
///   KeepRunningUntilFailure cannot succeed (a `_successIf` or `_failureIf` precondition
///   adds the one it decides).
/// - Running and Halted for a node that can be Running: a leaf that runs over ticks
///   (Sleep, WaitValueUpdate, a stateful, async, custom or mock leaf; never a condition,
///   Script or other sync action), a
///   node that returns Running by itself (Delay, KeepRunningUntilFailure, Repeat,
///   RetryUntilSuccessful, AsyncSequence, AsyncFallback, a custom control), or any other
///   control, decorator or SubTree with such a node below it.
/// - Skipped for a node with a `_skipIf` or `_while` precondition, a RunOnce that may
///   skip after its run, a SkipUnlessUpdated, and a Precondition whose `else` is SKIPPED. A control whose children were all skipped also returns Skipped;
///   that is seen and shown but not counted as possible.
pub fn possible_outcomes<C>(blueprint: &Blueprint<C>, id: NodeId) -> OutcomeSet {
    possible_all(blueprint)[id.index()]
}

/// [`possible_outcomes`] of every node, indexed by [`NodeId`].
fn possible_all<C>(blueprint: &Blueprint<C>) -> Vec<OutcomeSet> {
    use Outcome::{Failure, Halted, Running, Skipped, Success};
    let n = blueprint.len();
    // What each node returns by itself, where its kind or type says so.
    let own: Vec<Option<Outcomes>> = blueprint
        .ids()
        .map(|id| {
            let kind = blueprint.kind(id);
            kind.built_in().map(|node| node.outcomes()).or_else(|| {
                crate::nodes::std_outcomes(
                    blueprint.type_id(id),
                    kind.type_name(),
                    blueprint.ports(id),
                )
            })
        })
        .collect();
    let mut can_run = vec![false; n];
    // Children come after their parent in pre-order, so a reverse walk sees them first.
    let ids: Vec<NodeId> = blueprint.ids().collect();
    for &id in ids.iter().rev() {
        can_run[id.index()] = runs_by_itself(blueprint.kind(id), own[id.index()])
            || blueprint.children(id).iter().any(|c| can_run[c.index()]);
    }
    blueprint
        .ids()
        .map(|id| {
            let own = own[id.index()];
            let mut set = OutcomeSet::of(&[]);
            if own.is_none_or(|o| o.success) {
                set = set.with(Success);
            }
            if own.is_none_or(|o| o.failure) {
                set = set.with(Failure);
            }
            if can_run[id.index()] {
                set = set.with(Running).with(Halted);
            }
            if own.is_some_and(|o| o.skipped) {
                set = set.with(Skipped);
            }
            if let Some(hooks) = blueprint.node_hooks(id) {
                hooks.attributes(&mut |name, _| match name {
                    "_skipIf" | "_while" => set = set.with(Skipped),
                    "_successIf" => set = set.with(Success),
                    "_failureIf" => set = set.with(Failure),
                    _ => {}
                });
            }
            set
        })
        .collect()
}

/// `true` for kinds that return Running whatever their children do: the leaves of user
/// code that run over ticks, and the nodes whose outcomes (`own`) say so of themselves.
fn runs_by_itself<C>(kind: &NodeKind<C>, own: Option<Outcomes>) -> bool {
    match own {
        Some(outcomes) => outcomes.running,
        None => matches!(
            kind,
            NodeKind::Stateful(_) | NodeKind::Async(_) | NodeKind::Custom(_)
        ),
    }
}

/// What a run covered of one node.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NodeCoverage {
    /// The node's [`path`](Blueprint::path).
    pub path: String,
    /// The type name shown in pictures (`Fallback`, `MoveTo`).
    pub type_name: String,
    /// Whether it was ticked or decided by a precondition at least once.
    pub reached: bool,
    /// The outcomes it was seen with.
    pub seen: OutcomeSet,
    /// The outcomes it could have ([`possible_outcomes`]).
    pub possible: OutcomeSet,
}

impl NodeCoverage {
    /// The possible outcomes not seen.
    pub fn missing(&self) -> OutcomeSet {
        self.possible.without(self.seen)
    }

    /// `true` if it was reached and every possible outcome was seen.
    pub fn is_covered(&self) -> bool {
        self.reached && self.missing().is_empty()
    }
}

/// What a run covered of a tree, node by node in pre-order ([`Coverage::report`]).
///
/// Its `Display` is a table: a line with the totals, then a line per node with what was
/// seen and what was not (`never reached` for a node that never ran).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CoverageReport {
    nodes: Vec<NodeCoverage>,
}

impl CoverageReport {
    /// The report for `blueprint` given each node's outcomes seen and whether it was
    /// reached (both indexed by [`NodeId`]; missing entries read as none and not reached).
    /// [`Coverage::report`] makes it from a run.
    pub fn new<C>(blueprint: &Blueprint<C>, seen: &[OutcomeSet], reached: &[bool]) -> Self {
        let possible = possible_all(blueprint);
        let nodes = blueprint
            .ids()
            .map(|id| {
                let i = id.index();
                NodeCoverage {
                    path: blueprint.path(id),
                    type_name: blueprint.type_id(id).to_string(),
                    reached: reached.get(i).copied().unwrap_or(false),
                    seen: seen.get(i).copied().unwrap_or_default(),
                    possible: possible[i],
                }
            })
            .collect();
        Self { nodes }
    }

    /// The report of `nodes` as they were recorded elsewhere (a file written by
    /// `neurotree run --coverage-json`), each with its own possible outcomes, indexed by
    /// [`NodeId`].
    pub fn from_nodes(nodes: Vec<NodeCoverage>) -> Self {
        Self { nodes }
    }

    /// Every node, indexed by [`NodeId`].
    pub fn nodes(&self) -> &[NodeCoverage] {
        &self.nodes
    }

    /// The first node (in pre-order) whose path is `path`.
    pub fn node_by_path(&self, path: &str) -> Option<&NodeCoverage> {
        self.nodes.iter().find(|n| n.path == path)
    }

    /// The nodes that never ran.
    pub fn never_reached(&self) -> impl Iterator<Item = &NodeCoverage> {
        self.nodes.iter().filter(|n| !n.reached)
    }

    /// Possible outcomes seen, summed over the nodes.
    pub fn covered_outcomes(&self) -> usize {
        self.nodes
            .iter()
            .map(|n| n.seen.and(n.possible).len())
            .sum()
    }

    /// Possible outcomes, summed over the nodes.
    pub fn possible_outcomes(&self) -> usize {
        self.nodes.iter().map(|n| n.possible.len()).sum()
    }

    /// [`covered_outcomes`](Self::covered_outcomes) as a percentage of
    /// [`possible_outcomes`](Self::possible_outcomes) (100 for an empty tree).
    pub fn percent(&self) -> f64 {
        match self.possible_outcomes() {
            0 => 100.0,
            possible => 100.0 * self.covered_outcomes() as f64 / possible as f64,
        }
    }
}

impl fmt::Display for CoverageReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        const HEADERS: [&str; 4] = ["node", "type", "seen", "not seen"];
        let reached = self.nodes.iter().filter(|n| n.reached).count();
        writeln!(
            f,
            "coverage: {} of {} outcomes ({:.1}%), {reached} of {} nodes reached",
            self.covered_outcomes(),
            self.possible_outcomes(),
            self.percent(),
            self.nodes.len(),
        )?;
        let rows: Vec<[String; 4]> = self
            .nodes
            .iter()
            .map(|n| {
                let missing = if n.reached {
                    n.missing().to_string()
                } else {
                    "never reached".to_string()
                };
                [
                    n.path.clone(),
                    n.type_name.clone(),
                    n.seen.to_string(),
                    missing,
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
            let last = row.len() - 1;
            for (i, (cell, w)) in row.iter().zip(widths).enumerate() {
                if i == last {
                    writeln!(f, "{cell}")?;
                } else {
                    write!(f, "{cell:<w$}  ")?;
                }
            }
        }
        Ok(())
    }
}
