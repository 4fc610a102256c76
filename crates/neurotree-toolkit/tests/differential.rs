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
//! Run: `BTCPP_PYTHON=/path/to/venv/bin/python cargo test -p neurotree-toolkit --test integration
//! differential:: -- --nocapture`, with `behaviortreepy==0.1.4` installed in that venv
//! (`.ci/run` does it). Without `BTCPP_PYTHON`, or when that Python cannot import
//! `behaviortreepy`, the test fails saying why under `.ci/run`
//! (`NEUROTREE_REQUIRE_REFERENCES=1`), and elsewhere prints why it skips and passes.
//! `NEUROTREE_DIFF_TREES=20000`
//! runs more trees (default 500), `NEUROTREE_DIFF_SEED` changes the seed,
//! `NEUROTREE_DIFF_SHOW` how many differing trees are printed (default 8).
//!
//! Differences that are known are listed in [`KNOWN_DIFFERENCES`], each with what
//! BehaviorTree.CPP does and why it is not (yet) what NeuroTree does; NeuroTree's
//! deliberate, documented differences in [`DELIBERATE_DIFFERENCES`]. A step that differs in
//! any other way fails the test with the tree, the steps and both sides' records.
//!
//! Here: the two tables, what a step records, the comparison. In `differential/`:
//! `trees.rs` makes the cases, `neurotree_side.rs` and `btcpp_side.rs` run them,
//! `btcpp_run.py` is the BehaviorTree.CPP driver.

#[path = "differential/btcpp_side.rs"]
mod btcpp_side;
#[path = "differential/neurotree_side.rs"]
mod neurotree_side;
#[path = "differential/trees.rs"]
mod trees;

use std::collections::BTreeMap;
use std::fmt::Write as _;

use trees::{Case, Rng};

/// Trees per run unless `NEUROTREE_DIFF_TREES` says otherwise.
const DEFAULT_TREES: usize = 500;
/// Seed of the first tree unless `NEUROTREE_DIFF_SEED` says otherwise.
const DEFAULT_SEED: u64 = 0x5eed_b7c9;

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
// What one step did, on either side
// ---------------------------------------------------------------------------------------

/// What one step did. Nodes are named `n<i>`; statuses are BehaviorTree.CPP's names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Step {
    /// The root's result, `halted` for a halt, or `error` (the message is not compared).
    pub outcome: String,
    /// Every stored-status change: node, from, to.
    pub changes: Vec<[String; 3]>,
    /// Every scripted-leaf call: node, `start` / `running` / `halted` / `tick`, result.
    pub calls: Vec<[String; 3]>,
    /// Per node, the ticks that began with it Idle or Running (nodes with none left out).
    pub ticks: BTreeMap<String, u64>,
    /// The error's text, if any (shown, not compared).
    pub error: Option<String>,
    /// NeuroTree only: the nodes that returned Skipped, in order (for the filters).
    pub skipped: Vec<String>,
    /// BehaviorTree.CPP only: a wake-up from an earlier call was pending before this
    /// `tickOnce`, and the driver consumed it.
    pub stale_wake: bool,
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

/// What the comparison found: per entry of [`set_aside`], how often it was used; and a
/// report of each case that differs in a way no entry explains.
#[derive(Default)]
struct Tally {
    set_aside: Vec<usize>,
    unexplained: Vec<String>,
    steps: usize,
}

/// The known differences, then the deliberate ones.
fn set_aside() -> Vec<&'static KnownDifference> {
    KNOWN_DIFFERENCES
        .iter()
        .chain(DELIBERATE_DIFFERENCES)
        .collect()
}

