//! Nav2's navigator file, loaded unchanged from the repository, driving the simulated robot:
//! the leaves of `neurotree::sim::nav2` against Nav2's own tree and node model.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use neurotree::robotics::Pose2D;
use neurotree::sim::nav2::{
    register_nav2_leaves, EventLog, FailureNotes, Nav2Sim, RecoveryCounter, LEAVES,
};
use neurotree::sim::{Cell, GridWorld, TimedObstacle};
use neurotree::{nav2, PortDirection, Registry, Status, Tree, XmlLoader};

fn trees_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../corpus/nav2")
}

const NAVIGATOR: &str = "navigate_to_pose_w_replanning_and_recovery.xml";
const MODEL: &str = "nav2_tree_nodes.xml";

fn registry() -> Registry<Nav2Sim> {
    let mut registry = Registry::new();
    nav2::register_controls(&mut registry).unwrap();
    register_nav2_leaves(&mut registry).unwrap();
    registry
}

/// How a navigation went.
#[derive(Debug, PartialEq)]
struct Outcome {
    status: Status,
    ticks: u32,
    time: Duration,
    plans: u32,
    replans: u32,
    recoveries: Vec<(String, u32)>,
    stops: u32,
}

/// Loads the navigator from the repository, sends the robot of `world` to `goal`, and
/// ticks (stepping the world 100 ms after each Running tick) until it completes.
fn navigate(world: GridWorld, goal: Pose2D) -> (Outcome, Nav2Sim, Vec<String>) {
    let registry = registry();
    let mut loader = XmlLoader::new(&registry);
    loader.load_file(trees_dir().join(NAVIGATOR)).unwrap();
    let blueprint = Arc::new(loader.build_main().unwrap());
    let log = EventLog::new();
    let mut sim = Nav2Sim::new(world).with_log(log.clone());
    let mut tree = Tree::with_clock(Arc::clone(&blueprint), sim.world.clock());
    let recoveries = RecoveryCounter::new(&blueprint).with_log(log.clone());
    let failures = FailureNotes::new(&blueprint, log.clone());
    tree.set_observer((recoveries.clone(), failures));
    tree.blackboard_mut().set("goal", goal).unwrap();
    let mut ticks = 0;
    let status = loop {
        ticks += 1;
        match tree.tick_once(&mut sim).unwrap() {
            Status::Running if ticks < 5000 => sim.step(),
            done => break done,
        };
    };
    let outcome = Outcome {
        status,
        ticks,
        time: sim.world.now(),
        plans: sim.plans(),
        replans: sim.replans(),
        recoveries: recoveries
            .branches()
            .into_iter()
            .filter(|(_, n)| *n > 0)
            .collect(),
        stops: sim.world.stop_count(),
    };
    (outcome, sim, log.take())
}

fn runs(list: &[(&str, u32)]) -> Vec<(String, u32)> {
    list.iter().map(|(l, n)| (l.to_string(), *n)).collect()
}

/// A model default as a comparable value: quotes dropped, numbers in one form.
fn normalized(default: &str) -> String {
    let text = default.trim_matches('"');
    if text == "numeric_limits<double>::infinity()" {
        return "inf".into();
    }
    match text.parse::<f64>() {
        Ok(n) => format!("{n:?}"),
        Err(_) => text.to_string(),
    }
}

#[test]
fn every_leaf_has_the_ports_of_nav2s_model() {
    let mut model = Registry::<()>::new();
    let text = std::fs::read_to_string(trees_dir().join(MODEL)).unwrap();
    model.add_model_str(&text, MODEL).unwrap();
    let ours = registry();
    for name in LEAVES {
        let theirs = model
            .get(name)
            .unwrap_or_else(|| panic!("{name} not in the model"));
        let mine = ours.get(name).unwrap();
        assert_eq!(mine.category, theirs.category, "{name}");
        let ports =
            |t: &neurotree::registry::NodeType<_>| -> Vec<(String, PortDirection, Option<String>)> {
                t.ports
                    .iter()
                    .map(|p| {
                        (
                            p.name.clone(),
                            p.direction,
                            p.default.as_deref().map(normalized),
                        )
                    })
                    .collect()
            };
        let theirs: Vec<_> = theirs
            .ports
            .iter()
            .map(|p| {
                (
                    p.name.clone(),
                    p.direction,
                    p.default.as_deref().map(normalized),
                )
            })
            .collect();
        assert_eq!(ports(mine), theirs, "{name}");
    }
}

#[test]
fn the_navigator_validates_against_the_model_and_loads_with_the_simulated_leaves() {
    let mut model = Registry::<()>::new();
    model
        .add_model_str(
            &std::fs::read_to_string(trees_dir().join(MODEL)).unwrap(),
            MODEL,
        )
        .unwrap();
    let mut loader = XmlLoader::new(&model);
    loader.load_file(trees_dir().join(NAVIGATOR)).unwrap();
    loader
        .validate("NavigateToPoseWReplanningAndRecovery")
        .unwrap();
    let registry = registry();
    let mut loader = XmlLoader::new(&registry);
    loader.load_file(trees_dir().join(NAVIGATOR)).unwrap();
    assert_eq!(loader.build_main().unwrap().len(), 38);
}

