//! NeuroTree against BehaviorTree.CPP 4 itself, on random trees of the built-in nodes.
//!
//! Each case is a seeded random tree of the built-in controls, decorators and leaves that
//! both libraries have, whose leaves are scripted mocks, and a random list of steps
//! (`tick_once`, `tick_exactly_once`, halt). The tree is written as BehaviorTree.CPP XML;
//! NeuroTree loads it with [`XmlLoader`], and `differential/btcpp_run.py` runs the whole
//! batch through BehaviorTree.CPP 4.8.2 (the `behaviortreepy` 0.1.4 bindings) in one
//! process. For every step the two must agree on:
//!
//! - the root's result (or both raising an error);
//! - every stored-status change, in order (node, from, to): BehaviorTree.CPP's
//!   `StdCoutLogger`, NeuroTree's [`Observer::on_status_change`];
//! - every call of a scripted leaf, in order, with its result: `on_start`, `on_running`,
//!   `on_halted` of the stateful `Act`, the tick of the sync action `Sync` and of the
//!   condition `Cond` (so leaf ticks and leaf halts are compared call by call);
//! - per node, the ticks that began with the node Idle or Running (BehaviorTree.CPP: a
//!   counting `_while` precondition, evaluated exactly then; NeuroTree:
//!   [`Observer::on_node_tick`] while the observed status is Idle or Running).
//!
//! Halts of controls and decorators have no callback in the bindings; they are the
//! Running → Idle changes of the status stream, compared with it.
//!
//! Scripts: leaf `n<i>` plays its letters (S, F, R) one per call, the last one repeating.
//!
//! Run: `BTCPP_PYTHON=/path/to/venv/bin/python cargo test -p neurotree --test differential
//! -- --nocapture`, with `behaviortreepy==0.1.4` installed in that venv (`.ci/run` does
//! it). Without `BTCPP_PYTHON`, or when that Python cannot import `behaviortreepy`, the
//! test prints why it skipped and passes. `NEUROTREE_DIFF_TREES=20000` runs more trees
//! (default 500), `NEUROTREE_DIFF_SEED` changes the seed, `NEUROTREE_DIFF_SHOW` how many
//! differing trees are printed (default 8).
//!
//! Differences that are known are listed in [`KNOWN_DIFFERENCES`], each with what
//! BehaviorTree.CPP does and why it is not (yet) what NeuroTree does; a step that differs
//! in any other way fails the test with the tree, the steps and both sides' records.

use std::cell::{Cell, RefCell};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use neurotree::{
    Handle, ManualClock, NodeId, NodeStatus, Observer, Registry, StatefulAction, Status,
    StatusChange, TickError, Tree, XmlLoader,
};
use serde_json::{json, Value};

/// Trees per run unless `NEUROTREE_DIFF_TREES` says otherwise.
const DEFAULT_TREES: usize = 500;
/// Seed of the first tree unless `NEUROTREE_DIFF_SEED` says otherwise.
const DEFAULT_SEED: u64 = 0x5eed_b7c9;
/// Passes one NeuroTree `tick_once` may make. A step whose `tick_once` makes more (a tree
/// that yields on every pass, as `Repeat -1` over a child that succeeds at once) becomes a
/// `tick_exactly_once` for both sides, since BehaviorTree.CPP's `tickOnce` would not end.
const MAX_PASSES: u32 = 1000;
/// How long the BehaviorTree.CPP process may take for the whole batch.
const PYTHON_TIMEOUT: Duration = Duration::from_secs(600);

// ---------------------------------------------------------------------------------------
// Known differences
// ---------------------------------------------------------------------------------------

/// A known difference: what BehaviorTree.CPP does, why NeuroTree differs, and how the
/// test sets it aside. Remove an entry once NeuroTree matches.
struct KnownDifference {
    /// A short name, printed with the count of steps it concerned.
    name: &'static str,
    /// What BehaviorTree.CPP does.
    btcpp: &'static str,
    /// Why NeuroTree does otherwise (one line).
    reason: &'static str,
    how: SetAside,
}

/// How a known difference is set aside.
enum SetAside {
    /// Rewrites BehaviorTree.CPP's record of a step into what it would be without the
    /// difference (returns whether it changed anything); the rest is still compared.
    Rewrite(fn(&Case, &mut Step) -> bool),
    /// Explains a step whose records differ (NeuroTree's, BehaviorTree.CPP's); the rest of
    /// that case is not compared, since the two trees' states now differ.
    Explains(fn(&Case, &Step, &Step) -> bool),
    /// Explains why BehaviorTree.CPP refuses to load a tree that NeuroTree loads.
    LoadRefused(fn(&Case, &str) -> bool),
    /// Set aside by `btcpp_run.py` before the step ran; tells whether it did so.
    InDriver(fn(&Step) -> bool),
}

