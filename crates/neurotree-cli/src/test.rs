//! `neurotree test`: run scenario files — a tree, its mocks and substitutions, blackboard
//! inputs per tick, and expectations per tick — and report as `cargo test` does.
//!
//! A scenario is turned into the arguments of `neurotree run` and run by it (see
//! `run::execute_watched`), so a scenario behaves exactly as the same `run` command would;
//! a [`Checker`] watches the tree after each tick and checks the expectations due.

use std::collections::BTreeMap;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use clap::Parser;
use neurotree::observe::Coverage;
use neurotree::render::LastTickStatuses;
use neurotree::{NodeId, NodeStatus, Observer, StatusChange, Tree};
use serde::Deserialize;
use serde_json::{json, Value};

use crate::run::{self, RunArgs};
use crate::testbench::Watch;
use crate::Outcome;

/// What `neurotree test --help` says after the options: the scenario format.
const TEST_AFTER_HELP: &str = r#"A scenario is a TOML file:

  name = "patrol docks when the battery runs low"  # optional; default: the file's stem
  description = "..."                 # optional, for people
  tree = "patrol.xml"                 # relative to the scenario file
  files = ["subtrees.xml"]            # optional: more files loaded with it
  main = "MainTree"                   # optional, as run --tree
  substitute = "rules.json"           # optional: BehaviorTree.CPP substitution rules
  mock_unknown = true                 # optional, as run --mock-unknown
  ticks = 20                          # optional: the most ticks to run (default 100)
  step_ms = 100                       # optional, as run --step-ms
  coverage = 0.5                      # optional: the least share of outcomes covered
  [mocks]                             # as run --mock NAME=OUTCOMES[;PORT=VALUE...]
  BatteryOK = "SUCCESS*3,FAILURE"
  [enums]                             # as run --enum
  DOCKING = 2
  [[set]]                             # as run --set-at TICK:KEY=VALUE
  tick = 2                            # written just before tick 2 (default 1)
  key = "target"
  value = "dock"
  [[expect]]
  tick = 3                            # after tick 3; without it, at the end of the run
  root = "RUNNING"                    # the root's status
  nodes = { BatteryOK = "SUCCESS" }   # statuses during the tick, by path, name or type
  blackboard = { target = "dock" }    # root blackboard values
  halted = ["Spin"]                   # nodes halted during the tick
  failure = { node = "Spin", reason = "timed out" }  # a link of why the root failed

Ticks are numbered as run prints them. A node key matches the nodes of that path, else
of that name, else of that type; the expectation holds if one of them had the status.
The run stops when the root completes or after `ticks`; an expectation for a tick the run
did not reach fails.

Each scenario prints `test NAME ... ok` or `test NAME ... FAILED` and why, then the last
line is `N passed, M failed`.

Exit status:
  0  every scenario passed
  1  a scenario failed, or could not be read or run"#;

/// What `neurotree test` was asked to do.
#[derive(clap::Args, Debug)]
#[command(after_help = TEST_AFTER_HELP)]
pub struct TestArgs {
    /// The scenario files (TOML; see below).
    #[arg(required = true, value_name = "SCENARIO")]
    pub scenarios: Vec<PathBuf>,
    /// Also write the results as JUnit XML to FILE, for CI systems.
    #[arg(long, value_name = "FILE")]
    pub junit: Option<PathBuf>,
}

/// A scenario file.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Scenario {
    name: Option<String>,
    #[allow(dead_code)]
    description: Option<String>,
    tree: String,
    #[serde(default)]
    files: Vec<String>,
    main: Option<String>,
    substitute: Option<String>,
    #[serde(default)]
    mock_unknown: bool,
    ticks: Option<u32>,
    step_ms: Option<u64>,
    coverage: Option<f64>,
    #[serde(default)]
    mocks: BTreeMap<String, String>,
    #[serde(default)]
    enums: BTreeMap<String, i64>,
    #[serde(default)]
    set: Vec<SetAt>,
    #[serde(default)]
    expect: Vec<Expect>,
}

/// A value written before a tick.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SetAt {
    #[serde(default = "first_tick")]
    tick: u32,
    key: String,
    value: toml::Value,
}

fn first_tick() -> u32 {
    1
}

