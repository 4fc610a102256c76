//! Nav2's route, docking, navigation-through-poses, following and assisted-teleop clients
//! over ROS 2, and their cancel nodes, against [`SimServers`](neurotree_ros2::nav2::SimServers)
//! serving the grid world.

use crate::common;

use std::time::{Duration, Instant};

use common::{free_domain, nav2_tree, node, tick_until_done, Served};
use neurotree_nav2::robotics::{Path, Pose2D, Route, RouteNode};
use neurotree_ros2::msg::geometry_msgs::PoseStamped;
use neurotree_ros2::msg::nav2_msgs::{
    AssistedTeleopResult, ComputeRouteResult, DockRobotResult, FollowObjectResult,
    NavigateThroughPosesResult,
};
use neurotree_ros2::msg::std_msgs::Empty;
use neurotree_ros2::nav2::convert::pose_stamped;
use neurotree_ros2::nav2::{OBJECT_POSE_TOPIC, PREEMPT_TELEOP_TOPIC};
use neurotree_sim::nav2::{Dock, Nav2Sim, RouteGraph};
use neurotree_sim::GridWorld;
use neurotree_toolkit::{Status, Tree};

/// A hall three cells high; the robot at the left end, (1.5, 3.5).
const HALL: &str = "
    ##############
    #R...........#
    #............#
    #............#
    ##############";

const LIMIT: Duration = common::HANG;

fn hall() -> Nav2Sim {
    Nav2Sim::new(GridWorld::parse(HALL, 1.0).unwrap())
}

/// Nodes 1, 2 and 3 along the hall's top row, joined both ways 1–2 and 2–3.
fn graph() -> RouteGraph {
    RouteGraph::new(vec![
        RouteNode::new(1, 1.5, 3.5),
        RouteNode::new(2, 6.5, 3.5),
        RouteNode::new(3, 12.5, 3.5),
    ])
    .with_way(1, 2)
    .with_way(2, 3)
}

fn code(tree: &Tree<()>) -> u16 {
    tree.blackboard().get::<u16>("code").unwrap_or(u16::MAX)
}

pub(crate) fn compute_route_writes_the_servers_route_and_fails_with_its_code() {
    let domain = free_domain();
    let served = Served::start(
        domain.id,
        hall().with_route_graph(graph()),
        common::TIME_SCALE,
    );
    let mut tree = nav2_tree(
        domain.id,
        r#"<ComputeRoute start_id="1" goal_id="{to}" route="{route}" path="{path}" planning_time="{took}" error_code_id="{code}"/>"#,
    );
    tree.blackboard_mut().set("to", 3_u16).unwrap();
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Success);
    assert_eq!(code(&tree), 0);
    let route: Route = tree.blackboard().get("route").unwrap();
    let ids: Vec<u16> = route.nodes.iter().map(|n| n.id).collect();
    assert_eq!(ids, [1, 2, 3]);
    let edges: Vec<(u16, u16)> = route.edges.iter().map(|e| (e.start, e.end)).collect();
    assert_eq!(edges, [(1, 2), (2, 3)]);
    assert!((route.cost - 11.0).abs() < 1e-4, "{route:?}");
    let path: Path = tree.blackboard().get("path").unwrap();
    assert!(path.goal().unwrap().distance(&Pose2D::new(12.5, 3.5, 0.0)) < 1e-6);
    // A node the graph does not have: the server's code, and no route.
    tree.blackboard_mut().set("to", 9_u16).unwrap();
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Failure);
    assert_eq!(
        code(&tree),
        ComputeRouteResult::INDETERMINANT_NODES_ON_GRAPH
    );
    assert!(tree.blackboard().get::<Route>("route").unwrap().is_empty());
    assert!(tree
        .blackboard()
        .get::<Path>("path")
        .unwrap()
        .poses
        .is_empty());
    let seen = served.stats.get();
    assert_eq!(
        (seen.route.succeeded, seen.route.aborted),
        (1, 1),
        "{seen:?}"
    );
    // Halted while it runs: no route either, as Nav2's node's `halt` resets its outputs.
    let mut halted = nav2_tree(
        domain.id,
        r#"<Parallel success_count="2" failure_count="1">
             <ComputeRoute start_id="1" goal_id="3" route="{route}"/>
             <AlwaysFailure/>
           </Parallel>"#,
    );
    let stale = Route {
        nodes: vec![RouteNode::new(1, 1.5, 3.5)],
        ..Route::default()
    };
    halted.blackboard_mut().set("route", stale).unwrap();
    assert_eq!(halted.tick_once(&mut ()).unwrap(), Status::Failure);
    assert!(halted
        .blackboard()
        .get::<Route>("route")
        .unwrap()
        .is_empty());
}