/// NeuroTree's deliberate, documented differences from BehaviorTree.CPP: set aside like
/// the known ones, but meant to stay.
const DELIBERATE_DIFFERENCES: &[KnownDifference] = &[
    KnownDifference {
        name: "a wake-up counts only within its call",
        btcpp: "a wake-up signal emitted during `tickExactlyOnce`, or during a pass whose root \
                completed, stays pending and makes the next `tickOnce` run one extra pass",
        reason: "documented in `Tree` (module doc): NeuroTree drops it, so the work of one \
                 call never leaks into the next; the driver consumes the pending signal \
                 with `Tree::sleep(0)` before each `tickOnce`",
        how: SetAside::InDriver(|step| step.stale_wake),
    },
    KnownDifference {
        name: "a Skipped node is stored Idle",
        btcpp: "`executeTick` stores nothing for SKIPPED, so a control or decorator that set \
            itself RUNNING before its child was skipped stays RUNNING",
        reason: "documented in the engine (`Ticker::store_result`, `Observer::on_node_skipped`): \
             a skipped node keeps, or returns to, Idle",
        how: SetAside::Explains(skipped_stored_idle),
    },
];

/// Every known difference. A differing step that none of these, nor a deliberate
/// difference, explains fails the test.
const KNOWN_DIFFERENCES: &[KnownDifference] = &[
    KnownDifference {
        name: "simple action passes through RUNNING",
        btcpp: "a `registerSimpleAction` node (SimpleActionNode) ticked from IDLE is set to \
                RUNNING before its functor runs, so loggers see IDLE->RUNNING->SUCCESS",
        reason: "NeuroTree's `register_action` stores only the result: IDLE->SUCCESS",
        how: SetAside::Rewrite(simple_action_running),
    },
    KnownDifference {
        name: "skipped condition of WhileDoElse / IfThenElse",
        btcpp: "a condition child that returns SKIPPED makes the tick throw: WhileDoElse is \
                left with IDLE, which may not be stored; IfThenElse throws \"Something \
                unexpected happened in IfThenElseNode\"",
        reason: "NeuroTree returns Skipped instead of raising an error",
        how: SetAside::Explains(skipped_condition_throws),
    },
    KnownDifference {
        name: "ReactiveSequence with two AsyncSequence children",
        btcpp: "the XML parser refuses a ReactiveSequence with more than one AsyncSequence \
                child (\"cannot have more than one async child\")",
        reason: "NeuroTree's loader does not make this check",
        how: SetAside::LoadRefused(reactive_sequence_async_children),
    },
];

/// The step where a skip first shows: once the IDLE <-> RUNNING changes of the nodes that
/// NeuroTree saw skipped are left out on both sides (NeuroTree sets such a node back to
/// IDLE when it returns Skipped, and sets it RUNNING again when it is ticked again;
/// BehaviorTree.CPP leaves it RUNNING until, or unless, a parent resets it), the changes
/// are the same, and all else agrees.
fn skipped_stored_idle(_: &Case, nt: &Step, bt: &Step) -> bool {
    if nt.skipped.is_empty() {
        return false;
    }
    let other = |c: &&[String; 3]| {
        let idle_running = matches!(
            (c[1].as_str(), c[2].as_str()),
            ("RUNNING", "IDLE") | ("IDLE", "RUNNING")
        );
        !(idle_running && nt.skipped.iter().any(|s| s == &c[0]))
    };
    nt.changes
        .iter()
        .filter(other)
        .eq(bt.changes.iter().filter(other))
        && nt.outcome == bt.outcome
        && nt.calls == bt.calls
        && nt.ticks == bt.ticks
}

/// BehaviorTree.CPP's WhileDoElse stores the IDLE it is left with ("not allowed to set
/// manually the status to IDLE", naming it); its IfThenElse throws "Something unexpected
/// happened in IfThenElseNode" (naming none). NeuroTree saw such a node skipped.
fn skipped_condition_throws(case: &Case, nt: &Step, bt: &Step) -> bool {
    let Some(error) = &bt.error else {
        return false;
    };
    let skipped_kind = |kind: &str| {
        nt.skipped
            .iter()
            .any(|s| case.tags.get(s).copied() == Some(kind))
    };
    let named = error
        .strip_prefix("Node [")
        .and_then(|rest| rest.split(']').next())
        .map(|node| {
            error.contains("not allowed to set manually the status to IDLE")
                && case.tags.get(node).copied() == Some("WhileDoElse")
                && nt.skipped.iter().any(|s| s == node)
        });
    named == Some(true)
        || (error.contains("Something unexpected happened in IfThenElseNode")
            && skipped_kind("IfThenElse"))
}

