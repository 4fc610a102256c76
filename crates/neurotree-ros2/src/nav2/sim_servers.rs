//! [`SimServers`]: the grid world served as the Nav2 servers a navigator calls.
//!
//! | server | name | what it does on the world |
//! |---|---|---|
//! | planner | actions `compute_path_to_pose`, `compute_path_through_poses` | A* on the global costmap (the sim's ComputePathToPose, ComputePathThroughPoses) |
//! | smoother | action `smooth_path` | the sim's SmoothPath |
//! | controller | action `follow_path` | follows the path, fails when blocked (the sim's FollowPath) |
//! | behaviors | actions `spin`, `backup`, `drive_on_heading`, `wait` | turn, drive back, drive on, stand still (the sim's Spin, BackUp, DriveOnHeading, Wait) |
//! | costmaps | services `global_costmap/clear_entirely_global_costmap`, `local_costmap/clear_entirely_local_costmap` | forget the sensed obstacles |
//! | costmaps | services `clear_around_`, `clear_except_` and `clear_around_pose_` of each costmap (`local_costmap/clear_around_local_costmap`, ...) | forget them in, or outside, a square (the sim's ClearCostmapAroundRobot, ClearCostmapExceptRegion, ClearCostmapAroundPose) |
//! | costmaps | services `global_costmap/get_cost_global_costmap`, `local_costmap/get_cost_local_costmap` (`nav2_msgs/srv/GetCosts`) | the cost at each pose: 254 on a wall or sensed obstacle, 0 on a free cell; off the map 255 and `success` false (the sim's CheckPoseOccupancy, RemoveInCollisionGoals) |
//! | route server | actions `compute_route`, `compute_and_track_route` | the cheapest route on the world's [`RouteGraph`](neurotree_sim::nav2::RouteGraph), and the robot tracked along it with feedback (the sim's ComputeRoute, ComputeAndTrackRoute) |
//! | docking server | actions `dock_robot`, `undock_robot` | dock at one of the world's [`Dock`](neurotree_sim::nav2::Dock)s, back off it (the sim's DockRobot, UndockRobot) |
//! | navigator | action `navigate_through_poses` | plan and follow through the poses (the sim's NavigateThroughPoses) |
//! | following server | action `follow_object` | follow the world's object ([`Nav2Sim::set_object`]), a metre behind (the sim's FollowObject); a pose on [`OBJECT_POSE_TOPIC`] moves the object (a goal naming another `pose_topic` follows it all the same) |
//! | behaviors | action `assisted_teleop` | no one drives: the robot stands still until the time allowance runs out (TIMEOUT 731) or a message on [`PREEMPT_TELEOP_TOPIC`] ends it with success |
//! | collision monitor | service `collision_monitor/toggle` (`nav2_msgs/srv/Toggle`) | turns the world's collision monitor on or off |
//! | localization | service `reinitialize_global_localization` (`std_srvs/srv/Empty`) | counted: the simulated robot knows where it is |
//! | pose | topic [`ROBOT_POSE_TOPIC`] | the robot's pose, each step |
//! | odometry | topic [`ODOM_TOPIC`](super::ODOM_TOPIC) | `nav_msgs/Odometry`: the robot's pose, its speed and turn rate over the last step, stamped with the simulated time, each step |
//! | battery | topic [`BATTERY_TOPIC`](super::BATTERY_TOPIC) | the world's battery (`sensor_msgs/BatteryState`: percentage, charging on the charger), each step |
//!
//! Each goal runs the in-process leaf of `neurotree_sim::nav2` of the same name, alone in a
//! tree of its own, over the one [`Nav2Sim`]: the servers behave as the simulated leaves do
//! (the same error codes, tolerances and time allowances). The world steps on its own
//! clock: every `period / time_scale` of wall time, it moves on by one period
//! ([`Nav2Params::period`](neurotree_sim::nav2::Nav2Params)), from the first goal on
//! ([`SimOptions::start_on_first_goal`]). The controller, the behaviors, the docking
//! server, the navigator through poses and the following server command the one robot: a
//! goal for one of them aborts the goal another one is running. A cancel request halts the goal's tree, which stops the robot.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use neurotree_nav2::robotics::{Path, Pose2D, Route};
use neurotree_nav2::Nav2Release;
use neurotree_sim::nav2::costmaps::clear_square;
use neurotree_sim::nav2::{register_nav2_leaves, FailureNotes, Nav2Sim, TrackingFeedback};
use neurotree_sim::CostmapLayer;
use neurotree_toolkit::{Blackboard, Blueprint, Registry, Status, Tree, XmlLoader};
use ros2_client::action::GoalStatusEnum;
use ros2_client::service::Server;
use ros2_client::{Publisher, Subscription};

use super::clearing::ClearLayout;
use super::convert::{goals_2d, path_2d, path_msg, pose_2d, pose_stamped, route_msg};
use super::goal_server::{GoalServer, Request};
use super::navigator::{NavigatorError, ROBOT_POSE_TOPIC};
use super::GET_COST_GLOBAL_COSTMAP;
use crate::msg::geometry_msgs::PoseStamped;
use crate::msg::geometry_msgs::{Twist, Vector3};
use crate::msg::nav2_msgs::{
    kilted, BackUpGoal, ComputePathThroughPosesGoal, ComputePathToPoseGoal, DriveOnHeadingGoal,
    FollowPathGoal, SpinGoal,
};
use crate::msg::nav2_msgs::{
    main, BackUp, BackUpResult, ClearCostmapAroundPose, ClearCostmapAroundRobot,
    ClearCostmapExceptRegion, ClearEntireCostmap, ComputePathThroughPoses,
    ComputePathThroughPosesResult, ComputePathToPose, ComputePathToPoseResult, DriveOnHeading,
    DriveOnHeadingResult, FollowPath, FollowPathFeedback, FollowPathResult, Spin, SpinResult, Wait,
    WaitResult,
};
use crate::msg::nav2_msgs::{
    AssistedTeleop, AssistedTeleopFeedback, AssistedTeleopResult, ComputeAndTrackRoute,
    ComputeAndTrackRouteFeedback, ComputeAndTrackRouteResult, ComputeRoute, ComputeRouteResult,
    DockRobot, DockRobotResult, FollowObject, FollowObjectResult, GetCosts, GetCostsRequest,
    GetCostsResponse, NavigateThroughPoses, NavigateThroughPosesResult, Toggle, ToggleRequest,
    ToggleResponse, UndockRobot, UndockRobotResult,
};
use crate::msg::nav2_msgs::{SmoothPath, SmoothPathResult};
use crate::msg::nav_msgs::Odometry;
use crate::msg::sensor_msgs::BatteryState;
use crate::msg::std_msgs::{Empty, Header};
use crate::msg::std_srvs::{self, EmptyRequest, EmptyResponse};
use crate::{Ros2Error, RosAction, RosNode, RosService};