/// What must hold after a tick (or at the end).
#[derive(Deserialize, Debug, Default, Clone)]
#[serde(deny_unknown_fields)]
struct Expect {
    tick: Option<u32>,
    root: Option<String>,
    #[serde(default)]
    nodes: BTreeMap<String, String>,
    #[serde(default)]
    blackboard: BTreeMap<String, toml::Value>,
    #[serde(default)]
    halted: Vec<String>,
    failure: Option<FailureExpect>,
}

/// A link of the chain of why the root failed.
#[derive(Deserialize, Debug, Default, Clone)]
#[serde(deny_unknown_fields)]
struct FailureExpect {
    node: Option<String>,
    reason: Option<String>,
}

/// How one scenario went.
struct Report {
    name: String,
    file: String,
    seconds: f64,
    /// Why it failed; empty if it passed.
    problems: Vec<String>,
}

/// Runs the scenarios; [`Outcome::Refused`] (exit 1) if one failed.
pub fn execute(opts: &TestArgs, out: &mut impl Write, err: &mut impl Write) -> io::Result<Outcome> {
    let n = opts.scenarios.len();
    writeln!(out, "running {n} scenario{}", if n == 1 { "" } else { "s" })?;
    let mut reports = Vec::new();
    for file in &opts.scenarios {
        let started = Instant::now();
        let shown = file.display().to_string();
        let (name, problems) = match read(file) {
            Ok(scenario) => {
                let name = scenario.name.clone().unwrap_or_else(|| stem(file));
                (name, run_scenario(&scenario, file))
            }
            Err(e) => (stem(file), vec![e]),
        };
        let verdict = if problems.is_empty() { "ok" } else { "FAILED" };
        writeln!(out, "test {name} ... {verdict}")?;
        for problem in &problems {
            for line in problem.lines() {
                writeln!(out, "    {line}")?;
            }
        }
        reports.push(Report {
            name,
            file: shown,
            seconds: started.elapsed().as_secs_f64(),
            problems,
        });
    }
    let failed = reports.iter().filter(|r| !r.problems.is_empty()).count();
    writeln!(out, "\n{} passed, {failed} failed", n - failed)?;
    if let Some(path) = &opts.junit {
        if let Err(e) = std::fs::write(path, junit(&reports)) {
            writeln!(err, "neurotree: --junit {}: {e}", path.display())?;
            return Ok(Outcome::Refused);
        }
    }
    Ok(if failed == 0 {
        Outcome::Done
    } else {
        Outcome::Refused
    })
}

/// The file's name without its extension.
fn stem(file: &Path) -> String {
    file.file_stem().map_or_else(
        || file.display().to_string(),
        |s| s.to_string_lossy().into(),
    )
}

/// Reads and parses a scenario file; the error names the file and, for TOML, the place.
fn read(file: &Path) -> Result<Scenario, String> {
    let shown = file.display();
    let text = std::fs::read_to_string(file)
        .map_err(|e| format!("{shown}: cannot read the scenario: {e}"))?;
    toml::from_str(&text).map_err(|e| {
        let place = e
            .span()
            .map(|span| {
                let before = &text[..span.start.min(text.len())];
                let line = before.matches('\n').count() + 1;
                let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
                format!("{line}:{col}: ")
            })
            .unwrap_or_default();
        format!(
            "{shown}:{place}error: {}; see `neurotree test --help` for the scenario format",
            e.message()
        )
    })
}

/// The text `--set` reads for a TOML value.
fn value_text(value: &toml::Value) -> Result<String, String> {
    match value {
        toml::Value::String(s) => Ok(s.clone()),
        toml::Value::Integer(i) => Ok(i.to_string()),
        toml::Value::Float(f) => Ok(f.to_string()),
        toml::Value::Boolean(b) => Ok(b.to_string()),
        other => Err(format!(
            "a {} cannot be written to the blackboard; use a string, number or boolean",
            other.type_str()
        )),
    }
}

/// The JSON a blackboard entry of a TOML value prints as.
fn value_json(value: &toml::Value) -> Result<Value, String> {
    match value {
        toml::Value::String(s) => Ok(json!(s)),
        toml::Value::Integer(i) => Ok(json!(i)),
        toml::Value::Float(f) => Ok(json!(f)),
        toml::Value::Boolean(b) => Ok(json!(b)),
        other => Err(format!(
            "a {} is no blackboard value; use a string, number or boolean",
            other.type_str()
        )),
    }
}