fn reactive_sequence_async_children(_: &Case, error: &str) -> bool {
    error.contains("cannot have more than one async child")
}

/// Drops the IDLE -> RUNNING that BehaviorTree.CPP's SimpleActionNode (`Sync` here) stores
/// before its functor runs, joining it with the change that follows.
fn simple_action_running(case: &Case, step: &mut Step) -> bool {
    let mut changed = false;
    let mut i = 0;
    while i + 1 < step.changes.len() {
        let [node, from, to] = &step.changes[i];
        let next = &step.changes[i + 1];
        if case.tags.get(node).copied() == Some("Sync")
            && from == "IDLE"
            && to == "RUNNING"
            && &next[0] == node
            && next[1] == "RUNNING"
        {
            step.changes[i + 1][1] = "IDLE".to_string();
            step.changes.remove(i);
            changed = true;
        }
        i += 1;
    }
    changed
}

// ---------------------------------------------------------------------------------------
// Random trees
// ---------------------------------------------------------------------------------------

/// SplitMix64: small, seedable, and the same on every platform and version.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// In `lo..=hi`.
    fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next() % (hi - lo + 1) as u64) as i64
    }
    /// An index into `weights`, drawn in proportion to them.
    fn weighted(&mut self, weights: &[u32]) -> usize {
        let total: u32 = weights.iter().sum();
        let mut x = (self.next() % u64::from(total)) as u32;
        for (i, w) in weights.iter().enumerate() {
            if x < *w {
                return i;
            }
            x -= w;
        }
        unreachable!("x < total")
    }
}

/// A tree: XML element name, attributes, children; a scripted leaf has its script.
#[derive(Clone, Debug)]
struct Spec {
    tag: &'static str,
    attrs: Vec<(&'static str, String)>,
    script: Option<String>,
    children: Vec<Spec>,
}

impl Spec {
    fn node(tag: &'static str, children: Vec<Spec>) -> Self {
        Spec {
            tag,
            attrs: Vec::new(),
            script: None,
            children,
        }
    }
    fn attr(mut self, name: &'static str, value: impl ToString) -> Self {
        self.attrs.push((name, value.to_string()));
        self
    }
}

fn script(rng: &mut Rng, running: bool) -> String {
    let len = rng.range(1, 4);
    (0..len)
        .map(
            |_| match rng.weighted(&[2, 2, if running { 3 } else { 0 }]) {
                0 => 'S',
                1 => 'F',
                _ => 'R',
            },
        )
        .collect()
}

fn leaf(rng: &mut Rng) -> Spec {
    let (tag, script) = match rng.weighted(&[6, 2, 2, 1, 1]) {
        0 => ("Act", Some(script(rng, true))),
        1 => ("Sync", Some(script(rng, false))),
        2 => ("Cond", Some(script(rng, false))),
        3 => ("AlwaysSuccess", None),
        _ => ("AlwaysFailure", None),
    };
    Spec {
        script,
        ..Spec::node(tag, Vec::new())
    }
}

fn children(rng: &mut Rng, depth: u32, lo: i64, hi: i64) -> Vec<Spec> {
    (0..rng.range(lo, hi))
        .map(|_| tree(rng, depth + 1))
        .collect()
}

/// A random tree: depth at most 4, at most 4 children a node.
fn tree(rng: &mut Rng, depth: u32) -> Spec {
    if depth >= 4 || (depth > 0 && rng.weighted(&[2, 3]) == 0) {
        return leaf(rng);
    }
    match rng.weighted(&[7, 2, 1, 2, 6]) {
        0 => {
            let tags = [
                "Sequence",
                "SequenceWithMemory",
                "ReactiveSequence",
                "Fallback",
                "ReactiveFallback",
                "AsyncSequence",
                "AsyncFallback",
            ];
            let tag = tags[rng.range(0, tags.len() as i64 - 1) as usize];
            Spec::node(tag, children(rng, depth, 1, 4))
        }
        1 => {
            let kids = children(rng, depth, 1, 4);
            let n = kids.len() as i64;
            // Thresholds BehaviorTree.CPP accepts: resolved, at most the children.
            let success = rng.range(-(n + 1), n);
            let failure = rng.range(-(n + 1), n);
            Spec::node("Parallel", kids)
                .attr("success_count", success)
                .attr("failure_count", failure)
        }
        2 => {
            let kids = children(rng, depth, 1, 4);
            let n = kids.len() as i64;
            let max_failures = rng.range(-(n + 1), n);
            Spec::node("ParallelAll", kids).attr("max_failures", max_failures)
        }
        3 => {
            let tag = ["IfThenElse", "WhileDoElse"][rng.range(0, 1) as usize];
            Spec::node(tag, children(rng, depth, 2, 3))
        }
        _ => {
            let kid = vec![tree(rng, depth + 1)];
            // -1 (forever) now and then.
            let count = |rng: &mut Rng| {
                if rng.weighted(&[1, 9]) == 0 {
                    -1
                } else {
                    rng.range(0, 3)
                }
            };
            match rng.range(0, 6) {
                0 => Spec::node("Inverter", kid),
                1 => Spec::node("ForceSuccess", kid),
                2 => Spec::node("ForceFailure", kid),
                3 => Spec::node("Repeat", kid).attr("num_cycles", count(rng)),
                4 => Spec::node("RetryUntilSuccessful", kid).attr("num_attempts", count(rng)),
                5 => Spec::node("KeepRunningUntilFailure", kid),
                _ => Spec::node("RunOnce", kid).attr("then_skip", rng.range(0, 1) == 1),
            }
        }
    }
}

/// One step of a case.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Op {
    TickOnce,
    TickExactlyOnce,
    Halt,
}

