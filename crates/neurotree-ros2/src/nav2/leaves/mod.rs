//! The navigator's leaves that call Nav2's servers over ROS 2, with the ports of Nav2's
//! `nav2_tree_nodes.xml`, as [`ActionSpec`]s and a [`ServiceSpec`].
//!
//! | node | server (default name) | goal from the ports | Success | on failure |
//! |---|---|---|---|---|
//! | ComputePathToPose | `compute_path_to_pose` | `goal`, `start` / `use_start`, `planner_id` | writes `path` | empties `path` |
//! | ComputePathThroughPoses | `compute_path_through_poses` | `goals`, `start` / `use_start`, `planner_id` | writes `path` | empties `path` |
//! | SmoothPath | `smooth_path` | `unsmoothed_path`, `smoother_id`, `max_smoothing_duration`, `check_for_collisions` | writes `smoothed_path`, `smoothing_duration`, `was_completed` | |
//! | NavigateToPose | `navigate_to_pose` | `goal`, `behavior_tree` | | |
//! | FollowPath | `follow_path` | `path`, `controller_id`, `goal_checker_id`, `progress_checker_id` (main: `path_handler_id`) | main: each feedback's tracking to `tracking_feedback` | |
//! | Spin | `spin` | `spin_dist`, `time_allowance` | | |
//! | BackUp | `backup` | `backup_dist`, `backup_speed`, `time_allowance` | | |
//! | DriveOnHeading | `drive_on_heading` | `dist_to_travel`, `speed`, `time_allowance` | | |
//! | Wait | `wait` | `wait_duration` | | |
//! | AssistedTeleop | `assisted_teleop` | `time_allowance`, `is_recovery` | | aborted: Success unless `is_recovery` (Nav2's) |
//! | ComputeRoute | `compute_route` | `start_id`, `goal_id`, or with `use_poses` `goal` and (`use_start`) `start` | writes `route`, `path`, `planning_time` | empties `route`, `path` (halted too, as Nav2's) |
//! | ComputeAndTrackRoute | `compute_and_track_route` | as ComputeRoute | feedback to `last_node_id`, `next_node_id`, `current_edge_id`, `route`, `path`, `rerouted`; at the end they are reset and `execution_duration` written | the same, `execution_duration` 0 |
//! | DockRobot | `dock_robot` | `dock_id`, or without `use_dock_id` `dock_pose`, `dock_type`, `max_staging_time`; `navigate_to_staging_pose` | writes `success`, `num_retries` | the same, from the server's result |
//! | UndockRobot | `undock_robot` | `dock_type`, `max_undocking_time` | writes `success` | the same |
//! | NavigateThroughPoses | `navigate_through_poses` | `goals` (as `nav_msgs/Goals`), `behavior_tree` | | |
//! | FollowObject | `follow_object` | `pose_topic`, `tracked_frame`, `max_duration` | writes `total_elapsed_time` | the same, when the server answered |
//! | CheckPoseOccupancy | `service_name` ([`GET_COST_GLOBAL_COSTMAP`]) | `pose`, `use_footprint` | Success when the cost is at least `cost_threshold` (255 counts only with `consider_unknown_as_obstacle`) | Failure |
//! | RemoveInCollisionGoals | `service_name` ([`GET_COST_GLOBAL_COSTMAP`]) | `input_goals`, `use_footprint` | writes the goals below `cost_threshold` to `output_goals` | writes `input_goals` back (no goals: no request) |
//! | ToggleCollisionMonitor | `service_name` ([`TOGGLE_COLLISION_MONITOR`]) | `enable` | on the response | |
//! | ReinitializeGlobalLocalization | `service_name` ([`REINITIALIZE_GLOBAL_LOCALIZATION`]) | | on the response | |
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
//! `is_recovery` of Spin, `disable_collision_checks`, `plugins`) are declared, so that Nav2's files
//! load, and sent where the message has a field for them (`disable_collision_checks` in the
//! goals of Kilted and main, `plugins` in main's clearing requests:
//! [`register_nav2_ros_leaves_for`]). Nav2 names the server with
//! `server_name`; here, as in BehaviorTree.ROS2, it is `action_name` (`server_name` is
//! declared and not read).
//!
//! As Nav2's, FollowPath sends a new goal in place of the running one when `path` (not
//! empty) or one of its plugin ids changes while it runs, and ComputeAndTrackRoute when one
//! of its inputs does; the server preempts the running goal.

use std::marker::PhantomData;
use std::time::Duration;

use neurotree_nav2::robotics::{Path, Pose2D, Route};
use neurotree_nav2::Nav2Release;
use neurotree_toolkit::{Handle, PortError, PortSpec, Registry, RegistryError, Status};

