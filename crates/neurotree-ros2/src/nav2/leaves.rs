//! The navigator's leaves that call Nav2's servers over ROS 2, with the ports of Nav2's
//! `nav2_tree_nodes.xml`, as [`ActionSpec`]s and a [`ServiceSpec`].
//!
//! | node | server (default name) | goal from the ports | Success | on failure |
//! |---|---|---|---|---|
//! | ComputePathToPose | `compute_path_to_pose` | `goal`, `start` / `use_start`, `planner_id` | writes `path` | empties `path` |
//! | ComputePathThroughPoses | `compute_path_through_poses` | `goals`, `start` / `use_start`, `planner_id` | writes `path` | empties `path` |
//! | SmoothPath | `smooth_path` | `unsmoothed_path`, `smoother_id`, `max_smoothing_duration`, `check_for_collisions` | writes `smoothed_path`, `smoothing_duration`, `was_completed` | |
//! | NavigateToPose | `navigate_to_pose` | `goal`, `behavior_tree` | | |
//! | FollowPath | `follow_path` | `path`, `controller_id`, `goal_checker_id`, `progress_checker_id` | | |
//! | Spin | `spin` | `spin_dist`, `time_allowance` | | |
//! | BackUp | `backup` | `backup_dist`, `backup_speed`, `time_allowance` | | |
//! | DriveOnHeading | `drive_on_heading` | `dist_to_travel`, `speed`, `time_allowance` | | |
//! | Wait | `wait` | `wait_duration` | | |
//! | ClearEntireCostmap | `service_name` (`local_costmap/clear_entirely_local_costmap`) | | on the response | |
//! | ClearCostmapAroundRobot | `service_name` (`local_costmap/clear_around_local_costmap`) | `reset_distance` | on the response | |
//! | ClearCostmapExceptRegion | `service_name` (`local_costmap/clear_except_local_costmap`) | `reset_distance` | on the response | |
//! | ClearCostmapAroundPose | `service_name` (`local_costmap/clear_around_pose_local_costmap`) | `pose`, `reset_distance` | on the response | |
//!
//! The actions write the server's `error_code` to `error_code_id` (0 on success; the
//! server's code when it aborted; the node's UNKNOWN code when the server could not be
//! reached or answered nothing), and the reason to `error_msg`, so that Nav2's
//! `WouldA…RecoveryHelp` conditions read them as in Nav2. A goal someone else cancelled
//! ends the node with Success and code 0, as Nav2's `on_cancelled` does.
//!
//! Ports that name Nav2 plugins the simulator does not have (`path_handler_id`,
//! `is_recovery`, `disable_collision_checks`, `plugins`) are declared, so that Nav2's files
//! load, and sent where the goal has a field for them. Nav2 names the server with
//! `server_name`; here, as in BehaviorTree.ROS2, it is `action_name` (`server_name` is
//! declared and not read).
//!
//! Unlike Nav2's FollowPath, a new `path` while the goal runs is not sent to the controller:
//! the node follows the path it started with, and takes up the newest one when it starts
//! again.

use std::time::Duration;

use neurotree_nav2::robotics::{Path, Pose2D};
use neurotree_toolkit::{Handle, PortError, PortSpec, Registry, RegistryError, Status};

