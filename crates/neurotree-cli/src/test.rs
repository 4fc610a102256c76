//! `neurotree test`: run scenario files — a tree, its mocks and substitutions, blackboard
//! inputs per tick, and expectations per tick — and report as `cargo test` does.
//!
//! The library's [`ScenarioBench`] runs them, on the node types `neurotree run` knows
//! (the built-ins and Nav2's controls); this command prints its results and writes them as
//! JUnit XML.

use std::io::{self, Write};
use std::path::PathBuf;

use neurotree::scenario::{ScenarioBench, ScenarioResult};

use crate::registry::{with_nav2_controls, Nav2Args};
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
  faults = ["Main/Spin=FAILURE@2"]    # optional: node PATH (else type, else name) returns
                                      # STATUS on its Kth call, as in campaigns (#CODE too)
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

/// What the error for a node type no scenario file declares advises.
const UNKNOWN_TYPE_ADVICE: &str =
    "declare it in a TreeNodesModel in one of the scenario's files, or mock it";

/// Runs the scenarios; [`Outcome::Refused`] (exit 1) if one failed.
pub fn execute(opts: &TestArgs, out: &mut impl Write, err: &mut impl Write) -> io::Result<Outcome> {
    let n = opts.scenarios.len();
    writeln!(out, "running {n} scenario{}", if n == 1 { "" } else { "s" })?;
    let registry = with_nav2_controls::<()>(Nav2Args::default());
    let mut bench =
        ScenarioBench::with_registry(&registry, |_| ()).unknown_type_advice(UNKNOWN_TYPE_ADVICE);
    let mut results = Vec::new();
    for file in &opts.scenarios {
        let result = bench.run_file(file);
        writeln!(out, "{result}")?;
        results.push(result);
    }
    let failed = results.iter().filter(|r| !r.passed()).count();
    writeln!(out, "\n{} passed, {failed} failed", n - failed)?;
    if let Some(path) = &opts.junit {
        if let Err(e) = std::fs::write(path, junit(&results)) {
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

/// The results as JUnit XML: one `testsuite` of one `testcase` per scenario.
fn junit(reports: &[ScenarioResult]) -> String {
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
            escape(&r.file.display().to_string()),
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
