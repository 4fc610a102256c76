//! `neurotree run`: dry-run a BehaviorTree.CPP file with mocks and print what happened.
//!
//! Each tick prints one JSON line `{"tick":1,"status":"RUNNING"}` (with `--trace`, also one
//! line per status change), and the run ends with a summary line: ticks, final status,
//! per-node tick and halt counts (summed over nodes sharing a name) and the root blackboard.
//! With `--view`, the tree is also drawn after every tick, with that tick's statuses, on
//! standard error.

use std::collections::BTreeMap;
use std::io::{self, Write};
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree::render::LastTickStatuses;
use neurotree::{
    Blueprint, ManualClock, NodeId, NodeStatus, Observer, Status, StatusChange, TickError, Tree,
    XmlLoader,
};
use serde_json::{json, Map, Value};

/// What `neurotree run` was asked to do.
pub struct RunOptions {
    /// The tree to run (default: the file's main tree).
    pub tree: Option<String>,
    /// `(name, outcomes)` pairs.
    pub mocks: Vec<(String, String)>,
    /// Mock every unregistered leaf with SUCCESS.
    pub mock_unknown: bool,
    /// `(key, value)` pairs written to the root blackboard first.
    pub sets: Vec<(String, String)>,
    /// Stop after this many ticks.
    pub max_ticks: u32,
    /// `tick_exactly_once` instead of `tick_once`.
    pub exactly_once: bool,
    /// Clock step before every tick.
    pub step: Duration,
    /// Print every status change.
    pub trace: bool,
    /// Draw the tree with each tick's statuses on the error stream.
    pub view: bool,
}

#[derive(Default)]
struct Record {
    tick: u32,
    ticks: Vec<u32>,
    halts: Vec<u32>,
    trace: Vec<String>,
    tracing: bool,
    paths: Vec<String>,
}

#[derive(Clone)]
struct Recorder(Arc<Mutex<Record>>);

impl Observer for Recorder {
    fn on_node_tick(&mut self, node: NodeId) {
        let mut r = self.0.lock().unwrap_or_else(|e| e.into_inner());
        r.ticks[node.index()] += 1;
    }
    fn on_status_change(&mut self, c: StatusChange) {
        let mut r = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if c.from == NodeStatus::Running && c.to == NodeStatus::Idle {
            r.halts[c.node.index()] += 1;
        }
        if r.tracing {
            let line = json!({
                "tick": r.tick,
                "node": r.paths[c.node.index()],
                "from": c.from.as_str(),
                "to": c.to.as_str(),
            })
            .to_string();
            r.trace.push(line);
        }
    }
}

/// The value of `--set KEY=VALUE`: integer, else float, else bool, else text.
fn set_value(bb: &mut neurotree::Blackboard, key: &str, text: &str) {
    let result = if let Ok(i) = text.parse::<i64>() {
        bb.set(key, i)
    } else if let Ok(f) = text.parse::<f64>() {
        bb.set(key, f)
    } else if let Ok(b) = text.parse::<bool>() {
        bb.set(key, b)
    } else {
        bb.set(key, text.to_string())
    };
    if result.is_err() {
        bb.replace_in(
            neurotree::ScopeId::ROOT,
            key,
            text.to_string(),
            Duration::ZERO,
        );
    }
}

/// A blackboard value as JSON (types it does not know print as their type name).
fn json_of(bb: &neurotree::Blackboard, key: &str) -> Value {
    let Some(any) = bb.get_any_in(neurotree::ScopeId::ROOT, key) else {
        return Value::Null;
    };
    if let Some(v) = any.downcast_ref::<i64>() {
        json!(v)
    } else if let Some(v) = any.downcast_ref::<f64>() {
        json!(v)
    } else if let Some(v) = any.downcast_ref::<bool>() {
        json!(v)
    } else if let Some(v) = any.downcast_ref::<String>() {
        json!(v)
    } else {
        let type_name = bb.info(key).map_or("unknown", |i| i.type_name);
        json!(format!("<{type_name}>"))
    }
}