use super::convert::{path_2d, path_msg, pose_stamped};
use crate::msg::geometry_msgs::Point;
use crate::msg::nav2_msgs::{
    BackUp, BackUpGoal, BackUpResult, ClearCostmapAroundPose, ClearCostmapAroundPoseRequest,
    ClearCostmapAroundPoseResponse, ClearCostmapAroundRobot, ClearCostmapAroundRobotRequest,
    ClearCostmapAroundRobotResponse, ClearCostmapExceptRegion, ClearCostmapExceptRegionRequest,
    ClearCostmapExceptRegionResponse, ClearEntireCostmap, ClearEntireCostmapRequest,
    ClearEntireCostmapResponse, ComputePathThroughPoses, ComputePathThroughPosesGoal,
    ComputePathThroughPosesResult, ComputePathToPose, ComputePathToPoseGoal,
    ComputePathToPoseResult, DriveOnHeading, DriveOnHeadingGoal, DriveOnHeadingResult, FollowPath,
    FollowPathGoal, FollowPathResult, Spin, SpinGoal, SpinResult, Wait, WaitGoal, WaitResult,
};
use crate::msg::nav2_msgs::{
    NavigateToPose, NavigateToPoseGoal, NavigateToPoseResult, SmoothPath, SmoothPathGoal,
    SmoothPathResult,
};
use crate::{ActionError, ActionSpec, RosActionNode, RosNode, RosServiceNode, ServiceSpec};

/// Nav2's BT navigator waits this long for a server (its `wait_for_service_timeout`), in
/// milliseconds: the `wait_for_server_timeout` default of these leaves.
pub const WAIT_FOR_SERVER_MS: u64 = 1000;

/// Registers ComputePathToPose, ComputePathThroughPoses, SmoothPath, NavigateToPose,
/// FollowPath, Spin, BackUp, DriveOnHeading, Wait,
/// ClearEntireCostmap, ClearCostmapAroundRobot, ClearCostmapExceptRegion and
/// ClearCostmapAroundPose as ROS 2 clients on `ros`, the cancel nodes
/// ([`register_cancel_nodes`](super::register_cancel_nodes)) and the battery conditions as
/// subscribers ([`register_battery_conditions`](super::register_battery_conditions)). Fails if one of the names is taken.
pub fn register_nav2_ros_leaves<C: 'static>(
    registry: &mut Registry<C>,
    ros: &RosNode,
) -> Result<(), RegistryError> {
    register_action(
        registry,
        "ComputePathToPose",
        ros,
        "compute_path_to_pose",
        || ComputePath,
    )?;
    register_action(
        registry,
        "ComputePathThroughPoses",
        ros,
        "compute_path_through_poses",
        || ComputeThrough,
    )?;
    register_action(registry, "SmoothPath", ros, "smooth_path", || Smooth)?;
    register_action(registry, "NavigateToPose", ros, "navigate_to_pose", || {
        Navigate
    })?;
    register_action(registry, "FollowPath", ros, "follow_path", || Follow)?;
    register_action(registry, "Spin", ros, "spin", || SpinBy)?;
    register_action(registry, "BackUp", ros, "backup", || BackUpBy)?;
    register_action(registry, "DriveOnHeading", ros, "drive_on_heading", || {
        DriveOn
    })?;
    register_action(registry, "Wait", ros, "wait", || WaitFor)?;
    let ros_node = ros.clone();
    let name = "local_costmap/clear_entirely_local_costmap";
    let ports = with_wait_default(RosServiceNode::<C, ClearCostmap>::ports(name));
    registry.register_stateful("ClearEntireCostmap", ports, move || {
        RosServiceNode::new(ros_node.clone(), name, ClearCostmap)
    })?;
    registry.describe(
        "ClearEntireCostmap",
        "Asks the costmap server `service_name` to forget every obstacle.",
    );
    register_service(
        registry,
        "ClearCostmapAroundRobot",
        ros,
        "local_costmap/clear_around_local_costmap",
        || ClearAround,
        "Asks the costmap server `service_name` to forget the obstacles around the robot.",
    )?;
    register_service(
        registry,
        "ClearCostmapExceptRegion",
        ros,
        "local_costmap/clear_except_local_costmap",
        || ClearExcept,
        "Asks the costmap server `service_name` to forget the obstacles away from the robot.",
    )?;
    register_service(
        registry,
        "ClearCostmapAroundPose",
        ros,
        "local_costmap/clear_around_pose_local_costmap",
        || ClearAroundPose,
        "Asks the costmap server `service_name` to forget the obstacles around `pose`.",
    )?;
    super::register_cancel_nodes(registry, ros)?;
    super::register_battery_conditions(registry, ros)
}

