//! Nav2's navigator over ROS 2, in one process: a [`Navigator`] running Nav2's unmodified
//! `navigate_to_pose_w_replanning_and_recovery.xml`, the grid world served by
//! [`SimServers`], and a goal client, each on its own participant over 127.0.0.1.

use crate::common;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use common::{free_domain, node};
use neurotree_nav2::robotics::Pose2D;
use neurotree_ros2::msg::nav2_msgs::{NavigateToPose, NavigateToPoseGoal, NavigateToPoseResult};
use neurotree_ros2::nav2::convert::pose_stamped;
use neurotree_ros2::nav2::{
    Navigator, NavigatorOptions, SimOptions, SimServers, SimStats, SimStatsHandle,
};
use neurotree_ros2::ros2_client::action::{GoalId, GoalStatusEnum};
use neurotree_ros2::RosActionClient;
use neurotree_sim::nav2::Nav2Sim;
use neurotree_sim::{Cell, GridWorld, TimedObstacle};

const NAVIGATOR_XML: &str =
    include_str!("../../../corpus/nav2/navigate_to_pose_w_replanning_and_recovery.xml");

/// A hall three cells high; the robot at the left end, (1.5, 3.5).
const HALL: &str = "
    ##############
    #R...........#
    #............#
    #............#
    ##############";

/// The far end of the hall.
const FAR_END: Pose2D = Pose2D::new(12.5, 3.5, 0.0);