use super::clearing::ClearLayout;
use super::convert::{goals_msg, path_2d, path_msg, pose_stamped, route_2d};
use crate::msg::builtin_interfaces::Duration as MsgDuration;
use crate::msg::geometry_msgs::{Point, PoseStamped};
use crate::msg::nav2_msgs::{kilted, main};
use crate::msg::nav2_msgs::{
    AssistedTeleop, AssistedTeleopGoal, AssistedTeleopResult, ComputeAndTrackRoute,
    ComputeAndTrackRouteFeedback, ComputeAndTrackRouteGoal, ComputeAndTrackRouteResult,
    ComputeRoute, ComputeRouteGoal, ComputeRouteResult, DockRobot, DockRobotGoal, DockRobotResult,
    FollowObject, FollowObjectGoal, FollowObjectResult, GetCosts, GetCostsRequest,
    GetCostsResponse, NavigateThroughPoses, NavigateThroughPosesGoal, NavigateThroughPosesResult,
    Toggle, ToggleRequest, ToggleResponse, UndockRobot, UndockRobotGoal, UndockRobotResult,
};
use crate::msg::nav2_msgs::{
    BackUp, BackUpGoal, BackUpResult, ClearCostmapAroundPose, ClearCostmapAroundRobot,
    ClearCostmapExceptRegion, ClearEntireCostmap, ComputePathThroughPoses,
    ComputePathThroughPosesGoal, ComputePathThroughPosesResult, ComputePathToPose,
    ComputePathToPoseGoal, ComputePathToPoseResult, DriveOnHeading, DriveOnHeadingGoal,
    DriveOnHeadingResult, FollowPath, FollowPathGoal, FollowPathResult, Spin, SpinGoal, SpinResult,
    Wait, WaitGoal, WaitResult,
};
use crate::msg::nav2_msgs::{
    NavigateToPose, NavigateToPoseGoal, NavigateToPoseResult, SmoothPath, SmoothPathGoal,
    SmoothPathResult,
};
use crate::msg::nav_msgs::{Goals, Path as NavPath};
use crate::msg::std_srvs::{Empty as EmptyService, EmptyRequest, EmptyResponse};
use crate::{
    ActionError, ActionSpec, RosAction, RosActionNode, RosNode, RosServiceNode, ServiceSpec,
};
use neurotree_nav2::robotics::TrackingFeedback;

/// The global costmap's cost service, where CheckPoseOccupancy and RemoveInCollisionGoals
/// ask by default (Nav2's `get_cost_` service of the costmap `global_costmap`).
pub const GET_COST_GLOBAL_COSTMAP: &str = "/global_costmap/get_cost_global_costmap";
/// The collision monitor's switch, where ToggleCollisionMonitor asks by default (Nav2's
/// `collision_monitor` node's `~/toggle`).
pub const TOGGLE_COLLISION_MONITOR: &str = "collision_monitor/toggle";
/// AMCL's service that spreads its particles over the map, where
/// ReinitializeGlobalLocalization asks by default.
pub const REINITIALIZE_GLOBAL_LOCALIZATION: &str = "reinitialize_global_localization";

/// Nav2's BT navigator waits this long for a server (its `wait_for_service_timeout`), in
/// milliseconds: the `wait_for_server_timeout` default of these leaves.
pub const WAIT_FOR_SERVER_MS: u64 = 1000;

/// Registers ComputePathToPose, ComputePathThroughPoses, SmoothPath, NavigateToPose,
/// NavigateThroughPoses, FollowPath, Spin, BackUp, DriveOnHeading, Wait, AssistedTeleop,
/// ComputeRoute, ComputeAndTrackRoute, DockRobot, UndockRobot and FollowObject as ROS 2
/// action clients on `ros`; ClearEntireCostmap, ClearCostmapAroundRobot,
/// ClearCostmapExceptRegion, ClearCostmapAroundPose, CheckPoseOccupancy,
/// RemoveInCollisionGoals, ToggleCollisionMonitor and ReinitializeGlobalLocalization as
/// service clients; the cancel nodes ([`register_cancel_nodes`](super::register_cancel_nodes)), and the battery and
/// odometry conditions as subscribers
/// ([`register_battery_conditions`](super::register_battery_conditions),
/// [`register_odometry_conditions`](super::register_odometry_conditions)). Fails if one of
/// the names is taken.
pub fn register_nav2_ros_leaves<C: 'static>(
    registry: &mut Registry<C>,
    ros: &RosNode,
) -> Result<(), RegistryError> {
    register_nav2_ros_leaves_for(registry, ros, Nav2Release::default())
}