/// The global costmap's clearing service.
pub const CLEAR_GLOBAL_COSTMAP: &str = "global_costmap/clear_entirely_global_costmap";
/// The local costmap's clearing service.
pub const CLEAR_LOCAL_COSTMAP: &str = "local_costmap/clear_entirely_local_costmap";
/// The local costmap's cost service (the global one's is
/// [`GET_COST_GLOBAL_COSTMAP`](super::GET_COST_GLOBAL_COSTMAP)).
pub const GET_COST_LOCAL_COSTMAP: &str = "local_costmap/get_cost_local_costmap";

/// What one action server saw.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ServerCounts {
    /// Goals accepted.
    pub goals: u32,
    /// Cancel requests for a running goal.
    pub cancels: u32,
    /// Goals that succeeded.
    pub succeeded: u32,
    /// Goals that aborted (failed, or preempted).
    pub aborted: u32,
}

/// What the servers saw, for tests and summaries.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SimStats {
    /// `compute_path_to_pose`.
    pub planner: ServerCounts,
    /// `compute_path_through_poses`.
    pub planner_through_poses: ServerCounts,
    /// `smooth_path`.
    pub smoother: ServerCounts,
    /// `follow_path`.
    pub controller: ServerCounts,
    /// `spin`.
    pub spin: ServerCounts,
    /// `backup`.
    pub backup: ServerCounts,
    /// `drive_on_heading`.
    pub drive_on_heading: ServerCounts,
    /// `wait`.
    pub wait: ServerCounts,
    /// `compute_route`.
    pub route: ServerCounts,
    /// `compute_and_track_route`.
    pub route_tracking: ServerCounts,
    /// `dock_robot`.
    pub dock: ServerCounts,
    /// `undock_robot`.
    pub undock: ServerCounts,
    /// `navigate_through_poses`.
    pub navigate_through_poses: ServerCounts,
    /// `follow_object`.
    pub follow_object: ServerCounts,
    /// `assisted_teleop`.
    pub assisted_teleop: ServerCounts,
    /// Costmap clearings served (entire and regions).
    pub clears: u32,
    /// Cost requests served (`get_cost_` of either costmap).
    pub cost_requests: u32,
    /// Whether the collision monitor is on (`collision_monitor/toggle`).
    pub collision_monitor: bool,
    /// Requests served by `reinitialize_global_localization`.
    pub relocalizations: u32,
    /// The `disable_collision_checks` of the last Spin, BackUp or DriveOnHeading goal in
    /// Kilted's layout; `None` while only Jazzy's (which has no such field) came.
    pub disable_collision_checks: Option<bool>,
    /// How many `viapoints` the last ComputePathToPose goal in main's layout had; `None`
    /// while only the older layout (which has no such field) came.
    pub viapoints: Option<usize>,
    /// Obstacle cells the global costmap remembers.
    pub global_obstacles: usize,
    /// Obstacle cells the local costmap remembers.
    pub local_obstacles: usize,
    /// Where the robot is.
    pub robot: Pose2D,
    /// Simulated time.
    pub time: Duration,
    /// Metres the robot drove.
    pub distance: f64,
}

/// Shared [`SimStats`]: clones read the same counts.
#[derive(Clone, Debug, Default)]
pub struct SimStatsHandle(Arc<Mutex<SimStats>>);

impl SimStatsHandle {
    /// The counts now.
    pub fn get(&self) -> SimStats {
        *self.lock()
    }

    fn lock(&self) -> MutexGuard<'_, SimStats> {
        // Plain counters: still meaningful after a panic elsewhere.
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// How the servers run.
#[derive(Clone, Copy, Debug)]
pub struct SimOptions {
    /// Simulated seconds per wall second: 2.0 runs the world twice as fast as real time.
    pub time_scale: f64,
    /// Hold the world's clock until the first goal arrives, so that its timed obstacles
    /// are timed from the start of the navigation, however long the navigator took to
    /// come up.
    pub start_on_first_goal: bool,
    /// The Nav2 release whose goal and clearing layouts the servers read (see
    /// [`register_nav2_ros_leaves_for`](super::register_nav2_ros_leaves_for)).
    pub release: Nav2Release,
}

impl Default for SimOptions {
    /// Real time, from the first goal, Nav2 main's goals.
    fn default() -> Self {
        Self {
            time_scale: 1.0,
            start_on_first_goal: true,
            release: Nav2Release::default(),
        }
    }
}

/// An action whose goals the sim runs with its leaf of the same name.
trait SimAction: RosAction
where
    Self::Result: Default,
{
    /// The one-node tree: the leaf with its ports on blackboard entries.
    const XML: &'static str;
    /// The goal's fields to the blackboard.
    fn put(goal: &Self::Goal, bb: &mut Blackboard);
    /// The result, from the blackboard after the leaf ended.
    fn result(bb: &Blackboard, code: u16, message: String, elapsed: Duration) -> Self::Result;
    /// Feedback after a Running tick.
    fn feedback(_bb: &Blackboard, _sim: &Nav2Sim) -> Option<Self::Feedback> {
        None
    }
    /// Which counts of [`SimStats`] are this server's.
    fn counts(stats: &mut SimStats) -> &mut ServerCounts;
    /// Notes what of the goal the stats keep.
    fn record(_goal: &Self::Goal, _stats: &mut SimStats) {}
}

// The entries are written before the tree first ticks: set fails only for a type that
// an entry already has with another type, which a fresh tree does not.

impl SimAction for ComputePathToPose {
    const XML: &'static str = r#"<ComputePathToPose goal="{goal}" start="{start}" planner_id="{planner_id}" path="{path}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let _ = bb.set("goal", pose_2d(&goal.goal));
        if goal.use_start {
            let _ = bb.set("start", pose_2d(&goal.start));
        }
        let _ = bb.set("planner_id", goal.planner_id.clone());
    }
    fn result(bb: &Blackboard, code: u16, message: String, elapsed: Duration) -> Self::Result {
        ComputePathToPoseResult {
            path: path_msg(&bb.get::<Path>("path").unwrap_or_default()),
            planning_time: elapsed.into(),
            error_code: code,
            error_msg: message,
        }
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.planner
    }
}

impl SimAction for ComputePathThroughPoses {
    const XML: &'static str = r#"<ComputePathThroughPoses goals="{goals}" start="{start}" planner_id="{planner_id}" path="{path}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let goals: Vec<Pose2D> = goal.goals.iter().map(pose_2d).collect();
        let _ = bb.set("goals", goals);
        if goal.use_start {
            let _ = bb.set("start", pose_2d(&goal.start));
        }
        let _ = bb.set("planner_id", goal.planner_id.clone());
    }
    fn result(bb: &Blackboard, code: u16, message: String, elapsed: Duration) -> Self::Result {
        ComputePathThroughPosesResult {
            path: path_msg(&bb.get::<Path>("path").unwrap_or_default()),
            planning_time: elapsed.into(),
            error_code: code,
            error_msg: message,
        }
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.planner_through_poses
    }
}