impl Op {
    fn letter(self) -> char {
        match self {
            Op::TickOnce => 'T',
            Op::TickExactlyOnce => 'E',
            Op::Halt => 'H',
        }
    }
}

fn ops(rng: &mut Rng) -> Vec<Op> {
    (0..rng.range(1, 10))
        .map(|_| match rng.weighted(&[4, 3, 1]) {
            0 => Op::TickOnce,
            1 => Op::TickExactlyOnce,
            _ => Op::Halt,
        })
        .collect()
}

/// One case: the XML, the leaves' scripts by node name, the steps.
struct Case {
    id: usize,
    seed: u64,
    xml: String,
    scripts: BTreeMap<String, String>,
    /// Each node's element name, by node name.
    tags: BTreeMap<String, &'static str>,
    ops: Vec<Op>,
}

/// Writes `spec` as XML, naming every node `n<i>` (its pre-order index).
fn write_xml(spec: &Spec, next: &mut usize, case: &mut Case) {
    let name = format!("n{next}");
    *next += 1;
    case.tags.insert(name.clone(), spec.tag);
    let out = &mut case.xml;
    let _ = write!(out, "<{} name=\"{name}\"", spec.tag);
    for (k, v) in &spec.attrs {
        let _ = write!(out, " {k}=\"{v}\"");
    }
    if let Some(s) = &spec.script {
        case.scripts.insert(name, s.clone());
    }
    if spec.children.is_empty() {
        out.push_str("/>");
    } else {
        out.push('>');
        for c in &spec.children {
            write_xml(c, next, case);
        }
        let _ = write!(case.xml, "</{}>", spec.tag);
    }
}

fn case(id: usize, seed: u64) -> Case {
    let mut rng = Rng(seed);
    let spec = tree(&mut rng, 0);
    let mut case = Case {
        id,
        seed,
        xml: String::from(
            "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\"><BehaviorTree ID=\"Main\">",
        ),
        scripts: BTreeMap::new(),
        tags: BTreeMap::new(),
        ops: Vec::new(),
    };
    write_xml(&spec, &mut 0, &mut case);
    case.xml.push_str("</BehaviorTree></root>");
    case.ops = ops(&mut rng);
    case
}

// ---------------------------------------------------------------------------------------
// What one step did, on either side
// ---------------------------------------------------------------------------------------

/// What one step did. Nodes are named `n<i>`; statuses are BehaviorTree.CPP's names.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Step {
    /// The root's result, `halted` for a halt, or `error` (the message is not compared).
    outcome: String,
    /// Every stored-status change: node, from, to.
    changes: Vec<[String; 3]>,
    /// Every scripted-leaf call: node, `start` / `running` / `halted` / `tick`, result.
    calls: Vec<[String; 3]>,
    /// Per node, the ticks that began with it Idle or Running (nodes with none left out).
    ticks: BTreeMap<String, u64>,
    /// The error's text, if any (shown, not compared).
    error: Option<String>,
    /// NeuroTree only: the nodes that returned Skipped, in order (for the filters).
    skipped: Vec<String>,
    /// BehaviorTree.CPP only: a wake-up from an earlier call was pending before this
    /// `tickOnce`, and the driver consumed it.
    stale_wake: bool,
}

