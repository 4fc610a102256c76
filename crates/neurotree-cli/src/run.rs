//! `neurotree run`: dry-run a BehaviorTree.CPP file with mocks and print what happened.
//!
//! The files load together and the tree to run is picked as `files.rs` says. Each tick
//! prints one JSON line `{"tick":1,"status":"RUNNING"}` (with `--trace`, also one line per
//! status change; a change to FAILURE for which the node gave a reason carries `reason`
//! and, if not 0, `code`, as the `--jsonl` trace does). Ticks count passes of the root: a `tick_once` that passes again at once
//! for a node that asks to be woken counts each pass, toward `--max-ticks` too, and its
//! line carries the number of its last pass. The run ends with a summary line: ticks,
//! final status, per-node tick and halt counts by name in `nodes` (summed over nodes
//! sharing a name, as other tools read it) and by path in `paths` (the paths of
//! [`Blueprint::paths`], one entry per node), and the root blackboard; a run whose root
//! ended FAILURE adds `failure`, why it failed ([`failure_json`]). How the run ended is
//! the exit status (see [`Outcome`]).
//! With `--view`, the tree is also drawn after every tick, with that tick's statuses, on
//! standard error.
//! With `--groot PORT`, the run is also served to Groot2 (see `groot.rs`).
//! With `--studio PORT`, to the browser studio: a page that went back to tick T and
//! stepped or continued from there forks the run, which prints `{"rewind":{"to":T}}` and
//! numbers the ticks that follow on from T. A result a page forced on a node prints
//! `{"force":{"tick":T,"node":PATH,"status":S,"until":"once"|"cleared"}}` before the line
//! of the tick it applied in.
//!
//! The loggers of `neurotree::observe` can watch the run too ([`ObserveArgs`]); they write
//! to stderr or to files, so stdout keeps only the lines above. `--coverage` prints what
//! the run covered (`observe::Coverage`) on stderr at the end, and `--coverage-json FILE`
//! writes it as `observe::coverage_json` does for `neurotree show --coverage FILE`.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree::observe::{
    BtlogWriter, ConsoleLogger, Coverage, CoverageReport, JsonlTrace, Statistics,
};
use neurotree::render::LastTickStatuses;
use neurotree::scenario::write_text;
use neurotree::xml::SharedHookWrapper;
use neurotree::{
    Blueprint, LoadErrorKind, LoadWarning, ManualClock, NodeId, NodeStatus, Observer, Reason,
    Registry, Status, StatusChange, TickError, Tree, XmlLoader,
};
use serde_json::{json, Map, Value};

use crate::files::{self, LoadLimits};
use crate::groot::{GrootArgs, Served as GrootServed};
use crate::live::{self, LiveArgs, SavedRun, Watcher};
use crate::studio::Served;
use crate::testbench::TestbenchArgs;
use crate::Outcome;

mod observe;
mod reload;
mod rewind;

use observe::observers;
pub use observe::{failure_json, ObserveArgs};
use reload::{reload, save_run};
use rewind::RunWorld;

/// What `neurotree run --help` says after the options.
const RUN_AFTER_HELP: &str = "\
Several files load together, as BehaviorTree.CPP's registerBehaviorTreeFromFile loads each:
`neurotree run main.xml subtrees.xml` runs a tree that uses the trees of another file. The
tree run is --tree, else the main_tree_to_execute of the first file, else the only tree,
else the only tree that no other tree uses (said on stderr).

Ticks count passes of the root: with `--tick once`, a tick that passes again at once for a
node that asks to be woken (a Repeat, a Retry) counts each pass, and its line carries the
number of its last pass.

The last line is the summary: ticks, final status, per-node ticks and halts in `nodes`
(keyed by node name, nodes sharing a name summed) and in `paths` (keyed by the node's path
from the root, a list with one entry per node of that path, in tree order), and the root
blackboard.

Exit status:
  0  the root ended SUCCESS
  1  the files did not load (or a log could not be written)
  2  the root ended FAILURE or SKIPPED, or a tick failed with an error
  3  --max-ticks stopped the run while it was RUNNING";