impl SimAction for SmoothPath {
    const XML: &'static str = r#"<SmoothPath unsmoothed_path="{unsmoothed_path}" smoother_id="{smoother_id}" check_for_collisions="{check_for_collisions}" smoothed_path="{smoothed_path}" was_completed="{was_completed}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let _ = bb.set("unsmoothed_path", path_2d(&goal.path));
        let _ = bb.set("smoother_id", goal.smoother_id.clone());
        let _ = bb.set("check_for_collisions", goal.check_for_collisions);
    }
    fn result(bb: &Blackboard, code: u16, message: String, elapsed: Duration) -> Self::Result {
        SmoothPathResult {
            path: path_msg(&bb.get::<Path>("smoothed_path").unwrap_or_default()),
            smoothing_duration: elapsed.into(),
            was_completed: bb.get::<bool>("was_completed").unwrap_or(false),
            error_code: code,
            error_msg: message,
        }
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.smoother
    }
}

impl SimAction for FollowPath {
    const XML: &'static str = r#"<FollowPath path="{path}" controller_id="{controller_id}" tracking_feedback="{tracking_feedback}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let _ = bb.set("path", path_2d(&goal.path));
        let _ = bb.set("controller_id", goal.controller_id.clone());
    }
    fn result(_bb: &Blackboard, code: u16, message: String, _elapsed: Duration) -> Self::Result {
        FollowPathResult {
            error_code: code,
            error_msg: message,
            ..FollowPathResult::default()
        }
    }
    fn feedback(bb: &Blackboard, sim: &Nav2Sim) -> Option<FollowPathFeedback> {
        let path = bb.get::<Path>("path").ok()?;
        let robot = sim.world.robot();
        let goal = path.goal()?;
        let left = super::convert::distance_remaining(Some(&path), robot, goal);
        Some(FollowPathFeedback {
            distance_to_goal: left as f32,
            speed: sim.params.speed as f32,
        })
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.controller
    }
}

impl SimAction for Spin {
    const XML: &'static str = r#"<Spin spin_dist="{spin_dist}" time_allowance="{time_allowance}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let _ = bb.set("spin_dist", f64::from(goal.target_yaw));
        let allowance: Duration = goal.time_allowance.into();
        let _ = bb.set("time_allowance", allowance.as_secs_f64());
    }
    fn result(_bb: &Blackboard, code: u16, message: String, elapsed: Duration) -> Self::Result {
        SpinResult {
            total_elapsed_time: elapsed.into(),
            error_code: code,
            error_msg: message,
        }
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.spin
    }
}

impl SimAction for BackUp {
    const XML: &'static str = r#"<BackUp backup_dist="{backup_dist}" backup_speed="{backup_speed}" time_allowance="{time_allowance}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let _ = bb.set("backup_dist", goal.target.x);
        let _ = bb.set("backup_speed", f64::from(goal.speed));
        let allowance: Duration = goal.time_allowance.into();
        let _ = bb.set("time_allowance", allowance.as_secs_f64());
    }
    fn result(_bb: &Blackboard, code: u16, message: String, elapsed: Duration) -> Self::Result {
        BackUpResult {
            total_elapsed_time: elapsed.into(),
            error_code: code,
            error_msg: message,
        }
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.backup
    }
}

impl SimAction for DriveOnHeading {
    const XML: &'static str = r#"<DriveOnHeading dist_to_travel="{dist_to_travel}" speed="{speed}" time_allowance="{time_allowance}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let _ = bb.set("dist_to_travel", goal.target.x);
        let _ = bb.set("speed", f64::from(goal.speed));
        let allowance: Duration = goal.time_allowance.into();
        let _ = bb.set("time_allowance", allowance.as_secs_f64());
    }
    fn result(_bb: &Blackboard, code: u16, message: String, elapsed: Duration) -> Self::Result {
        DriveOnHeadingResult {
            total_elapsed_time: elapsed.into(),
            error_code: code,
            error_msg: message,
        }
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.drive_on_heading
    }
}

impl SimAction for Wait {
    const XML: &'static str = r#"<Wait wait_duration="{wait_duration}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let time: Duration = goal.time.into();
        let _ = bb.set("wait_duration", time.as_secs_f64());
    }
    fn result(_bb: &Blackboard, code: u16, message: String, elapsed: Duration) -> Self::Result {
        WaitResult {
            total_elapsed_time: elapsed.into(),
            error_code: code,
            error_msg: message,
        }
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.wait
    }
}

/// The route goals' fields to the blackboard, for the route leaves' ports.
fn put_route_goal(
    bb: &mut Blackboard,
    (start_id, start, goal_id, goal): (u16, &PoseStamped, u16, &PoseStamped),
    (use_start, use_poses): (bool, bool),
) {
    let _ = bb.set("start_id", start_id);
    let _ = bb.set("goal_id", goal_id);
    let _ = bb.set("use_start", use_start);
    let _ = bb.set("use_poses", use_poses);
    if use_poses {
        let _ = bb.set("goal", pose_2d(goal));
        if use_start {
            let _ = bb.set("start", pose_2d(start));
        }
    }
}

impl SimAction for ComputeRoute {
    const XML: &'static str = r#"<ComputeRoute start="{start}" goal="{goal}" start_id="{start_id}" goal_id="{goal_id}" use_start="{use_start}" use_poses="{use_poses}" route="{route}" path="{path}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        put_route_goal(
            bb,
            (goal.start_id, &goal.start, goal.goal_id, &goal.goal),
            (goal.use_start, goal.use_poses),
        );
    }
    fn result(bb: &Blackboard, code: u16, message: String, elapsed: Duration) -> Self::Result {
        ComputeRouteResult {
            planning_time: elapsed.into(),
            path: path_msg(&bb.get::<Path>("path").unwrap_or_default()),
            route: route_msg(&bb.get::<Route>("route").unwrap_or_default()),
            error_code: code,
            error_msg: message,
        }
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.route
    }
}

impl SimAction for ComputeAndTrackRoute {
    const XML: &'static str = r#"<ComputeAndTrackRoute start="{start}" goal="{goal}" start_id="{start_id}" goal_id="{goal_id}" use_start="{use_start}" use_poses="{use_poses}" route="{route}" path="{path}" last_node_id="{last_node_id}" next_node_id="{next_node_id}" current_edge_id="{current_edge_id}" rerouted="{rerouted}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        put_route_goal(
            bb,
            (goal.start_id, &goal.start, goal.goal_id, &goal.goal),
            (goal.use_start, goal.use_poses),
        );
    }
    fn result(_bb: &Blackboard, code: u16, message: String, elapsed: Duration) -> Self::Result {
        ComputeAndTrackRouteResult {
            execution_duration: elapsed.into(),
            error_code: code,
            error_msg: message,
        }
    }
    fn feedback(bb: &Blackboard, _sim: &Nav2Sim) -> Option<ComputeAndTrackRouteFeedback> {
        Some(ComputeAndTrackRouteFeedback {
            last_node_id: bb.get::<u16>("last_node_id").unwrap_or(0),
            next_node_id: bb.get::<u16>("next_node_id").unwrap_or(0),
            current_edge_id: bb.get::<u16>("current_edge_id").unwrap_or(0),
            route: route_msg(&bb.get::<Route>("route").unwrap_or_default()),
            path: path_msg(&bb.get::<Path>("path").unwrap_or_default()),
            operations_triggered: Vec::new(),
            rerouted: bb.get::<bool>("rerouted").unwrap_or(false),
        })
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.route_tracking
    }
}

