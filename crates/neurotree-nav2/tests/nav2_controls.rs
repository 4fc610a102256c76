//! Nav2's control and decorator nodes through the XML loader: a tree using the first seven, run
//! tick by tick; Nav2's own navigator files, loaded, built and run with scripted leaves; and a
//! navigator that ticks without allocating.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Duration;

use neurotree::robotics::Pose2D;
use neurotree::{
    nav2, Handle, ManualClock, PortSpec, Registry, StatefulAction, Status, Tree, XmlLoader,
};

use crate::counting_alloc;
use counting_alloc::allocations;

use Status::{Failure as F, Running as R, Success as S};

use crate::corpus_dir;

fn nav2_corpus() -> PathBuf {
    corpus_dir::corpus("nav2")
}

/// The context of these tests: each [`Step`] leaf plays the outcomes scripted under its node
/// name (Success when none are), and its calls and halts are counted under that name.
#[derive(Default)]
struct Robot {
    scripts: BTreeMap<String, Vec<Status>>,
    ticks: BTreeMap<String, u32>,
    halts: BTreeMap<String, u32>,
}

impl Robot {
    fn new(scripts: &[(&str, &[Status])]) -> Self {
        Self {
            scripts: scripts
                .iter()
                .map(|(name, s)| (name.to_string(), s.to_vec()))
                .collect(),
            ..Self::default()
        }
    }

    fn next(&mut self, name: &str) -> Status {
        let n = self.ticks.entry(name.to_string()).or_insert(0);
        *n += 1;
        match self.scripts.get(name) {
            Some(script) => script[(*n as usize - 1).min(script.len() - 1)],
            None => S,
        }
    }

    /// Calls (`on_start` or `on_running`) of the named leaves, in order.
    fn ticks(&self, names: &[&str]) -> Vec<u32> {
        names
            .iter()
            .map(|n| self.ticks.get(*n).copied().unwrap_or(0))
            .collect()
    }

    /// Halts of all leaves together.
    fn halts(&self) -> u32 {
        self.halts.values().sum()
    }
}

/// A stateful leaf playing the script of its node name.
struct Step;

impl StatefulAction<Robot> for Step {
    fn on_start(&mut self, h: &mut Handle<'_, Robot>) -> Status {
        let name = h.name().to_string();
        h.ctx_mut().next(&name)
    }
    fn on_running(&mut self, h: &mut Handle<'_, Robot>) -> Status {
        let name = h.name().to_string();
        h.ctx_mut().next(&name)
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Robot>) {
        let name = h.name().to_string();
        *h.ctx_mut().halts.entry(name).or_insert(0) += 1;
    }
}

/// The Nav2 nodes, and a `Step` leaf.
fn registry() -> Registry<Robot> {
    let mut r = Registry::new();
    nav2::register_controls(&mut r).unwrap();
    r.register_stateful("Step", vec![], || Step).unwrap();
    r
}

/// All seven Nav2 nodes in a navigator: plan at 1 Hz when the goal is new, announce each new
/// goal, follow the path; on failure, take turns at two recoveries and try once more.
const NAVIGATOR: &str = r#"
<root BTCPP_format="4" main_tree_to_execute="Navigate">
  <BehaviorTree ID="Navigate">
    <RecoveryNode number_of_retries="1" name="navigate_recovery">
      <PipelineSequence name="navigate">
        <RateController hz="1.0">
          <Fallback name="plan_if_needed">
            <Inverter><GlobalUpdatedGoal/></Inverter>
            <Step name="plan"/>
          </Fallback>
        </RateController>
        <GoalUpdatedController>
          <Step name="announce"/>
        </GoalUpdatedController>
        <Step name="follow"/>
      </PipelineSequence>
      <ReactiveFallback name="recovery">
        <GoalUpdated goal="{goal}"/>
        <RoundRobin name="recoveries">
          <Step name="spin"/>
          <Step name="back_up"/>
        </RoundRobin>
      </ReactiveFallback>
    </RecoveryNode>
  </BehaviorTree>
</root>"#;

const LEAVES: [&str; 5] = ["plan", "announce", "follow", "spin", "back_up"];

fn navigator(registry: &Registry<Robot>, clock: &ManualClock) -> Tree<Robot> {
    let mut loader = XmlLoader::new(registry);
    loader.load_str(NAVIGATOR, "navigator.xml").unwrap();
    Tree::with_clock(loader.build_main().unwrap().into(), clock.clone())
}