fn load(file: &Path, opts: &RunOptions) -> Result<Blueprint<()>, String> {
    let mut registry = crate::registry::with_nav2_controls::<()>();
    if let Ok(text) = std::fs::read_to_string(file) {
        registry
            .add_model_str(&text, &file.display().to_string())
            .map_err(|e| e.to_string())?;
    }
    let mut loader = XmlLoader::new(&registry).mock_unknown(opts.mock_unknown);
    for (name, outcomes) in &opts.mocks {
        let outcomes = neurotree::xml::parse_outcomes(outcomes)
            .map_err(|e| format!("--mock {name}={outcomes}: {e}"))?;
        loader = loader.mock(name, outcomes);
    }
    loader.load_file(file).map_err(|e| e.to_string())?;
    match &opts.tree {
        Some(id) => loader.build(id),
        None => loader.build_main(),
    }
    .map_err(|e| e.to_string())
}

/// Runs `file`; `Ok(false)` if it did not load (the error is on `err`).
pub fn run(
    file: &Path,
    opts: &RunOptions,
    out: &mut impl Write,
    err: &mut impl Write,
) -> io::Result<bool> {
    let blueprint = match load(file, opts) {
        Ok(bp) => Arc::new(bp),
        Err(e) => {
            writeln!(err, "{e}")?;
            return Ok(false);
        }
    };
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(Arc::clone(&blueprint), clock.clone());
    for (key, value) in &opts.sets {
        set_value(tree.blackboard_mut(), key, value);
    }
    let n = blueprint.len();
    let record = Arc::new(Mutex::new(Record {
        ticks: vec![0; n],
        halts: vec![0; n],
        tracing: opts.trace,
        paths: blueprint.ids().map(|id| blueprint.path(id)).collect(),
        ..Record::default()
    }));
    let recorder = Recorder(Arc::clone(&record));
    let view = opts.view.then(LastTickStatuses::new);
    match &view {
        Some(seen) => tree.set_observer((recorder, seen.clone())),
        None => tree.set_observer(recorder),
    };
    let mut status = "IDLE";
    let mut ticks = 0;
    while ticks < opts.max_ticks {
        ticks += 1;
        record.lock().unwrap_or_else(|e| e.into_inner()).tick = ticks;
        clock.advance(opts.step);
        let result = if opts.exactly_once {
            tree.tick_exactly_once(&mut ())
        } else {
            tree.tick_once(&mut ())
        };
        status = match &result {
            Ok(s) => s.as_str(),
            Err(TickError::RootSkipped) => "SKIPPED",
            Err(_) => "ERROR",
        };
        let trace = std::mem::take(&mut record.lock().unwrap_or_else(|e| e.into_inner()).trace);
        for line in trace {
            writeln!(out, "{line}")?;
        }
        let mut line = json!({ "tick": ticks, "status": status });
        if let Err(e) = &result {
            if !matches!(e, TickError::RootSkipped) {
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
        if matches!(result, Ok(Status::Success | Status::Failure) | Err(_)) {
            break;
        }
    }
    let r = record.lock().unwrap_or_else(|e| e.into_inner());
    let mut nodes: BTreeMap<String, (u32, u32)> = BTreeMap::new();
    for id in blueprint.ids() {
        let entry = nodes.entry(blueprint.name(id).to_string()).or_default();
        entry.0 += r.ticks[id.index()];
        entry.1 += r.halts[id.index()];
    }
    let nodes: Map<String, Value> = nodes
        .into_iter()
        .map(|(name, (t, h))| (name, json!({ "ticks": t, "halts": h })))
        .collect();
    let bb = tree.blackboard();
    let blackboard: Map<String, Value> =
        bb.keys().map(|k| (k.to_string(), json_of(bb, k))).collect();
    let summary = json!({ "summary": {
        "ticks": ticks,
        "status": status,
        "nodes": nodes,
        "blackboard": blackboard,
    }});
    writeln!(out, "{summary}")?;
    Ok(true)
}
