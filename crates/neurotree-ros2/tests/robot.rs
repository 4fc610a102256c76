//! A robot's own program over ROS 2: a [`Navigator`] over the robot's context (not the
//! simulator's), its tree made of Nav2's ROS 2 clients and a leaf of the robot's own,
//! against the grid world served as Nav2's servers on another participant.

use crate::common;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

use common::{free_domain, node, Served};
use neurotree_nav2::robotics::Pose2D;
use neurotree_nav2::Nav2Release;
use neurotree_ros2::msg::nav2_msgs::{NavigateToPose, NavigateToPoseGoal, NavigateToPoseResult};
use neurotree_ros2::nav2::convert::pose_stamped;
use neurotree_ros2::nav2::{
    register_navigator_nodes, Navigator, NavigatorContext, NavigatorOptions, NavigatorStats,
};
use neurotree_ros2::ros2_client::action::GoalStatusEnum;
use neurotree_sim::nav2::Nav2Sim;
use neurotree_sim::GridWorld;
use neurotree_toolkit::{Registry, Status};

/// A corridor; the robot at its left end, (1.5, 1.5).
const CORRIDOR: &str = "
    ##########
    #R.......#
    ##########";

/// The corridor's far end.
const FAR_END: Pose2D = Pose2D::new(8.5, 1.5, 0.0);

/// Plan, mark, follow, mark: the robot's leaf `Mark` between Nav2's clients.
const ROBOT_XML: &str = r#"
    <root BTCPP_format="4">
      <BehaviorTree ID="Deliver">
        <Sequence>
          <ComputePathToPose goal="{goal}" path="{path}"/>
          <Mark/>
          <FollowPath path="{path}"/>
          <Mark/>
        </Sequence>
      </BehaviorTree>
    </root>"#;

/// The robot's context: what its own leaves and the navigator give it.
#[derive(Debug, Default)]
struct Robot {
    /// The last pose the navigator passed on.
    at: Option<Pose2D>,
    /// Poses the navigator passed on.
    poses: u32,
    /// Where the robot was at each tick of `Mark`.
    marks: Vec<Option<Pose2D>>,
}

impl NavigatorContext for Robot {
    fn set_robot_pose(&mut self, pose: Pose2D) {
        self.at = Some(pose);
        self.poses += 1;
    }
}

/// The navigator in a thread until `stop`; then what its context saw and its stats.
fn navigate(
    domain: u16,
    stop: Arc<AtomicBool>,
) -> std::thread::JoinHandle<(Robot, NavigatorStats)> {
    let (tx, rx) = mpsc::channel();
    let thread = std::thread::spawn(move || {
        let ros = node("robot", domain);
        let mut registry = Registry::<Robot>::new();
        register_navigator_nodes(&mut registry, &ros, Nav2Release::default()).unwrap();
        registry
            .register_action("Mark", vec![], |h| {
                let robot = h.ctx_mut();
                let at = robot.at;
                robot.marks.push(at);
                Status::Success
            })
            .unwrap();
        let options = NavigatorOptions::default();
        let mut navigator = Navigator::new(
            &ros,
            &registry,
            ROBOT_XML,
            "deliver.xml",
            Robot::default(),
            &options,
        )
        .unwrap();
        tx.send(()).unwrap();
        navigator.run(&stop).unwrap();
        let stats = navigator.stats();
        (std::mem::take(navigator.context_mut()), stats)
    });
    rx.recv_timeout(common::HANG).unwrap();
    thread
}

pub(crate) fn a_navigator_over_the_robots_own_context_runs_its_leaf_between_nav2s_clients() {
    let domain = free_domain();
    let world = GridWorld::parse(CORRIDOR, 1.0).unwrap();
    let served = Served::start(domain.id, Nav2Sim::new(world), common::TIME_SCALE);
    let stop = Arc::new(AtomicBool::new(false));
    let navigator = navigate(domain.id, Arc::clone(&stop));
    let ros = node("goal_client", domain.id);
    let client = ros
        .action_client::<NavigateToPose>("navigate_to_pose")
        .unwrap();

    // The first goal may go out before the navigator is discovered: send until accepted.
    let until = Instant::now() + common::HANG;
    let goal_id = 'sent: loop {
        assert!(
            Instant::now() < until,
            "the navigator did not answer the goal"
        );
        let goal = NavigateToPoseGoal {
            pose: pose_stamped(FAR_END),
            behavior_tree: String::new(),
        };
        let (request, goal_id) = client.send_goal(goal).unwrap();
        let answer_by = Instant::now() + Duration::from_secs(2);
        while Instant::now() < answer_by {
            if let Some(response) = client.receive_goal_response(request).unwrap() {
                assert!(response.accepted);
                break 'sent goal_id;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    };
    let request = client.request_result(goal_id).unwrap();
    let until = Instant::now() + common::HANG;
    let (status, result) = loop {
        assert!(
            Instant::now() < until,
            "no result: {:?}",
            served.stats.get()
        );
        if let Some(answer) = client.receive_result(request).unwrap() {
            break answer;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    stop.store(true, Ordering::SeqCst);
    let (robot, stats) = navigator.join().unwrap();
    let seen = served.stats.get();

    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}, {seen:?}");
    assert_eq!(result.error_code, NavigateToPoseResult::NONE);
    assert_eq!(
        stats,
        NavigatorStats {
            goals: 1,
            succeeded: 1,
            ..NavigatorStats::default()
        }
    );
    // One plan, one path followed to its end, by Nav2's clients on the simulated servers.
    assert_eq!(
        (seen.planner.goals, seen.planner.succeeded),
        (1, 1),
        "{seen:?}"
    );
    assert_eq!(
        (seen.controller.goals, seen.controller.succeeded),
        (1, 1),
        "{seen:?}"
    );
    assert!(seen.robot.distance(&FAR_END) <= 0.25, "{seen:?}");
    // The robot's leaf ran once after planning and once on arrival, where the pose topic,
    // passed on by the navigator, put the robot.
    assert_eq!(robot.marks.len(), 2, "{robot:?}");
    let arrived = robot.marks[1].expect("a pose came before the arrival");
    assert!(arrived.distance(&FAR_END) <= 0.25, "{robot:?}");
    assert!(robot.poses >= 2, "{robot:?}");
}