#[test]
fn a_navigator_using_every_node_loads_and_runs_tick_by_tick() {
    let registry = registry();
    let clock = ManualClock::new();
    let mut tree = navigator(&registry, &clock);
    let mut robot = Robot::new(&[("follow", &[R, F, R, R, R, F])]);
    tree.blackboard_mut()
        .set("goal", Pose2D::new(1.0, 2.0, 0.0))
        .unwrap();
    // 0 s: a first goal: plan, announce, start following.
    assert_eq!(tree.tick_once(&mut robot), Ok(R));
    assert_eq!(robot.ticks(&LEAVES), [1, 1, 1, 0, 0]);
    // 0.5 s: too early to plan, same goal: only follow is ticked, and fails. The recovery
    // runs the first recovery (spin) and the navigation again in the same tick: the goal is
    // not new, so no plan; the controller's new run announces again.
    clock.advance(Duration::from_millis(500));
    assert_eq!(tree.tick_once(&mut robot), Ok(R));
    assert_eq!(robot.ticks(&LEAVES), [1, 2, 3, 1, 0]);
    // 1.0 s: a second since the first plan, but only half a second since the new run.
    clock.advance(Duration::from_millis(500));
    assert_eq!(tree.tick_once(&mut robot), Ok(R));
    assert_eq!(robot.ticks(&LEAVES), [1, 2, 4, 1, 0]);
    // 1.6 s: a new goal and the period elapsed: plan and announce while following.
    tree.blackboard_mut()
        .set("goal", Pose2D::new(5.0, 0.0, 1.0))
        .unwrap();
    clock.advance(Duration::from_millis(600));
    assert_eq!(tree.tick_once(&mut robot), Ok(R));
    assert_eq!(robot.ticks(&LEAVES), [2, 3, 5, 1, 0]);
    // 1.7 s: follow fails again and the one retry is spent: Failure.
    clock.advance(Duration::from_millis(100));
    assert_eq!(tree.tick_once(&mut robot), Ok(F));
    assert_eq!(robot.ticks(&LEAVES), [2, 3, 6, 1, 0]);
    // A new run fails at once (follow keeps failing): the second recovery has its turn,
    // and, being the last, ends the RoundRobin's turns without wrap-around: the recovery
    // fails although back_up succeeded, so the navigation is not tried again.
    assert_eq!(tree.tick_once(&mut robot), Ok(F));
    assert_eq!(robot.ticks(&LEAVES), [2, 4, 7, 1, 1]);
    // The RoundRobin starts over at the first recovery on the next use.
    assert_eq!(tree.tick_once(&mut robot), Ok(F));
    assert_eq!(robot.ticks(&LEAVES), [2, 6, 9, 2, 1]);
    assert_eq!(robot.halts(), 0);
    assert!(tree
        .statuses()
        .iter()
        .all(|s| *s == neurotree::NodeStatus::Idle));
}

#[test]
fn halting_a_navigator_halts_the_running_leaf_once() {
    let registry = registry();
    let clock = ManualClock::new();
    let mut tree = navigator(&registry, &clock);
    let mut robot = Robot::new(&[("follow", &[R])]);
    assert_eq!(tree.tick_once(&mut robot), Ok(R));
    assert_eq!(tree.tick_once(&mut robot), Ok(R));
    tree.halt(&mut robot);
    assert_eq!(robot.halts.get("follow"), Some(&1));
    assert_eq!(robot.halts(), 1);
    // A new run: the rate controller ticks at once, the goal is not new (no plan), the
    // goal controller's new run announces.
    assert_eq!(tree.tick_once(&mut robot), Ok(R));
    assert_eq!(robot.ticks(&LEAVES), [1, 2, 3, 0, 0]);
}