/// What `neurotree run` was asked to do.
#[derive(clap::Args, Debug)]
#[command(after_help = RUN_AFTER_HELP)]
pub struct RunArgs {
    /// The file to run, then any files with trees it uses (all loaded into one loader).
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// The tree to run (default: main_tree_to_execute of the first file, else the only
    /// tree, else the only tree no other tree uses).
    #[arg(long)]
    pub tree: Option<String>,
    /// NAME=OUTCOMES: replace the leaves named NAME (else of type NAME) by a mock playing
    /// OUTCOMES, a comma list of SUCCESS, FAILURE, RUNNING, each optionally `*k`, then the
    /// outputs it writes at every tick: `;PORT=VALUE` or `;PORT:TYPE=VALUE` (the entry the
    /// node's attribute PORT binds, else the entry PORT). Controls and decorators are not
    /// mocked: a NAME only they have is an error, as is a NAME no node has.
    #[arg(long = "mock", value_parser = key_value)]
    pub mocks: Vec<(String, String)>,
    /// Mock with SUCCESS every leaf without an implementation: unregistered, or known only
    /// from a `TreeNodesModel`. Mocks replace leaves only (Actions, Conditions).
    #[arg(long)]
    pub mock_unknown: bool,
    /// A file whose `TreeNodesModel` declares node types the files use (repeatable), as
    /// for `check`, `show` and `lint`: their leaves run as mocks (--mock, --mock-unknown).
    #[arg(long = "model", value_name = "FILE")]
    pub models: Vec<PathBuf>,
    /// KEY=VALUE written to the root blackboard first (integer, else float, else
    /// true/false, else text).
    #[arg(long = "set", value_parser = key_value)]
    pub sets: Vec<(String, String)>,
    /// Stop after this many ticks; every pass of the root counts, including the passes
    /// `--tick once` makes at once for a node that asks to be woken.
    #[arg(long, default_value_t = 100)]
    pub max_ticks: u32,
    /// `once` re-ticks while a node asks to be woken; `exactly-once` does not.
    #[arg(long, default_value = "once", value_parser = ["once", "exactly-once"])]
    pub tick: String,
    /// Milliseconds the manual clock advances before every tick (at most a day: the clock
    /// must not run to its end).
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u64).range(0..=MAX_STEP_MS))]
    pub step_ms: u64,
    /// Also print every status change.
    #[arg(long)]
    pub trace: bool,
    #[command(flatten)]
    pub groot: GrootArgs,
    #[command(flatten)]
    pub studio: crate::studio::StudioFlags,
    /// After each tick, draw the tree with the statuses of that tick on standard error.
    #[arg(long)]
    pub view: bool,
    #[command(flatten)]
    pub observe: ObserveArgs,
    #[command(flatten)]
    pub limits: LoadLimits,
    #[command(flatten)]
    pub nav2: crate::registry::Nav2Args,
    #[command(flatten)]
    pub live: LiveArgs,
    #[command(flatten)]
    pub testbench: TestbenchArgs,
}

impl RunArgs {
    /// `tick_exactly_once` instead of `tick_once`.
    fn exactly_once(&self) -> bool {
        self.tick == "exactly-once"
    }

    /// How far the clock advances before every tick.
    fn step(&self) -> Duration {
        Duration::from_millis(self.step_ms)
    }
}

/// The longest `--step-ms`: a day, in milliseconds.
const MAX_STEP_MS: u64 = 24 * 60 * 60 * 1000;

/// A `NAME=VALUE` of `--mock` or `--set`.
fn key_value(text: &str) -> Result<(String, String), String> {
    text.split_once('=')
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .ok_or_else(|| format!("`{text}` should be NAME=VALUE"))
}

#[derive(Default)]
struct Record {
    /// The pass of the root under way, counted from 1 (a tick of `tick_once` may make
    /// several).
    tick: u32,
    ticks: Vec<u32>,
    halts: Vec<u32>,
    trace: Vec<String>,
    tracing: bool,
    paths: Vec<String>,
    /// The reason given for the coming change of this node to Failure, for its trace line.
    reason: Option<(NodeId, Reason)>,
}