impl SimAction for DockRobot {
    const XML: &'static str = r#"<DockRobot use_dock_id="{use_dock_id}" dock_id="{dock_id}" dock_pose="{dock_pose}" dock_type="{dock_type}" max_staging_time="{max_staging_time}" navigate_to_staging_pose="{navigate_to_staging_pose}" success="{success}" num_retries="{num_retries}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let _ = bb.set("use_dock_id", goal.use_dock_id);
        let _ = bb.set("dock_id", goal.dock_id.clone());
        let _ = bb.set("dock_pose", pose_2d(&goal.dock_pose));
        let _ = bb.set("dock_type", goal.dock_type.clone());
        let _ = bb.set("max_staging_time", f64::from(goal.max_staging_time));
        let _ = bb.set("navigate_to_staging_pose", goal.navigate_to_staging_pose);
    }
    fn result(bb: &Blackboard, code: u16, message: String, _elapsed: Duration) -> Self::Result {
        DockRobotResult {
            success: bb.get::<bool>("success").unwrap_or(code == 0),
            error_code: code,
            num_retries: bb.get::<u16>("num_retries").unwrap_or(0),
            error_msg: message,
        }
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.dock
    }
}

impl SimAction for UndockRobot {
    const XML: &'static str = r#"<UndockRobot dock_type="{dock_type}" max_undocking_time="{max_undocking_time}" success="{success}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let _ = bb.set("dock_type", goal.dock_type.clone());
        let _ = bb.set("max_undocking_time", f64::from(goal.max_undocking_time));
    }
    fn result(bb: &Blackboard, code: u16, message: String, _elapsed: Duration) -> Self::Result {
        UndockRobotResult {
            success: bb.get::<bool>("success").unwrap_or(code == 0),
            error_code: code,
            error_msg: message,
        }
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.undock
    }
}

impl SimAction for NavigateThroughPoses {
    const XML: &'static str = r#"<NavigateThroughPoses goals="{goals}" behavior_tree="{behavior_tree}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let _ = bb.set("goals", goals_2d(&goal.poses));
        let _ = bb.set("behavior_tree", goal.behavior_tree.clone());
    }
    fn result(_bb: &Blackboard, code: u16, message: String, _elapsed: Duration) -> Self::Result {
        NavigateThroughPosesResult {
            error_code: code,
            error_msg: message,
            waypoint_statuses: Vec::new(),
        }
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.navigate_through_poses
    }
}

impl SimAction for FollowObject {
    const XML: &'static str = r#"<FollowObject pose_topic="{pose_topic}" max_duration="{max_duration}" total_elapsed_time="{total_elapsed_time}" error_code_id="{error_code}" error_msg="{error_msg}"/>"#;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let _ = bb.set("pose_topic", goal.pose_topic.clone());
        let max: Duration = goal.max_duration.into();
        let _ = bb.set("max_duration", max.as_secs_f64());
    }
    fn result(_bb: &Blackboard, code: u16, message: String, elapsed: Duration) -> Self::Result {
        FollowObjectResult {
            total_elapsed_time: elapsed.into(),
            error_code: code,
            num_retries: 0,
            error_msg: message,
        }
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        &mut stats.follow_object
    }
}

/// Implements [`SimAction`] for a newer goal layout (Kilted's, main's) as the Jazzy
/// action's, its goal made Jazzy's by `$to_jazzy`; `$record` notes the new fields in the
/// stats (the sim reads none: the world never lets the robot into an occupied cell, and
/// its planner plans straight to the goal).
macro_rules! kilted_as_jazzy {
    ($kilted:ty, $jazzy:ty, $to_jazzy:expr, $record:expr) => {
        impl SimAction for $kilted {
            const XML: &'static str = <$jazzy as SimAction>::XML;
            fn put(goal: &Self::Goal, bb: &mut Blackboard) {
                <$jazzy as SimAction>::put(&$to_jazzy(goal), bb);
            }
            fn result(
                bb: &Blackboard,
                code: u16,
                message: String,
                elapsed: Duration,
            ) -> Self::Result {
                <$jazzy as SimAction>::result(bb, code, message, elapsed)
            }
            fn counts(stats: &mut SimStats) -> &mut ServerCounts {
                <$jazzy as SimAction>::counts(stats)
            }
            fn record(goal: &Self::Goal, stats: &mut SimStats) {
                $record(goal, stats);
            }
        }
    };
}

kilted_as_jazzy!(
    kilted::Spin,
    Spin,
    |g: &kilted::SpinGoal| SpinGoal {
        target_yaw: g.target_yaw,
        time_allowance: g.time_allowance,
    },
    |g: &kilted::SpinGoal, stats: &mut SimStats| {
        stats.disable_collision_checks = Some(g.disable_collision_checks);
    }
);
kilted_as_jazzy!(
    kilted::BackUp,
    BackUp,
    |g: &kilted::BackUpGoal| BackUpGoal {
        target: g.target,
        speed: g.speed,
        time_allowance: g.time_allowance,
    },
    |g: &kilted::BackUpGoal, stats: &mut SimStats| {
        stats.disable_collision_checks = Some(g.disable_collision_checks);
    }
);
kilted_as_jazzy!(
    kilted::DriveOnHeading,
    DriveOnHeading,
    |g: &kilted::DriveOnHeadingGoal| DriveOnHeadingGoal {
        target: g.target,
        speed: g.speed,
        time_allowance: g.time_allowance,
    },
    |g: &kilted::DriveOnHeadingGoal, stats: &mut SimStats| {
        stats.disable_collision_checks = Some(g.disable_collision_checks);
    }
);
kilted_as_jazzy!(
    main::ComputePathToPose,
    ComputePathToPose,
    |g: &main::ComputePathToPoseGoal| ComputePathToPoseGoal {
        goal: g.goal.clone(),
        start: g.start.clone(),
        planner_id: g.planner_id.clone(),
        use_start: g.use_start,
    },
    |g: &main::ComputePathToPoseGoal, stats: &mut SimStats| {
        stats.viapoints = Some(g.viapoints.len());
    }
);
/// Main's FollowPath: Jazzy's, but for the path handler (which the sim has not) and the
/// feedback, the sim's tracking feedback with the robot's pose, distance and speed.
impl SimAction for main::FollowPath {
    const XML: &'static str = <FollowPath as SimAction>::XML;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let jazzy = FollowPathGoal {
            path: goal.path.clone(),
            controller_id: goal.controller_id.clone(),
            goal_checker_id: goal.goal_checker_id.clone(),
            progress_checker_id: goal.progress_checker_id.clone(),
        };
        <FollowPath as SimAction>::put(&jazzy, bb);
    }
    fn result(bb: &Blackboard, code: u16, message: String, elapsed: Duration) -> Self::Result {
        <FollowPath as SimAction>::result(bb, code, message, elapsed)
    }
    fn feedback(bb: &Blackboard, sim: &Nav2Sim) -> Option<main::FollowPathFeedback> {
        let old = <FollowPath as SimAction>::feedback(bb, sim)?;
        let t = bb
            .get::<TrackingFeedback>("tracking_feedback")
            .unwrap_or_default();
        Some(main::FollowPathFeedback {
            tracking_feedback: main::TrackingFeedback {
                header: pose_stamped(sim.world.robot()).header,
                position_tracking_error: t.position_tracking_error as f32,
                heading_tracking_error: t.heading_tracking_error as f32,
                current_path_index: u32::try_from(t.current_path_index).unwrap_or(u32::MAX),
                robot_pose: pose_stamped(sim.world.robot()),
                distance_to_goal: old.distance_to_goal,
                speed: old.speed,
                remaining_path_length: t.remaining_path_length as f32,
            },
        })
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        <FollowPath as SimAction>::counts(stats)
    }
}