fn register_service<C: 'static, S: ServiceSpec<C>>(
    registry: &mut Registry<C>,
    type_name: &str,
    ros: &RosNode,
    default_name: &'static str,
    make: fn() -> S,
    description: &str,
) -> Result<(), RegistryError> {
    let ros = ros.clone();
    let ports = with_wait_default(RosServiceNode::<C, S>::ports(default_name));
    registry.register_stateful(type_name, ports, move || {
        RosServiceNode::new(ros.clone(), default_name, make())
    })?;
    registry.describe(type_name, description);
    Ok(())
}

fn register_action<C: 'static, S: ActionSpec<C>>(
    registry: &mut Registry<C>,
    type_name: &str,
    ros: &RosNode,
    default_name: &'static str,
    make: fn() -> S,
) -> Result<(), RegistryError> {
    let ros = ros.clone();
    let ports = with_wait_default(RosActionNode::<C, S>::ports(default_name));
    registry.register_stateful(type_name, ports, move || {
        RosActionNode::new(ros.clone(), default_name, make())
    })?;
    registry.describe(
        type_name,
        &format!("Sends a goal to the Nav2 action server `{default_name}` (port `action_name`)."),
    );
    Ok(())
}

/// BehaviorTree.ROS2's ports, with Nav2's wait for the server.
fn with_wait_default(mut ports: Vec<PortSpec>) -> Vec<PortSpec> {
    for port in &mut ports {
        if port.name == "wait_for_server_timeout" {
            port.default = Some(WAIT_FOR_SERVER_MS.to_string());
        }
    }
    ports
}

fn error_code_port(server: &str) -> PortSpec {
    PortSpec::output::<u16>("error_code_id")
        .describe(&format!("0, or the {server} server's error code."))
}

fn server_name_port() -> PortSpec {
    PortSpec::input::<String>("server_name").describe("Nav2's name port (unused: `action_name`).")
}

/// Writes output `port` when the tree binds it.
fn emit<C, T: std::any::Any + Send + Sync>(h: &mut Handle<'_, C>, port: &str, value: T) {
    // An unbound output is the tree's choice not to read it.
    let _ = h.output(port, value);
}