pub(crate) fn compute_and_track_route_follows_the_robot_along_the_route_to_its_end() {
    let domain = free_domain();
    let served = Served::start(
        domain.id,
        hall().with_route_graph(graph()),
        common::TIME_SCALE,
    );
    let mut tree = nav2_tree(
        domain.id,
        r#"<Sequence>
             <ComputeRoute start_id="1" goal_id="3" path="{path}"/>
             <Parallel success_count="2" failure_count="1">
               <ComputeAndTrackRoute start_id="1" goal_id="3" next_node_id="{next}" execution_duration="{took}" error_code_id="{code}"/>
               <FollowPath path="{path}"/>
             </Parallel>
           </Sequence>"#,
    );
    // The feedback's next node, as the tree sees it while the robot drives.
    let mut next_nodes = Vec::new();
    let until = Instant::now() + LIMIT;
    let status = loop {
        let status = tree.tick_once(&mut ()).unwrap();
        if status != Status::Running || Instant::now() > until {
            break status;
        }
        if let Ok(next) = tree.blackboard().get::<u16>("next") {
            if next_nodes.last() != Some(&next) {
                next_nodes.push(next);
            }
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let seen = served.stats.get();
    assert_eq!(status, Status::Success, "{seen:?}");
    assert_eq!(code(&tree), 0);
    assert!(
        next_nodes.contains(&2) && next_nodes.contains(&3),
        "{next_nodes:?}"
    );
    // As Nav2's node: the feedback outputs are reset once the goal ends.
    assert_eq!(tree.blackboard().get::<u16>("next").unwrap(), 0);
    let took: f64 = tree.blackboard().get("took").unwrap();
    assert!(took > 5.0, "{took}");
    assert_eq!(seen.route_tracking.succeeded, 1, "{seen:?}");
    assert!(
        seen.robot.distance(&Pose2D::new(12.5, 3.5, 0.0)) <= 0.25,
        "{seen:?}"
    );
}

pub(crate) fn the_new_cancel_nodes_cancel_route_tracking_following_and_teleop_which_then_succeed() {
    let domain = free_domain();
    let mut sim = hall().with_route_graph(graph());
    sim.set_object(Some(Pose2D::new(8.5, 3.5, 0.0)));
    let served = Served::start(domain.id, sim, common::TIME_SCALE);
    for (action, cancel) in [
        (
            r#"<ComputeAndTrackRoute start_id="1" goal_id="3" error_code_id="{code}"/>"#,
            "CancelComputeAndTrackRoute",
        ),
        (
            r#"<FollowObject error_code_id="{code}"/>"#,
            "CancelFollowObject",
        ),
        (
            r#"<AssistedTeleop time_allowance="60" error_code_id="{code}"/>"#,
            "CancelAssistedTeleop",
        ),
    ] {
        let mut tree = nav2_tree(
            domain.id,
            &format!(
                r#"<Parallel success_count="2" failure_count="1">
                     {action}
                     <Delay delay_msec="500"><{cancel}/></Delay>
                   </Parallel>"#
            ),
        );
        let status = tick_until_done(&mut tree, &mut (), LIMIT);
        assert_eq!((status, code(&tree)), (Status::Success, 0), "{cancel}");
    }
    let seen = served.stats.get();
    for (name, counts) in [
        ("route", seen.route_tracking),
        ("follow", seen.follow_object),
        ("teleop", seen.assisted_teleop),
    ] {
        assert_eq!(
            (counts.goals, counts.cancels, counts.succeeded),
            (1, 1, 0),
            "{name}: {seen:?}"
        );
    }
}

pub(crate) fn dock_robot_docks_at_the_servers_dock_and_undock_robot_backs_off_it() {
    let domain = free_domain();
    let dock = Dock::new("home", "charging_dock", Pose2D::new(10.5, 3.5, 0.0));
    let served = Served::start(domain.id, hall().with_dock(dock), common::TIME_SCALE);
    let mut tree = nav2_tree(
        domain.id,
        r#"<DockRobot dock_id="{dock}" success="{ok}" num_retries="{retries}" error_code_id="{code}"/>"#,
    );
    tree.blackboard_mut()
        .set("dock", "home".to_owned())
        .unwrap();
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Success);
    assert_eq!(code(&tree), 0);
    assert!(tree.blackboard().get::<bool>("ok").unwrap());
    assert_eq!(tree.blackboard().get::<u16>("retries").unwrap(), 0);
    let seen = served.stats.get();
    assert!(
        seen.robot.distance(&Pose2D::new(10.5, 3.5, 0.0)) < 0.06,
        "{seen:?}"
    );
    let mut undock = nav2_tree(
        domain.id,
        r#"<UndockRobot success="{ok}" error_code_id="{code}"/>"#,
    );
    assert_eq!(
        tick_until_done(&mut undock, &mut (), LIMIT),
        Status::Success
    );
    assert!(undock.blackboard().get::<bool>("ok").unwrap());
    let seen = served.stats.get();
    assert!(
        seen.robot.distance(&Pose2D::new(9.5, 3.5, 0.0)) < 0.06,
        "{seen:?}"
    );
    // A dock the server does not know: its code, and `success` false.
    tree.blackboard_mut()
        .set("dock", "nowhere".to_owned())
        .unwrap();
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Failure);
    assert_eq!(code(&tree), DockRobotResult::DOCK_NOT_IN_DB);
    assert!(!tree.blackboard().get::<bool>("ok").unwrap());
    let seen = served.stats.get();
    assert_eq!((seen.dock.succeeded, seen.dock.aborted), (1, 1), "{seen:?}");
    assert_eq!(seen.undock.succeeded, 1, "{seen:?}");
}