/// The demo's scene without its seeded obstacle: a room and a wall with two doors.
const ROOMS: &str = "
    ###############
    #R.....#......#
    #......#......#
    #.............#
    #......#......#
    #......#......#
    #.............#
    #......#......#
    ###############";

#[test]
fn a_free_run_replans_every_second_and_needs_no_recovery() {
    let world = GridWorld::parse(ROOMS, 1.0).unwrap();
    let (outcome, sim, _) = navigate(world, Pose2D::new(12.5, 1.5, 0.0));
    // A plan a second until the goal is within IsGoalNearby's 4 m; FollowPath stops the
    // robot once within the goal checker's 0.25 m.
    assert_eq!(
        outcome,
        Outcome {
            status: Status::Success,
            ticks: 134,
            time: Duration::from_millis(13_300),
            plans: 10,
            replans: 9,
            recoveries: runs(&[]),
            stops: 1,
        }
    );
    assert!(sim.world.robot().distance(&Pose2D::new(12.5, 1.5, 0.0)) <= 0.25);
}

#[test]
fn an_obstacle_on_the_path_makes_the_navigator_recover_and_go_round() {
    // A crate drops into the lower door, which the robot is heading for, just after the
    // plan of the seventh second: the robot meets it before the next plan.
    let world = GridWorld::parse(ROOMS, 1.0)
        .unwrap()
        .with_timed_obstacle(TimedObstacle::new(
            Cell::new(7, 2),
            Duration::from_millis(7050),
        ));
    let (outcome, sim, log) = navigate(world, Pose2D::new(12.5, 1.5, 0.0));
    assert_eq!(
        outcome,
        Outcome {
            status: Status::Success,
            ticks: 195,
            time: Duration::from_millis(19_400),
            plans: 17,
            replans: 15,
            recoveries: runs(&[
                ("FollowPath recovery", 2),
                ("ClearingActions", 1),
                ("Spin", 1)
            ]),
            stops: 1,
        }
    );
    assert!(sim.world.robot().distance(&Pose2D::new(12.5, 1.5, 0.0)) <= 0.25);
    // Blocked, the controller's recovery clears the local costmap and fails again; the
    // navigator's first recovery clears both costmaps, so the next plan goes through the
    // crate once more; blocked again, the navigator spins, by which time the robot has
    // sensed the crate for good, and the next plan takes the upper door.
    let story: Vec<&str> = log
        .iter()
        .map(String::as_str)
        .filter(|l| !l.starts_with("ComputePathToPose: "))
        .collect();
    let blocked = "FollowPath failed: blocked (error 106)";
    assert_eq!(
        story,
        [
            blocked,
            "recovery: FollowPath recovery",
            "ClearLocalCostmap-Context: cleared the local costmap",
            blocked,
            "recovery: ClearingActions",
            "ClearLocalCostmap-Subtree: cleared the local costmap",
            "ClearGlobalCostmap-Subtree: cleared the global costmap",
            blocked,
            "recovery: FollowPath recovery",
            "ClearLocalCostmap-Context: cleared the local costmap",
            blocked,
            "recovery: Spin",
            "Spin: done",
        ]
    );
    let through_upper_door = sim.world.distance_travelled();
    assert!(through_upper_door > 13.0, "{through_upper_door}");
}

#[test]
fn a_doorway_blocked_for_a_while_is_waited_out() {
    // One door, blocked from just after the third second's plan until 10 s.
    let world = GridWorld::parse(
        "
        ###########
        #R...#....#
        #....#....#
        #.........#
        ###########",
        1.0,
    )
    .unwrap()
    .with_timed_obstacle(
        TimedObstacle::new(Cell::new(5, 1), Duration::from_millis(3050))
            .until(Duration::from_secs(10)),
    );
    let (outcome, _, log) = navigate(world, Pose2D::new(9.5, 3.5, 0.0));
    assert_eq!(
        outcome,
        Outcome {
            status: Status::Success,
            ticks: 168,
            time: Duration::from_millis(16_700),
            plans: 9,
            replans: 7,
            recoveries: runs(&[
                ("ComputePathToPose recovery", 3),
                ("FollowPath recovery", 3),
                ("ClearingActions", 1),
                ("Spin", 1),
                ("Wait", 1)
            ]),
            stops: 1,
        }
    );
    // With the costmap remembering the crate there is no path (208): the planner's
    // recovery clears the global costmap, the plan goes through the door, the robot is
    // blocked again. The navigator's recoveries take turns until the crate has gone.
    let recoveries: Vec<&str> = log
        .iter()
        .filter_map(|l| l.strip_prefix("recovery: "))
        .collect();
    assert_eq!(
        recoveries,
        [
            "FollowPath recovery",
            "ComputePathToPose recovery",
            "ClearingActions",
            "FollowPath recovery",
            "Spin",
            "ComputePathToPose recovery",
            "FollowPath recovery",
            "Wait",
            "ComputePathToPose recovery",
        ]
    );
    assert!(log.contains(&"ComputePathToPose failed: no valid path (error 208)".to_string()));
}