impl Step {
    fn same(&self, other: &Step) -> bool {
        self.outcome == other.outcome
            && self.changes == other.changes
            && self.calls == other.calls
            && self.ticks == other.ticks
    }
}

// ---------------------------------------------------------------------------------------
// NeuroTree's side
// ---------------------------------------------------------------------------------------

/// The scripted leaves' context: scripts and call counts by node index, and the calls.
struct Ctx {
    names: Vec<String>,
    scripts: Vec<Vec<Status>>,
    calls: Vec<Cell<usize>>,
    log: RefCell<Vec<[String; 3]>>,
}

impl Ctx {
    fn play(&self, id: NodeId, what: &str) -> Status {
        let i = id.index();
        let k = self.calls[i].get();
        self.calls[i].set(k + 1);
        let script = &self.scripts[i];
        let s = script[k.min(script.len() - 1)];
        self.log.borrow_mut().push([
            self.names[i].clone(),
            what.to_string(),
            NodeStatus::from(s).as_str().to_string(),
        ]);
        s
    }
}

struct Act;

impl StatefulAction<Ctx> for Act {
    fn on_start(&mut self, h: &mut Handle<'_, Ctx>) -> Status {
        let id = h.node();
        h.ctx().play(id, "start")
    }
    fn on_running(&mut self, h: &mut Handle<'_, Ctx>) -> Status {
        let id = h.node();
        h.ctx().play(id, "running")
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Ctx>) {
        let name = h.ctx().names[h.node().index()].clone();
        h.ctx()
            .log
            .borrow_mut()
            .push([name, "halted".into(), "null".into()]);
    }
}

fn registry() -> Registry<Ctx> {
    let mut r = Registry::new();
    r.register_stateful("Act", vec![], || Act).unwrap();
    r.register_action("Sync", vec![], |h| {
        let id = h.node();
        h.ctx().play(id, "tick")
    })
    .unwrap();
    r.register_condition("Cond", vec![], |h| {
        h.ctx().play(h.node(), "tick") == Status::Success
    })
    .unwrap();
    r
}

/// What the observer saw in the current step.
#[derive(Default)]
struct Seen {
    /// The stored statuses, as the changes told them.
    statuses: Vec<NodeStatus>,
    changes: Vec<(NodeId, NodeStatus, NodeStatus)>,
    ticks: Vec<u64>,
    skipped: Vec<NodeId>,
}

struct Watch(Arc<Mutex<Seen>>);

impl Observer for Watch {
    fn on_status_change(&mut self, c: StatusChange) {
        let mut s = self.0.lock().unwrap();
        s.statuses[c.node.index()] = c.to;
        s.changes.push((c.node, c.from, c.to));
    }
    fn on_node_tick(&mut self, node: NodeId) {
        let mut s = self.0.lock().unwrap();
        // BehaviorTree.CPP's side counts with `_while`, which runs only from these two.
        if matches!(
            s.statuses[node.index()],
            NodeStatus::Idle | NodeStatus::Running
        ) {
            s.ticks[node.index()] += 1;
        }
    }
    fn on_node_skipped(&mut self, node: NodeId) {
        self.0.lock().unwrap().skipped.push(node);
    }
}