kilted_as_jazzy!(
    kilted::ComputePathThroughPoses,
    ComputePathThroughPoses,
    |g: &kilted::ComputePathThroughPosesGoal| ComputePathThroughPosesGoal {
        goals: g.goals.goals.clone(),
        start: g.start.clone(),
        planner_id: g.planner_id.clone(),
        use_start: g.use_start,
    },
    |_: &kilted::ComputePathThroughPosesGoal, _: &mut SimStats| {}
);

/// One action server and the tree of its running goal.
struct Served<A: SimAction>
where
    A::Result: Default,
{
    goals: GoalServer<A>,
    blueprint: Arc<Blueprint<Nav2Sim>>,
    running: Option<(Tree<Nav2Sim>, Duration)>,
}

impl<A: SimAction> Served<A>
where
    A::Result: Default,
{
    fn new(
        ros: &RosNode,
        name: &str,
        registry: &Registry<Nav2Sim>,
    ) -> Result<Self, NavigatorError> {
        let mut loader = XmlLoader::new(registry);
        let xml = format!(
            r#"<root BTCPP_format="4"><BehaviorTree ID="Server">{}</BehaviorTree></root>"#,
            A::XML
        );
        loader.load_str(&xml, name)?;
        Ok(Self {
            goals: GoalServer::new(ros, name)?,
            blueprint: Arc::new(loader.build_main()?),
            running: None,
        })
    }

    /// Reads the requests; `true` if a new goal started.
    fn poll(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) -> Result<bool, Ros2Error> {
        let mut started = false;
        for request in self.goals.poll()? {
            match request {
                Request::Goal(goal) => {
                    if let Some((mut tree, _)) = self.running.take() {
                        // The server already ended the preempted goal.
                        tree.halt(sim);
                        A::counts(&mut stats.lock()).aborted += 1;
                    }
                    let mut tree = Tree::with_clock(Arc::clone(&self.blueprint), sim.world.clock());
                    if let Some(log) = sim.log() {
                        // The leaf's failures, with their reasons, in the sim's log.
                        tree.set_observer(FailureNotes::new(&self.blueprint, log.clone()));
                    }
                    A::put(&goal, tree.blackboard_mut());
                    self.running = Some((tree, sim.world.now()));
                    let mut stats = stats.lock();
                    A::counts(&mut stats).goals += 1;
                    A::record(&goal, &mut stats);
                    started = true;
                }
                Request::Cancel => {
                    // Counted before the answer goes out, which a client may act on at once.
                    A::counts(&mut stats.lock()).cancels += 1;
                    if let Some((mut tree, since)) = self.running.take() {
                        tree.halt(sim);
                        let elapsed = sim.world.now().saturating_sub(since);
                        let result = A::result(tree.blackboard(), 0, String::new(), elapsed);
                        self.goals.finish(GoalStatusEnum::Canceled, result);
                        started = false;
                    }
                }
            }
        }
        Ok(started)
    }

    /// Aborts the running goal: another server took the robot.
    fn preempt(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) {
        if let Some((mut tree, since)) = self.running.take() {
            tree.halt(sim);
            let elapsed = sim.world.now().saturating_sub(since);
            let message = "preempted by another motion".to_owned();
            let result = A::result(tree.blackboard(), 0, message, elapsed);
            A::counts(&mut stats.lock()).aborted += 1;
            self.goals.finish(GoalStatusEnum::Aborted, result);
        }
    }

    fn is_running(&self) -> bool {
        self.running.is_some()
    }

    /// Ticks the running goal's tree; sends feedback or ends the goal.
    fn tick(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) {
        let Some((tree, since)) = &mut self.running else {
            return;
        };
        let status = tree.tick_once(sim);
        if status == Ok(Status::Running) {
            if let Some(feedback) = A::feedback(tree.blackboard(), sim) {
                self.goals.feedback(feedback);
            }
            return;
        }
        let bb = tree.blackboard();
        let elapsed = sim.world.now().saturating_sub(*since);
        let code = bb.get::<u16>("error_code").unwrap_or(0);
        let message = bb.get::<String>("error_msg").unwrap_or_default();
        let (status, result) = match status {
            Ok(Status::Success) => (
                GoalStatusEnum::Succeeded,
                A::result(bb, 0, String::new(), elapsed),
            ),
            Ok(_) => (
                GoalStatusEnum::Aborted,
                A::result(bb, code, message, elapsed),
            ),
            Err(e) => (
                GoalStatusEnum::Aborted,
                A::result(bb, code, e.to_string(), elapsed),
            ),
        };
        {
            let mut stats = stats.lock();
            let counts = A::counts(&mut stats);
            if status == GoalStatusEnum::Succeeded {
                counts.succeeded += 1;
            } else {
                counts.aborted += 1;
            }
        }
        self.running = None;
        self.goals.finish(status, result);
    }
}

/// An action server whose goals the sim runs.
trait Serving {
    /// Reads the requests; `true` if a new goal started.
    fn poll(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) -> Result<bool, Ros2Error>;
    /// Aborts the running goal: another server took the robot.
    fn preempt(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle);
    /// A goal runs.
    fn is_running(&self) -> bool;
    /// Works on the running goal for one step.
    fn tick(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle);
}

impl<A: SimAction> Serving for Served<A>
where
    A::Result: Default,
{
    fn poll(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) -> Result<bool, Ros2Error> {
        Served::poll(self, sim, stats)
    }
    fn preempt(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) {
        Served::preempt(self, sim, stats);
    }
    fn is_running(&self) -> bool {
        Served::is_running(self)
    }
    fn tick(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) {
        Served::tick(self, sim, stats);
    }
}

/// Where the object FollowObject follows is published (FollowObject's default
/// `pose_topic`): each pose moves the world's object there.
pub const OBJECT_POSE_TOPIC: &str = "dynamic_pose";

/// The topic on which a person ends assisted teleoperation with success (Nav2's
/// AssistedTeleop behavior listens on it).
pub const PREEMPT_TELEOP_TOPIC: &str = "preempt_teleop";

/// The behavior server's `assisted_teleop`. No one drives the simulated robot, so a goal
/// holds it still until its time allowance runs out (Aborted, TIMEOUT 731, as Nav2's
/// behavior ends), or a message on [`PREEMPT_TELEOP_TOPIC`] ends it (Succeeded, as Nav2's
/// does); a zero allowance runs until then.
struct Teleop {
    goals: GoalServer<AssistedTeleop>,
    preempts: Subscription<Empty>,
    /// When the running goal started and its allowance.
    running: Option<(Duration, Duration)>,
    preempted: bool,
}

