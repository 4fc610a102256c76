//! lint's findings hold on every run: random trees of every built-in and Nav2 control and
//! decorator (loop counts 0, 1, 2 and -1, preconditions, skip attributes, Parallel
//! thresholds, Switches) over mock leaves are linted, then run many times with random leaf
//! outcomes; no run may refute a finding. NT0201 (never ticked) is refuted by a tick of the
//! child, NT0202 (never chosen) by a tick of the case's child, NT0301 and NT0302 (never
//! ends) by the loop returning anything but RUNNING, NT0303 (never finishes) by the root
//! doing so. Runs are bounded, so "never ends" is only ever refuted, never confirmed.
//! The Nav2 controls that read the blackboard (PersistentSequence's place, the goals, the
//! robot's pose and speed) and Service's interval read a world moved at random between
//! ticks, and each of them is seen to succeed, fail and run.
//!
//! The same runs check coverage's "outcomes the tree could have": no node is seen with an
//! outcome its declared signature leaves out, a Nav2 control's read from the registry the
//! tree was loaded with (Skipped aside: a control whose children were
//! all skipped is seen Skipped without it being counted as possible).
//!
//! `NEUROTREE_LINT_TREES=20000` runs that many trees instead of the few CI runs.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree::lint::{lint, LintOptions};
use neurotree::nodes::semantics::{Order, Semantics, Statuses};
use neurotree::observe::{Coverage, Outcome, OutcomeSet};
use neurotree::robotics::Pose2D;
use neurotree::{
    Handle, ManualClock, NodeId, NodeStatus, Observer, Registry, StatefulAction, Status,
    StatusChange, TickError, Tree, XmlLoader,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

/// A small random source shared by the mock leaves of one tree's runs.
#[derive(Clone)]
struct Dice(Arc<Mutex<u64>>);

impl Dice {
    fn new(seed: u64) -> Self {
        Self(Arc::new(Mutex::new(seed | 1)))
    }

    /// A number below `n`.
    fn below(&self, n: usize) -> usize {
        let mut x = self.0.lock().unwrap();
        *x ^= *x << 13;
        *x ^= *x >> 7;
        *x ^= *x << 17;
        (*x % n as u64) as usize
    }

    fn pick<T: Copy>(&self, from: &[T]) -> T {
        from[self.below(from.len())]
    }
}

/// A mock leaf: each tick returns one of `outcomes` at random.
struct Mock {
    outcomes: &'static [Status],
    dice: Dice,
}

impl StatefulAction<()> for Mock {
    fn on_start(&mut self, _: &mut Handle<'_, ()>) -> Status {
        self.dice.pick(self.outcomes)
    }
    fn on_running(&mut self, _: &mut Handle<'_, ()>) -> Status {
        self.dice.pick(self.outcomes)
    }
}

const S: Status = Status::Success;
const F: Status = Status::Failure;
const R: Status = Status::Running;

/// The mock leaves: name, what it returns, and that declared.
const MOCKS: [(&str, &[Status]); 5] = [
    ("OnlySucceeds", &[S]),
    ("SucceedsOrRuns", &[S, R]),
    ("FailsOrRuns", &[F, R]),
    ("AnyOutcome", &[S, F, R]),
    ("OnlyFails", &[F]),
];

fn registry(dice: &Dice) -> Registry<()> {
    let mut registry = Registry::<()>::new();
    neurotree::nav2::register_controls(&mut registry).unwrap();
    for (name, outcomes) in MOCKS {
        let d = dice.clone();
        registry
            .register_stateful(name, vec![], move || Mock {
                outcomes,
                dice: d.clone(),
            })
            .unwrap();
        let declared = |o: &[Status]| {
            o.iter().fold(Statuses::NONE, |set, s| {
                set.or(match s {
                    Status::Success => Statuses::SUCCESS,
                    Status::Failure => Statuses::FAILURE,
                    Status::Running => Statuses::RUNNING,
                })
            })
        };
        // A signature is a plain function: the mocks' sets are spelt out.
        let semantics = match declared(outcomes) {
            s if s == Statuses::SUCCESS => {
                Semantics::new(Order::AllAtOnce, |_, _| Statuses::SUCCESS)
            }
            s if s == Statuses::FAILURE => {
                Semantics::new(Order::AllAtOnce, |_, _| Statuses::FAILURE)
            }
            s if s == Statuses::SUCCESS.or(Statuses::RUNNING) => {
                Semantics::new(Order::AllAtOnce, |_, _| {
                    Statuses::SUCCESS.or(Statuses::RUNNING)
                })
            }
            s if s == Statuses::FAILURE.or(Statuses::RUNNING) => {
                Semantics::new(Order::AllAtOnce, |_, _| {
                    Statuses::FAILURE.or(Statuses::RUNNING)
                })
            }
            _ => Semantics::new(Order::AllAtOnce, |_, _| {
                Statuses::DONE.or(Statuses::RUNNING)
            }),
        };
        registry.declare_semantics(name, semantics).unwrap();
    }
    let d = dice.clone();
    registry
        .register_condition("Coin", vec![], move |_| d.below(2) == 0)
        .unwrap();
    registry
}

/// A node of a generated tree: its element's opening (tag and attributes) and children.
struct Gen {
    open: String,
    children: Vec<Gen>,
}

/// Makes a random tree from `dice`, at most `depth` levels deep.
fn tree(dice: &Dice, depth: u32) -> Gen {
    let leaf = depth == 0 || dice.below(3) == 0;
    let (open, count) = if leaf {
        let open = match dice.below(9) {
            0 => "AlwaysSuccess".to_string(),
            1 => "AlwaysFailure".to_string(),
            2 => format!("Sleep msec=\"{}\"", dice.pick(&[0, 20])),
            3 => "Coin".to_string(),
            i => MOCKS[i - 4].0.to_string(),
        };
        (open, 0)
    } else {
        let n = 2 + dice.below(2);
        let count = |x: i32| x.to_string();
        let loops = [0, 1, 2, -1];
        match dice.below(35) {
            0 => ("Sequence".into(), n),
            1 => ("SequenceWithMemory".into(), n),
            2 => ("ReactiveSequence".into(), n),
            3 => ("Fallback".into(), n),
            4 => ("ReactiveFallback".into(), n),
            5 => ("AsyncSequence".into(), n),
            6 => ("AsyncFallback".into(), n),
            7 => {
                let t = [-1, 1, 2];
                let (s, f) = (dice.pick(&t), dice.pick(&t));
                let s = if s > n as i32 { -1 } else { s };
                let f = if f > n as i32 { 1 } else { f };
                (
                    format!("Parallel success_count=\"{s}\" failure_count=\"{f}\""),
                    n,
                )
            }
            8 => (
                format!("ParallelAll max_failures=\"{}\"", dice.pick(&[-1, 1, 2])),
                n,
            ),
            9 => ("IfThenElse".into(), n),
            10 => ("WhileDoElse".into(), n),
            11 => ("TryCatch".into(), n),
            12 => {
                let v = ["a", "b", "{mode}"];
                let open = format!(
                    "Switch2 variable=\"{}\" case_1=\"{}\" case_2=\"{}\"",
                    dice.pick(&v),
                    dice.pick(&v[..2]),
                    dice.pick(&v[..2])
                );
                (open, 3)
            }
            13 => ("PipelineSequence".into(), n),
            14 => (
                format!(
                    "RecoveryNode number_of_retries=\"{}\"",
                    dice.pick(&[0, 1, 2])
                ),
                2,
            ),
            15 => (
                format!(
                    "RoundRobin wrap_around=\"{}\"",
                    dice.pick(&["true", "false"])
                ),
                n,
            ),
            16 => ("NonblockingSequence".into(), n),
            17 => ("PauseResumeController".into(), 1 + dice.below(2)),
            18 => ("Inverter".into(), 1),
            19 => ("ForceSuccess".into(), 1),
            20 => ("ForceFailure".into(), 1),
            21 => (
                format!("Repeat num_cycles=\"{}\"", count(dice.pick(&loops))),
                1,
            ),
            22 => (
                format!(
                    "RetryUntilSuccessful num_attempts=\"{}\"",
                    count(dice.pick(&loops))
                ),
                1,
            ),
            23 => ("KeepRunningUntilFailure".into(), 1),
            24 => (format!("Delay delay_msec=\"{}\"", dice.pick(&[0, 10])), 1),
            25 => (format!("Timeout msec=\"{}\"", dice.pick(&[0, 25])), 1),
            26 => (
                format!("RunOnce then_skip=\"{}\"", dice.pick(&["true", "false"])),
                1,
            ),
            27 => (
                format!(
                    "Precondition if=\"{}\" else=\"{}\"",
                    dice.pick(&["true", "false"]),
                    dice.pick(&["SUCCESS", "FAILURE", "RUNNING", "SKIPPED"])
                ),
                1,
            ),
            28 => (
                format!("RateController hz=\"{}\"", dice.pick(&[10, 0, -1])),
                1,
            ),
            29 => ("PersistentSequence current_child_idx=\"{idx}\"".into(), n),
            30 => ("GoalUpdatedController".into(), 1),
            31 => (
                format!(
                    "SpeedController min_rate=\"{}\" max_rate=\"50\" max_speed=\"1\"",
                    dice.pick(&[5, 20])
                ),
                1,
            ),
            32 => (
                format!(
                    "DistanceController distance=\"{}\"",
                    dice.pick(&["0", "0.5", "2"])
                ),
                1,
            ),
            33 => (
                format!(
                    "Service interval_msec=\"{}\"",
                    dice.pick(&["0", "20", "50", "{interval}"])
                ),
                2,
            ),
            _ => ("SingleTrigger".into(), 1),
        }
    };
    let mut open = open;
    if dice.below(6) == 0 {
        let attr = dice.pick(&["_skipIf", "_successIf", "_failureIf", "_while"]);
        open += &format!(" {attr}=\"{}\"", dice.pick(&["true", "false"]));
    }
    let children = (0..count).map(|_| tree(dice, depth - 1)).collect();
    Gen { open, children }
}

/// Writes `node` one element a line, each named `nK` by its line number, and records each
/// node's children by line.
fn write(node: &Gen, xml: &mut Vec<String>, children: &mut HashMap<u32, Vec<u32>>) -> u32 {
    let line = xml.len() as u32 + 1;
    let tag = node.open.split(' ').next().unwrap().to_string();
    if node.children.is_empty() {
        xml.push(format!("<{} name=\"n{line}\"/>", node.open));
        return line;
    }
    xml.push(format!("<{} name=\"n{line}\">", node.open));
    let kids = node
        .children
        .iter()
        .map(|c| write(c, xml, children))
        .collect();
    children.insert(line, kids);
    xml.push(format!("</{tag}>"));
    line
}

/// Poses for goals and the robot: near each other, and far apart.
const POSES: [Pose2D; 3] = [
    Pose2D::new(0.0, 0.0, 0.0),
    Pose2D::new(0.3, 0.0, 0.0),
    Pose2D::new(3.0, 0.0, 1.0),
];

/// The world the Nav2 controls read, moved at random between ticks so that their
/// branches are all taken: PersistentSequence's place (before the first child, inside,
/// past the last), new goals or the same again, the robot's speed, its pose moving far,
/// near or gone. `start` writes every entry.
fn world(tree: &mut Tree<()>, dice: &Dice, start: bool) {
    let bb = tree.blackboard_mut();
    let now = |n: usize| start || dice.below(n) == 0;
    if now(4) {
        bb.set("idx", dice.pick(&[-1_i32, 0, 0, 1, 2, 5])).unwrap();
    }
    if now(4) {
        bb.set("goal", dice.pick(&POSES)).unwrap();
    }
    if now(6) {
        let goals = (0..1 + dice.below(2)).map(|_| dice.pick(&POSES)).collect();
        bb.set::<Vec<Pose2D>>("goals", goals).unwrap();
    }
    if now(3) {
        bb.set("robot_speed", dice.pick(&[0.0_f64, 0.3, 1.0, -0.5]))
            .unwrap();
    }
    if now(3) {
        if dice.below(4) == 0 {
            bb.unset("robot_pose");
        } else {
            bb.set("robot_pose", dice.pick(&POSES)).unwrap();
        }
    }
    if start {
        bb.set("interval", dice.pick(&[0_u64, 20, 50])).unwrap();
    }
}

/// What the runs saw, by node name's line: ticked, and ended (returned anything but
/// RUNNING).
#[derive(Default)]
struct Seen {
    ticked: Vec<bool>,
    ended: Vec<bool>,
}

struct Watch(Arc<Mutex<Seen>>);

impl Observer for Watch {
    fn on_node_tick(&mut self, node: NodeId) {
        self.0.lock().unwrap().ticked[node.index()] = true;
    }
    fn on_node_skipped(&mut self, node: NodeId) {
        let mut seen = self.0.lock().unwrap();
        seen.ticked[node.index()] = true;
        seen.ended[node.index()] = true;
    }
    fn on_status_change(&mut self, change: StatusChange) {
        if matches!(
            change.to,
            NodeStatus::Success | NodeStatus::Failure | NodeStatus::Skipped
        ) {
            self.0.lock().unwrap().ended[change.node.index()] = true;
        }
    }
}

/// The node types whose outcomes [`check`] tallies: those that read the [`world`], so that
/// the runs are shown to reach them and their branches.
const TALLIED: [&str; 5] = [
    "PersistentSequence",
    "GoalUpdatedController",
    "SpeedController",
    "DistanceController",
    "Service",
];

/// Lints the tree of `seed`, runs it, and returns how many findings the runs could refute,
/// or the refuted one. Adds to `tally` the outcomes seen of the [`TALLIED`] types.
fn check(seed: u64, runs: usize, tally: &mut HashMap<String, OutcomeSet>) -> Result<usize, String> {
    let dice = Dice::new(seed);
    let registry = registry(&dice);
    let mut xml = vec![
        "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\">".to_string(),
        "<BehaviorTree ID=\"Main\">".to_string(),
    ];
    let mut children = HashMap::new();
    let root = write(&tree(&dice, 4), &mut xml, &mut children);
    xml.push("</BehaviorTree>".into());
    xml.push("</root>".into());
    let xml = xml.join("\n");
    let mut loader = XmlLoader::new(&registry);
    // A tree the loader refuses, as BehaviorTree.CPP does (two async children of a
    // ReactiveSequence), is not run.
    if loader.load_str(&xml, "main.xml").is_err() || loader.validate("Main").is_err() {
        return Ok(0);
    }
    let findings: Vec<_> = lint(&loader, &LintOptions::default())
        .into_iter()
        .filter(|d| d.code.starts_with("NT02") || d.code.starts_with("NT03"))
        .filter(|d| d.code != "NT0203")
        .collect();
    let Ok(blueprint) = loader.build_main() else {
        return Ok(0);
    };
    let blueprint = Arc::new(blueprint);
    // Node ids by the line their name gives.
    let by_line: HashMap<u32, usize> = blueprint
        .ids()
        .filter_map(|id| {
            let line = blueprint.name(id).strip_prefix('n')?.parse().ok()?;
            Some((line, id.index()))
        })
        .collect();
    let seen = Arc::new(Mutex::new(Seen {
        ticked: vec![false; blueprint.len()],
        ended: vec![false; blueprint.len()],
    }));
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(Arc::clone(&blueprint), clock.clone());
    let coverage = Coverage::with_registry(&blueprint, &registry);
    tree.set_observer((Watch(Arc::clone(&seen)), coverage.clone()));
    // A Repeat of -1 over an instant child asks for pass after pass: a few are enough.
    tree.set_max_passes(64);
    world(&mut tree, &dice, true);
    'runs: for run in 0..runs {
        for _ in 0..30 {
            clock.advance(Duration::from_millis(10));
            world(&mut tree, &dice, false);
            // Both ways of ticking: passes until nothing asks to be woken, and exactly one.
            let ticked = if run % 2 == 0 {
                tree.tick_once(&mut ())
            } else {
                tree.tick_exactly_once(&mut ())
            };
            match ticked {
                Ok(Status::Running) => {}
                Ok(_) | Err(TickError::RootSkipped) => continue 'runs,
                // A tick error (two Running children of a ReactiveSequence, ...) ends what
                // the runs can show.
                Err(_) => break 'runs,
            }
        }
        tree.halt(&mut ());
    }
    let skipped = OutcomeSet::of(&[Outcome::Skipped]);
    for n in coverage.report(&blueprint).nodes() {
        if TALLIED.contains(&n.type_name.as_str()) {
            let set = tally.entry(n.type_name.clone()).or_default();
            *set = n.seen.iter().fold(*set, OutcomeSet::with);
        }
        let unforeseen = n.seen.without(skipped).without(n.possible);
        if !unforeseen.is_empty() {
            return Err(format!(
                "a run sees {} {unforeseen}, not among its possible outcomes {}\n{xml}",
                n.path, n.possible
            ));
        }
    }
    let seen = seen.lock().unwrap();
    let node = |line: u32| by_line[&line];
    for d in &findings {
        let refuted = match d.code {
            "NT0201" => seen.ticked[node(d.line)],
            "NT0202" => {
                let case: usize = d.message[6..7].parse().unwrap();
                seen.ticked[node(children[&d.line][case - 1])]
            }
            "NT0301" | "NT0302" => seen.ended[node(d.line)],
            "NT0303" => seen.ended[node(root)],
            _ => false,
        };
        if refuted {
            return Err(format!("a run refutes {d}\n{xml}"));
        }
    }
    Ok(findings.len())
}