/// Runs `case` in NeuroTree: a load error, or one record per step. A `tick_once` that makes
/// more than [`MAX_PASSES`] passes is recorded as `error` ("runaway").
fn run_neurotree(registry: &Registry<Ctx>, case: &Case) -> Result<Vec<Step>, String> {
    let mut loader = XmlLoader::new(registry);
    loader
        .load_str(&case.xml, "case.xml")
        .map_err(|e| e.to_string())?;
    let blueprint = Arc::new(loader.build_main().map_err(|e| e.to_string())?);
    let names: Vec<String> = blueprint
        .ids()
        .map(|id| blueprint.name(id).to_string())
        .collect();
    let scripts = names
        .iter()
        .map(|n| match case.scripts.get(n) {
            Some(s) => s
                .chars()
                .map(|c| match c {
                    'S' => Status::Success,
                    'F' => Status::Failure,
                    _ => Status::Running,
                })
                .collect(),
            None => Vec::new(),
        })
        .collect();
    let mut ctx = Ctx {
        calls: names.iter().map(|_| Cell::new(0)).collect(),
        names: names.clone(),
        scripts,
        log: RefCell::new(Vec::new()),
    };
    let seen = Arc::new(Mutex::new(Seen {
        statuses: vec![NodeStatus::Idle; names.len()],
        changes: Vec::new(),
        ticks: vec![0; names.len()],
        skipped: Vec::new(),
    }));
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    tree.set_max_passes(MAX_PASSES);
    tree.set_observer(Watch(Arc::clone(&seen)));
    let mut steps = Vec::new();
    for op in &case.ops {
        let result = match op {
            Op::TickOnce => Some(tree.tick_once(&mut ctx)),
            Op::TickExactlyOnce => Some(tree.tick_exactly_once(&mut ctx)),
            Op::Halt => {
                tree.halt(&mut ctx);
                None
            }
        };
        let (outcome, error) = match result {
            None => ("halted".to_string(), None),
            Some(Ok(s)) => (NodeStatus::from(s).as_str().to_string(), None),
            // NeuroTree's tick returns a `Status`, which has no Skipped: a skipped root is
            // this error, where BehaviorTree.CPP's tick returns SKIPPED. The same outcome.
            Some(Err(TickError::RootSkipped)) => ("SKIPPED".into(), None),
            Some(Err(TickError::TooManyPasses { .. })) => ("error".into(), Some("runaway".into())),
            Some(Err(e)) => ("error".into(), Some(e.to_string())),
        };
        let mut s = seen.lock().unwrap();
        let changes = s
            .changes
            .drain(..)
            .map(|(n, from, to)| {
                [
                    names[n.index()].clone(),
                    from.as_str().to_string(),
                    to.as_str().to_string(),
                ]
            })
            .collect();
        let ticks = s
            .ticks
            .iter_mut()
            .enumerate()
            .filter(|(_, t)| **t > 0)
            .map(|(i, t)| (names[i].clone(), std::mem::take(t)))
            .collect();
        let skipped = s
            .skipped
            .drain(..)
            .map(|n| names[n.index()].clone())
            .collect();
        drop(s);
        let failed = error.is_some();
        steps.push(Step {
            outcome,
            changes,
            calls: std::mem::take(&mut *ctx.log.borrow_mut()),
            ticks,
            error,
            skipped,
            stale_wake: false,
        });
        if failed {
            break;
        }
    }
    Ok(steps)
}

/// Turns each `tick_once` that NeuroTree finds running away into a `tick_exactly_once`,
/// so that BehaviorTree.CPP's `tickOnce` (which has no bound) is never asked to run one.
fn tame(registry: &Registry<Ctx>, case: &mut Case) {
    for _ in 0..case.ops.len() {
        let Ok(steps) = run_neurotree(registry, case) else {
            return;
        };
        let runaway = steps
            .iter()
            .position(|s| s.error.as_deref() == Some("runaway"));
        match runaway {
            Some(i) if case.ops[i] == Op::TickOnce => case.ops[i] = Op::TickExactlyOnce,
            _ => return,
        }
    }
}

// ---------------------------------------------------------------------------------------
// BehaviorTree.CPP's side
// ---------------------------------------------------------------------------------------