impl Teleop {
    fn new(ros: &RosNode) -> Result<Self, NavigatorError> {
        Ok(Self {
            goals: GoalServer::new(ros, "assisted_teleop")?,
            preempts: ros.subscription(PREEMPT_TELEOP_TOPIC)?,
            running: None,
            preempted: false,
        })
    }

    fn result(&self, sim: &Nav2Sim, code: u16, message: &str) -> AssistedTeleopResult {
        let since = self.running.map_or(Duration::ZERO, |(since, _)| since);
        AssistedTeleopResult {
            total_elapsed_time: sim.world.now().saturating_sub(since).into(),
            error_code: code,
            error_msg: message.to_owned(),
        }
    }

    fn end(&mut self, sim: &Nav2Sim, stats: &SimStatsHandle, status: GoalStatusEnum, code: u16) {
        let message = if code == AssistedTeleopResult::TIMEOUT {
            "Exceeded time allowance before reaching the assisted_teleop goal"
        } else {
            ""
        };
        let result = self.result(sim, code, message);
        // Counted before the result goes out, which a client may act on at once.
        {
            let mut stats = stats.lock();
            if status == GoalStatusEnum::Succeeded {
                stats.assisted_teleop.succeeded += 1;
            } else {
                stats.assisted_teleop.aborted += 1;
            }
        }
        self.running = None;
        self.goals.finish(status, result);
    }
}

impl Serving for Teleop {
    fn poll(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) -> Result<bool, Ros2Error> {
        // A read error is a message lost; the next one still ends the goal.
        while let Ok(Some(_)) = self.preempts.take() {
            self.preempted = self.running.is_some();
        }
        let mut started = false;
        for request in self.goals.poll()? {
            match request {
                Request::Goal(goal) => {
                    if self.running.is_some() {
                        // The goal server already ended the replaced goal.
                        stats.lock().assisted_teleop.aborted += 1;
                    }
                    sim.world.stop();
                    self.running = Some((sim.world.now(), goal.time_allowance.into()));
                    self.preempted = false;
                    stats.lock().assisted_teleop.goals += 1;
                    started = true;
                }
                Request::Cancel => {
                    stats.lock().assisted_teleop.cancels += 1;
                    if self.running.is_some() {
                        let result = self.result(sim, 0, "");
                        self.running = None;
                        self.goals.finish(GoalStatusEnum::Canceled, result);
                        started = false;
                    }
                }
            }
        }
        Ok(started)
    }

    fn preempt(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) {
        if self.running.is_some() {
            self.end(sim, stats, GoalStatusEnum::Aborted, 0);
        }
    }

    fn is_running(&self) -> bool {
        self.running.is_some()
    }

    fn tick(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) {
        let Some((since, allowance)) = self.running else {
            return;
        };
        let elapsed = sim.world.now().saturating_sub(since);
        if self.preempted {
            self.preempted = false;
            self.end(
                sim,
                stats,
                GoalStatusEnum::Succeeded,
                AssistedTeleopResult::NONE,
            );
        } else if !allowance.is_zero() && elapsed > allowance {
            self.end(
                sim,
                stats,
                GoalStatusEnum::Aborted,
                AssistedTeleopResult::TIMEOUT,
            );
        } else {
            self.goals.feedback(AssistedTeleopFeedback {
                current_teleop_duration: elapsed.into(),
            });
        }
    }
}

/// One clearing service of one costmap, in a release's layout.
type ClearServer<S> = Server<<S as RosService>::Request, <S as RosService>::Response>;

/// What a clearing request asks of a costmap.
#[derive(Clone, Copy)]
enum Clearing {
    Entire,
    AroundRobot,
    ExceptRegion,
    AroundPose,
}

/// Takes `server`'s requests and clears `layer` as each asks, counting each in `stats`. A
/// request in another release's layout cannot be read: it is dropped, and its client times
/// out.
fn serve_clearing<S: ClearLayout>(
    server: &ClearServer<S>,
    clearing: Clearing,
    layer: CostmapLayer,
    sim: &mut Nav2Sim,
    stats: &SimStatsHandle,
) -> Result<(), Ros2Error> {
    let mut undecodable = 0;
    loop {
        let (id, request) = match server.receive_request() {
            Ok(Some(request)) => request,
            Ok(None) => return Ok(()),
            Err(ros2_client::ReadError::Deserialization { .. }) if undecodable < 64 => {
                undecodable += 1;
                continue;
            }
            Err(e) => {
                return Err(Ros2Error::Serve {
                    kind: "service server",
                    name: format!("{layer:?} costmap clearing"),
                    message: format!("{e:?}"),
                })
            }
        };
        let side = S::reset_distance(&request);
        let robot = sim.world.robot();
        match clearing {
            Clearing::Entire => sim.world.clear_costmap(layer),
            Clearing::AroundRobot => {
                clear_square(sim, layer, robot, side, false);
            }
            Clearing::ExceptRegion => {
                clear_square(sim, layer, robot, side, true);
            }
            Clearing::AroundPose => {
                let centre = S::pose(&request).map_or(robot, pose_2d);
                clear_square(sim, layer, centre, side, false);
            }
        }
        stats.lock().clears += 1;
        // A client gone since it asked does not need the answer: responses are best effort.
        let _ = server.send_response(id, S::response(true));
    }
}

/// The clearing services of a costmap.
trait ServeClearings {
    /// Answers the requests that came, counting each in `stats` before its answer goes
    /// out (a client that has its answer may read the count at once).
    fn serve(&self, sim: &mut Nav2Sim, stats: &SimStatsHandle) -> Result<(), Ros2Error>;
}

/// The four clearing services of one costmap, in the layouts `E`, `A`, `X` and `P`,
/// named as Nav2's costmaps name them (`local_costmap/clear_around_local_costmap`, ...).
struct Clearings<E: ClearLayout, A: ClearLayout, X: ClearLayout, P: ClearLayout> {
    layer: CostmapLayer,
    entire: ClearServer<E>,
    around: ClearServer<A>,
    except: ClearServer<X>,
    around_pose: ClearServer<P>,
}

impl<E: ClearLayout, A: ClearLayout, X: ClearLayout, P: ClearLayout> Clearings<E, A, X, P> {
    /// Both costmaps' services.
    fn both(ros: &RosNode) -> Result<Vec<Box<dyn ServeClearings>>, Ros2Error>
    where
        Self: 'static,
    {
        let mut both: Vec<Box<dyn ServeClearings>> = Vec::new();
        for (costmap, layer) in [
            ("global_costmap", CostmapLayer::Global),
            ("local_costmap", CostmapLayer::Local),
        ] {
            both.push(Box::new(Self {
                layer,
                entire: ros.service_server::<E>(&format!("{costmap}/clear_entirely_{costmap}"))?,
                around: ros.service_server::<A>(&format!("{costmap}/clear_around_{costmap}"))?,
                except: ros.service_server::<X>(&format!("{costmap}/clear_except_{costmap}"))?,
                around_pose: ros
                    .service_server::<P>(&format!("{costmap}/clear_around_pose_{costmap}"))?,
            }));
        }
        Ok(both)
    }
}

