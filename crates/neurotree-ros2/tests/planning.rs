//! Nav2's planner and smoother over ROS 2: ComputePathThroughPoses and SmoothPath as
//! clients of the `compute_path_through_poses` and `smooth_path` actions, served by
//! [`SimServers`].

use crate::common;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};

use common::{free_domain, node, tick_until_done};
use neurotree_nav2::robotics::{Path, Pose2D};
use neurotree_ros2::msg::nav2_msgs::{ComputePathThroughPosesResult, SmoothPathResult};
use neurotree_ros2::nav2::{register_nav2_ros_leaves, SimOptions, SimServers, SimStats};
use neurotree_sim::nav2::Nav2Sim;
use neurotree_sim::GridWorld;
use neurotree_toolkit::{Blackboard, Registry, Status, Tree, XmlLoader};

/// A hall with a pillar; the robot at (1.5, 1.5).
const HALL: &str = "
    #########
    #.......#
    #R..#...#
    #.......#
    #########";

/// Runs the tree body `xml`, its blackboard set by `set`, against the simulator serving
/// the hall; the tree's status, the tree and what the servers counted.
fn run(xml: &str, set: impl FnOnce(&mut Blackboard)) -> (Status, Tree<()>, SimStats) {
    let domain = free_domain();
    let stop = Arc::new(AtomicBool::new(false));
    let stopped = Arc::clone(&stop);
    let (tx, rx) = mpsc::channel();
    let id = domain.id;
    let thread = std::thread::spawn(move || {
        let ros = node("nav2_sim", id);
        let world = GridWorld::parse(HALL, 1.0).unwrap();
        let mut servers =
            SimServers::new(&ros, Nav2Sim::new(world), SimOptions::default()).unwrap();
        tx.send(servers.stats()).unwrap();
        servers.run(&stopped).unwrap();
    });
    let stats = rx.recv_timeout(common::HANG).unwrap();
    let ros = node("bt_navigator", domain.id);
    let mut registry = Registry::<()>::new();
    register_nav2_ros_leaves(&mut registry, &ros).unwrap();
    let mut loader = XmlLoader::new(&registry);
    let file =
        format!(r#"<root BTCPP_format="4"><BehaviorTree ID="T">{xml}</BehaviorTree></root>"#);
    loader.load_str(&file, "plan.xml").unwrap();
    let mut tree = Tree::new(Arc::new(loader.build_main().unwrap()));
    set(tree.blackboard_mut());
    let status = tick_until_done(&mut tree, &mut (), common::HANG);
    let seen = common::after_steps(&stats, 3);
    stop.store(true, Ordering::SeqCst);
    let _ = thread.join();
    (status, tree, seen)
}

const PLAN_AND_SMOOTH: &str = r#"<Sequence>
      <ComputePathThroughPoses goals="{goals}" path="{raw}" error_code_id="{plan_code}"/>
      <SmoothPath unsmoothed_path="{raw}" smoothed_path="{path}" check_for_collisions="true" error_code_id="{smooth_code}"/>
    </Sequence>"#;

pub(crate) fn a_path_through_the_poses_is_planned_and_smoothed_by_the_servers() {
    let via = Pose2D::new(4.5, 3.5, 0.0);
    let end = Pose2D::new(7.5, 2.5, 0.0);
    let (status, tree, seen) = run(PLAN_AND_SMOOTH, |bb| {
        bb.set("goals", vec![via, end]).unwrap();
    });
    assert_eq!(status, Status::Success, "{seen:?}");
    assert_eq!(tree.blackboard().get::<u16>("plan_code").unwrap(), 0);
    assert_eq!(tree.blackboard().get::<u16>("smooth_code").unwrap(), 0);
    let path: Path = tree.blackboard().get("path").unwrap();
    assert_eq!(path.poses.first().map(|p| (p.x, p.y)), Some((1.5, 2.5)));
    assert_eq!(path.goal().map(|p| (p.x, p.y)), Some((7.5, 2.5)));
    assert!(
        path.poses.iter().any(|p| p.distance(&via) < 1e-9),
        "{path:?}"
    );
    assert_eq!(
        (
            seen.planner_through_poses.succeeded,
            seen.smoother.succeeded
        ),
        (1, 1),
        "{seen:?}"
    );
}

pub(crate) fn the_servers_error_codes_reach_the_tree() {
    // A goal in the pillar: GOAL_OCCUPIED of ComputePathThroughPoses.
    let (status, tree, seen) = run(PLAN_AND_SMOOTH, |bb| {
        bb.set("goals", vec![Pose2D::new(4.5, 2.5, 0.0)]).unwrap();
    });
    assert_eq!(status, Status::Failure);
    assert_eq!(tree.blackboard().get::<u16>("plan_code").unwrap(), 306);
    assert_eq!(seen.planner_through_poses.aborted, 1, "{seen:?}");
    let (status, tree, _) = run(PLAN_AND_SMOOTH, |bb| {
        bb.set("goals", Vec::<Pose2D>::new()).unwrap();
    });
    assert_eq!(status, Status::Failure);
    assert_eq!(
        tree.blackboard().get::<u16>("plan_code").unwrap(),
        ComputePathThroughPosesResult::NO_VIAPOINTS_GIVEN
    );
    let (status, tree, _) = run(
        r#"<SmoothPath unsmoothed_path="{raw}" smoothed_path="{path}" error_code_id="{smooth_code}"/>"#,
        |bb| bb.set("raw", Path::default()).unwrap(),
    );
    assert_eq!(status, Status::Failure);
    assert_eq!(
        tree.blackboard().get::<u16>("smooth_code").unwrap(),
        SmoothPathResult::INVALID_PATH
    );
}