/// Compares one case's records, step by step, up to the first difference.
fn compare(
    case: &Case,
    nt: Result<Vec<Step>, String>,
    bt: &Result<Vec<Step>, String>,
    tally: &mut Tally,
) {
    let known = set_aside();
    let (nt, bt) = match (nt, bt) {
        (Ok(nt), Ok(bt)) => (nt, bt),
        (Err(_), Err(_)) => return,
        (Ok(_), Err(error)) => {
            let refused = |k: &&KnownDifference| match k.how {
                SetAside::LoadRefused(f) => f(case, error),
                _ => false,
            };
            match known.iter().position(refused) {
                Some(k) => tally.set_aside[k] += 1,
                None => tally.unexplained.push(format!(
                    "case {}: BT.CPP refuses to load it: {error}\n  xml: {}",
                    case.id, case.xml
                )),
            }
            return;
        }
        (Err(error), Ok(_)) => {
            tally.unexplained.push(format!(
                "case {}: NeuroTree refuses to load it: {error}\n  xml: {}",
                case.id, case.xml
            ));
            return;
        }
    };
    for i in 0..nt.len().max(bt.len()) {
        let (Some(a), Some(b)) = (nt.get(i), bt.get(i)) else {
            let at = i.min(nt.len().min(bt.len()));
            tally.unexplained.push(report(case, at, &nt, bt));
            return;
        };
        tally.steps += 1;
        let mut b = b.clone();
        for (k, difference) in known.iter().enumerate() {
            let done = match difference.how {
                SetAside::Rewrite(rewrite) => rewrite(case, &mut b),
                SetAside::InDriver(did) => did(&b),
                _ => false,
            };
            if done {
                tally.set_aside[k] += 1;
            }
        }
        if a.same(&b) {
            continue;
        }
        let explains = |k: &&KnownDifference| match k.how {
            SetAside::Explains(explains) => explains(case, a, &b),
            _ => false,
        };
        match known.iter().position(explains) {
            Some(k) => tally.set_aside[k] += 1,
            None => tally.unexplained.push(report(case, i, &nt, bt)),
        }
        // After a difference the two states need not match any more.
        return;
    }
}

/// The reference this test compares with is missing. Under `.ci/run`, which installs it and
/// sets `NEUROTREE_REQUIRE_REFERENCES=1`, the test fails: a run without it proves nothing.
/// Elsewhere (a fresh checkout's `cargo test`) it says on stderr what it skipped, and passes.
fn reference_missing(why: &str) {
    if std::env::var("NEUROTREE_REQUIRE_REFERENCES").as_deref() == Ok("1") {
        panic!("{why}; `.ci/run` installs it (with NEUROTREE_ALLOW_SKIP=1 it goes without)");
    }
    use std::io::Write as _;
    // Straight to stderr, past the test harness's capture, so that the run says so.
    let _ = writeln!(
        std::io::stderr(),
        "skipped: {why} (`bash .ci/run` installs it and runs this test)"
    );
}

#[test]
fn random_trees_behave_as_in_behaviortree_cpp() {
    let python = match btcpp_side::python() {
        Ok(p) => p,
        Err(why) => {
            reference_missing(&format!("differential: {why}"));
            return;
        }
    };
    let trees = env_number("NEUROTREE_DIFF_TREES", DEFAULT_TREES as u64) as usize;
    let seed = env_number("NEUROTREE_DIFF_SEED", DEFAULT_SEED);
    let registry = neurotree_side::registry();
    let mut seeder = Rng(seed);
    let mut cases: Vec<Case> = (0..trees).map(|i| trees::case(i, seeder.next())).collect();
    for c in &mut cases {
        neurotree_side::tame(&registry, c);
    }
    let btcpp = btcpp_side::run(&python, &cases);

    let mut tally = Tally {
        set_aside: vec![0; set_aside().len()],
        ..Tally::default()
    };
    for case in &cases {
        let bt = btcpp
            .get(&case.id)
            .unwrap_or_else(|| panic!("no BehaviorTree.CPP result for case {}", case.id));
        compare(case, neurotree_side::run(&registry, case), bt, &mut tally);
    }

    println!(
        "{trees} trees (seed {seed:#x}), {} steps compared with BehaviorTree.CPP 4.8.2",
        tally.steps
    );
    for (i, (k, n)) in set_aside().iter().zip(&tally.set_aside).enumerate() {
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
    if !tally.unexplained.is_empty() {
        let show = env_number("NEUROTREE_DIFF_SHOW", 8) as usize;
        for r in tally.unexplained.iter().take(show) {
            println!("{r}");
        }
        panic!(
            "{} of {trees} trees behave differently in BehaviorTree.CPP (first ones above)",
            tally.unexplained.len()
        );
    }
}