/// A thread running a server loop until dropped.
struct Running {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Drop for Running {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

fn hall(obstacle: Option<TimedObstacle>) -> GridWorld {
    let world = GridWorld::parse(HALL, 1.0).unwrap();
    match obstacle {
        Some(obstacle) => world.with_timed_obstacle(obstacle),
        None => world,
    }
}

/// The simulator on its own participant in `domain`; its counts.
fn sim(domain: u16, world: GridWorld) -> (Running, SimStatsHandle) {
    let stop = Arc::new(AtomicBool::new(false));
    let stopped = Arc::clone(&stop);
    let (tx, rx) = mpsc::channel();
    let thread = std::thread::spawn(move || {
        let ros = node("nav2_sim", domain);
        let options = SimOptions {
            time_scale: common::TIME_SCALE,
            ..SimOptions::default()
        };
        let mut servers = SimServers::new(&ros, Nav2Sim::new(world), options).unwrap();
        tx.send(servers.stats()).unwrap();
        servers.run(&stopped).unwrap();
    });
    let stats = rx.recv_timeout(common::HANG).unwrap();
    let running = Running {
        stop,
        thread: Some(thread),
    };
    (running, stats)
}

/// The navigator on its own participant in `domain`, over the static hall.
fn navigator(domain: u16) -> Running {
    let stop = Arc::new(AtomicBool::new(false));
    let stopped = Arc::clone(&stop);
    let (tx, rx) = mpsc::channel();
    let thread = std::thread::spawn(move || {
        let ros = node("bt_navigator", domain);
        let mut navigator = Navigator::on_map(
            &ros,
            NAVIGATOR_XML,
            "navigate_to_pose_w_replanning_and_recovery.xml",
            hall(None),
            &NavigatorOptions::default(),
        )
        .unwrap();
        tx.send(()).unwrap();
        navigator.run(&stopped).unwrap();
    });
    rx.recv_timeout(common::HANG).unwrap();
    Running {
        stop,
        thread: Some(thread),
    }
}

/// Sends `goal` until the navigator accepts it (the first may go out before discovery).
fn send_goal(client: &RosActionClient<NavigateToPose>, goal: Pose2D) -> GoalId {
    let until = Instant::now() + common::HANG;
    while Instant::now() < until {
        let message = NavigateToPoseGoal {
            pose: pose_stamped(goal),
            behavior_tree: String::new(),
        };
        let (request, goal_id) = client.send_goal(message).unwrap();
        let answer_by = Instant::now() + Duration::from_secs(2);
        while Instant::now() < answer_by {
            if let Some(response) = client.receive_goal_response(request).unwrap() {
                assert!(response.accepted);
                return goal_id;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }
    panic!("the navigator did not answer the goal");
}

/// The goal's end, and the most recoveries its feedback reported.
fn wait_for_result(
    client: &RosActionClient<NavigateToPose>,
    goal_id: GoalId,
    limit: Duration,
) -> (GoalStatusEnum, NavigateToPoseResult, i16) {
    let request = client.request_result(goal_id).unwrap();
    let until = Instant::now() + limit;
    let mut recoveries = 0;
    while Instant::now() < until {
        while let Ok(Some(feedback)) = client.receive_feedback(goal_id) {
            recoveries = recoveries.max(feedback.number_of_recoveries);
        }
        if let Some((status, result)) = client.receive_result(request).unwrap() {
            return (status, result, recoveries);
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    panic!("no result within {limit:?}");
}

fn wait_until(limit: Duration, stats: &SimStatsHandle, done: impl Fn(&SimStats) -> bool) -> bool {
    let until = Instant::now() + limit;
    while Instant::now() < until {
        if done(&stats.get()) {
            return true;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    false
}

pub(crate) fn the_navigator_drives_the_robot_to_the_goal_through_an_obstacle_with_a_recovery() {
    let domain = free_domain();
    // On the straight path, appearing after the first plan, before the robot gets there.
    let obstacle = TimedObstacle::new(Cell::new(7, 3), Duration::from_secs(1));
    let (_sim, stats) = sim(domain.id, hall(Some(obstacle)));
    let _navigator = navigator(domain.id);
    let ros = node("goal_client", domain.id);
    let client = ros
        .action_client::<NavigateToPose>("navigate_to_pose")
        .unwrap();

    let goal_id = send_goal(&client, FAR_END);
    let (status, result, recoveries) = wait_for_result(&client, goal_id, common::HANG);

    let seen = stats.get();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}, {seen:?}");
    assert_eq!(result.error_code, NavigateToPoseResult::NONE);
    assert!(
        seen.robot.distance(&FAR_END) <= 0.25,
        "the robot is at {:?}",
        seen.robot
    );
    assert!(seen.planner.succeeded >= 2, "replanned: {seen:?}");
    assert!(
        seen.controller.aborted >= 1,
        "the obstacle stopped the controller: {seen:?}"
    );
    assert!(recoveries >= 1, "feedback counted {recoveries} recoveries");
}

pub(crate) fn cancelling_the_goal_halts_the_tree_and_cancels_follow_path_on_the_server() {
    let domain = free_domain();
    let (_sim, stats) = sim(domain.id, hall(None));
    let _navigator = navigator(domain.id);
    let ros = node("goal_client", domain.id);
    let client = ros
        .action_client::<NavigateToPose>("navigate_to_pose")
        .unwrap();

    let goal_id = send_goal(&client, FAR_END);
    assert!(
        wait_until(common::HANG, &stats, |s| s.controller.goals >= 1
            && s.distance > 0.5),
        "the controller never started: {:?}",
        stats.get()
    );
    client.cancel_goal(goal_id).unwrap();
    let (status, _, _) = wait_for_result(&client, goal_id, common::HANG);

    assert_eq!(status, GoalStatusEnum::Canceled);
    assert!(
        wait_until(common::HANG, &stats, |s| s.controller.cancels >= 1),
        "the controller saw no cancel: {:?}",
        stats.get()
    );
    let stopped_at = stats.get().distance;
    // Half a second of wall time, as many steps as the servers take in it.
    let seen = common::after_steps(&stats, 60);
    assert_eq!(seen.distance, stopped_at, "the robot stopped: {seen:?}");
    assert!(seen.robot.distance(&FAR_END) > 1.0, "{seen:?}");
}

pub(crate) fn an_application_trees_navigate_to_pose_is_served_by_the_navigator() {
    let domain = free_domain();
    let (_sim, stats) = sim(domain.id, hall(None));
    let _navigator = navigator(domain.id);
    let ros = node("application", domain.id);
    let mut registry = neurotree_toolkit::Registry::<()>::new();
    neurotree_ros2::nav2::register_nav2_ros_leaves(&mut registry, &ros).unwrap();
    let mut loader = neurotree_toolkit::XmlLoader::new(&registry);
    loader
        .load_str(
            r#"<root BTCPP_format="4"><BehaviorTree ID="App">
                 <NavigateToPose goal="{goal}" error_code_id="{code}" error_msg="{msg}"/>
               </BehaviorTree></root>"#,
            "app.xml",
        )
        .unwrap();
    let mut tree = common::tree(Arc::new(loader.build_main().unwrap()));
    tree.blackboard_mut().set("goal", FAR_END).unwrap();
    let status = common::tick_until_done(&mut tree, &mut (), common::HANG);
    let seen = stats.get();
    assert_eq!(status, neurotree_toolkit::Status::Success, "{seen:?}");
    assert_eq!(tree.blackboard().get::<u16>("code").unwrap(), 0);
    assert!(seen.robot.distance(&FAR_END) <= 0.25, "{seen:?}");
    // A goal in a wall: the navigator's tree fails, and its code reaches the application.
    tree.blackboard_mut()
        .set("goal", Pose2D::new(0.5, 0.5, 0.0))
        .unwrap();
    let status = common::tick_until_done(&mut tree, &mut (), common::HANG);
    assert_eq!(status, neurotree_toolkit::Status::Failure);
    assert_eq!(
        tree.blackboard().get::<u16>("code").unwrap(),
        NavigateToPoseResult::UNKNOWN
    );
}

pub(crate) fn the_navigator_loads_every_node_type_of_nav2_main_and_refuses_an_unknown_one_by_name()
{
    let domain = free_domain();
    let ros = node("bt_navigator", domain.id);
    let tree = |body: &str| {
        format!(r#"<root BTCPP_format="4"><BehaviorTree ID="N">{body}</BehaviorTree></root>"#)
    };
    let known = tree(
        r#"<Sequence>
             <GetCurrentPose current_pose="{pose}"/>
             <ArePosesNear ref_pose="{pose}" target_pose="{goal}"/>
             <GoalReached goal="{goal}"/>
             <RemovePassedGoals input_goals="{goals}" output_goals="{goals}"/>
             <GetNextFewGoals num_goals="2" input_goals="{goals}" output_goals="{next}"/>
             <ComputePathThroughPoses goals="{next}" path="{path}"/>
             <TruncatePath input_path="{path}" output_path="{path}"/>
             <SmoothPath unsmoothed_path="{path}" smoothed_path="{path}"/>
             <IsBatteryLow min_battery="0.2"/>
             <CancelSpin/>
             <TimeExpired seconds="2"/>
             <DistanceTraveled distance="1"/>
             <InitialPoseReceived/>
             <TransformAvailable child="base_link" parent="map"/>
           </Sequence>"#,
    );
    let options = NavigatorOptions::default();
    assert!(Navigator::on_map(&ros, &known, "known.xml", hall(None), &options).is_ok());
    // Every node type of Nav2 main loads in the navigator.
    let model = neurotree_nav2::NAV2_TREE_NODES_MODEL;
    let mut missing = Vec::new();
    for name in model
        .split("ID=\"")
        .skip(1)
        .filter_map(|r| r.split('"').next())
    {
        let one = tree(&format!("<{name}/>"));
        if let Err(e) = Navigator::on_map(&ros, &one, "one.xml", hall(None), &options) {
            if e.to_string().contains("unknown node type") {
                missing.push(name.to_owned());
            }
        }
    }
    assert_eq!(missing, Vec::<String>::new());
    let unknown = tree(r#"<DockRobotTwice dock_id="home"/>"#);
    let Err(error) = Navigator::on_map(&ros, &unknown, "dock.xml", hall(None), &options) else {
        panic!("a node type Nav2 does not have loaded");
    };
    assert!(
        error
            .to_string()
            .contains("unknown node type `DockRobotTwice`"),
        "{error}"
    );
}