#[test]
fn no_run_refutes_a_finding() {
    let trees = std::env::var("NEUROTREE_LINT_TREES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(300);
    let mut runner = TestRunner::new(Config {
        cases: trees,
        failure_persistence: None,
        ..Config::default()
    });
    let checked = Arc::new(Mutex::new(0usize));
    let counted = Arc::clone(&checked);
    let result = runner.run(&any::<u64>(), move |seed| {
        let n = check(seed, 6, &mut HashMap::new()).map_err(TestCaseError::fail)?;
        *counted.lock().unwrap() += n;
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    // The trees make findings for the runs to try.
    assert!(*checked.lock().unwrap() > trees as usize / 10);
}

/// The nodes that read the world are run to each of their outcomes: the world reaches their
/// branches. Fixed seeds, so that a rare node is not missed by chance.
#[test]
fn the_world_leads_each_node_to_each_outcome() {
    let mut tally = HashMap::new();
    for seed in 1..=600 {
        check(seed, 6, &mut tally).unwrap();
    }
    let done = OutcomeSet::of(&[Outcome::Success, Outcome::Failure, Outcome::Running]);
    for name in TALLIED {
        let seen = tally.get(name).copied().unwrap_or_default();
        assert!(done.without(seen).is_empty(), "{name} is seen only {seen}");
    }
}
