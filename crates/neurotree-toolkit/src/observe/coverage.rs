//! Coverage of a tree under test: which nodes a run reached and which of their possible
//! outcomes it saw.

use std::fmt;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree_core::nodes::semantics::{first, Statuses};
use neurotree_core::nodes::{Literals, NodeDecl, Semantics};
use neurotree_core::{
    Blueprint, NodeId, NodeKind, NodeStatus, Observer, Port, PortValue, StatusChange,
};

use super::lock;
use super::outcome::{Outcome, OutcomeReader, OutcomeSet};
use crate::Registry;

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
    /// Per node, what a registry declares of its type (empty: nothing).
    registered: Vec<Option<Registered>>,
    outcomes: OutcomeReader,
    seen: Vec<OutcomeSet>,
    ticked: Vec<bool>,
}

impl Coverage {
    /// A record for the nodes of `blueprint`, none reached.
    pub fn new<C>(blueprint: &Blueprint<C>) -> Self {
        Self::with_declared(blueprint, Vec::new())
    }

    /// As [`new`](Self::new), with the declarations of `registry`, the registry
    /// `blueprint` was loaded with: a control, decorator or leaf of a type declared there
    /// ([`Registry::declare_semantics`], a registered condition) can have what its
    /// declaration gives, not anything. Use it whenever the registry is at hand.
    pub fn with_registry<C: 'static>(blueprint: &Blueprint<C>, registry: &Registry<C>) -> Self {
        Self::with_declared(blueprint, registered(blueprint, registry))
    }

    fn with_declared<C>(blueprint: &Blueprint<C>, registered: Vec<Option<Registered>>) -> Self {
        Self {
            state: Arc::new(Mutex::new(Record {
                registered,
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
        CoverageReport::made(blueprint, &state.registered, &state.seen, &reached)
    }
}

/// What a registry declares of a node's type: its semantics and its ports' defaults.
struct Registered {
    semantics: Semantics,
    defaults: Vec<(String, String)>,
}

/// Per node of `blueprint`, its type's declaration in `registry`, when the node is made by
/// that type (not a mock, test node or substitution standing in for it) and it declares
/// something; the engine's built-ins are read from their kind.
fn registered<C: 'static>(
    blueprint: &Blueprint<C>,
    registry: &Registry<C>,
) -> Vec<Option<Registered>> {
    blueprint
        .ids()
        .map(|id| {
            let kind = blueprint.kind(id);
            let type_id = blueprint.type_id(id);
            // A mock or a substitution is a Custom of another type name; a leaf kind is
            // named by its category, so only a user control or decorator's name is checked.
            let made_by_type = match kind {
                NodeKind::Custom(_) => kind.type_name() == type_id,
                _ => false,
            };
            if kind.decl().is_some() || !made_by_type {
                return None;
            }
            let t = registry.get(type_id)?;
            Some(Registered {
                semantics: t.semantics?,
                defaults: t
                    .ports
                    .iter()
                    .filter_map(|p| Some((p.name.clone(), p.default.clone()?)))
                    .collect(),
            })
        })
        .collect()
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

/// The outcomes node `id` of `blueprint` can have; what a [`CoverageReport`] counts as
/// possible. They are the statuses its type's declared outcome signature
/// ([`NodeDecl::semantics`]) gives over its children's possible statuses and its ports'
/// literals, widened by its preconditions (`_successIf` adds Success, `_failureIf`
/// Failure, `_skipIf` and `_while` Skipped):
///
/// - Success and Failure where the signature gives them (an AlwaysSuccess cannot fail, a
///   `Repeat num_cycles="-1"` over a child that cannot fail cannot end, ...).
/// - Running and Halted where it gives Running: by itself (Sleep, Delay, a Repeat of more
///   than one cycle) or through a child that can be Running.
/// - Skipped where the node itself may skip: a `_skipIf` or `_while`, a RunOnce that skips
///   after its run, a SkipUnlessUpdated, a Precondition whose `else` is SKIPPED. A control
///   whose children were all skipped also returns Skipped; that is seen and shown but not
///   counted as possible.
///
/// A SubTree has its root's. A node of user code declares nothing: a condition or a sync
/// action can succeed or fail, a stateful or async action also run, a custom control or
/// decorator (or a mock) anything; a control or decorator of a type its registry declares
/// has what the declaration gives when the record is made by [`Coverage::with_registry`].
///
/// [`NodeDecl::semantics`]: neurotree_core::nodes::NodeDecl::semantics
pub fn possible_outcomes<C>(blueprint: &Blueprint<C>, id: NodeId) -> OutcomeSet {
    possible_all(blueprint, &[])[id.index()]
}

/// What declares node `id`'s statuses.
enum Declared<'a> {
    /// A built-in's or a std node's declaration.
    Decl(&'static NodeDecl),
    /// A SubTree: its root's statuses.
    SubTree,
    /// A node of user code: these statuses.
    User(Statuses),
    /// A node whose type a registry declares.
    Registered(&'a Registered),
}

/// The declaration of node `id`: the engine's built-ins by their kind; this crate's by
/// their registered type, when the kind is the one their declaration makes (a mock
/// standing in for a Script is not a Script).
fn declared<'a, C>(
    blueprint: &Blueprint<C>,
    registered: &'a [Option<Registered>],
    id: NodeId,
) -> Declared<'a> {
    let kind = blueprint.kind(id);
    if let Some(decl) = kind.decl() {
        return Declared::Decl(decl);
    }
    if let Some(Some(r)) = registered.get(id.index()) {
        return Declared::Registered(r);
    }
    let user = |statuses| {
        // A std action or condition is a plain leaf kind of its registered type; a std
        // control or decorator a kind of its own name.
        let name = match kind.type_name() {
            "Action" | "Condition" => blueprint.type_id(id),
            name => name,
        };
        crate::nodes::STD_BUILT_INS
            .iter()
            .copied()
            .find(|d| d.name == name && d.arity == kind.arity())
            .map_or(Declared::User(statuses), Declared::Decl)
    };
    match kind {
        NodeKind::SubTree(_) => Declared::SubTree,
        NodeKind::ConditionFn(_)
        | NodeKind::Condition(_)
        | NodeKind::SharedCondition(_)
        | NodeKind::ActionFn(_)
        | NodeKind::Action(_) => user(Statuses::DONE),
        NodeKind::Stateful(_) | NodeKind::Async(_) => {
            Declared::User(Statuses::DONE.or(Statuses::RUNNING))
        }
        _ => user(Statuses::ANY),
    }
}

/// [`possible_outcomes`] of every node, indexed by [`NodeId`].
/// `registered` holds what a registry declares of each node's type (empty: nothing).
fn possible_all<C>(blueprint: &Blueprint<C>, registered: &[Option<Registered>]) -> Vec<OutcomeSet> {
    use Outcome::{Failure, Halted, Running, Skipped, Success};
    let n = blueprint.len();
    // Every status each node can return (SKIPPED included: it decides what its parent
    // does next), and whether the node can be skipped of itself.
    let mut full = vec![Statuses::ANY; n];
    let mut own_skip = vec![false; n];
    // Children come after their parent in pre-order, so a reverse walk sees them first.
    let ids: Vec<NodeId> = blueprint.ids().collect();
    for &id in ids.iter().rev() {
        let children: Vec<Statuses> = blueprint
            .children(id)
            .iter()
            .map(|c| full[c.index()])
            .collect();
        // Skipped of itself: still Skipped when no child can be.
        let unskipped: Vec<Statuses> = children
            .iter()
            .map(|c| c.without(Statuses::SKIPPED))
            .collect();
        let (mut statuses, mut skips) = match declared(blueprint, registered, id) {
            Declared::Decl(decl) => {
                let values = blueprint
                    .kind(id)
                    .built_in()
                    .map(|b| b.port_values(children.len()))
                    .unwrap_or_default();
                let ports = blueprint.ports(id);
                let text = |name: &str| literal(decl, &values, ports, name);
                let literals = Literals::new(&text);
                let statuses = decl.semantics.outcomes(&literals, &children);
                let skips = decl.semantics.outcomes(&literals, &unskipped).can_skip();
                (statuses, skips)
            }
            Declared::Registered(r) => {
                let ports = blueprint.ports(id);
                let text = |name: &str| match ports.iter().find(|p| p.name == name) {
                    Some(Port {
                        value: PortValue::Literal(text),
                        ..
                    }) => Some(text.as_str()),
                    Some(_) => None,
                    None => r
                        .defaults
                        .iter()
                        .find(|(port, _)| port == name)
                        .map(|(_, text)| text.as_str()),
                };
                let literals = Literals::new(&text);
                let statuses = r.semantics.outcomes(&literals, &children);
                let skips = r.semantics.outcomes(&literals, &unskipped).can_skip();
                (statuses, skips)
            }
            Declared::SubTree => (first(&children), false),
            Declared::User(statuses) => (statuses, false),
        };
        if let Some(hooks) = blueprint.node_hooks(id) {
            hooks.attributes(&mut |name, _| match name {
                "_skipIf" | "_while" => {
                    statuses = statuses.or(Statuses::SKIPPED);
                    skips = true;
                }
                "_successIf" => statuses = statuses.or(Statuses::SUCCESS),
                "_failureIf" => statuses = statuses.or(Statuses::FAILURE),
                _ => {}
            });
        }
        full[id.index()] = statuses;
        own_skip[id.index()] = skips;
    }
    (0..n)
        .map(|i| {
            let s = full[i];
            let mut set = OutcomeSet::NONE;
            if s.can_succeed() {
                set = set.with(Success);
            }
            if s.can_fail() {
                set = set.with(Failure);
            }
            if s.can_run() {
                set = set.with(Running).with(Halted);
            }
            if s.can_skip() && own_skip[i] {
                set = set.with(Skipped);
            }
            set
        })
        .collect()
}

/// The literal text of port `name` of a node declared by `decl`: a built-in's own
/// parameter (`values`, in the order of its declared ports), else its binding in
/// `ports`, else the declared default; `None` when it is read from a blackboard entry.
fn literal<'a>(
    decl: &'static NodeDecl,
    values: &'a [Option<String>],
    ports: &'a [Port],
    name: &str,
) -> Option<&'a str> {
    let index = decl.ports.iter().position(|p| p.name == name);
    if let Some(value) = index.and_then(|i| values.get(i)) {
        return value.as_deref();
    }
    match ports.iter().find(|p| p.name == name).map(|p| &p.value) {
        Some(PortValue::Literal(text)) => Some(text),
        Some(_) => None,
        None => decl.port(name).and_then(|p| p.default),
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
        Self::made(blueprint, &[], seen, reached)
    }

    fn made<C>(
        blueprint: &Blueprint<C>,
        registered: &[Option<Registered>],
        seen: &[OutcomeSet],
        reached: &[bool],
    ) -> Self {
        let possible = possible_all(blueprint, registered);
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