/// The `neurotree run` arguments the scenario stands for.
fn run_args(s: &Scenario, file: &Path) -> Result<RunArgs, String> {
    let dir = file.parent().unwrap_or(Path::new(""));
    let path = |p: &str| dir.join(p).display().to_string();
    let mut argv: Vec<String> = vec!["run".into(), path(&s.tree)];
    argv.extend(s.files.iter().map(|f| path(f)));
    let mut flag = |name: &str, value: String| {
        argv.push(format!("--{name}"));
        argv.push(value);
    };
    if let Some(main) = &s.main {
        flag("tree", main.clone());
    }
    if let Some(rules) = &s.substitute {
        flag("substitute", path(rules));
    }
    for (name, outcomes) in &s.mocks {
        flag("mock", format!("{name}={outcomes}"));
    }
    for (name, value) in &s.enums {
        flag("enum", format!("{name}={value}"));
    }
    for set in &s.set {
        let value = value_text(&set.value).map_err(|e| format!("[[set]] {}: {e}", set.key))?;
        flag("set-at", format!("{}:{}={value}", set.tick, set.key));
    }
    flag("max-ticks", s.ticks.unwrap_or(100).to_string());
    if let Some(step) = s.step_ms {
        flag("step-ms", step.to_string());
    }
    if s.mock_unknown {
        argv.push("--mock-unknown".into());
    }
    /// `neurotree run`'s arguments alone.
    #[derive(Parser)]
    struct AsRun {
        #[command(flatten)]
        run: RunArgs,
    }
    AsRun::try_parse_from(&argv)
        .map(|a| a.run)
        .map_err(|e| e.to_string().trim_end().to_string())
}

/// Runs a scenario; the problems found (none if it passed).
fn run_scenario(s: &Scenario, file: &Path) -> Vec<String> {
    let shown = file.display();
    if let Some(c) = s.coverage {
        if !(0.0..=1.0).contains(&c) {
            return vec![format!(
                "{shown}: coverage = {c}: the share of outcomes covered is from 0 to 1"
            )];
        }
    }
    let args = match run_args(s, file) {
        Ok(args) => args,
        Err(e) => return vec![format!("{shown}: {e}")],
    };
    let mut checker = Checker::new(s);
    let mut sink = Vec::new();
    let mut errors = Vec::new();
    let outcome = match run::execute_watched(&args, &mut sink, &mut errors, &mut checker) {
        Ok(outcome) => outcome,
        Err(e) => return vec![format!("the run failed: {e}")],
    };
    if outcome == Outcome::Refused {
        let said = String::from_utf8_lossy(&errors);
        return vec![format!("the tree did not load:\n{}", said.trim_end())];
    }
    checker.finish(s)
}

/// Checks the expectations as the run goes.
struct Checker {
    /// Expectations by tick (`None`: the end), with whether each was checked.
    due: Vec<(Option<u32>, bool)>,
    statuses: LastTickStatuses,
    halts: Halts,
    coverage: Option<Coverage>,
    problems: Vec<String>,
    /// The problems of the end expectations, as of the latest tick.
    at_end: Vec<String>,
    /// The last tick and the root's status then.
    last: Option<(u32, String)>,
    /// The expectations of the scenario.
    expects: Vec<Expect>,
    /// Outcomes covered and possible as of the latest tick, if the scenario asks for a
    /// coverage (`Some((0, 0))` until the first tick).
    covered: Option<(usize, usize)>,
}

impl Checker {
    fn new(s: &Scenario) -> Self {
        let expects = s.expect.clone();
        Self {
            due: expects.iter().map(|e| (e.tick, false)).collect(),
            statuses: LastTickStatuses::new(),
            halts: Halts::default(),
            coverage: None,
            problems: Vec::new(),
            at_end: Vec::new(),
            last: None,
            expects,
            // The observer is made once the tree is known (`attach`).
            covered: s.coverage.map(|_| (0, 0)),
        }
    }

    /// The problems once the run is over.
    fn finish(mut self, s: &Scenario) -> Vec<String> {
        let (last_tick, last_status) = self.last.clone().unwrap_or((0, "IDLE".into()));
        for (tick, checked) in &self.due {
            if let (Some(tick), false) = (tick, checked) {
                self.problems.push(format!(
                    "tick {tick}: not reached; the run ended after tick {last_tick} with \
                     {last_status}"
                ));
            }
        }
        self.problems.append(&mut self.at_end);
        if let (Some(least), Some((covered, possible))) = (s.coverage, self.covered) {
            let share = if possible == 0 {
                1.0
            } else {
                covered as f64 / possible as f64
            };
            if share < least {
                self.problems.push(format!(
                    "coverage {covered}/{possible} ({:.0}%) is below the {:.0}% asked for",
                    share * 100.0,
                    least * 100.0
                ));
            }
        }
        self.problems
    }