#[derive(Clone)]
struct Recorder(Arc<Mutex<Record>>);

impl Observer for Recorder {
    fn on_tick_start(&mut self, _now: Duration) {
        let mut r = self.0.lock().unwrap_or_else(|e| e.into_inner());
        r.tick += 1;
    }
    fn on_node_tick(&mut self, node: NodeId) {
        let mut r = self.0.lock().unwrap_or_else(|e| e.into_inner());
        r.ticks[node.index()] += 1;
    }
    fn on_status_change(&mut self, c: StatusChange) {
        let mut r = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if c.from == NodeStatus::Running && c.to == NodeStatus::Idle {
            r.halts[c.node.index()] += 1;
        }
        let given = match r.reason.take() {
            Some((node, reason)) if node == c.node && c.to == NodeStatus::Failure => Some(reason),
            _ => None,
        };
        if r.tracing {
            let mut line = json!({
                "tick": r.tick,
                "node": r.paths[c.node.index()],
                "from": c.from.as_str(),
                "to": c.to.as_str(),
            });
            if let Some(reason) = given {
                line["reason"] = json!(reason.message());
                if reason.code() != 0 {
                    line["code"] = json!(reason.code());
                }
            }
            r.trace.push(line.to_string());
        }
    }
    fn on_failure_reason(&mut self, node: NodeId, reason: &Reason) {
        let mut r = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if r.tracing {
            r.reason = Some((node, reason.clone()));
        }
    }
}

/// The tree to run, the registry it was loaded with, and which tree it is.
/// The loader's warnings (deprecated or misspelt names) go to `warnings`, whether or not the
/// tree then builds.
/// `wrap`, when the run is served to the studio, gives the nodes the hooks through which
/// a page forces their results.
fn load(
    files: &[PathBuf],
    opts: &RunArgs,
    warnings: &mut Vec<LoadWarning>,
    wrap: Option<&SharedHookWrapper<()>>,
) -> Result<(Blueprint<()>, Registry<()>, files::Picked), String> {
    let mut registry = crate::registry::with_nav2_controls::<()>(opts.nav2);
    for model in &opts.models {
        let text = files::read(model).map_err(|e| e.to_string())?;
        registry
            .add_model_str(&text, &files::shown(model))
            .map_err(|e| e.to_string())?;
    }
    files::add_models(&mut registry, files).map_err(|e| e.to_string())?;
    opts.testbench.register_enums(&mut registry)?;
    let mut loader = XmlLoader::new(&registry)
        .unknown_type_advice(files::UNKNOWN_TYPE_ADVICE)
        .mock_unknown(opts.mock_unknown)
        .max_nodes(opts.limits.max_nodes);
    for (name, outcomes) in &opts.mocks {
        let outcomes = neurotree::xml::parse_outcomes(outcomes)
            .map_err(|e| format!("--mock {name}={outcomes}: {e}"))?;
        loader = loader.mock(name, outcomes);
    }
    if let Some(wrap) = wrap {
        loader = loader.wrap_hooks(Arc::clone(wrap));
    }
    let mut loader = opts.testbench.substitute(loader)?;
    // Clap asks for at least one file.
    let first = files.first().map(|f| files::shown(f)).unwrap_or_default();
    let loaded = files::load_all(&mut loader, files);
    warnings.extend_from_slice(loader.warnings());
    let picked = loaded.and_then(|()| files::pick_tree(&loader, opts.tree.as_deref(), &first));
    let built = picked
        .map_err(|e| vec![e])
        .and_then(|picked| match loader.build(&picked.id) {
            Ok(blueprint) => Ok((blueprint, picked)),
            // Every error of the tree, as `check` reports them: the builder stops at the first.
            Err(first_error) => Err(all_errors(&loader, &picked.id, first_error)),
        });
    let errors = match built {
        Ok((blueprint, picked)) => return Ok((blueprint, registry, picked)),
        Err(errors) => errors,
    };
    let mut text: Vec<String> = errors
        .iter()
        .map(|e| {
            let mut e = e.clone();
            // An error about the files as a whole (a main tree that is not there) names no
            // file.
            if e.file.is_empty() {
                e.file.clone_from(&first);
            }
            e.to_string()
        })
        .collect();
    let has = |kind| errors.iter().any(|e| e.kind() == kind);
    // Only what was not given already: with --mock-unknown, an unknown node left is one
    // with children, which no mock replaces.
    if (has(LoadErrorKind::UnknownNode) || has(LoadErrorKind::ModelOnly)) && !opts.mock_unknown {
        text.push(
            "hint: mock the leaves without an implementation with --mock-unknown, or one \
             with --mock NAME=OUTCOMES"
                .to_string(),
        );
    }
    if has(LoadErrorKind::TooManyNodes) {
        text.push(files::MAX_NODES_HINT.to_string());
    }
    Err(text.join("\n"))
}