impl<E: ClearLayout, A: ClearLayout, X: ClearLayout, P: ClearLayout> ServeClearings
    for Clearings<E, A, X, P>
{
    fn serve(&self, sim: &mut Nav2Sim, stats: &SimStatsHandle) -> Result<(), Ros2Error> {
        let layer = self.layer;
        serve_clearing::<E>(&self.entire, Clearing::Entire, layer, sim, stats)?;
        serve_clearing::<A>(&self.around, Clearing::AroundRobot, layer, sim, stats)?;
        serve_clearing::<X>(&self.except, Clearing::ExceptRegion, layer, sim, stats)?;
        serve_clearing::<P>(&self.around_pose, Clearing::AroundPose, layer, sim, stats)
    }
}

/// The grid world as Nav2's servers; see the [module](crate::nav2).
pub struct SimServers {
    sim: Nav2Sim,
    /// The planner, the smoother and the route server: they plan, and move nothing.
    planning: Vec<Box<dyn Serving>>,
    /// The controller, the behaviors, the docking server, the navigator through poses,
    /// the following server and assisted teleoperation: the servers that move the robot.
    motions: Vec<Box<dyn Serving>>,
    /// Both costmaps' clearing services.
    clearings: Vec<Box<dyn ServeClearings>>,
    costs: [(CostmapLayer, Server<GetCostsRequest, GetCostsResponse>); 2],
    toggle: Server<ToggleRequest, ToggleResponse>,
    relocalize: Server<EmptyRequest, EmptyResponse>,
    poses: Publisher<PoseStamped>,
    battery: Publisher<BatteryState>,
    odometry: Publisher<Odometry>,
    object: Subscription<PoseStamped>,
    stats: SimStatsHandle,
    wall_period: Duration,
    clock_running: bool,
}

impl SimServers {
    /// Serves `sim` on `ros`.
    pub fn new(ros: &RosNode, sim: Nav2Sim, options: SimOptions) -> Result<Self, NavigatorError> {
        let mut registry = Registry::<Nav2Sim>::new();
        register_nav2_leaves(&mut registry)?;
        let scale = if options.time_scale.is_finite() && options.time_scale > 0.0 {
            options.time_scale
        } else {
            1.0
        };
        let wall_period = sim.params.period.div_f64(scale);
        let jazzy = options.release == Nav2Release::Jazzy;
        let through_poses = "compute_path_through_poses";
        let planning: Vec<Box<dyn Serving>> = vec![
            if options.release == Nav2Release::Main {
                Box::new(Served::<main::ComputePathToPose>::new(
                    ros,
                    "compute_path_to_pose",
                    &registry,
                )?)
            } else {
                Box::new(Served::<ComputePathToPose>::new(
                    ros,
                    "compute_path_to_pose",
                    &registry,
                )?)
            },
            if jazzy {
                Box::new(Served::<ComputePathThroughPoses>::new(
                    ros,
                    through_poses,
                    &registry,
                )?)
            } else {
                Box::new(Served::<kilted::ComputePathThroughPoses>::new(
                    ros,
                    through_poses,
                    &registry,
                )?)
            },
            Box::new(Served::<SmoothPath>::new(ros, "smooth_path", &registry)?),
            Box::new(Served::<ComputeRoute>::new(
                ros,
                "compute_route",
                &registry,
            )?),
            Box::new(Served::<ComputeAndTrackRoute>::new(
                ros,
                "compute_and_track_route",
                &registry,
            )?),
        ];
        let behaviors: [Box<dyn Serving>; 3] = if jazzy {
            [
                Box::new(Served::<Spin>::new(ros, "spin", &registry)?),
                Box::new(Served::<BackUp>::new(ros, "backup", &registry)?),
                Box::new(Served::<DriveOnHeading>::new(
                    ros,
                    "drive_on_heading",
                    &registry,
                )?),
            ]
        } else {
            [
                Box::new(Served::<kilted::Spin>::new(ros, "spin", &registry)?),
                Box::new(Served::<kilted::BackUp>::new(ros, "backup", &registry)?),
                Box::new(Served::<kilted::DriveOnHeading>::new(
                    ros,
                    "drive_on_heading",
                    &registry,
                )?),
            ]
        };
        let [spin, backup, drive_on_heading] = behaviors;
        let motions: Vec<Box<dyn Serving>> = vec![
            if options.release == Nav2Release::Main {
                Box::new(Served::<main::FollowPath>::new(
                    ros,
                    "follow_path",
                    &registry,
                )?)
            } else {
                Box::new(Served::<FollowPath>::new(ros, "follow_path", &registry)?)
            },
            spin,
            backup,
            drive_on_heading,
            Box::new(Served::<Wait>::new(ros, "wait", &registry)?),
            Box::new(Served::<DockRobot>::new(ros, "dock_robot", &registry)?),
            Box::new(Served::<UndockRobot>::new(ros, "undock_robot", &registry)?),
            Box::new(Served::<NavigateThroughPoses>::new(
                ros,
                "navigate_through_poses",
                &registry,
            )?),
            Box::new(Served::<FollowObject>::new(
                ros,
                "follow_object",
                &registry,
            )?),
            Box::new(Teleop::new(ros)?),
        ];
        let clearings = if options.release == Nav2Release::Main {
            Clearings::<
                main::ClearEntireCostmap,
                main::ClearCostmapAroundRobot,
                main::ClearCostmapExceptRegion,
                main::ClearCostmapAroundPose,
            >::both(ros)?
        } else {
            Clearings::<
                ClearEntireCostmap,
                ClearCostmapAroundRobot,
                ClearCostmapExceptRegion,
                ClearCostmapAroundPose,
            >::both(ros)?
        };
        let stats = SimStatsHandle::default();
        stats.lock().collision_monitor = sim.collision_monitor();
        let servers = Self {
            planning,
            motions,
            clearings,
            costs: [
                (
                    CostmapLayer::Global,
                    ros.service_server::<GetCosts>(GET_COST_GLOBAL_COSTMAP)?,
                ),
                (
                    CostmapLayer::Local,
                    ros.service_server::<GetCosts>(GET_COST_LOCAL_COSTMAP)?,
                ),
            ],
            toggle: ros.service_server::<Toggle>(super::TOGGLE_COLLISION_MONITOR)?,
            relocalize: ros
                .service_server::<std_srvs::Empty>(super::REINITIALIZE_GLOBAL_LOCALIZATION)?,
            poses: ros.publisher(ROBOT_POSE_TOPIC)?,
            battery: ros.publisher(super::BATTERY_TOPIC)?,
            odometry: ros.publisher(super::ODOM_TOPIC)?,
            object: ros.subscription(OBJECT_POSE_TOPIC)?,
            stats,
            wall_period,
            clock_running: !options.start_on_first_goal,
            sim,
        };
        servers.record();
        Ok(servers)
    }

    /// The counts, shared: read them while [`run`](Self::run) goes on in another thread.
    pub fn stats(&self) -> SimStatsHandle {
        self.stats.clone()
    }

    /// The simulation.
    pub fn sim(&self) -> &Nav2Sim {
        &self.sim
    }

    /// Wall time between steps.
    pub fn wall_period(&self) -> Duration {
        self.wall_period
    }

