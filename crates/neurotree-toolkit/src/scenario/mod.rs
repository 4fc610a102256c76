//! Scenario files: a tree, its mocks and substitutions, blackboard values written before
//! given ticks, and what must hold after given ticks, in TOML — tests of a tree that need
//! no code. `neurotree test` runs them from the command line, `neurotree.run_scenarios`
//! from Python; both through a [`ScenarioBench`].
//!
//! ```toml
//! name = "patrol docks when the battery runs low"  # optional; default: the file's stem
//! description = "..."                 # optional, for people
//! tree = "patrol.xml"                 # relative to the scenario file
//! files = ["subtrees.xml"]            # optional: more files loaded with it
//! main = "MainTree"                   # optional: the tree to run
//! substitute = "rules.json"           # optional: BehaviorTree.CPP substitution rules
//! mock_unknown = true                 # optional: leaves without an implementation succeed
//! ticks = 20                          # optional: the most ticks to run (default 100)
//! step_ms = 100                       # optional: the clock's advance before each tick
//! coverage = 0.5                      # optional: the least share of outcomes covered
//! faults = ["Root/Spin=FAILURE@2"]     # optional: node PATH (or name, or type) returns
//!                                     # STATUS on its Kth call ([`crate::fault`])
//! [mocks]                             # leaves by name or type, as `run --mock` reads them
//! BatteryOK = "SUCCESS*3,FAILURE"
//! [enums]                             # scripting enums
//! DOCKING = 2
//! [[set]]
//! tick = 2                            # written just before tick 2 (default 1)
//! key = "target"
//! value = "dock"
//! [[expect]]
//! tick = 3                            # after tick 3; without it, at the end of the run
//! root = "RUNNING"                    # the root's status
//! nodes = { BatteryOK = "SUCCESS" }   # statuses during the tick, by path, name or type
//! blackboard = { target = "dock" }    # root blackboard values
//! halted = ["Spin"]                   # nodes halted during the tick
//! failure = { node = "Spin", reason = "timed out" }  # a link of why the root failed
//! ```
//!
//! A scenario runs as `neurotree run` would run its tree with the same flags: ticks count
//! passes of the root, and a tick that passes again at once (a node that asks to be woken)
//! counts each pass. A node key matches the nodes of that path, else of that name, else of
//! that type; the expectation holds if one of them had the status. The run stops when the
//! root completes or after `ticks`; an expectation for a tick the run did not reach fails.
//!
//! The node types are those of the registry the bench is given (its own leaves, Nav2's
//! models), copied for each scenario, plus the `TreeNodesModel`s of the scenario's files.
//!
//! ```
//! use neurotree::scenario::ScenarioBench;
//!
//! let dir = tempfile::tempdir().unwrap();
//! std::fs::write(dir.path().join("door.xml"), r#"<root BTCPP_format="4">
//!     <BehaviorTree ID="Main"><Fallback><OpenDoor/><SmashDoor/></Fallback></BehaviorTree>
//! </root>"#).unwrap();
//! let file = dir.path().join("door.toml");
//! std::fs::write(&file, r#"
//!     tree = "door.xml"
//!     mocks = { OpenDoor = "FAILURE", SmashDoor = "SUCCESS" }
//!     [[expect]]
//!     root = "SUCCESS"
//!     nodes = { SmashDoor = "SUCCESS" }
//! "#).unwrap();
//! let result = ScenarioBench::new().run_file(&file);
//! assert!(result.passed(), "{result}");
//! assert_eq!(result.to_string(), "test door ... ok");
//! ```

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use neurotree_core::{Blackboard, Blueprint, ScopeId};
use serde::Deserialize;

use crate::Registry;

mod check;
mod run;

/// The longest `step_ms`: a day, so that the clock cannot run to its end.
pub const MAX_STEP_MS: u64 = 24 * 60 * 60 * 1000;

/// The ticks a scenario runs at most when it does not say.
pub const DEFAULT_TICKS: u32 = 100;