/// The errors of tree `id`, which `first` (the builder's) is one of: `first`, then the
/// others [`XmlLoader::validate_all`] finds, up to `check`'s limit.
fn all_errors(
    loader: &XmlLoader<'_, ()>,
    id: &str,
    first: neurotree::LoadError,
) -> Vec<neurotree::LoadError> {
    let mut errors = vec![first];
    for e in loader.validate_all(id, crate::check::LIMIT) {
        if errors.len() < crate::check::LIMIT && !errors.contains(&e) {
            errors.push(e);
        }
    }
    errors
}

/// Runs the tree of the files; how the run ended, or [`Outcome::Refused`] if the files did
/// not load or a logger could not write (the error is on `err`).
pub fn execute(opts: &RunArgs, out: &mut impl Write, err: &mut impl Write) -> io::Result<Outcome> {
    let files = &opts.files;
    // Before the tree is built: it is built with the studio's hooks, which force results.
    let mut studio = match Served::start(&opts.studio, files, opts.nav2, err)? {
        Ok(studio) => studio,
        Err(()) => return Ok(Outcome::Refused),
    };
    let wrap = studio.as_ref().map(|s| s.force_hooks::<()>(None));
    let mut warnings = Vec::new();
    let loaded = load(files, opts, &mut warnings, wrap.as_ref());
    for w in &warnings {
        writeln!(err, "{w}")?;
    }
    let (blueprint, registry, tree_id) = match loaded {
        Ok((bp, registry, picked)) => {
            picked.note("running", err)?;
            (Arc::new(bp), registry, picked.id)
        }
        Err(e) => {
            writeln!(err, "{e}")?;
            return Ok(Outcome::Refused);
        }
    };
    let groot = match opts.groot.port {
        Some(port) => {
            match GrootServed::start(&blueprint, &registry, &tree_id, port, &opts.groot) {
                Ok(served) => {
                    served.announce(err)?;
                    Some(served)
                }
                Err(e) => {
                    writeln!(err, "{e}")?;
                    return Ok(Outcome::Refused);
                }
            }
        }
        None => None,
    };
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(Arc::clone(&blueprint), clock.clone());
    neurotree::runtime::attach(&mut tree);
    for (key, value) in &opts.sets {
        write_text(tree.blackboard_mut(), key, value);
    }
    let n = blueprint.len();
    let record = Arc::new(Mutex::new(Record {
        ticks: vec![0; n],
        halts: vec![0; n],
        tracing: opts.trace,
        paths: blueprint.paths(),
        ..Record::default()
    }));
    let mut status = "IDLE".to_string();
    // Passes of the root so far: `tick_once` passes again at once for a node that asks to
    // be woken, and each of those counts toward `--max-ticks` (a `Repeat` of -1 over a
    // child that succeeds at once would otherwise spin within one tick).
    let mut ticks: u32 = 0;
    if let Some(path) = &opts.live.resume {
        // Before the clock is read by anything: the resumed run's clock is the saved one's.
        let saved = match SavedRun::read(path, &mut tree, &clock) {
            Ok(saved) => saved,
            Err(e) => {
                writeln!(err, "{e}")?;
                return Ok(Outcome::Refused);
            }
        };
        ticks = saved.ticks;
        status.clone_from(&saved.status);
        let mut r = record.lock().unwrap_or_else(|e| e.into_inner());
        r.tick = saved.ticks;
        r.ticks = saved.node_ticks;
        r.halts = saved.node_halts;
        // The state holds the blackboard: a `--set` given now changes it, a fork.
        for (key, value) in &opts.sets {
            write_text(tree.blackboard_mut(), key, value);
        }
    }
    if opts.live.watch && (opts.view || groot.is_some() || opts.observe.any()) {
        writeln!(
            err,
            "neurotree: --watch reloads the tree, which the loggers, --view and --groot \
             would not follow; run it without them"
        )?;
        return Ok(Outcome::Refused);
    }
    if let Err(e) = live::make_states_dir(&opts.live) {
        writeln!(err, "neurotree: cannot make the states directory: {e}")?;
        return Ok(Outcome::Refused);
    }
    let mut watcher = opts.live.watch.then(|| Watcher::new(files));
    let mut blueprint = blueprint;
    // The run stops at --stop-after as it stops at --max-ticks.
    let limit = opts.max_ticks.min(opts.live.stop_after.unwrap_or(u32::MAX));
    let (mut observers, outputs) = match observers(&opts.observe, &tree, &registry) {
        Ok(attached) => attached,
        Err(e) => {
            writeln!(err, "neurotree: {e}")?;
            return Ok(Outcome::Refused);
        }
    };
    let view = opts.view.then(LastTickStatuses::new);
    if let Some(seen) = &view {
        observers.push(Box::new(seen.clone()));
    }
    if let Some(served) = &groot {
        served.publish(&tree);
        observers.push(Box::new(served.monitor()));
    }
    if let Some(studio) = &mut studio {
        observers.push(studio.attach(&tree, &tree_id));
    }
    tree.set_observer((Recorder(Arc::clone(&record)), observers));
    // The `--set-at` ticks written so far: on a resumed run, those of the ticks it saved.
    let mut set_upto: u32 = ticks;
    // What a page going back restores beside the tree.
    let mut world = RunWorld {
        clock: clock.clone(),
        record: Arc::clone(&record),
    };
    while ticks < limit {
        live::pace(&opts.live);
        if let Some(watcher) = &mut watcher {
            if watcher.changed() {
                if let Some(new) = reload(&mut tree, files, opts, &record, wrap.as_ref(), out, err)?
                {
                    blueprint = new;
                    if let Some(studio) = &mut studio {
                        studio.reattach(&tree, &tree_id);
                    }
                }
            }
        }
        opts.testbench
            .set_due(set_upto, ticks + 1, tree.blackboard_mut());
        set_upto = ticks + 1;
        if let Some(studio) = &mut studio {
            // A page may pause here, edit the blackboard before the tick, or go back to an
            // earlier tick and go on from there.
            if let Some(to) = studio.between_ticks_with(&mut tree, &mut world) {
                let to = u32::try_from(to).unwrap_or(u32::MAX);
                writeln!(out, "{}", json!({ "rewind": { "to": to } }))?;
                ticks = to;
                set_upto = to;
            }
        }
        let left = limit - ticks;
        tree.set_max_passes(left);
        clock.advance(opts.step());
        let result = if opts.exactly_once() {
            tree.tick_exactly_once(&mut ())
        } else {
            tree.tick_once(&mut ())
        };
        // A pass that failed with an error is not in `last_passes`, but it was made.
        let passes = if opts.exactly_once() {
            1
        } else {
            tree.last_passes().max(1)
        };
        let before = ticks;
        ticks = ticks.saturating_add(passes).min(limit);
        // Out of passes because the ticks ran out: stopped as a run still RUNNING is.
        let stopped =
            matches!(&result, Err(TickError::TooManyPasses { passes, .. }) if *passes >= left);
        status = match &result {
            _ if stopped => "RUNNING",
            Ok(s) => s.as_str(),
            Err(TickError::RootSkipped) => "SKIPPED",
            Err(_) => "ERROR",
        }
        .to_string();
        if let Some(studio) = &mut studio {
            // Results a page forced in this tick, numbered as the tick's line is.
            for mut forced in studio.forced() {
                forced["tick"] = json!(ticks);
                writeln!(out, "{}", json!({ "force": forced }))?;
            }
        }
        let trace = std::mem::take(&mut record.lock().unwrap_or_else(|e| e.into_inner()).trace);
        for line in trace {
            writeln!(out, "{line}")?;
        }
        let mut line = json!({ "tick": ticks, "status": status });
        if let Err(e) = &result {
            if !stopped && !matches!(e, TickError::RootSkipped) {
                line["error"] = json!(e.to_string());
            }
        }
        writeln!(out, "{line}")?;
        if let Some(seen) = &view {
            writeln!(
                err,
                "tick {ticks}: {status}\n{}",
                seen.render(&blueprint, true)
            )?;
        }
        if let Some(served) = &groot {
            served.after_tick(&tree);
        }
        if let (Some(k), Some(dir)) = (opts.live.keep_states, &opts.live.states_dir) {
            // The first tick at or past each multiple of K (a tick of several passes may
            // step over one).
            if ticks / k > before / k {
                let path = live::kept_state_path(dir, ticks);
                if let Err(e) = save_run(&tree, ticks, &status, &record, &path) {
                    writeln!(err, "{e}")?;
                    return Ok(Outcome::Refused);
                }
            }
        }
        if matches!(result, Ok(Status::Success | Status::Failure) | Err(_)) {
            break;
        }
    }
    if let Some(path) = &opts.live.save_state {
        if let Err(e) = save_run(&tree, ticks, &status, &record, path) {
            writeln!(err, "{e}")?;
            return Ok(Outcome::Refused);
        }
        writeln!(err, "state after tick {ticks} saved to {}", path.display())?;
    }
    let r = record.lock().unwrap_or_else(|e| e.into_inner());
    let counts = |id: NodeId| json!({ "ticks": r.ticks[id.index()], "halts": r.halts[id.index()] });
    let mut nodes: BTreeMap<String, (u32, u32)> = BTreeMap::new();
    // Siblings of the same name share a path: each keeps its own entry, in tree order.
    let mut paths: BTreeMap<&str, Vec<Value>> = BTreeMap::new();
    for id in blueprint.ids() {
        let entry = nodes.entry(blueprint.name(id).to_string()).or_default();
        entry.0 += r.ticks[id.index()];
        entry.1 += r.halts[id.index()];
        paths
            .entry(&r.paths[id.index()])
            .or_default()
            .push(counts(id));
    }
    let nodes: Map<String, Value> = nodes
        .into_iter()
        .map(|(name, (t, h))| (name, json!({ "ticks": t, "halts": h })))
        .collect();
    let blackboard =
        neurotree::blackboard_json::scope_json(tree.blackboard(), neurotree::ScopeId::ROOT);
    let mut summary = json!({ "summary": {
        "ticks": ticks,
        "status": status,
        "nodes": nodes,
        "paths": paths,
        "blackboard": blackboard,
    }});
    if let Some(failure) = tree.last_failure() {
        summary["summary"]["failure"] = failure_json(&failure);
    }
    if let Some(all) = opts.testbench.blackboards(&tree) {
        summary["summary"]["blackboards"] = all;
    }
    writeln!(out, "{summary}")?;
    let written = outputs.finish(&blueprint, err)?;
    if let Some(served) = groot {
        out.flush()?;
        served.linger(err)?;
    }
    if let Some(mut studio) = studio {
        out.flush()?;
        let ended = match status.as_str() {
            "SUCCESS" => Status::Success,
            "RUNNING" | "IDLE" => Status::Running,
            _ => Status::Failure,
        };
        studio.end(&mut tree, ended);
        studio.linger(err)?;
    }
    Ok(match status.as_str() {
        _ if !written => Outcome::Refused,
        "SUCCESS" => Outcome::Done,
        "RUNNING" | "IDLE" => Outcome::Stopped,
        _ => Outcome::RunFailed,
    })
}