    /// The problems of `e` after tick `tick`.
    fn check(&self, e: &Expect, tick: u32, status: &str, tree: &Tree<()>) -> Vec<String> {
        let at = match e.tick {
            Some(_) => format!("tick {tick}"),
            None => format!("end (tick {tick})"),
        };
        let mut problems = Vec::new();
        if let Some(root) = &e.root {
            if !root.eq_ignore_ascii_case(status) {
                problems.push(format!("{at}: root is {status}, expected {root}"));
            }
        }
        let bp = tree.blueprint();
        let paths = bp.paths();
        for (key, expected) in &e.nodes {
            let ids = nodes_for(tree, &paths, key);
            if ids.is_empty() {
                problems.push(format!("{at}: no node has the path, name or type `{key}`"));
                continue;
            }
            let seen: Vec<&str> = ids
                .iter()
                .map(|&id| self.statuses.status(id).as_str())
                .collect();
            if !seen.iter().any(|s| s.eq_ignore_ascii_case(expected)) {
                problems.push(format!(
                    "{at}: node `{key}` is {}, expected {expected}",
                    seen.join("/")
                ));
            }
        }
        for (key, expected) in &e.blackboard {
            let expected = match value_json(expected) {
                Ok(v) => v,
                Err(err) => {
                    problems.push(format!("{at}: blackboard `{key}`: {err}"));
                    continue;
                }
            };
            let actual = neurotree::blackboard_json::entry_json(
                tree.blackboard(),
                neurotree::ScopeId::ROOT,
                key,
            );
            if !same_value(&actual, &expected) {
                let actual = if actual.is_null() {
                    "not set".to_string()
                } else {
                    actual.to_string()
                };
                problems.push(format!(
                    "{at}: blackboard `{key}` is {actual}, expected {expected}"
                ));
            }
        }
        let halted = self
            .halts
            .0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone();
        for key in &e.halted {
            let ids = nodes_for(tree, &paths, key);
            if !ids.iter().any(|id| halted.contains(id)) {
                problems.push(format!("{at}: `{key}` was not halted"));
            }
        }
        if let Some(f) = &e.failure {
            problems.extend(failure_problems(tree, f, &at, status));
        }
        problems
    }
}

impl Watch for Checker {
    fn attach(&mut self, tree: &Tree<()>) -> Vec<Box<dyn Observer>> {
        let mut attached: Vec<Box<dyn Observer>> = vec![
            Box::new(self.statuses.clone()),
            Box::new(self.halts.clone()),
        ];
        if self.covered.is_some() {
            let coverage = Coverage::new(tree.blueprint());
            attached.push(Box::new(coverage.clone()));
            self.coverage = Some(coverage);
        }
        attached
    }

    fn after_tick(&mut self, tick: u32, line: &Value, tree: &Tree<()>) {
        let status = line["status"].as_str().unwrap_or("ERROR");
        if let Some(error) = line["error"].as_str() {
            self.problems
                .push(format!("tick {tick}: the tick failed: {error}"));
        }
        for i in 0..self.expects.len() {
            match self.due[i] {
                (Some(at), false) if at <= tick => {
                    let found = self.check(&self.expects[i], tick, status, tree);
                    self.problems.extend(found);
                    self.due[i].1 = true;
                }
                _ => {}
            }
        }
        // The end expectations hold or not as of the latest tick.
        let mut at_end = Vec::new();
        for i in 0..self.expects.len() {
            if self.due[i].0.is_none() {
                at_end.extend(self.check(&self.expects[i], tick, status, tree));
            }
        }
        self.at_end = at_end;
        if let Some(coverage) = &self.coverage {
            let report = coverage.report(tree.blueprint());
            self.covered = Some((report.covered_outcomes(), report.possible_outcomes()));
        }
        self.last = Some((tick, status.to_string()));
        self.halts
            .0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
    }
}