    /// One step: answers the requests, ticks the running goals, steps the world and
    /// publishes the robot's pose.
    pub fn spin_once(&mut self) -> Result<(), Ros2Error> {
        let sim = &mut self.sim;
        let stats = &self.stats;
        let mut seen = None;
        // A pose lost is replaced by the next one the detector sends.
        while let Ok(Some((pose, _))) = self.object.take() {
            seen = Some(pose_2d(&pose));
        }
        if seen.is_some() {
            sim.set_object(seen);
        }
        let mut planned = false;
        for server in &mut self.planning {
            planned |= server.poll(sim, stats)?;
        }
        // The servers that move the robot share it: the newest goal has it.
        let mut moved = Vec::with_capacity(self.motions.len());
        for motion in &mut self.motions {
            moved.push(motion.poll(sim, stats)?);
        }
        self.clock_running |= planned || moved.contains(&true);
        if let Some(newest) = moved.iter().rposition(|m| *m) {
            for (i, motion) in self.motions.iter_mut().enumerate() {
                if i != newest && motion.is_running() {
                    motion.preempt(sim, stats);
                }
            }
        }
        for clearings in &self.clearings {
            clearings.serve(sim, stats)?;
        }
        serve_costs(&self.costs, sim, stats)?;
        serve_switches(&self.toggle, &self.relocalize, sim, stats)?;
        for server in &mut self.planning {
            server.tick(sim, stats);
        }
        for motion in &mut self.motions {
            motion.tick(sim, stats);
        }
        if self.clock_running {
            sim.step();
        }
        // Best effort: the next step publishes again.
        let _ = self.poses.publish(pose_stamped(sim.world.robot()));
        let _ = self.battery.publish(battery_state(sim));
        let _ = self.odometry.publish(odometry(sim));
        self.record();
        Ok(())
    }

    /// Calls [`spin_once`](Self::spin_once) every wall period until `stop` is raised.
    pub fn run(&mut self, stop: &AtomicBool) -> Result<(), Ros2Error> {
        let mut next = Instant::now();
        while !stop.load(Ordering::SeqCst) {
            self.spin_once()?;
            next += self.wall_period;
            let now = Instant::now();
            if next > now {
                std::thread::sleep(next - now);
            } else {
                next = now;
            }
        }
        Ok(())
    }

    fn record(&self) {
        let mut stats = self.stats.lock();
        stats.robot = self.sim.world.robot();
        stats.time = self.sim.world.now();
        stats.distance = self.sim.world.distance_travelled();
        stats.global_obstacles = self
            .sim
            .world
            .costmap(CostmapLayer::Global)
            .marked()
            .count();
        stats.local_obstacles = self.sim.world.costmap(CostmapLayer::Local).marked().count();
    }
}

fn serve_failed(name: &str) -> impl Fn(ros2_client::ReadError) -> Ros2Error + '_ {
    move |e| Ros2Error::Serve {
        kind: "service server",
        name: name.to_owned(),
        message: format!("{e:?}"),
    }
}

/// Answers the costmaps' cost requests, as Nav2's costmap does: a pose off the map costs
/// 255 (unknown) and makes the answer unsuccessful.
fn serve_costs(
    servers: &[(CostmapLayer, Server<GetCostsRequest, GetCostsResponse>)],
    sim: &Nav2Sim,
    stats: &SimStatsHandle,
) -> Result<(), Ros2Error> {
    for (layer, server) in servers {
        while let Some((id, request)) = server
            .receive_request()
            .map_err(serve_failed("costmap costs"))?
        {
            let costs: Vec<Option<f64>> = request
                .poses
                .iter()
                .map(|pose| sim.cost(*layer, &pose_2d(pose)))
                .collect();
            let response = GetCostsResponse {
                success: costs.iter().all(Option::is_some),
                costs: costs.iter().map(|c| c.unwrap_or(255.0) as f32).collect(),
            };
            stats.lock().cost_requests += 1;
            // A client gone since it asked does not need the answer.
            let _ = server.send_response(id, response);
        }
    }
    Ok(())
}

/// Answers the collision monitor's `toggle` and the localization's
/// `reinitialize_global_localization`.
fn serve_switches(
    toggle: &Server<ToggleRequest, ToggleResponse>,
    relocalize: &Server<EmptyRequest, EmptyResponse>,
    sim: &mut Nav2Sim,
    stats: &SimStatsHandle,
) -> Result<(), Ros2Error> {
    while let Some((id, request)) = toggle
        .receive_request()
        .map_err(serve_failed("collision monitor"))?
    {
        sim.set_collision_monitor(request.enable);
        let state = if request.enable { "on" } else { "off" };
        let response = ToggleResponse {
            success: true,
            message: format!("the collision monitor is {state}"),
        };
        stats.lock().collision_monitor = request.enable;
        let _ = toggle.send_response(id, response);
    }
    while let Some((id, _)) = relocalize
        .receive_request()
        .map_err(serve_failed("localization"))?
    {
        sim.count_relocalization();
        stats.lock().relocalizations += 1;
        let _ = relocalize.send_response(id, EmptyResponse::default());
    }
    Ok(())
}

/// The robot's odometry: its pose (in `odom`, which is the map here) and its speed and
/// turn rate over the last step (in `base_link`: straight ahead and about z), stamped
/// with the simulated time.
fn odometry(sim: &Nav2Sim) -> Odometry {
    let now = sim.world.now();
    let mut odometry = Odometry {
        header: Header {
            stamp: crate::msg::builtin_interfaces::Time {
                sec: i32::try_from(now.as_secs()).unwrap_or(i32::MAX),
                nanosec: now.subsec_nanos(),
            },
            frame_id: "odom".to_owned(),
        },
        child_frame_id: "base_link".to_owned(),
        ..Odometry::default()
    };
    odometry.pose.pose = pose_stamped(sim.world.robot()).pose;
    odometry.twist.twist = Twist {
        linear: Vector3 {
            x: sim.robot_speed(),
            ..Vector3::default()
        },
        angular: Vector3 {
            z: sim.turn_rate(),
            ..Vector3::default()
        },
    };
    odometry
}

/// The world's battery as a `BatteryState`: its charge as a fraction, charging while the
/// robot stands on the charger with the battery not full (full there: FULL; elsewhere:
/// DISCHARGING); nothing else is measured (NaN).
fn battery_state(sim: &Nav2Sim) -> BatteryState {
    let level = sim.world.battery().level();
    let status = match (sim.world.is_on_charger(), level < 100.0) {
        (true, true) => BatteryState::POWER_SUPPLY_STATUS_CHARGING,
        (true, false) => BatteryState::POWER_SUPPLY_STATUS_FULL,
        (false, _) => BatteryState::POWER_SUPPLY_STATUS_DISCHARGING,
    };
    BatteryState {
        voltage: f32::NAN,
        temperature: f32::NAN,
        current: f32::NAN,
        charge: f32::NAN,
        capacity: f32::NAN,
        design_capacity: f32::NAN,
        percentage: (level / 100.0) as f32,
        power_supply_status: status,
        present: true,
        ..BatteryState::default()
    }
}