/// A scenario file, as read (see the [module](self) for its fields).
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// The name results show; the file's stem when not given.
    pub name: Option<String>,
    /// For people.
    pub description: Option<String>,
    /// The tree file, relative to the scenario file.
    pub tree: String,
    /// More files loaded with it.
    #[serde(default)]
    pub files: Vec<String>,
    /// The tree to run.
    pub main: Option<String>,
    /// A BehaviorTree.CPP substitution rules file.
    pub substitute: Option<String>,
    /// Leaves without an implementation succeed.
    #[serde(default)]
    pub mock_unknown: bool,
    /// The most ticks to run ([`DEFAULT_TICKS`] when not given).
    pub ticks: Option<u32>,
    /// Milliseconds the clock advances before each tick (100 when not given).
    pub step_ms: Option<u64>,
    /// The least share of outcomes the run must cover, from 0 to 1.
    pub coverage: Option<f64>,
    /// Leaves replaced by scripted outcomes, by name or type.
    #[serde(default)]
    pub mocks: BTreeMap<String, String>,
    /// Faults injected into nodes, `PATH=STATUS@K` or `PATH=STATUS@K#CODE` as
    /// [`crate::fault::NodeFault`] reads them: a node chosen by its path (which tells apart
    /// leaves that share a name), else its type, else its name.
    #[serde(default)]
    pub faults: Vec<String>,
    /// Scripting enums.
    #[serde(default)]
    pub enums: BTreeMap<String, i64>,
    /// Values written before given ticks.
    #[serde(default)]
    pub set: Vec<SetAt>,
    /// What must hold.
    #[serde(default)]
    pub expect: Vec<Expect>,
}

/// A value written to the root blackboard just before a tick.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct SetAt {
    /// The tick, from 1.
    #[serde(default = "first_tick")]
    pub tick: u32,
    /// The entry.
    pub key: String,
    /// A string, number or boolean, written as [`write_text`] reads its text.
    pub value: toml::Value,
}

fn first_tick() -> u32 {
    1
}

/// What must hold after a tick (or at the end of the run).
#[derive(Deserialize, Debug, Default, Clone)]
#[serde(deny_unknown_fields)]
pub struct Expect {
    /// The tick; `None` for the end of the run.
    pub tick: Option<u32>,
    /// The root's status.
    pub root: Option<String>,
    /// Statuses during the tick, by node path, name or type.
    #[serde(default)]
    pub nodes: BTreeMap<String, String>,
    /// Root blackboard values.
    #[serde(default)]
    pub blackboard: BTreeMap<String, toml::Value>,
    /// Nodes halted during the tick.
    #[serde(default)]
    pub halted: Vec<String>,
    /// A link of the chain of why the root failed.
    pub failure: Option<FailureExpect>,
}

/// A link of the chain of why the root failed: a node in it, a reason one of its links gave.
#[derive(Deserialize, Debug, Default, Clone)]
#[serde(deny_unknown_fields)]
pub struct FailureExpect {
    /// A node's path, or its path's last part.
    pub node: Option<String>,
    /// Text a reason contains.
    pub reason: Option<String>,
}

impl Scenario {
    /// Reads and parses the scenario file at `file`; the error names the file and, for
    /// TOML, the line and column (`broken.toml:2:9: error: ...`).
    pub fn read(file: &Path) -> Result<Scenario, String> {
        let text = std::fs::read_to_string(file)
            .map_err(|e| format!("{}: cannot read the scenario: {e}", file.display()))?;
        Self::parse(&text, file)
    }

    /// Parses the text of the scenario file `file`.
    pub fn parse(text: &str, file: &Path) -> Result<Scenario, String> {
        toml::from_str(text).map_err(|e| {
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
                "{}:{place}error: {}; see `neurotree test --help` for the scenario format",
                file.display(),
                e.message()
            )
        })
    }
}

/// How one scenario went.
#[derive(Debug, Clone)]
pub struct ScenarioResult {
    /// The scenario's name, else its file's stem.
    pub name: String,
    /// The scenario file.
    pub file: PathBuf,
    /// How long it took to read and run.
    pub seconds: f64,
    /// Why it failed, one problem each (a problem may have several lines); empty if it
    /// passed.
    pub problems: Vec<String>,
}

impl ScenarioResult {
    /// `true` if every expectation held.
    pub fn passed(&self) -> bool {
        self.problems.is_empty()
    }
}

/// As `cargo test` reports a test: `test NAME ... ok`, or `test NAME ... FAILED` and each
/// line of each problem indented below it.
impl fmt::Display for ScenarioResult {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let verdict = if self.passed() { "ok" } else { "FAILED" };
        write!(f, "test {} ... {verdict}", self.name)?;
        for problem in &self.problems {
            for line in problem.lines() {
                write!(f, "\n    {line}")?;
            }
        }
        Ok(())
    }
}

/// Makes the context a scenario's tree is ticked with, once per scenario.
type ContextMaker<'a, C> = Box<dyn FnMut(&Blueprint<C>) -> C + 'a>;

/// Runs scenario files on copies of a registry.
///
/// The registry is the hook through which a program brings its node types (its own
/// leaves, Nav2's, a simulator's); the context maker gives what the tree is ticked with.
pub struct ScenarioBench<'a, C> {
    registry: &'a Registry<C>,
    context: ContextMaker<'a, C>,
    unknown_type_advice: Option<String>,
}