/// Reads input `port`; `None` when the node has no such port or its entry is unset.
fn optional<C, T>(h: &Handle<'_, C>, port: &str) -> Result<Option<T>, String>
where
    T: neurotree_toolkit::FromPortStr + std::any::Any + Clone,
{
    match h.input::<T>(port) {
        Ok(value) => Ok(Some(value)),
        Err(PortError::NoSuchPort { .. }) => Ok(None),
        Err(PortError::Blackboard { .. }) => Ok(None),
        Err(e) => Err(e.to_string()),
    }
}

fn required<C, T>(h: &Handle<'_, C>, port: &str) -> Result<T, String>
where
    T: neurotree_toolkit::FromPortStr + std::any::Any + Clone,
{
    optional(h, port)?.ok_or_else(|| format!("no `{port}`"))
}

fn seconds(secs: f64) -> crate::msg::builtin_interfaces::Duration {
    Duration::try_from_secs_f64(secs.max(0.0))
        .unwrap_or(Duration::MAX)
        .into()
}

/// Ends a run: the code and message to the outputs, and the status.
fn outcome<C>(h: &mut Handle<'_, C>, code: u16, message: &str) -> Status {
    emit(h, "error_code_id", code);
    emit(h, "error_msg", message.to_owned());
    if code == 0 {
        Status::Success
    } else {
        Status::Failure
    }
}

/// A failure: the server's code and message when it sent a result, else `unknown` and
/// the node's reason. A goal cancelled by someone else ends with Success and code 0, as
/// Nav2's nodes end then (`on_cancelled`).
fn failed<C>(
    h: &mut Handle<'_, C>,
    unknown: u16,
    error: &ActionError,
    server: Option<(u16, &str)>,
) -> Status {
    if matches!(error, ActionError::Canceled { .. }) {
        return outcome(h, 0, "");
    }
    let (code, message) = match server {
        Some((code, message)) if code != 0 => (code, message.to_owned()),
        _ => (unknown, error.to_string()),
    };
    emit(h, "error_code_id", code);
    emit(h, "error_msg", message);
    Status::Failure
}

/// ComputePathToPose: the planner server's path from the robot (or `start`) to `goal`.
struct ComputePath;

impl<C: 'static> ActionSpec<C> for ComputePath {
    type Action = ComputePathToPose;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<Pose2D>("goal").describe("Where the path ends."),
            PortSpec::input::<Pose2D>("start").describe("Where it starts, instead of the robot."),
            PortSpec::input::<bool>("use_start").describe("Use `start` (true when it is given)."),
            PortSpec::input::<Vec<Pose2D>>("viapoints").describe("Intermediate poses (unused)."),
            PortSpec::input::<String>("planner_id")
                .default_value("")
                .describe("The planner plugin; empty for the only one."),
            server_name_port(),
            PortSpec::output::<Path>("path").describe("The path found."),
            error_code_port("planner"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<ComputePathToPoseGoal, String> {
        let goal: Pose2D = required(h, "goal")?;
        let start: Option<Pose2D> = optional(h, "start")?;
        let use_start = optional::<C, bool>(h, "use_start")?.unwrap_or(start.is_some());
        Ok(ComputePathToPoseGoal {
            goal: pose_stamped(goal),
            start: pose_stamped(start.unwrap_or_default()),
            planner_id: optional(h, "planner_id")?.unwrap_or_default(),
            use_start: use_start && start.is_some(),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &ComputePathToPoseResult) -> Status {
        if result.error_code == ComputePathToPoseResult::NONE {
            emit(h, "path", path_2d(&result.path));
        }
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&ComputePathToPoseResult>,
    ) -> Status {
        // As Nav2's node does: no path rather than a stale one.
        emit(h, "path", Path::default());
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, ComputePathToPoseResult::UNKNOWN, error, server)
    }
}

/// ComputePathThroughPoses: the planner server's path from the robot (or `start`) through
/// each of `goals`.
struct ComputeThrough;

impl<C: 'static> ActionSpec<C> for ComputeThrough {
    type Action = ComputePathThroughPoses;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<Vec<Pose2D>>("goals").describe("The poses to pass, in order."),
            PortSpec::input::<Pose2D>("start").describe("Where it starts, instead of the robot."),
            PortSpec::input::<String>("planner_id")
                .default_value("")
                .describe("The planner plugin; empty for the only one."),
            server_name_port(),
            PortSpec::output::<Path>("path").describe("The path found."),
            error_code_port("planner"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<ComputePathThroughPosesGoal, String> {
        let goals: Vec<Pose2D> = optional(h, "goals")?.unwrap_or_default();
        let start: Option<Pose2D> = optional(h, "start")?;
        Ok(ComputePathThroughPosesGoal {
            goals: goals.into_iter().map(pose_stamped).collect(),
            start: pose_stamped(start.unwrap_or_default()),
            planner_id: optional(h, "planner_id")?.unwrap_or_default(),
            use_start: start.is_some(),
        })
    }

    fn on_result(
        &mut self,
        h: &mut Handle<'_, C>,
        result: &ComputePathThroughPosesResult,
    ) -> Status {
        if result.error_code == ComputePathThroughPosesResult::NONE {
            emit(h, "path", path_2d(&result.path));
        }
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&ComputePathThroughPosesResult>,
    ) -> Status {
        emit(h, "path", Path::default());
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, ComputePathThroughPosesResult::UNKNOWN, error, server)
    }
}

/// SmoothPath: the smoother server smooths `unsmoothed_path`.
struct Smooth;

impl<C: 'static> ActionSpec<C> for Smooth {
    type Action = SmoothPath;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<Path>("unsmoothed_path").describe("The path to smooth."),
            PortSpec::input::<f64>("max_smoothing_duration")
                .default_value("3.0")
                .describe("Seconds smoothing may take."),
            PortSpec::input::<bool>("check_for_collisions")
                .default_value("false")
                .describe("Fail when the smoothed path collides."),
            PortSpec::input::<String>("smoother_id").describe("The smoother plugin."),
            server_name_port(),
            PortSpec::output::<Path>("smoothed_path").describe("The smoothed path."),
            PortSpec::output::<f64>("smoothing_duration").describe("Seconds smoothing took."),
            PortSpec::output::<bool>("was_completed").describe("Smoothing finished in time."),
            error_code_port("smoother"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<SmoothPathGoal, String> {
        let path: Path = required(h, "unsmoothed_path")?;
        let allowed: f64 = optional(h, "max_smoothing_duration")?.unwrap_or(3.0);
        Ok(SmoothPathGoal {
            path: path_msg(&path),
            smoother_id: optional(h, "smoother_id")?.unwrap_or_default(),
            max_smoothing_duration: seconds(allowed),
            check_for_collisions: optional(h, "check_for_collisions")?.unwrap_or(false),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &SmoothPathResult) -> Status {
        if result.error_code == SmoothPathResult::NONE {
            emit(h, "smoothed_path", path_2d(&result.path));
            let took: Duration = result.smoothing_duration.into();
            emit(h, "smoothing_duration", took.as_secs_f64());
            emit(h, "was_completed", result.was_completed);
        }
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&SmoothPathResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, SmoothPathResult::UNKNOWN, error, server)
    }
}

/// NavigateToPose: another navigator (Nav2's, or a [`Navigator`](super::Navigator)) takes
/// the robot to `goal`.
struct Navigate;

impl<C: 'static> ActionSpec<C> for Navigate {
    type Action = NavigateToPose;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<Pose2D>("goal").describe("Where to go."),
            PortSpec::input::<String>("behavior_tree")
                .describe("The navigator's tree to run; empty for its default."),
            server_name_port(),
            error_code_port("navigator"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<NavigateToPoseGoal, String> {
        let goal: Pose2D = required(h, "goal")?;
        Ok(NavigateToPoseGoal {
            pose: pose_stamped(goal),
            behavior_tree: optional(h, "behavior_tree")?.unwrap_or_default(),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &NavigateToPoseResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&NavigateToPoseResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, NavigateToPoseResult::UNKNOWN, error, server)
    }
}

/// FollowPath: the controller server drives along `path`.
struct Follow;

impl<C: 'static> ActionSpec<C> for Follow {
    type Action = FollowPath;

    fn ports() -> Vec<PortSpec> {
        let plugin = |name: &str, what: &str| {
            PortSpec::input::<String>(name).describe(&format!("The {what} plugin."))
        };
        vec![
            PortSpec::input::<Path>("path").describe("The path to follow."),
            plugin("controller_id", "controller"),
            plugin("goal_checker_id", "goal checker"),
            plugin("progress_checker_id", "progress checker"),
            plugin("path_handler_id", "path handler (unused)"),
            server_name_port(),
            PortSpec::output::<String>("tracking_feedback")
                .describe("The controller's tracking feedback (not written)."),
            error_code_port("controller"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<FollowPathGoal, String> {
        let path: Path = required(h, "path")?;
        Ok(FollowPathGoal {
            path: path_msg(&path),
            controller_id: optional(h, "controller_id")?.unwrap_or_default(),
            goal_checker_id: optional(h, "goal_checker_id")?.unwrap_or_default(),
            progress_checker_id: optional(h, "progress_checker_id")?.unwrap_or_default(),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &FollowPathResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&FollowPathResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, FollowPathResult::UNKNOWN, error, server)
    }
}

fn time_allowance() -> PortSpec {
    PortSpec::input::<f64>("time_allowance")
        .default_value("10.0")
        .describe("Seconds the behavior may take.")
}

fn collision_checks() -> PortSpec {
    PortSpec::input::<bool>("disable_collision_checks")
        .default_value("false")
        .describe("Disable collision checking (unused).")
}

/// Spin: the behavior server turns the robot by `spin_dist`.
struct SpinBy;

impl<C: 'static> ActionSpec<C> for SpinBy {
    type Action = Spin;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<f64>("spin_dist")
                .default_value("1.57")
                .describe("Radians to turn."),
            time_allowance(),
            PortSpec::input::<bool>("is_recovery")
                .default_value("true")
                .describe("Used as a recovery (unused)."),
            collision_checks(),
            server_name_port(),
            error_code_port("spin"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<SpinGoal, String> {
        let angle: f64 = required(h, "spin_dist")?;
        let allowance: f64 = required(h, "time_allowance")?;
        Ok(SpinGoal {
            target_yaw: angle as f32,
            time_allowance: seconds(allowance),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &SpinResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&SpinResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, SpinResult::UNKNOWN, error, server)
    }
}

/// BackUp: the behavior server drives the robot `backup_dist` backwards.
struct BackUpBy;

impl<C: 'static> ActionSpec<C> for BackUpBy {
    type Action = BackUp;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<f64>("backup_dist")
                .default_value("0.15")
                .describe("Metres to drive back."),
            PortSpec::input::<f64>("backup_speed")
                .default_value("0.025")
                .describe("Metres per second."),
            time_allowance(),
            collision_checks(),
            server_name_port(),
            error_code_port("back-up"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<BackUpGoal, String> {
        let distance: f64 = required(h, "backup_dist")?;
        let speed: f64 = required(h, "backup_speed")?;
        let allowance: f64 = required(h, "time_allowance")?;
        Ok(BackUpGoal {
            target: Point {
                x: distance,
                y: 0.0,
                z: 0.0,
            },
            speed: speed as f32,
            time_allowance: seconds(allowance),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &BackUpResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&BackUpResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, BackUpResult::UNKNOWN, error, server)
    }
}

/// DriveOnHeading: the behavior server drives the robot `dist_to_travel` straight on.
struct DriveOn;

impl<C: 'static> ActionSpec<C> for DriveOn {
    type Action = DriveOnHeading;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<f64>("dist_to_travel")
                .default_value("0.15")
                .describe("Metres to drive, negative backwards."),
            PortSpec::input::<f64>("speed")
                .default_value("0.025")
                .describe("Metres per second, negative backwards."),
            time_allowance(),
            collision_checks(),
            server_name_port(),
            error_code_port("drive-on-heading"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<DriveOnHeadingGoal, String> {
        let distance: f64 = required(h, "dist_to_travel")?;
        let speed: f64 = required(h, "speed")?;
        let allowance: f64 = required(h, "time_allowance")?;
        Ok(DriveOnHeadingGoal {
            target: Point {
                x: distance,
                y: 0.0,
                z: 0.0,
            },
            speed: speed as f32,
            time_allowance: seconds(allowance),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &DriveOnHeadingResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&DriveOnHeadingResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, DriveOnHeadingResult::UNKNOWN, error, server)
    }
}

/// Wait: the behavior server stands still for `wait_duration`.
struct WaitFor;

impl<C: 'static> ActionSpec<C> for WaitFor {
    type Action = Wait;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<f64>("wait_duration")
                .default_value("1.0")
                .describe("Seconds to wait."),
            server_name_port(),
            error_code_port("wait"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<WaitGoal, String> {
        let secs: f64 = required(h, "wait_duration")?;
        Ok(WaitGoal {
            time: seconds(secs),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &WaitResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&WaitResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        // Wait defines no error code of its own: Nav2's behaviors' UNKNOWN.
        failed(h, 700, error, server)
    }
}

/// ClearEntireCostmap: the costmap server forgets every obstacle.
struct ClearCostmap;

impl<C: 'static> ServiceSpec<C> for ClearCostmap {
    type Service = ClearEntireCostmap;

    fn ports() -> Vec<PortSpec> {
        vec![PortSpec::input::<Vec<String>>("plugins")
            .describe("The costmap plugins to clear (unused: all of them).")]
    }

    fn request(&mut self, _h: &mut Handle<'_, C>) -> Result<ClearEntireCostmapRequest, String> {
        Ok(ClearEntireCostmapRequest::default())
    }

    fn on_response(
        &mut self,
        _h: &mut Handle<'_, C>,
        _response: &ClearEntireCostmapResponse,
    ) -> Status {
        Status::Success
    }
}

fn reset_distance() -> PortSpec {
    PortSpec::input::<f64>("reset_distance")
        .default_value("1.0")
        .describe("The square's side, in metres.")
}

fn plugins() -> PortSpec {
    PortSpec::input::<Vec<String>>("plugins")
        .describe("The costmap plugins to clear (unused: all of them).")
}

/// ClearCostmapAroundRobot: the costmap server forgets the obstacles around the robot.
struct ClearAround;

impl<C: 'static> ServiceSpec<C> for ClearAround {
    type Service = ClearCostmapAroundRobot;

    fn ports() -> Vec<PortSpec> {
        vec![reset_distance(), plugins()]
    }

    fn request(&mut self, h: &mut Handle<'_, C>) -> Result<ClearCostmapAroundRobotRequest, String> {
        let distance: f64 = optional(h, "reset_distance")?.unwrap_or(1.0);
        Ok(ClearCostmapAroundRobotRequest {
            reset_distance: distance as f32,
        })
    }

    fn on_response(
        &mut self,
        _h: &mut Handle<'_, C>,
        _: &ClearCostmapAroundRobotResponse,
    ) -> Status {
        Status::Success
    }
}

/// ClearCostmapExceptRegion: the costmap server forgets the obstacles away from the robot.
struct ClearExcept;

impl<C: 'static> ServiceSpec<C> for ClearExcept {
    type Service = ClearCostmapExceptRegion;

    fn ports() -> Vec<PortSpec> {
        vec![reset_distance(), plugins()]
    }

    fn request(
        &mut self,
        h: &mut Handle<'_, C>,
    ) -> Result<ClearCostmapExceptRegionRequest, String> {
        let distance: f64 = optional(h, "reset_distance")?.unwrap_or(1.0);
        Ok(ClearCostmapExceptRegionRequest {
            reset_distance: distance as f32,
        })
    }

    fn on_response(
        &mut self,
        _h: &mut Handle<'_, C>,
        _: &ClearCostmapExceptRegionResponse,
    ) -> Status {
        Status::Success
    }
}

/// ClearCostmapAroundPose: the costmap server forgets the obstacles around `pose`.
struct ClearAroundPose;

impl<C: 'static> ServiceSpec<C> for ClearAroundPose {
    type Service = ClearCostmapAroundPose;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<Pose2D>("pose").describe("The square's centre."),
            reset_distance(),
            plugins(),
        ]
    }

    fn request(&mut self, h: &mut Handle<'_, C>) -> Result<ClearCostmapAroundPoseRequest, String> {
        let pose: Pose2D = required(h, "pose")?;
        let distance: f64 = optional(h, "reset_distance")?.unwrap_or(1.0);
        Ok(ClearCostmapAroundPoseRequest {
            pose: pose_stamped(pose),
            reset_distance: distance,
        })
    }

    fn on_response(
        &mut self,
        _h: &mut Handle<'_, C>,
        _: &ClearCostmapAroundPoseResponse,
    ) -> Status {
        Status::Success
    }
}