/// [`register_nav2_ros_leaves`] speaking the layouts of Nav2 `release`: Jazzy's Spin,
/// BackUp, DriveOnHeading and ComputePathThroughPoses goals, or those of Kilted (and main),
/// which add `disable_collision_checks` to the behaviors' and take ComputePathThroughPoses's
/// goals as a `nav_msgs/Goals` ([`kilted`](crate::msg::nav2_msgs::kilted)); and Jazzy's
/// (and Kilted's) costmap clearings, ComputePathToPose goal and FollowPath, or main's:
/// clearings that send `plugins` and fail on an unsuccessful answer, a goal that sends
/// `viapoints`, a FollowPath that sends `path_handler_id` and writes the controller's
/// tracking feedback ([`main`](crate::msg::nav2_msgs::main)). The other messages have
/// one layout whatever the release (see [`nav2_msgs`](crate::msg::nav2_msgs)).
pub fn register_nav2_ros_leaves_for<C: 'static>(
    registry: &mut Registry<C>,
    ros: &RosNode,
    release: Nav2Release,
) -> Result<(), RegistryError> {
    let jazzy = release == Nav2Release::Jazzy;
    let name = "compute_path_to_pose";
    if release == Nav2Release::Main {
        let make = ComputePath::<main::ComputePathToPose>::default;
        register_action(registry, "ComputePathToPose", ros, name, make)?;
    } else {
        let make = ComputePath::<ComputePathToPose>::default;
        register_action(registry, "ComputePathToPose", ros, name, make)?;
    }
    let name = "compute_path_through_poses";
    if jazzy {
        let make = ComputeThrough::<ComputePathThroughPoses>::default;
        register_action(registry, "ComputePathThroughPoses", ros, name, make)?;
    } else {
        let make = ComputeThrough::<kilted::ComputePathThroughPoses>::default;
        register_action(registry, "ComputePathThroughPoses", ros, name, make)?;
    }
    register_action(registry, "SmoothPath", ros, "smooth_path", || Smooth)?;
    register_action(registry, "NavigateToPose", ros, "navigate_to_pose", || {
        Navigate
    })?;
    if release == Nav2Release::Main {
        let make = Follow::<main::FollowPath>::default;
        register_action(registry, "FollowPath", ros, "follow_path", make)?;
    } else {
        let make = Follow::<FollowPath>::default;
        register_action(registry, "FollowPath", ros, "follow_path", make)?;
    }
    if jazzy {
        register_action(registry, "Spin", ros, "spin", SpinBy::<Spin>::default)?;
        register_action(
            registry,
            "BackUp",
            ros,
            "backup",
            BackUpBy::<BackUp>::default,
        )?;
        let make = DriveOn::<DriveOnHeading>::default;
        register_action(registry, "DriveOnHeading", ros, "drive_on_heading", make)?;
    } else {
        let make = SpinBy::<kilted::Spin>::default;
        register_action(registry, "Spin", ros, "spin", make)?;
        let make = BackUpBy::<kilted::BackUp>::default;
        register_action(registry, "BackUp", ros, "backup", make)?;
        let make = DriveOn::<kilted::DriveOnHeading>::default;
        register_action(registry, "DriveOnHeading", ros, "drive_on_heading", make)?;
    }
    register_action(registry, "Wait", ros, "wait", || WaitFor)?;
    register_action(registry, "ComputeRoute", ros, "compute_route", || RouteOnce)?;
    register_action(
        registry,
        "ComputeAndTrackRoute",
        ros,
        "compute_and_track_route",
        TrackRoute::default,
    )?;
    register_action(registry, "DockRobot", ros, "dock_robot", || Dock)?;
    register_action(registry, "UndockRobot", ros, "undock_robot", || Undock)?;
    register_action(
        registry,
        "NavigateThroughPoses",
        ros,
        "navigate_through_poses",
        || NavigateThrough,
    )?;
    register_action(registry, "FollowObject", ros, "follow_object", || {
        FollowTarget
    })?;
    register_action(registry, "AssistedTeleop", ros, "assisted_teleop", || {
        Teleop::default()
    })?;
    if release == Nav2Release::Main {
        register_clearings::<
            C,
            main::ClearEntireCostmap,
            main::ClearCostmapAroundRobot,
            main::ClearCostmapExceptRegion,
            main::ClearCostmapAroundPose,
        >(registry, ros)?;
    } else {
        register_clearings::<
            C,
            ClearEntireCostmap,
            ClearCostmapAroundRobot,
            ClearCostmapExceptRegion,
            ClearCostmapAroundPose,
        >(registry, ros)?;
    }
    register_service(
        registry,
        "CheckPoseOccupancy",
        ros,
        GET_COST_GLOBAL_COSTMAP,
        PoseOccupancy::default,
        "Asks the costmap server `service_name` for the cost at `pose`: Success when occupied.",
    )?;
    register_service(
        registry,
        "RemoveInCollisionGoals",
        ros,
        GET_COST_GLOBAL_COSTMAP,
        InCollisionGoals::default,
        "Asks the costmap server `service_name` for the costs at `input_goals` and keeps the free ones.",
    )?;
    register_service(
        registry,
        "ToggleCollisionMonitor",
        ros,
        TOGGLE_COLLISION_MONITOR,
        || ToggleMonitor,
        "Asks the collision monitor `service_name` to turn on (`enable`) or off.",
    )?;
    register_service(
        registry,
        "ReinitializeGlobalLocalization",
        ros,
        REINITIALIZE_GLOBAL_LOCALIZATION,
        || Relocalize,
        "Asks the localization `service_name` to spread its estimate over the whole map.",
    )?;
    super::register_cancel_nodes(registry, ros)?;
    super::register_battery_conditions(registry, ros)?;
    super::register_odometry_conditions(registry, ros)
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

mod behaviors;
mod docking;
mod follow;
mod navigate;
mod planning;
mod route;
mod services;

use behaviors::*;
use docking::*;
use follow::*;
use navigate::*;
use planning::*;
use route::*;
use services::*;