#[test]
fn misuse_is_reported_when_loading() {
    let registry = registry();
    let error = |body: &str| {
        let text =
            format!(r#"<root BTCPP_format="4"><BehaviorTree ID="T">{body}</BehaviorTree></root>"#);
        let mut loader = XmlLoader::new(&registry);
        loader.load_str(&text, "bad.xml").unwrap();
        match loader.build("T") {
            Err(e) => e.message,
            Ok(_) => panic!("expected an error for {body}"),
        }
    };
    assert_eq!(
        error(r#"<RecoveryNode><Step name="a"/></RecoveryNode>"#),
        "`RecoveryNode` takes exactly 2 children, found 1"
    );
    assert_eq!(
        error(r#"<RateController><Step name="a"/><Step name="b"/></RateController>"#),
        "`RateController` takes exactly 1 child, found 2"
    );
    assert_eq!(
        error(r#"<GoalUpdated><Step name="a"/></GoalUpdated>"#),
        "`GoalUpdated` is a leaf and takes no children, found 1"
    );
    assert!(
        error(r#"<RateController hz="fast"><Step name="a"/></RateController>"#)
            .starts_with("port `hz` of `RateController`: cannot read `fast`")
    );
    assert!(
        error(r#"<RoundRobin wrap="true"><Step name="a"/></RoundRobin>"#)
            .starts_with("unknown port `wrap` on `RoundRobin`; its ports are: wrap_around")
    );
    assert!(error(r#"<GoalUpdated goal="north"/>"#)
        .starts_with("port `goal` of `GoalUpdated`: cannot read `north`"));
}

/// The XML files of the Nav2 corpus.
fn corpus_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(nav2_corpus())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "xml"))
        .collect();
    files.sort();
    files
}

fn file_name(path: &Path) -> String {
    path.file_name().unwrap().to_string_lossy().to_string()
}

/// Loads `file` with the Nav2 nodes registered and every other leaf mocked; builds its trees.
fn load_and_build(registry: &Registry<Robot>, file: &Path) -> Result<usize, String> {
    let mut loader = XmlLoader::new(registry)
        .mock_unknown(true)
        .base_dir(nav2_corpus());
    loader.load_file(file).map_err(|e| e.message)?;
    let ids: Vec<String> = loader.tree_ids().map(String::from).collect();
    for id in &ids {
        loader.build(id).map_err(|e| e.message)?;
    }
    Ok(ids.len())
}

#[test]
fn nav2_files_using_these_nodes_and_leaves_load_and_build() {
    let registry = registry();
    let mut built = BTreeMap::new();
    let mut failed = BTreeMap::new();
    for file in corpus_files() {
        match load_and_build(&registry, &file) {
            Ok(trees) => {
                built.insert(file_name(&file), trees);
            }
            Err(message) => {
                failed.insert(file_name(&file), message);
            }
        }
    }
    // Every navigator file: all of Nav2's controls and decorators are implemented.
    assert!(failed.is_empty(), "{failed:#?}");
    // The model file loads too, and holds no tree.
    assert_eq!(built.remove("nav2_tree_nodes.xml"), Some(0));
    assert_eq!(built.len(), 16, "{built:?}");
    assert!(built.contains_key("follow_point.xml"));
    assert!(built.contains_key("navigate_w_replanning_speed.xml"));
    assert!(built.values().all(|trees| *trees == 1), "{built:?}");
}

/// The Nav2 registry plus `Step` leaves under the given Nav2 leaf names, with the ports Nav2
/// declares for them (read from its `TreeNodesModel`), so that their calls are counted.
fn nav2_registry(leaves: &[&str]) -> Registry<Robot> {
    let model_text = std::fs::read_to_string(nav2_corpus().join("nav2_tree_nodes.xml")).unwrap();
    let mut model = Registry::<()>::new();
    model
        .add_model_str(&model_text, "nav2_tree_nodes.xml")
        .unwrap();
    let mut r = registry();
    for leaf in leaves {
        let ports = model
            .get(leaf)
            .unwrap()
            .ports
            .iter()
            .map(|p| PortSpec::input::<String>(&p.name))
            .collect();
        r.register_stateful(leaf, ports, || Step).unwrap();
    }
    r
}

fn load_nav2(registry: &Registry<Robot>, file: &str, clock: &ManualClock) -> Tree<Robot> {
    let mut loader = XmlLoader::new(registry).mock_unknown(true);
    loader.load_file(nav2_corpus().join(file)).unwrap();
    Tree::with_clock(loader.build_main().unwrap().into(), clock.clone())
}

#[test]
fn nav2_replanning_only_if_the_goal_is_updated() {
    let registry = nav2_registry(&["ComputePathToPose", "FollowPath"]);
    let clock = ManualClock::new();
    let mut tree = load_nav2(
        &registry,
        "navigate_w_replanning_only_if_goal_is_updated.xml",
        &clock,
    );
    let leaves = ["ComputePathToPose", "FollowPath"];
    let mut robot = Robot::new(&[
        ("ComputePathToPose", &[R, S, R, S]),
        ("FollowPath", &[R, R, R, R, S]),
    ]);
    tree.blackboard_mut()
        .set("goal", Pose2D::new(1.0, 1.0, 0.0))
        .unwrap();
    // Planning runs; the pipeline waits for it.
    assert_eq!(tree.tick_once(&mut robot), Ok(R));
    assert_eq!(robot.ticks(&leaves), [1, 0]);
    // Planned: following starts.
    assert_eq!(tree.tick_once(&mut robot), Ok(R));
    assert_eq!(robot.ticks(&leaves), [2, 1]);
    // Same goal: no planning, following goes on.
    assert_eq!(tree.tick_once(&mut robot), Ok(R));
    assert_eq!(robot.ticks(&leaves), [2, 2]);
    // A new goal: planning starts again while following goes on.
    tree.blackboard_mut()
        .set("goal", Pose2D::new(4.0, 1.0, 0.0))
        .unwrap();
    assert_eq!(tree.tick_once(&mut robot), Ok(R));
    assert_eq!(robot.ticks(&leaves), [3, 3]);
    assert_eq!(tree.tick_once(&mut robot), Ok(R));
    assert_eq!(robot.ticks(&leaves), [4, 4]);
    // Arrived.
    assert_eq!(tree.tick_once(&mut robot), Ok(S));
    assert_eq!(robot.ticks(&leaves), [4, 5]);
    assert_eq!(robot.halts(), 0);
}

#[test]
fn nav2_recovery_tree_gives_up_once_each_recovery_had_its_turn() {
    let leaves = ["FollowPath", "ClearEntireCostmap", "Spin", "Wait", "BackUp"];
    let registry = nav2_registry(&leaves);
    let clock = ManualClock::new();
    let mut tree = load_nav2(
        &registry,
        "navigate_to_pose_w_replanning_and_recovery.xml",
        &clock,
    );
    // The path cannot be followed; everything else works (unregistered leaves are mocks
    // that succeed). All leaves complete at once, so the whole story is one tick.
    let mut robot = Robot::new(&[("FollowPath", &[F])]);
    assert_eq!(tree.tick_once(&mut robot), Ok(F));
    let counted = [
        "FollowPath",
        "ClearLocalCostmap-Context",
        "ClearGlobalCostmap-Context",
        "ClearLocalCostmap-Subtree",
        "ClearGlobalCostmap-Subtree",
        "Spin",
        "Wait",
        "BackUp",
    ];
    // Four runs of the navigation (the first and one after each of the first three
    // recoveries), each following twice around its own local recovery; then the last
    // recovery (BackUp) succeeds, but the RoundRobin, without wrap-around, fails after its
    // last child, and the tree fails with retries to spare.
    assert_eq!(robot.ticks(&counted), [8, 4, 0, 1, 1, 1, 1, 1]);
    assert_eq!(robot.halts(), 0);
}

/// A navigator of plain leaves, for the allocation count.
#[derive(Default)]
struct Counts {
    plans: u32,
    follows: u32,
}

struct Follow;

impl StatefulAction<Counts> for Follow {
    fn on_start(&mut self, h: &mut Handle<'_, Counts>) -> Status {
        self.on_running(h)
    }
    fn on_running(&mut self, h: &mut Handle<'_, Counts>) -> Status {
        h.ctx_mut().follows += 1;
        R
    }
}

#[test]
fn a_nav2_navigator_ticks_without_allocating() {
    // Guards the guard: a broken counter would make this test pass whatever the tree does.
    assert!(allocations(|| drop(std::hint::black_box(vec![1u8; 8]))) >= 1);
    let mut registry = Registry::<Counts>::new();
    nav2::register_controls(&mut registry).unwrap();
    registry
        .register_action("Plan", vec![], |h| {
            h.ctx_mut().plans += 1;
            S
        })
        .unwrap();
    registry
        .register_stateful("Follow", vec![], || Follow)
        .unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            r#"
            <root BTCPP_format="4">
              <BehaviorTree ID="Main">
                <RecoveryNode number_of_retries="3">
                  <PipelineSequence>
                    <RateController hz="2">
                      <Fallback><Inverter><GlobalUpdatedGoal/></Inverter><Plan/></Fallback>
                    </RateController>
                    <GoalUpdatedController><Plan/></GoalUpdatedController>
                    <Inverter><GoalUpdated goals="{goals}"/></Inverter>
                    <Follow/>
                  </PipelineSequence>
                  <RoundRobin wrap_around="true"><AlwaysSuccess/><AlwaysSuccess/></RoundRobin>
                </RecoveryNode>
              </BehaviorTree>
            </root>"#,
            "navigator.xml",
        )
        .unwrap();
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), clock.clone());
    let goals = [
        vec![Pose2D::new(1.0, 0.0, 0.0), Pose2D::new(2.0, 0.0, 0.0)],
        vec![Pose2D::new(3.0, 0.0, 0.0), Pose2D::new(4.0, 0.0, 0.0)],
    ];
    let mut counts = Counts::default();
    tree.blackboard_mut()
        .set("goals", goals[0].clone())
        .unwrap();
    assert_eq!(tree.tick_once(&mut counts), Ok(R));
    // Ten seconds at 10 ticks a second, a new goal list every second.
    let mut lists: Vec<Vec<Pose2D>> = (0..10).map(|i| goals[(i + 1) % 2].clone()).collect();
    let n = allocations(|| {
        for list in lists.iter_mut() {
            tree.blackboard_mut()
                .set("goals", std::mem::take(list))
                .unwrap();
            for _ in 0..10 {
                clock.advance(Duration::from_millis(100));
                assert_eq!(tree.tick_once(&mut counts), Ok(R));
            }
        }
    });
    assert_eq!(n, 0);
    // Two plans on the first tick; then per new list, one by the RateController's branch
    // (at its next period, when GlobalUpdatedGoal sees the list) and one by the controller.
    assert_eq!(counts.plans, 2 + 10 * 2);
    assert_eq!(counts.follows, 1 + 100);
}