/// The Python to run BehaviorTree.CPP with, or why the test skips.
fn btcpp_python() -> Result<String, String> {
    let python = std::env::var("BTCPP_PYTHON")
        .map_err(|_| "BTCPP_PYTHON is not set (a Python with behaviortreepy==0.1.4)".to_string())?;
    let out = Command::new(&python)
        .args([
            "-c",
            "import importlib.metadata as m, behaviortreepy; print(m.version('behaviortreepy'))",
        ])
        .output()
        .map_err(|e| format!("cannot run BTCPP_PYTHON={python}: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "BTCPP_PYTHON={python} cannot import behaviortreepy: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    let version = String::from_utf8_lossy(&out.stdout).trim().to_string();
    if version != "0.1.4" {
        return Err(format!(
            "BTCPP_PYTHON={python} has behaviortreepy {version}; this test is pinned to 0.1.4"
        ));
    }
    Ok(python)
}

/// Runs every case through BehaviorTree.CPP in one process: its record per case id.
fn run_btcpp(python: &str, cases: &[Case]) -> BTreeMap<usize, Result<Vec<Step>, String>> {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("cases.jsonl");
    let output = dir.path().join("results.jsonl");
    let mut f = std::fs::File::create(&input).unwrap();
    for c in cases {
        let ops: String = c.ops.iter().map(|o| o.letter()).collect();
        let line = json!({ "id": c.id, "xml": c.xml, "scripts": c.scripts, "ops": ops });
        writeln!(f, "{line}").unwrap();
    }
    drop(f);
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/differential/btcpp_run.py");
    let mut child = Command::new(python)
        .arg(&script)
        .arg(&input)
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&output).unwrap())
        .stderr(std::fs::File::create(dir.path().join("stderr.txt")).unwrap())
        .spawn()
        .expect("start the BehaviorTree.CPP driver");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > PYTHON_TIMEOUT {
            child.kill().ok();
            child.wait().ok();
            panic!(
                "the BehaviorTree.CPP driver took more than {PYTHON_TIMEOUT:?} (a tick that \
                 never ends on its side?)"
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stderr = std::fs::read_to_string(dir.path().join("stderr.txt")).unwrap_or_default();
    assert!(
        status.success(),
        "the BehaviorTree.CPP driver failed ({status}):\n{stderr}"
    );
    let text = std::fs::read_to_string(&output).unwrap();
    text.lines()
        .map(|line| {
            let v: Value = serde_json::from_str(line).expect("the driver writes JSON lines");
            let id = v["id"].as_u64().unwrap() as usize;
            if let Some(e) = v.get("load_error") {
                return (id, Err(e.to_string()));
            }
            let steps = v["steps"]
                .as_array()
                .unwrap()
                .iter()
                .map(btcpp_step)
                .collect();
            (id, Ok(steps))
        })
        .collect()
}

fn btcpp_step(v: &Value) -> Step {
    let triples = |key: &str| -> Vec<[String; 3]> {
        v[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| {
                let s = |i: usize| match &t[i] {
                    Value::String(s) => s.clone(),
                    other => other.to_string(),
                };
                [s(0), s(1), s(2)]
            })
            .collect()
    };
    let error = v
        .get("error")
        .map(|e| e.as_str().unwrap_or("?").to_string());
    let outcome = match (&error, &v["status"]) {
        (Some(_), _) => "error".to_string(),
        (None, Value::String(s)) => s.clone(),
        (None, _) => "halted".to_string(),
    };
    Step {
        outcome,
        changes: triples("changes"),
        calls: triples("calls"),
        ticks: v["ticks"]
            .as_object()
            .unwrap()
            .iter()
            .map(|(k, n)| (k.clone(), n.as_u64().unwrap()))
            .collect(),
        error,
        skipped: Vec::new(),
        stale_wake: v["stale_wake"].as_bool().unwrap_or(false),
    }
}

// ---------------------------------------------------------------------------------------
// The test
// ---------------------------------------------------------------------------------------

fn env_number(name: &str, default: u64) -> u64 {
    match std::env::var(name) {
        Ok(v) => v
            .parse()
            .unwrap_or_else(|_| panic!("{name}={v} is not a number")),
        Err(_) => default,
    }
}

fn show_step(out: &mut String, side: &str, s: &Step) {
    let _ = writeln!(
        out,
        "    {side}: {}{}",
        s.outcome,
        s.error
            .as_ref()
            .map(|e| format!(" ({e})"))
            .unwrap_or_default()
    );
    let changes: Vec<String> = s
        .changes
        .iter()
        .map(|[n, a, b]| format!("{n} {a}->{b}"))
        .collect();
    let calls: Vec<String> = s
        .calls
        .iter()
        .map(|[n, w, r]| format!("{n} {w} {r}"))
        .collect();
    let _ = writeln!(out, "      changes: {}", changes.join(", "));
    let _ = writeln!(out, "      calls:   {}", calls.join(", "));
    let _ = writeln!(out, "      ticks:   {:?}", s.ticks);
}

/// The case, and both sides' records up to and including step `at`.
fn report(case: &Case, at: usize, nt: &[Step], bt: &[Step]) -> String {
    let mut out = String::new();
    let ops: String = case.ops.iter().map(|o| o.letter()).collect();
    let _ = writeln!(
        out,
        "case {} (seed {:#x}), steps {ops}, differs at step {} ({:?})",
        case.id,
        case.seed,
        at + 1,
        case.ops[at]
    );
    let _ = writeln!(out, "  xml: {}", case.xml);
    let _ = writeln!(out, "  scripts: {:?}", case.scripts);
    for i in 0..=at {
        let _ = writeln!(out, "  step {} {:?}", i + 1, case.ops[i]);
        if let Some(s) = nt.get(i) {
            show_step(&mut out, "NeuroTree", s);
        }
        if let Some(s) = bt.get(i) {
            show_step(&mut out, "BT.CPP   ", s);
        }
    }
    out
}

#[test]
fn random_trees_behave_as_in_behaviortree_cpp() {
    let python = match btcpp_python() {
        Ok(p) => p,
        Err(why) => {
            // Straight to stderr, past the test harness's capture, so that a run without
            // BehaviorTree.CPP says so.
            let _ = writeln!(std::io::stderr(), "differential: skipped: {why}");
            return;
        }
    };
    let trees = env_number("NEUROTREE_DIFF_TREES", DEFAULT_TREES as u64) as usize;
    let seed = env_number("NEUROTREE_DIFF_SEED", DEFAULT_SEED);
    let registry = registry();
    let mut seeder = Rng(seed);
    let mut cases: Vec<Case> = (0..trees).map(|i| case(i, seeder.next())).collect();
    for c in &mut cases {
        tame(&registry, c);
    }
    let btcpp = run_btcpp(&python, &cases);

    // Known differences first, then the deliberate ones, counted in one list.
    let set_aside: Vec<&KnownDifference> = KNOWN_DIFFERENCES
        .iter()
        .chain(DELIBERATE_DIFFERENCES)
        .collect();
    let mut explained = vec![0usize; set_aside.len()];
    let mut unexplained = Vec::new();
    let mut steps_compared = 0;
    for case in &cases {
        let nt = run_neurotree(&registry, case);
        let bt = btcpp
            .get(&case.id)
            .unwrap_or_else(|| panic!("no BehaviorTree.CPP result for case {}", case.id));
        let (nt, bt) = match (nt, bt) {
            (Ok(nt), Ok(bt)) => (nt, bt),
            (Err(_), Err(_)) => continue,
            (Ok(_), Err(error)) => {
                let refused = |k: &&KnownDifference| match k.how {
                    SetAside::LoadRefused(f) => f(case, error),
                    _ => false,
                };
                match set_aside.iter().position(refused) {
                    Some(k) => explained[k] += 1,
                    None => unexplained.push(format!(
                        "case {}: BT.CPP refuses to load it: {error}\n  xml: {}",
                        case.id, case.xml
                    )),
                }
                continue;
            }
            (Err(error), Ok(_)) => {
                unexplained.push(format!(
                    "case {}: NeuroTree refuses to load it: {error}\n  xml: {}",
                    case.id, case.xml
                ));
                continue;
            }
        };
        for i in 0..nt.len().max(bt.len()) {
            let (Some(a), Some(b)) = (nt.get(i), bt.get(i)) else {
                unexplained.push(report(case, i.min(nt.len().min(bt.len())), &nt, bt));
                break;
            };
            steps_compared += 1;
            let mut b = b.clone();
            for (k, known) in set_aside.iter().enumerate() {
                let done = match known.how {
                    SetAside::Rewrite(rewrite) => rewrite(case, &mut b),
                    SetAside::InDriver(did) => did(&b),
                    _ => false,
                };
                if done {
                    explained[k] += 1;
                }
            }
            if a.same(&b) {
                continue;
            }
            let explains = |k: &&KnownDifference| match k.how {
                SetAside::Explains(explains) => explains(case, a, &b),
                _ => false,
            };
            match set_aside.iter().position(explains) {
                Some(k) => explained[k] += 1,
                None => unexplained.push(report(case, i, &nt, bt)),
            }
            // After a difference the two states need not match any more.
            break;
        }
    }

    println!(
        "{trees} trees (seed {seed:#x}), {steps_compared} steps compared with BehaviorTree.CPP 4.8.2"
    );
    for (i, (k, n)) in set_aside.iter().zip(&explained).enumerate() {
        let kind = if i < KNOWN_DIFFERENCES.len() {
            "known"
        } else {
            "deliberate"
        };
        println!(
            "{kind} difference `{}`: set aside {n} times (BT.CPP: {}; {})",
            k.name, k.btcpp, k.reason
        );
    }
    if !unexplained.is_empty() {
        let show = env_number("NEUROTREE_DIFF_SHOW", 8) as usize;
        for r in unexplained.iter().take(show) {
            println!("{r}");
        }
        panic!(
            "{} of {trees} trees behave differently in BehaviorTree.CPP (first ones above)",
            unexplained.len()
        );
    }
}
