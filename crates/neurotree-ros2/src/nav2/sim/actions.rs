//! The actions the simulated servers run with the simulator's leaves: how each goal goes
//! to the leaf's blackboard, and how its result and feedback come back.

use std::time::Duration;

use neurotree_nav2::robotics::{Path, Pose2D, Route};
use neurotree_sim::nav2::Nav2Sim;
use neurotree_toolkit::Blackboard;

use super::stats::{ServerCounts, SimStats};
use crate::msg::geometry_msgs::PoseStamped;
use crate::msg::nav2_msgs::{
    BackUp, BackUpResult, ComputeAndTrackRoute, ComputeAndTrackRouteFeedback,
    ComputeAndTrackRouteResult, ComputePathThroughPoses, ComputePathThroughPosesResult,
    ComputePathToPose, ComputePathToPoseResult, ComputeRoute, ComputeRouteResult, DockRobot,
    DockRobotResult, DriveOnHeading, DriveOnHeadingResult, FollowObject, FollowObjectResult,
    FollowPath, FollowPathFeedback, FollowPathResult, NavigateThroughPoses,
    NavigateThroughPosesResult, SmoothPath, SmoothPathResult, Spin, SpinResult, UndockRobot,
    UndockRobotResult, Wait, WaitResult,
};
use crate::nav2::convert::{goals_2d, path_2d, path_msg, pose_2d, route_msg};
use crate::RosAction;

/// An action whose goals the sim runs with its leaf of the same name.
pub(super) trait SimAction: RosAction
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
        let left = crate::nav2::convert::distance_remaining(Some(&path), robot, goal);
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
