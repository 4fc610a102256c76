//! The layouts of Nav2's releases over ROS 2: Jazzy's Spin, BackUp, DriveOnHeading and
//! ComputePathThroughPoses goals, and Kilted's and main's (with `disable_collision_checks`,
//! and `nav_msgs/Goals`); Jazzy's and Kilted's costmap clearings and ComputePathToPose goal,
//! and main's (with `plugins` and `success`, and `viapoints`); FollowPath's, whose main
//! feedback tracks the path; each client against [`SimServers`] reading the same release.

use crate::common;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};

use common::{free_domain, node, tick_until_done};
use neurotree_nav2::robotics::{Path, Pose2D};
use neurotree_nav2::Nav2Release;
use neurotree_ros2::nav2::{register_nav2_ros_leaves_for, SimOptions, SimServers, SimStatsHandle};
use neurotree_sim::nav2::{Nav2Sim, TrackingFeedback};
use neurotree_sim::GridWorld;
use neurotree_toolkit::{Registry, Status, Tree, XmlLoader};

/// A hall three cells high; the robot at the left end, (1.5, 3.5).
const HALL: &str = "
    ##############
    #R...........#
    #............#
    #............#
    ##############";

/// Serves the hall for `release` until `stop` is raised; the stats.
fn serve(domain: u16, release: Nav2Release, stop: Arc<AtomicBool>) -> SimStatsHandle {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let ros = node("nav2_sim", domain);
        let options = SimOptions {
            time_scale: common::TIME_SCALE,
            release,
            ..SimOptions::default()
        };
        let world = GridWorld::parse(HALL, 1.0).unwrap();
        let mut servers = SimServers::new(&ros, Nav2Sim::new(world), options).unwrap();
        tx.send(servers.stats()).unwrap();
        servers.run(&stop).unwrap();
    });
    rx.recv_timeout(common::HANG).unwrap()
}

fn tree(domain: u16, release: Nav2Release, body: &str) -> Tree<()> {
    let ros = node("bt_navigator", domain);
    let mut registry = Registry::<()>::new();
    register_nav2_ros_leaves_for(&mut registry, &ros, release).unwrap();
    let mut loader = XmlLoader::new(&registry);
    let file =
        format!(r#"<root BTCPP_format="4"><BehaviorTree ID="T">{body}</BehaviorTree></root>"#);
    loader.load_str(&file, "release.xml").unwrap();
    Tree::new(Arc::new(loader.build_main().unwrap()))
}

const BODY: &str = r#"<Sequence>
    <Spin spin_dist="0.5" disable_collision_checks="false"/>
    <BackUp backup_dist="0.3" backup_speed="1.0" disable_collision_checks="true"/>
    <ComputePathToPose goal="12.5;3.5;0" viapoints="{via}"/>
    <ComputePathThroughPoses goals="{goals}" path="{path}"/>
    <ClearEntireCostmap plugins="obstacle_layer;voxel_layer"/>
    <ClearCostmapAroundPose pose="1.5;3.5;0" reset_distance="2"/>
    <FollowPath path="{path}" tracking_feedback="{tracking}"/>
  </Sequence>"#;

pub(crate) fn each_release_sends_its_goals_and_its_servers_read_them() {
    for (release, checks, viapoints) in [
        (Nav2Release::Jazzy, None, None),
        (Nav2Release::Kilted, Some(true), None),
        (Nav2Release::Main, Some(true), Some(2)),
    ] {
        let domain = free_domain();
        let stop = Arc::new(AtomicBool::new(false));
        let stats = serve(domain.id, release, Arc::clone(&stop));
        let mut tree = tree(domain.id, release, BODY);
        let goals = vec![Pose2D::new(6.5, 1.5, 0.0), Pose2D::new(12.5, 3.5, 0.0)];
        tree.blackboard_mut().set("goals", goals).unwrap();
        let via = vec![Pose2D::new(6.5, 1.5, 0.0), Pose2D::new(8.5, 1.5, 0.0)];
        tree.blackboard_mut().set("via", via).unwrap();
        let status = tick_until_done(&mut tree, &mut (), common::HANG);
        let seen = stats.get();
        stop.store(true, Ordering::SeqCst);
        assert_eq!(status, Status::Success, "{release:?}: {seen:?}");
        assert_eq!(
            (seen.spin.succeeded, seen.backup.succeeded),
            (1, 1),
            "{release:?}"
        );
        assert_eq!(seen.planner_through_poses.succeeded, 1, "{release:?}");
        assert_eq!(seen.clears, 2, "{release:?}");
        // The last goal read carried its flag only in Kilted's layout.
        assert_eq!(seen.disable_collision_checks, checks, "{release:?}");
        // Only main's ComputePathToPose goal has viapoints.
        assert_eq!(seen.planner.succeeded, 1, "{release:?}");
        assert_eq!(seen.viapoints, viapoints, "{release:?}");
        // Only main's FollowPath feedback tracks the path.
        assert_eq!(seen.controller.succeeded, 1, "{release:?}");
        let tracking = tree.blackboard().get::<TrackingFeedback>("tracking");
        assert_eq!(
            tracking.is_ok(),
            viapoints.is_some(),
            "{release:?}: {tracking:?}"
        );
        if let Ok(tracking) = tracking {
            assert!(tracking.position_tracking_error.abs() < 0.5, "{tracking:?}");
            assert!(tracking.current_path_index > 0, "{tracking:?}");
        }
        let path: Path = tree.blackboard().get("path").unwrap();
        let end = path.goal().unwrap();
        assert!(
            end.distance(&Pose2D::new(12.5, 3.5, 0.0)) < 1e-6,
            "{release:?}"
        );
    }
}

pub(crate) fn a_jazzy_goal_is_not_read_by_main_servers_which_go_on_serving() {
    let domain = free_domain();
    let stop = Arc::new(AtomicBool::new(false));
    let stats = serve(domain.id, Nav2Release::Main, Arc::clone(&stop));
    let spin = r#"<Spin spin_dist="0.5" server_timeout="1000" error_code_id="{code}"/>"#;
    let mut jazzy = tree(domain.id, Nav2Release::Jazzy, spin);
    let status = tick_until_done(&mut jazzy, &mut (), common::HANG);
    assert_eq!(status, Status::Failure);
    assert_eq!(stats.get().spin.goals, 0);
    // Jazzy's empty clearing request reads as main's with no plugins (CDR pads the one
    // byte to four, a zero count), and main's answer as Jazzy's empty one: they agree.
    let clear = r#"<ClearEntireCostmap server_timeout="1000"/>"#;
    let mut jazzy = tree(domain.id, Nav2Release::Jazzy, clear);
    let status = tick_until_done(&mut jazzy, &mut (), common::HANG);
    assert_eq!(status, Status::Success);
    assert_eq!(stats.get().clears, 1);
    let body = format!("<Sequence>{spin}{clear}</Sequence>");
    let mut main = tree(domain.id, Nav2Release::Main, &body);
    let status = tick_until_done(&mut main, &mut (), common::HANG);
    stop.store(true, Ordering::SeqCst);
    assert_eq!(status, Status::Success);
    assert_eq!(stats.get().spin.succeeded, 1);
    assert_eq!(stats.get().clears, 2);
}