impl ScenarioBench<'static, ()> {
    /// A bench of the built-in nodes, ticking with `()`.
    pub fn new() -> Self {
        // One registry of built-ins serves every bench; copies are what scenarios change.
        static BUILT_INS: std::sync::OnceLock<Registry<()>> = std::sync::OnceLock::new();
        ScenarioBench::with_registry(BUILT_INS.get_or_init(Registry::new), |_| ())
    }
}

impl Default for ScenarioBench<'static, ()> {
    fn default() -> Self {
        Self::new()
    }
}

impl<'a, C: 'static> ScenarioBench<'a, C> {
    /// A bench of the node types of `registry`, ticking each scenario's tree with the
    /// context `context` makes for its blueprint.
    pub fn with_registry(
        registry: &'a Registry<C>,
        context: impl FnMut(&Blueprint<C>) -> C + 'a,
    ) -> Self {
        ScenarioBench {
            registry,
            context: Box::new(context),
            unknown_type_advice: None,
        }
    }

    /// What the error for an unknown node type advises (see
    /// [`XmlLoader::unknown_type_advice`](crate::XmlLoader::unknown_type_advice)).
    pub fn unknown_type_advice(mut self, advice: impl Into<String>) -> Self {
        self.unknown_type_advice = Some(advice.into());
        self
    }

    /// Reads and runs the scenario file at `file`.
    pub fn run_file(&mut self, file: &Path) -> ScenarioResult {
        let started = Instant::now();
        let (name, problems) = match Scenario::read(file) {
            Ok(scenario) => {
                let name = scenario.name.clone().unwrap_or_else(|| stem(file));
                (name, self.run(&scenario, file))
            }
            Err(e) => (stem(file), vec![e]),
        };
        ScenarioResult {
            name,
            file: file.to_path_buf(),
            seconds: started.elapsed().as_secs_f64(),
            problems,
        }
    }

    /// Runs `scenario`, read from `file` (the place its paths are relative to); the
    /// problems found, none if it passed.
    pub fn run(&mut self, scenario: &Scenario, file: &Path) -> Vec<String> {
        run::run(self, scenario, file)
    }
}

/// The file's name without its extension.
fn stem(file: &Path) -> String {
    file.file_stem().map_or_else(
        || file.display().to_string(),
        |s| s.to_string_lossy().into(),
    )
}