/// The nodes `key` names: by path, else name, else type.
fn nodes_for(tree: &Tree<()>, paths: &[String], key: &str) -> Vec<NodeId> {
    let bp = tree.blueprint();
    let ids: Vec<NodeId> = bp.ids().collect();
    let by_path: Vec<NodeId> = ids
        .iter()
        .copied()
        .filter(|id| paths[id.index()] == key)
        .collect();
    if !by_path.is_empty() {
        return by_path;
    }
    let by_name: Vec<NodeId> = ids
        .iter()
        .copied()
        .filter(|&id| bp.name(id) == key)
        .collect();
    if !by_name.is_empty() {
        return by_name;
    }
    ids.into_iter()
        .filter(|&id| bp.type_id(id) == key)
        .collect()
}

/// Two JSON values equal as the blackboard means them: numbers by value.
fn same_value(a: &Value, b: &Value) -> bool {
    match (a.as_f64(), b.as_f64()) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// The problems of a failure expectation.
fn failure_problems(tree: &Tree<()>, f: &FailureExpect, at: &str, status: &str) -> Vec<String> {
    let Some(failure) = tree.last_failure() else {
        return vec![format!(
            "{at}: expected the root to fail, but it is {status}"
        )];
    };
    let mut problems = Vec::new();
    let chain: Vec<(&str, Option<String>)> = failure
        .links
        .iter()
        .flat_map(|link| {
            std::iter::once((link.path.as_str(), link.reason.as_ref())).chain(
                link.tried
                    .iter()
                    .map(|t| (t.path.as_str(), t.reason.as_ref())),
            )
        })
        .map(|(path, reason)| (path, reason.map(|r| r.message().into_owned())))
        .collect();
    let names = |node: &str, path: &str| path == node || path.ends_with(&format!("/{node}"));
    if let Some(node) = &f.node {
        if !chain.iter().any(|(path, _)| names(node, path)) {
            let paths: Vec<&str> = failure.links.iter().map(|l| l.path.as_str()).collect();
            problems.push(format!(
                "{at}: `{node}` is not in the failure chain ({})",
                paths.join(" <- ")
            ));
        }
    }
    if let Some(reason) = &f.reason {
        let given: Vec<&str> = chain.iter().filter_map(|(_, r)| r.as_deref()).collect();
        if !given.iter().any(|r| r.contains(reason.as_str())) {
            problems.push(format!(
                "{at}: no failure reason contains `{reason}` (reasons: {})",
                if given.is_empty() {
                    "none".to_string()
                } else {
                    given.join("; ")
                }
            ));
        }
    }
    problems
}

/// The nodes halted since the last tick's check.
#[derive(Clone, Default)]
struct Halts(Arc<Mutex<Vec<NodeId>>>);

impl Observer for Halts {
    fn on_status_change(&mut self, c: StatusChange) {
        if c.from == NodeStatus::Running && c.to == NodeStatus::Idle {
            self.0
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(c.node);
        }
    }
}

/// The results as JUnit XML: one `testsuite` of one `testcase` per scenario.
fn junit(reports: &[Report]) -> String {
    use neurotree::xml::escape;
    let failed = reports.iter().filter(|r| !r.problems.is_empty()).count();
    let total: f64 = reports.iter().map(|r| r.seconds).sum();
    let mut xml = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    xml.push_str(&format!(
        "<testsuites name=\"neurotree test\" tests=\"{}\" failures=\"{failed}\" time=\"{total:.3}\">\n",
        reports.len()
    ));
    xml.push_str(&format!(
        "  <testsuite name=\"scenarios\" tests=\"{}\" failures=\"{failed}\" errors=\"0\" skipped=\"0\" time=\"{total:.3}\">\n",
        reports.len()
    ));
    for r in reports {
        let head = format!(
            "    <testcase name=\"{}\" classname=\"{}\" time=\"{:.3}\"",
            escape(&r.name),
            escape(&r.file),
            r.seconds
        );
        match r.problems.first() {
            None => xml.push_str(&format!("{head}/>\n")),
            Some(first) => {
                let first = first.lines().next().unwrap_or_default();
                let body = r.problems.join("\n");
                // Element text keeps its line breaks: only &, < and > need escaping.
                let body = body
                    .replace('&', "&amp;")
                    .replace('<', "&lt;")
                    .replace('>', "&gt;");
                xml.push_str(&format!(
                    "{head}>\n      <failure message=\"{}\">{body}</failure>\n    </testcase>\n",
                    escape(first)
                ));
            }
        }
    }
    xml.push_str("  </testsuite>\n</testsuites>\n");
    xml
}