pub(crate) fn navigate_through_poses_takes_the_robot_through_each_pose_and_fails_with_the_servers_code(
) {
    let domain = free_domain();
    let served = Served::start(domain.id, hall(), common::TIME_SCALE);
    let mut tree = nav2_tree(
        domain.id,
        r#"<NavigateThroughPoses goals="{goals}" error_code_id="{code}"/>"#,
    );
    let goals = vec![Pose2D::new(6.5, 1.5, 0.0), Pose2D::new(12.5, 3.5, 0.0)];
    tree.blackboard_mut().set("goals", goals).unwrap();
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Success);
    assert_eq!(code(&tree), 0);
    let seen = served.stats.get();
    assert!(
        seen.robot.distance(&Pose2D::new(12.5, 3.5, 0.0)) <= 0.25,
        "{seen:?}"
    );
    // Through the first pose: longer than the 11 m straight along the row, at least the
    // 11.7 m of the two straight lines through (6.5, 1.5).
    assert!(seen.distance > 11.6, "{seen:?}");
    tree.blackboard_mut()
        .set("goals", vec![Pose2D::new(0.5, 0.5, 0.0)])
        .unwrap();
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Failure);
    assert_eq!(code(&tree), NavigateThroughPosesResult::UNKNOWN);
    let seen = served.stats.get();
    assert_eq!(
        (
            seen.navigate_through_poses.succeeded,
            seen.navigate_through_poses.aborted
        ),
        (1, 1)
    );
}