/// Writes `text` to the root entry `key` as `neurotree run --set` reads it: an integer,
/// else a float, else `true`/`false`, else the text; an entry of another type already
/// there is replaced by the text.
pub fn write_text(bb: &mut Blackboard, key: &str, text: &str) {
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
        bb.replace_in(ScopeId::ROOT, key, text.to_string(), Duration::ZERO);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_core::{Handle, StatefulAction, Status};

    /// A patrol whose `Charge` is the program's own leaf, succeeding once the context it
    /// is ticked with has counted to 3.
    const CHARGE: &str = r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
        <Sequence><Script code="mode := DOCKING"/><Charge/></Sequence>
    </BehaviorTree></root>"#;

    /// Counts its ticks in the context; done at the third.
    struct Charge;

    impl StatefulAction<u32> for Charge {
        fn on_start(&mut self, h: &mut Handle<'_, u32>) -> Status {
            self.on_running(h)
        }

        fn on_running(&mut self, h: &mut Handle<'_, u32>) -> Status {
            *h.ctx_mut() += 1;
            if *h.ctx() >= 3 {
                Status::Success
            } else {
                Status::Running
            }
        }
    }

    fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn scenarios_run_on_copies_of_the_registry_ticking_with_the_context_made() {
        let dir = tempfile::tempdir().unwrap();
        write(dir.path(), "charge.xml", CHARGE);
        let file = write(
            dir.path(),
            "charge.toml",
            r#"tree = "charge.xml"
            enums = { DOCKING = 2 }
            [[expect]]
            tick = 2
            root = "RUNNING"
            nodes = { Charge = "RUNNING", Script = "SUCCESS" }
            blackboard = { mode = 2 }
            [[expect]]
            root = "SUCCESS"
            "#,
        );
        let mut registry = Registry::<u32>::new();
        registry
            .register_stateful("Charge", Vec::new(), || Charge)
            .unwrap();
        let mut made = 0;
        let mut bench = ScenarioBench::with_registry(&registry, |_| {
            made += 1;
            0
        });
        let first = bench.run_file(&file);
        assert_eq!(first.problems, Vec::<String>::new());
        assert_eq!(first.name, "charge");
        // The scenario's enum went into a copy: the registry, and the next scenario's copy,
        // start without it.
        assert_eq!(registry.enums().get("DOCKING"), None);
        let second = bench.run_file(&file);
        assert!(second.passed(), "{second}");
        drop(bench);
        // One context per scenario, counted from 0 each time.
        assert_eq!(made, 2);
    }

    #[test]
    fn a_tree_that_does_not_load_fails_with_the_errors_and_what_to_do() {
        let dir = tempfile::tempdir().unwrap();
        let tree = write(dir.path(), "charge.xml", CHARGE);
        let file = write(dir.path(), "unknown.toml", "tree = \"charge.xml\"\n");
        let result = ScenarioBench::new().run_file(&file);
        let [problem] = &result.problems[..] else {
            panic!("{result}");
        };
        let lines: Vec<&str> = problem.lines().collect();
        assert_eq!(lines[0], "the tree did not load:");
        assert!(
            lines[1].starts_with(&format!("{}:2:", tree.display()))
                && lines[1].contains("unknown node type `Charge`"),
            "{problem}"
        );
        assert_eq!(
            lines.last(),
            Some(
                &"hint: mock the leaves without an implementation with `mock_unknown = true`, \
                  or one in [mocks]"
            )
        );
        let file = write(
            dir.path(),
            "other.toml",
            "tree = \"charge.xml\"\nmain = \"Patrol\"\nmock_unknown = true\n",
        );
        let result = ScenarioBench::new().run_file(&file);
        assert_eq!(
            result.problems,
            [format!(
                "the tree did not load:\n{}: error: main = \"Patrol\": no tree with that ID is \
                 loaded; the trees are: Main",
                tree.display()
            )]
        );
    }

    #[test]
    fn what_fails_is_said_once_per_problem_under_the_scenarios_line() {
        let dir = tempfile::tempdir().unwrap();
        write(dir.path(), "charge.xml", CHARGE);
        let file = write(
            dir.path(),
            "late.toml",
            r#"name = "charges in time"
            tree = "charge.xml"
            ticks = 2
            mocks = { Charge = "RUNNING" }
            enums = { DOCKING = 2 }
            [[set]]
            key = "limit"
            value = [1, 2]
            "#,
        );
        let result = ScenarioBench::new().run_file(&file);
        assert_eq!(
            result.problems,
            [format!(
                "{}: [[set]] limit: a array cannot be written to the blackboard; use a \
                 string, number or boolean",
                file.display()
            )]
        );
        let file = write(
            dir.path(),
            "late.toml",
            r#"name = "charges in time"
            tree = "charge.xml"
            ticks = 2
            mocks = { Charge = "RUNNING" }
            enums = { DOCKING = 2 }
            [[expect]]
            tick = 2
            root = "SUCCESS"
            halted = ["Charge"]
            "#,
        );
        let result = ScenarioBench::new().run_file(&file);
        assert_eq!(
            result.to_string(),
            "test charges in time ... FAILED\n    \
             tick 2: root is RUNNING, expected SUCCESS\n    \
             tick 2: `Charge` was not halted"
        );
    }

    #[test]
    fn a_fault_by_path_lands_on_one_of_two_leaves_that_share_a_name() {
        let dir = tempfile::tempdir().unwrap();
        write(
            dir.path(),
            "two.xml",
            r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
                <Sequence name="seq">
                    <Fallback name="first"><Check/><AlwaysFailure/></Fallback>
                    <Fallback name="second"><Check/><AlwaysFailure/></Fallback>
                </Sequence>
            </BehaviorTree></root>"#,
        );
        let scenario = |faults: &str, root: &str| {
            format!(
                "tree = \"two.xml\"\nmocks = {{ Check = \"SUCCESS\" }}\nfaults = [{faults}]\n\
                 [[expect]]\nroot = \"{root}\"\n"
            )
        };
        let mut bench = ScenarioBench::new();
        for (faults, root) in [
            ("", "SUCCESS"),
            ("\"seq/second/Check=FAILURE@1\"", "FAILURE"),
            ("\"seq/first/Check=FAILURE@2\"", "SUCCESS"),
            ("\"Check=FAILURE@1\"", "FAILURE"),
        ] {
            let file = write(dir.path(), "two.toml", &scenario(faults, root));
            let result = bench.run_file(&file);
            assert!(result.passed(), "{faults}: {result}");
            let wrong = if root == "SUCCESS" {
                "FAILURE"
            } else {
                "SUCCESS"
            };
            let file = write(dir.path(), "two.toml", &scenario(faults, wrong));
            assert!(!bench.run_file(&file).passed(), "{faults} {wrong}");
        }
        let file = write(
            dir.path(),
            "two.toml",
            &scenario("\"seq/third=FAILURE@1\"", "SUCCESS"),
        );
        let result = bench.run_file(&file);
        assert!(
            result.problems[0].contains("the fault `seq/third=FAILURE@1` names no node"),
            "{result}"
        );
        let file = write(
            dir.path(),
            "two.toml",
            &scenario("\"Check=MAYBE@1\"", "SUCCESS"),
        );
        let result = bench.run_file(&file);
        assert!(
            result.problems[0].contains("faults: `Check=MAYBE@1` should be"),
            "{result}"
        );
    }
}