pub(crate) fn follow_object_follows_for_max_duration_fails_unseen_and_follows_a_published_pose() {
    let domain = free_domain();
    let mut sim = hall();
    sim.set_object(Some(Pose2D::new(8.5, 3.5, 0.0)));
    let served = Served::start(domain.id, sim, common::TIME_SCALE);
    let mut tree = nav2_tree(
        domain.id,
        r#"<FollowObject max_duration="2.0" total_elapsed_time="{took}" error_code_id="{code}"/>"#,
    );
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Success);
    assert_eq!(code(&tree), 0);
    let took: f64 = tree.blackboard().get("took").unwrap();
    assert!((2.0..2.5).contains(&took), "{took}");
    let seen = served.stats.get();
    // Two seconds at 1 m/s towards the object.
    assert!(seen.robot.x > 3.0 && seen.robot.x < 4.0, "{seen:?}");
    drop(served);
    let domain = free_domain();
    let served = Served::start(domain.id, hall(), common::TIME_SCALE);
    let mut tree = nav2_tree(domain.id, r#"<FollowObject error_code_id="{code}"/>"#);
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Failure);
    assert_eq!(code(&tree), FollowObjectResult::FAILED_TO_DETECT_OBJECT);
    // A detector publishes the object's pose, behind the robot and down the hall.
    let detector = node("detector", domain.id);
    let poses = detector
        .publisher::<PoseStamped>(OBJECT_POSE_TOPIC)
        .unwrap();
    let object = Pose2D::new(1.5, 1.5, 0.0);
    let mut tree = nav2_tree(
        domain.id,
        r#"<FollowObject max_duration="3.0" error_code_id="{code}"/>"#,
    );
    let until = Instant::now() + LIMIT;
    let status = loop {
        poses.publish(pose_stamped(object)).unwrap();
        let status = tree.tick_once(&mut ()).unwrap();
        if status != Status::Running || Instant::now() > until {
            break status;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let seen = served.stats.get();
    assert_eq!((status, code(&tree)), (Status::Success, 0), "{seen:?}");
    // A metre short of the object, on the goal tolerance.
    let gap = seen.robot.distance(&object);
    assert!((0.7..=1.3).contains(&gap), "{gap}: {seen:?}");
}

pub(crate) fn assisted_teleop_times_out_as_nav2s_and_fails_only_as_a_recovery() {
    let domain = free_domain();
    let served = Served::start(domain.id, hall(), common::TIME_SCALE);
    for (recovery, expected) in [("false", Status::Success), ("true", Status::Failure)] {
        let mut tree = nav2_tree(
            domain.id,
            &format!(
                r#"<AssistedTeleop time_allowance="0.5" is_recovery="{recovery}" error_code_id="{{code}}" error_msg="{{why}}"/>"#
            ),
        );
        assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), expected);
        assert_eq!(code(&tree), AssistedTeleopResult::TIMEOUT, "{recovery}");
        let why: String = tree.blackboard().get("why").unwrap();
        assert!(why.contains("time allowance"), "{why}");
    }
    // A person says the teleoperation is over: Success, code 0.
    let mut tree = nav2_tree(
        domain.id,
        r#"<AssistedTeleop time_allowance="60" is_recovery="true" error_code_id="{code}"/>"#,
    );
    let ros = node("teleop_panel", domain.id);
    let preempt = ros.publisher::<Empty>(PREEMPT_TELEOP_TOPIC).unwrap();
    let until = Instant::now() + LIMIT;
    let status = loop {
        let status = tree.tick_once(&mut ()).unwrap();
        if status != Status::Running || Instant::now() > until {
            break status;
        }
        if served.stats.get().assisted_teleop.goals == 3 {
            preempt.publish(Empty::default()).unwrap();
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!((status, code(&tree)), (Status::Success, 0));
    let seen = served.stats.get();
    assert_eq!(
        (seen.assisted_teleop.succeeded, seen.assisted_teleop.aborted),
        (1, 2),
        "{seen:?}"
    );
}

pub(crate) fn a_new_path_or_route_goal_while_the_goal_runs_is_sent_in_its_place_as_nav2s() {
    let domain = free_domain();
    let served = Served::start(
        domain.id,
        hall().with_route_graph(graph()),
        common::TIME_SCALE,
    );
    let row = |to: f64| {
        let poses = (0..)
            .map(|i| 1.5 + f64::from(i))
            .take_while(|x| *x <= to)
            .map(|x| Pose2D::new(x, 3.5, 0.0));
        Path::new(poses.collect())
    };
    let mut tree = nav2_tree(
        domain.id,
        r#"<FollowPath path="{path}" error_code_id="{code}"/>"#,
    );
    tree.blackboard_mut().set("path", row(12.5)).unwrap();
    let until = Instant::now() + LIMIT;
    let mut replaced = false;
    let status = loop {
        let status = tree.tick_once(&mut ()).unwrap();
        if status != Status::Running || Instant::now() > until {
            break status;
        }
        // A metre on, the path is replanned to end at x = 4.5.
        if !replaced && served.stats.get().robot.x > 2.5 {
            tree.blackboard_mut().set("path", row(4.5)).unwrap();
            replaced = true;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let seen = served.stats.get();
    assert_eq!((status, code(&tree)), (Status::Success, 0), "{seen:?}");
    assert_eq!(seen.controller.goals, 2, "{seen:?}");
    assert!(
        seen.robot.distance(&Pose2D::new(4.5, 3.5, 0.0)) <= 0.25,
        "{seen:?}"
    );
    // The route tracker: another goal node makes a new goal, whose route the feedback gives.
    let mut tree = nav2_tree(
        domain.id,
        r#"<ComputeAndTrackRoute start_id="1" goal_id="{to}" route="{route}"/>"#,
    );
    tree.blackboard_mut().set("to", 3_u16).unwrap();
    let until = Instant::now() + LIMIT;
    let mut ends = Vec::new();
    while Instant::now() < until {
        assert_eq!(tree.tick_once(&mut ()).unwrap(), Status::Running);
        if served.stats.get().route_tracking.goals == 1 {
            tree.blackboard_mut().set("to", 2_u16).unwrap();
        }
        if let Ok(route) = tree.blackboard().get::<Route>("route") {
            if let Some(end) = route.nodes.last().map(|n| n.id) {
                if ends.last() != Some(&end) {
                    ends.push(end);
                }
            }
        }
        if ends.last() == Some(&2) {
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_eq!(ends.last(), Some(&2), "{ends:?}");
    assert_eq!(served.stats.get().route_tracking.goals, 2);
}
