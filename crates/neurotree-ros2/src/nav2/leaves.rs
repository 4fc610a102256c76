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
use neurotree_sim::nav2::TrackingFeedback;

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

/// ComputePathToPose: the planner server's path from the robot (or `start`) to `goal`.
struct ComputePath<A>(PhantomData<fn() -> A>);

impl<A> Default for ComputePath<A> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

/// ComputePathToPose's goal in the layout of a release (main's adds `viapoints`).
trait ComputePathLayout: RosAction<Result = ComputePathToPoseResult> {
    fn goal(
        goal: PoseStamped,
        start: PoseStamped,
        viapoints: Vec<PoseStamped>,
        planner_id: String,
        use_start: bool,
    ) -> Self::Goal;
}

impl ComputePathLayout for ComputePathToPose {
    fn goal(
        goal: PoseStamped,
        start: PoseStamped,
        _: Vec<PoseStamped>,
        planner_id: String,
        use_start: bool,
    ) -> ComputePathToPoseGoal {
        ComputePathToPoseGoal {
            goal,
            start,
            planner_id,
            use_start,
        }
    }
}

impl ComputePathLayout for main::ComputePathToPose {
    fn goal(
        goal: PoseStamped,
        start: PoseStamped,
        viapoints: Vec<PoseStamped>,
        planner_id: String,
        use_start: bool,
    ) -> main::ComputePathToPoseGoal {
        main::ComputePathToPoseGoal {
            goal,
            start,
            viapoints,
            planner_id,
            use_start,
        }
    }
}

impl<C: 'static, A: ComputePathLayout> ActionSpec<C> for ComputePath<A> {
    type Action = A;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<Pose2D>("goal").describe("Where the path ends."),
            PortSpec::input::<Pose2D>("start").describe("Where it starts, instead of the robot."),
            PortSpec::input::<bool>("use_start").describe("Use `start` (true when it is given)."),
            PortSpec::input::<Vec<Pose2D>>("viapoints")
                .describe("Poses the path passes on its way (sent in Nav2 main's layout only)."),
            PortSpec::input::<String>("planner_id")
                .default_value("")
                .describe("The planner plugin; empty for the only one."),
            server_name_port(),
            PortSpec::output::<Path>("path").describe("The path found."),
            error_code_port("planner"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<A::Goal, String> {
        let goal: Pose2D = required(h, "goal")?;
        let start: Option<Pose2D> = optional(h, "start")?;
        let use_start = optional::<C, bool>(h, "use_start")?.unwrap_or(start.is_some());
        let viapoints: Vec<Pose2D> = optional(h, "viapoints")?.unwrap_or_default();
        Ok(A::goal(
            pose_stamped(goal),
            pose_stamped(start.unwrap_or_default()),
            viapoints.into_iter().map(pose_stamped).collect(),
            optional(h, "planner_id")?.unwrap_or_default(),
            use_start && start.is_some(),
        ))
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
struct ComputeThrough<A>(PhantomData<fn() -> A>);

impl<A> Default for ComputeThrough<A> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

/// ComputePathThroughPoses's goal in the layout of a release.
trait ThroughPosesLayout: RosAction<Result = ComputePathThroughPosesResult> {
    fn goal(
        goals: Vec<PoseStamped>,
        start: PoseStamped,
        planner_id: String,
        use_start: bool,
    ) -> Self::Goal;
}

impl ThroughPosesLayout for ComputePathThroughPoses {
    fn goal(
        goals: Vec<PoseStamped>,
        start: PoseStamped,
        planner_id: String,
        use_start: bool,
    ) -> ComputePathThroughPosesGoal {
        ComputePathThroughPosesGoal {
            goals,
            start,
            planner_id,
            use_start,
        }
    }
}

impl ThroughPosesLayout for kilted::ComputePathThroughPoses {
    fn goal(
        goals: Vec<PoseStamped>,
        start: PoseStamped,
        planner_id: String,
        use_start: bool,
    ) -> kilted::ComputePathThroughPosesGoal {
        kilted::ComputePathThroughPosesGoal {
            goals: Goals {
                header: pose_stamped(Pose2D::default()).header,
                goals,
            },
            start,
            planner_id,
            use_start,
        }
    }
}

impl<C: 'static, A: ThroughPosesLayout> ActionSpec<C> for ComputeThrough<A> {
    type Action = A;

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

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<A::Goal, String> {
        let goals: Vec<Pose2D> = optional(h, "goals")?.unwrap_or_default();
        let start: Option<Pose2D> = optional(h, "start")?;
        Ok(A::goal(
            goals.into_iter().map(pose_stamped).collect(),
            pose_stamped(start.unwrap_or_default()),
            optional(h, "planner_id")?.unwrap_or_default(),
            start.is_some(),
        ))
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
struct Follow<A: RosAction> {
    /// The goal sent last, to tell a new path or plugin from it.
    sent: Option<A::Goal>,
}

impl<A: RosAction> Default for Follow<A> {
    fn default() -> Self {
        Self { sent: None }
    }
}

/// FollowPath's goal and feedback in the layout of a release (main's names a path handler
/// and gives a tracking feedback).
trait FollowLayout: RosAction<Result = FollowPathResult, Goal: PartialEq> {
    /// The goal: the path, then the controller, goal checker, progress checker and path
    /// handler ids.
    fn goal(path: NavPath, ids: [String; 4]) -> Self::Goal;
    fn path(goal: &Self::Goal) -> &NavPath;
    fn tracking(feedback: &Self::Feedback) -> Option<TrackingFeedback>;
}

impl FollowLayout for FollowPath {
    fn goal(
        path: NavPath,
        [controller, goal_checker, progress_checker, _]: [String; 4],
    ) -> FollowPathGoal {
        FollowPathGoal {
            path,
            controller_id: controller,
            goal_checker_id: goal_checker,
            progress_checker_id: progress_checker,
        }
    }
    fn path(goal: &FollowPathGoal) -> &NavPath {
        &goal.path
    }
    fn tracking(_: &Self::Feedback) -> Option<TrackingFeedback> {
        None
    }
}

impl FollowLayout for main::FollowPath {
    fn goal(
        path: NavPath,
        [controller, goal_checker, progress_checker, handler]: [String; 4],
    ) -> main::FollowPathGoal {
        main::FollowPathGoal {
            path,
            controller_id: controller,
            goal_checker_id: goal_checker,
            progress_checker_id: progress_checker,
            path_handler_id: handler,
        }
    }
    fn path(goal: &main::FollowPathGoal) -> &NavPath {
        &goal.path
    }
    fn tracking(feedback: &main::FollowPathFeedback) -> Option<TrackingFeedback> {
        let t = &feedback.tracking_feedback;
        let (x, y) = (
            f64::from(t.position_tracking_error),
            f64::from(t.heading_tracking_error),
        );
        Some(TrackingFeedback {
            current_path_index: t.current_path_index as usize,
            remaining_path_length: f64::from(t.remaining_path_length),
            // The message does not carry the distance to the nearest pose: the distance to
            // the path stands for it.
            tracking_error: x.abs(),
            position_tracking_error: x,
            heading_tracking_error: y,
        })
    }
}

impl<A: FollowLayout> Follow<A> {
    fn read<C>(h: &Handle<'_, C>, path: NavPath) -> Result<A::Goal, String> {
        let id =
            |port: &str| -> Result<String, String> { Ok(optional(h, port)?.unwrap_or_default()) };
        Ok(A::goal(
            path,
            [
                id("controller_id")?,
                id("goal_checker_id")?,
                id("progress_checker_id")?,
                id("path_handler_id")?,
            ],
        ))
    }
}

impl<C: 'static, A: FollowLayout> ActionSpec<C> for Follow<A> {
    type Action = A;

    fn ports() -> Vec<PortSpec> {
        let plugin = |name: &str, what: &str| {
            PortSpec::input::<String>(name).describe(&format!("The {what} plugin."))
        };
        vec![
            PortSpec::input::<Path>("path").describe("The path to follow."),
            plugin("controller_id", "controller"),
            plugin("goal_checker_id", "goal checker"),
            plugin("progress_checker_id", "progress checker"),
            plugin(
                "path_handler_id",
                "path handler (sent in Nav2 main's layout only)",
            ),
            server_name_port(),
            PortSpec::output::<TrackingFeedback>("tracking_feedback")
                .describe("The controller's tracking feedback (in Nav2 main's layout only)."),
            error_code_port("controller"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<A::Goal, String> {
        let path: Path = required(h, "path")?;
        let goal = Self::read(h, path_msg(&path))?;
        self.sent = Some(goal.clone());
        Ok(goal)
    }

    fn updated_goal(&mut self, h: &mut Handle<'_, C>) -> Option<A::Goal> {
        // As Nav2's `on_wait_for_result`: a new non-empty path, or another plugin.
        let sent = self.sent.as_ref()?;
        let path = match optional::<C, Path>(h, "path").ok().flatten() {
            Some(path) if !path.poses.is_empty() => path_msg(&path),
            _ => A::path(sent).clone(),
        };
        let goal = Self::read(h, path).ok()?;
        if goal == *sent {
            return None;
        }
        self.sent = Some(goal.clone());
        Some(goal)
    }

    fn on_feedback(&mut self, h: &mut Handle<'_, C>, feedback: &A::Feedback) -> Status {
        if let Some(tracking) = A::tracking(feedback) {
            emit(h, "tracking_feedback", tracking);
        }
        Status::Running
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
struct SpinBy<A>(PhantomData<fn() -> A>);

impl<A> Default for SpinBy<A> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

/// Spin's goal in the layout of a release (Jazzy's has no `disable_collision_checks`).
trait SpinLayout: RosAction<Result = SpinResult> {
    fn goal(yaw: f32, allowance: MsgDuration, disable_collision_checks: bool) -> Self::Goal;
}

impl SpinLayout for Spin {
    fn goal(yaw: f32, allowance: MsgDuration, _: bool) -> SpinGoal {
        SpinGoal {
            target_yaw: yaw,
            time_allowance: allowance,
        }
    }
}

impl SpinLayout for kilted::Spin {
    fn goal(yaw: f32, allowance: MsgDuration, disable: bool) -> kilted::SpinGoal {
        kilted::SpinGoal {
            target_yaw: yaw,
            time_allowance: allowance,
            disable_collision_checks: disable,
        }
    }
}

/// A straight drive's goal (BackUp's, DriveOnHeading's) in the layout of a release.
trait StraightLayout: RosAction {
    fn goal(
        distance: f64,
        speed: f32,
        allowance: MsgDuration,
        disable_collision_checks: bool,
    ) -> Self::Goal;
}

/// Implements [`StraightLayout`] for a Jazzy goal and for a Kilted one.
macro_rules! straight_layouts {
    ($jazzy:ty: $jazzy_goal:ident, $kilted:ty: $kilted_goal:path) => {
        impl StraightLayout for $jazzy {
            fn goal(distance: f64, speed: f32, allowance: MsgDuration, _: bool) -> $jazzy_goal {
                $jazzy_goal {
                    target: Point {
                        x: distance,
                        y: 0.0,
                        z: 0.0,
                    },
                    speed,
                    time_allowance: allowance,
                }
            }
        }
        impl StraightLayout for $kilted {
            fn goal(
                distance: f64,
                speed: f32,
                allowance: MsgDuration,
                disable: bool,
            ) -> $kilted_goal {
                $kilted_goal {
                    target: Point {
                        x: distance,
                        y: 0.0,
                        z: 0.0,
                    },
                    speed,
                    time_allowance: allowance,
                    disable_collision_checks: disable,
                }
            }
        }
    };
}

straight_layouts!(BackUp: BackUpGoal, kilted::BackUp: kilted::BackUpGoal);
straight_layouts!(
    DriveOnHeading: DriveOnHeadingGoal,
    kilted::DriveOnHeading: kilted::DriveOnHeadingGoal
);

fn disable_collision_checks<C>(h: &Handle<'_, C>) -> Result<bool, String> {
    Ok(optional(h, "disable_collision_checks")?.unwrap_or(false))
}

impl<C: 'static, A: SpinLayout> ActionSpec<C> for SpinBy<A> {
    type Action = A;

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

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<A::Goal, String> {
        let angle: f64 = required(h, "spin_dist")?;
        let allowance: f64 = required(h, "time_allowance")?;
        let disable = disable_collision_checks(h)?;
        Ok(A::goal(angle as f32, seconds(allowance), disable))
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
struct BackUpBy<A>(PhantomData<fn() -> A>);

impl<A> Default for BackUpBy<A> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

impl<C: 'static, A: StraightLayout<Result = BackUpResult>> ActionSpec<C> for BackUpBy<A> {
    type Action = A;

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

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<A::Goal, String> {
        let distance: f64 = required(h, "backup_dist")?;
        let speed: f64 = required(h, "backup_speed")?;
        let allowance: f64 = required(h, "time_allowance")?;
        let disable = disable_collision_checks(h)?;
        Ok(A::goal(distance, speed as f32, seconds(allowance), disable))
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
struct DriveOn<A>(PhantomData<fn() -> A>);

impl<A> Default for DriveOn<A> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

impl<C: 'static, A: StraightLayout<Result = DriveOnHeadingResult>> ActionSpec<C> for DriveOn<A> {
    type Action = A;

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

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<A::Goal, String> {
        let distance: f64 = required(h, "dist_to_travel")?;
        let speed: f64 = required(h, "speed")?;
        let allowance: f64 = required(h, "time_allowance")?;
        let disable = disable_collision_checks(h)?;
        Ok(A::goal(distance, speed as f32, seconds(allowance), disable))
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

/// A clearing leaf: ClearEntireCostmap, ClearCostmapAroundRobot, ClearCostmapExceptRegion
/// or ClearCostmapAroundPose, in the layout `S` of a release. As Nav2 main's, an answer
/// that the plugins were not cleared fails the node.
struct Clear<S>(PhantomData<fn() -> S>);

impl<S> Default for Clear<S> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

impl<C: 'static, S: ClearLayout> ServiceSpec<C> for Clear<S> {
    type Service = S;

    fn ports() -> Vec<PortSpec> {
        let mut ports = Vec::new();
        if S::POSE {
            ports.push(PortSpec::input::<Pose2D>("pose").describe("The square's centre."));
        }
        if S::SQUARE {
            ports.push(
                PortSpec::input::<f64>("reset_distance")
                    .default_value("1.0")
                    .describe("The square's side, in metres."),
            );
        }
        ports.push(PortSpec::input::<Vec<String>>("plugins").describe(
            "The costmap plugins to clear; empty for all (sent in Nav2 main's layout only).",
        ));
        ports
    }

    fn request(&mut self, h: &mut Handle<'_, C>) -> Result<S::Request, String> {
        let pose = if S::POSE {
            pose_stamped(required(h, "pose")?)
        } else {
            PoseStamped::default()
        };
        let distance: f64 = optional(h, "reset_distance")?.unwrap_or(1.0);
        let plugins: Vec<String> = optional(h, "plugins")?.unwrap_or_default();
        Ok(S::request(pose, distance, plugins))
    }

    fn on_response(&mut self, h: &mut Handle<'_, C>, response: &S::Response) -> Status {
        if S::cleared(response) {
            Status::Success
        } else {
            emit(
                h,
                "error_msg",
                "the costmap did not clear its layers".to_owned(),
            );
            Status::Failure
        }
    }
}

/// Registers the four clearing leaves in the layouts `E`, `A`, `X` and `P`.
fn register_clearings<C: 'static, E, A, X, P>(
    registry: &mut Registry<C>,
    ros: &RosNode,
) -> Result<(), RegistryError>
where
    E: ClearLayout,
    A: ClearLayout,
    X: ClearLayout,
    P: ClearLayout,
{
    register_service(
        registry,
        "ClearEntireCostmap",
        ros,
        "local_costmap/clear_entirely_local_costmap",
        Clear::<E>::default,
        "Asks the costmap server `service_name` to forget every obstacle.",
    )?;
    register_service(
        registry,
        "ClearCostmapAroundRobot",
        ros,
        "local_costmap/clear_around_local_costmap",
        Clear::<A>::default,
        "Asks the costmap server `service_name` to forget the obstacles around the robot.",
    )?;
    register_service(
        registry,
        "ClearCostmapExceptRegion",
        ros,
        "local_costmap/clear_except_local_costmap",
        Clear::<X>::default,
        "Asks the costmap server `service_name` to forget the obstacles away from the robot.",
    )?;
    register_service(
        registry,
        "ClearCostmapAroundPose",
        ros,
        "local_costmap/clear_around_pose_local_costmap",
        Clear::<P>::default,
        "Asks the costmap server `service_name` to forget the obstacles around `pose`.",
    )
}

/// The route ports both route nodes read.
fn route_inputs(server: &str) -> Vec<PortSpec> {
    vec![
        PortSpec::input::<Pose2D>("start").describe("Where to start, with `use_start`."),
        PortSpec::input::<Pose2D>("goal").describe("Where to go, with `use_poses`."),
        PortSpec::input::<u16>("start_id").describe("The start node, without `use_poses`."),
        PortSpec::input::<u16>("goal_id").describe("The goal node, without `use_poses`."),
        PortSpec::input::<bool>("use_start")
            .default_value("false")
            .describe("Start at `start` rather than at the robot."),
        PortSpec::input::<bool>("use_poses")
            .default_value("false")
            .describe("Use `start` and `goal` rather than the node ids."),
        server_name_port(),
        PortSpec::output::<Route>("route").describe("The route; empty after a failure."),
        PortSpec::output::<Path>("path").describe("The route's path; empty after a failure."),
        error_code_port(server),
    ]
}

/// The goal of a route action from the ports, as Nav2's route nodes' `on_tick`: the poses
/// with `use_poses` (`start` only with `use_start`), else the node ids.
fn route_goal<C>(h: &Handle<'_, C>) -> Result<ComputeRouteGoal, String> {
    let use_poses: bool = optional(h, "use_poses")?.unwrap_or(false);
    if !use_poses {
        return Ok(ComputeRouteGoal {
            start_id: optional(h, "start_id")?.unwrap_or(0),
            goal_id: optional(h, "goal_id")?.unwrap_or(0),
            ..ComputeRouteGoal::default()
        });
    }
    let goal: Pose2D = required(h, "goal")?;
    let use_start: bool = optional(h, "use_start")?.unwrap_or(false);
    let start = if use_start {
        pose_stamped(required(h, "start")?)
    } else {
        Default::default()
    };
    Ok(ComputeRouteGoal {
        start,
        goal: pose_stamped(goal),
        use_start,
        use_poses: true,
        ..ComputeRouteGoal::default()
    })
}

/// ComputeRoute: the route server's route on its graph, and its path.
struct RouteOnce;

impl RouteOnce {
    /// As Nav2's `resetPorts`: no route rather than a stale one.
    fn reset<C>(h: &mut Handle<'_, C>) {
        emit(h, "path", Path::default());
        emit(h, "route", Route::default());
        emit(h, "planning_time", 0.0_f64);
    }
}

impl<C: 'static> ActionSpec<C> for RouteOnce {
    type Action = ComputeRoute;

    fn ports() -> Vec<PortSpec> {
        let mut ports = route_inputs("route");
        ports.push(PortSpec::output::<f64>("planning_time").describe("Seconds routing took."));
        ports
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<ComputeRouteGoal, String> {
        route_goal(h)
    }

    fn on_halt(&mut self, h: &mut Handle<'_, C>) {
        // As Nav2's node's `halt`.
        Self::reset(h);
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &ComputeRouteResult) -> Status {
        if result.error_code == ComputeRouteResult::NONE {
            emit(h, "path", path_2d(&result.path));
            emit(h, "route", route_2d(&result.route));
            let took: Duration = result.planning_time.into();
            emit(h, "planning_time", took.as_secs_f64());
        } else {
            Self::reset(h);
        }
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&ComputeRouteResult>,
    ) -> Status {
        Self::reset(h);
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, ComputeRouteResult::UNKNOWN, error, server)
    }
}

/// ComputeAndTrackRoute: the route server's route, then where the robot is along it, from
/// the server's feedback, until the robot reaches its end.
#[derive(Default)]
struct TrackRoute {
    /// The goal sent last, to tell new inputs from it.
    sent: Option<ComputeAndTrackRouteGoal>,
}

impl TrackRoute {
    /// As Nav2's `resetFeedbackAndOutputPorts`, when the goal ends whichever way.
    fn reset<C>(h: &mut Handle<'_, C>) {
        Self::write(h, &ComputeAndTrackRouteFeedback::default());
    }

    fn write<C>(h: &mut Handle<'_, C>, feedback: &ComputeAndTrackRouteFeedback) {
        emit(h, "last_node_id", feedback.last_node_id);
        emit(h, "next_node_id", feedback.next_node_id);
        emit(h, "current_edge_id", feedback.current_edge_id);
        emit(h, "route", route_2d(&feedback.route));
        emit(h, "path", path_2d(&feedback.path));
        emit(h, "rerouted", feedback.rerouted);
    }
}

impl<C: 'static> ActionSpec<C> for TrackRoute {
    type Action = ComputeAndTrackRoute;

    fn ports() -> Vec<PortSpec> {
        let mut ports = route_inputs("route");
        ports.extend([
            PortSpec::output::<f64>("execution_duration").describe("Seconds tracked."),
            PortSpec::output::<u16>("last_node_id").describe("The last node reached."),
            PortSpec::output::<u16>("next_node_id").describe("The next node."),
            PortSpec::output::<u16>("current_edge_id").describe("The edge being driven."),
            PortSpec::output::<bool>("rerouted").describe("The route was computed again."),
        ]);
        ports
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<ComputeAndTrackRouteGoal, String> {
        let goal = route_goal(h)?;
        let goal = ComputeAndTrackRouteGoal {
            start_id: goal.start_id,
            start: goal.start,
            goal_id: goal.goal_id,
            goal: goal.goal,
            use_start: goal.use_start,
            use_poses: goal.use_poses,
        };
        self.sent = Some(goal.clone());
        Ok(goal)
    }

    fn updated_goal(&mut self, h: &mut Handle<'_, C>) -> Option<ComputeAndTrackRouteGoal> {
        // As Nav2's `on_wait_for_result`: other inputs make a new goal.
        let sent = self.sent.as_ref()?;
        let goal = ActionSpec::<C>::goal(&mut TrackRoute::default(), h).ok()?;
        if goal == *sent {
            return None;
        }
        self.sent = Some(goal.clone());
        Some(goal)
    }

    fn on_feedback(
        &mut self,
        h: &mut Handle<'_, C>,
        feedback: &ComputeAndTrackRouteFeedback,
    ) -> Status {
        Self::write(h, feedback);
        Status::Running
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &ComputeAndTrackRouteResult) -> Status {
        Self::reset(h);
        let took: Duration = result.execution_duration.into();
        emit(h, "execution_duration", took.as_secs_f64());
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&ComputeAndTrackRouteResult>,
    ) -> Status {
        Self::reset(h);
        emit(h, "execution_duration", 0.0_f64);
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, ComputeAndTrackRouteResult::UNKNOWN, error, server)
    }
}

/// DockRobot: the docking server docks the robot at a dock of its database, or at a pose.
struct Dock;

impl<C: 'static> ActionSpec<C> for Dock {
    type Action = DockRobot;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<bool>("use_dock_id")
                .default_value("true")
                .describe("Dock at `dock_id` rather than at `dock_pose`."),
            PortSpec::input::<String>("dock_id").describe("The dock's id."),
            PortSpec::input::<Pose2D>("dock_pose").describe("The dock's pose."),
            PortSpec::input::<String>("dock_type").describe("The dock's type."),
            PortSpec::input::<f64>("max_staging_time")
                .default_value("1000.0")
                .describe("Seconds to reach the staging pose."),
            PortSpec::input::<bool>("navigate_to_staging_pose")
                .default_value("true")
                .describe("Drive to the staging pose first."),
            server_name_port(),
            PortSpec::output::<bool>("success").describe("Whether it docked."),
            PortSpec::output::<u16>("num_retries").describe("Retries made."),
            error_code_port("docking"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<DockRobotGoal, String> {
        let mut goal = DockRobotGoal {
            use_dock_id: optional(h, "use_dock_id")?.unwrap_or(true),
            navigate_to_staging_pose: optional(h, "navigate_to_staging_pose")?.unwrap_or(true),
            ..DockRobotGoal::default()
        };
        // As Nav2's node: the id, or the pose with its type and staging time.
        if goal.use_dock_id {
            goal.dock_id = required(h, "dock_id")?;
        } else {
            goal.dock_pose = pose_stamped(required(h, "dock_pose")?);
            goal.dock_type = optional(h, "dock_type")?.unwrap_or_default();
            let staging: f64 = optional(h, "max_staging_time")?.unwrap_or(1000.0);
            goal.max_staging_time = staging as f32;
        }
        Ok(goal)
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &DockRobotResult) -> Status {
        emit(h, "success", result.success);
        emit(h, "num_retries", result.num_retries);
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&DockRobotResult>,
    ) -> Status {
        if let (Some(result), false) = (result, matches!(error, ActionError::Canceled { .. })) {
            emit(h, "success", result.success);
            emit(h, "num_retries", result.num_retries);
        }
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, DockRobotResult::UNKNOWN, error, server)
    }
}

/// UndockRobot: the docking server backs the robot off its dock to the staging pose.
struct Undock;

impl<C: 'static> ActionSpec<C> for Undock {
    type Action = UndockRobot;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<String>("dock_type")
                .describe("The dock's type; empty for the one the server docked at."),
            PortSpec::input::<f64>("max_undocking_time")
                .default_value("30.0")
                .describe("Seconds undocking may take."),
            server_name_port(),
            PortSpec::output::<bool>("success").describe("Whether it undocked."),
            error_code_port("docking"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<UndockRobotGoal, String> {
        let allowed: f64 = optional(h, "max_undocking_time")?.unwrap_or(30.0);
        Ok(UndockRobotGoal {
            dock_type: optional(h, "dock_type")?.unwrap_or_default(),
            max_undocking_time: allowed as f32,
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &UndockRobotResult) -> Status {
        emit(h, "success", result.success);
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&UndockRobotResult>,
    ) -> Status {
        if let (Some(result), false) = (result, matches!(error, ActionError::Canceled { .. })) {
            emit(h, "success", result.success);
        }
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, UndockRobotResult::UNKNOWN, error, server)
    }
}

/// NavigateThroughPoses: another navigator takes the robot through `goals`.
struct NavigateThrough;

impl<C: 'static> ActionSpec<C> for NavigateThrough {
    type Action = NavigateThroughPoses;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<Vec<Pose2D>>("goals").describe("The poses to pass, in order."),
            PortSpec::input::<String>("behavior_tree")
                .describe("The navigator's tree to run; empty for its default."),
            server_name_port(),
            error_code_port("navigator"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<NavigateThroughPosesGoal, String> {
        let goals: Vec<Pose2D> = required(h, "goals")?;
        Ok(NavigateThroughPosesGoal {
            poses: goals_msg(&goals),
            behavior_tree: optional(h, "behavior_tree")?.unwrap_or_default(),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &NavigateThroughPosesResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&NavigateThroughPosesResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, NavigateThroughPosesResult::UNKNOWN, error, server)
    }
}

/// FollowObject: the following server keeps the robot behind the object whose pose comes
/// on `pose_topic`.
struct FollowTarget;

impl<C: 'static> ActionSpec<C> for FollowTarget {
    type Action = FollowObject;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<String>("pose_topic")
                .default_value("dynamic_pose")
                .describe("The topic of the object's pose."),
            PortSpec::input::<f64>("max_duration")
                .default_value("0.0")
                .describe("Seconds to follow; 0 follows until stopped."),
            PortSpec::input::<String>("tracked_frame")
                .describe("The object's frame, when `pose_topic` is empty."),
            server_name_port(),
            PortSpec::output::<f64>("total_elapsed_time").describe("Seconds followed."),
            error_code_port("following"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<FollowObjectGoal, String> {
        let secs: f64 = optional(h, "max_duration")?.unwrap_or(0.0);
        Ok(FollowObjectGoal {
            pose_topic: optional(h, "pose_topic")?.unwrap_or_else(|| "dynamic_pose".into()),
            tracked_frame: optional(h, "tracked_frame")?.unwrap_or_default(),
            max_duration: seconds(secs),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &FollowObjectResult) -> Status {
        let took: Duration = result.total_elapsed_time.into();
        emit(h, "total_elapsed_time", took.as_secs_f64());
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&FollowObjectResult>,
    ) -> Status {
        // Nav2's node writes the time followed when aborted and when cancelled.
        if let Some(result) = result {
            let took: Duration = result.total_elapsed_time.into();
            emit(h, "total_elapsed_time", took.as_secs_f64());
        }
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, FollowObjectResult::UNKNOWN, error, server)
    }
}

/// AssistedTeleop: the behavior server passes a person's velocity commands on for up to
/// `time_allowance`. As Nav2's `assisted_teleop_action.cpp`, an aborted goal (the time
/// allowance ran out) writes the server's code and fails only as a recovery
/// (`is_recovery`); otherwise the node succeeds, the code telling why it ended.
#[derive(Default)]
struct Teleop {
    is_recovery: bool,
}

impl<C: 'static> ActionSpec<C> for Teleop {
    type Action = AssistedTeleop;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<bool>("is_recovery")
                .default_value("false")
                .describe("Used as a recovery: an aborted goal fails the node."),
            time_allowance(),
            server_name_port(),
            error_code_port("assisted teleop"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<AssistedTeleopGoal, String> {
        let allowance: f64 = required(h, "time_allowance")?;
        self.is_recovery = optional(h, "is_recovery")?.unwrap_or(false);
        Ok(AssistedTeleopGoal {
            time_allowance: seconds(allowance),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &AssistedTeleopResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&AssistedTeleopResult>,
    ) -> Status {
        let aborted = matches!(error, ActionError::Aborted { .. });
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        let status = failed(h, AssistedTeleopResult::UNKNOWN, error, server);
        if aborted && !self.is_recovery {
            Status::Success
        } else {
            status
        }
    }
}

fn cost_ports() -> Vec<PortSpec> {
    vec![
        PortSpec::input::<f64>("cost_threshold")
            .default_value("254.0")
            .describe("The cost from which a pose counts as in collision."),
        PortSpec::input::<bool>("use_footprint")
            .default_value("true")
            .describe("The cost under the robot's footprint rather than at the point."),
        PortSpec::input::<bool>("consider_unknown_as_obstacle")
            .default_value("false")
            .describe("Count an unknown cost (255) as in collision."),
    ]
}

/// How the cost nodes judge a cost, from their ports.
#[derive(Clone, Copy, Debug)]
struct CostRule {
    threshold: f64,
    unknown_is_obstacle: bool,
}

impl Default for CostRule {
    fn default() -> Self {
        Self {
            threshold: 254.0,
            unknown_is_obstacle: false,
        }
    }
}

impl CostRule {
    fn read<C>(h: &Handle<'_, C>) -> Result<(Self, bool), String> {
        let rule = Self {
            threshold: optional(h, "cost_threshold")?.unwrap_or(254.0),
            unknown_is_obstacle: optional(h, "consider_unknown_as_obstacle")?.unwrap_or(false),
        };
        Ok((rule, optional(h, "use_footprint")?.unwrap_or(true)))
    }

    /// As Nav2's nodes: unknown (255) is free unless told otherwise; else the threshold.
    fn in_collision(&self, cost: f32) -> bool {
        let unknown_free = cost == 255.0 && !self.unknown_is_obstacle;
        !(unknown_free || f64::from(cost) < self.threshold)
    }
}

/// CheckPoseOccupancy: Success when the costmap's cost at `pose` is at least
/// `cost_threshold`; Failure when it is below, or the costmap could not answer.
#[derive(Default)]
struct PoseOccupancy {
    rule: CostRule,
}

impl<C: 'static> ServiceSpec<C> for PoseOccupancy {
    type Service = GetCosts;

    fn ports() -> Vec<PortSpec> {
        let mut ports = vec![PortSpec::input::<Pose2D>("pose").describe("The pose to check.")];
        ports.extend(cost_ports());
        ports
    }

    fn request(&mut self, h: &mut Handle<'_, C>) -> Result<GetCostsRequest, String> {
        let (rule, use_footprint) = CostRule::read(h)?;
        self.rule = rule;
        Ok(GetCostsRequest {
            use_footprint,
            poses: vec![pose_stamped(required(h, "pose")?)],
        })
    }

    fn on_response(&mut self, h: &mut Handle<'_, C>, response: &GetCostsResponse) -> Status {
        match (response.success, response.costs.first()) {
            (true, Some(cost)) if self.rule.in_collision(*cost) => Status::Success,
            (true, Some(_)) => Status::Failure,
            _ => {
                emit(
                    h,
                    "error_msg",
                    "the costmap could not give the cost".to_owned(),
                );
                Status::Failure
            }
        }
    }
}

/// RemoveInCollisionGoals: writes `input_goals` less those whose cost is at least
/// `cost_threshold` to `output_goals`. As Nav2's node, no goals sends no request and
/// fails (writing them back), and a call the costmap could not answer writes them back
/// unchanged and fails. Waypoint statuses are declared and not kept.
#[derive(Default)]
struct InCollisionGoals {
    rule: CostRule,
    goals: Vec<Pose2D>,
}

impl<C: 'static> ServiceSpec<C> for InCollisionGoals {
    type Service = GetCosts;

    fn ports() -> Vec<PortSpec> {
        let mut ports =
            vec![PortSpec::input::<Vec<Pose2D>>("input_goals").describe("The goals to check.")];
        ports.extend(cost_ports());
        ports.extend([
            PortSpec::input::<String>("input_waypoint_statuses")
                .describe("The goals' statuses (not kept)."),
            PortSpec::output::<Vec<Pose2D>>("output_goals").describe("The goals not in collision."),
            PortSpec::output::<String>("output_waypoint_statuses")
                .describe("The statuses with the removed goals skipped (not written)."),
        ]);
        ports
    }

    fn request(&mut self, h: &mut Handle<'_, C>) -> Result<GetCostsRequest, String> {
        let (rule, use_footprint) = CostRule::read(h)?;
        self.rule = rule;
        self.goals = optional(h, "input_goals")?.unwrap_or_default();
        if self.goals.is_empty() {
            emit(h, "output_goals", Vec::<Pose2D>::new());
            return Err("no goals to check".into());
        }
        Ok(GetCostsRequest {
            use_footprint,
            poses: self.goals.iter().copied().map(pose_stamped).collect(),
        })
    }

    fn on_response(&mut self, h: &mut Handle<'_, C>, response: &GetCostsResponse) -> Status {
        if !response.success || response.costs.len() != self.goals.len() {
            emit(h, "output_goals", self.goals.clone());
            emit(
                h,
                "error_msg",
                "the costmap could not give the costs".to_owned(),
            );
            return Status::Failure;
        }
        let kept: Vec<Pose2D> = self
            .goals
            .iter()
            .zip(&response.costs)
            .filter(|(_, cost)| !self.rule.in_collision(**cost))
            .map(|(goal, _)| *goal)
            .collect();
        emit(h, "output_goals", kept);
        Status::Success
    }
}

/// ToggleCollisionMonitor: turns the collision monitor on or off; Success once it
/// answered, whatever it answered, as Nav2's node.
struct ToggleMonitor;

impl<C: 'static> ServiceSpec<C> for ToggleMonitor {
    type Service = Toggle;

    fn ports() -> Vec<PortSpec> {
        vec![PortSpec::input::<bool>("enable")
            .default_value("true")
            .describe("Turn the collision monitor on (true) or off.")]
    }

    fn request(&mut self, h: &mut Handle<'_, C>) -> Result<ToggleRequest, String> {
        Ok(ToggleRequest {
            enable: optional(h, "enable")?.unwrap_or(true),
        })
    }

    fn on_response(&mut self, _h: &mut Handle<'_, C>, _: &ToggleResponse) -> Status {
        Status::Success
    }
}

/// ReinitializeGlobalLocalization: asks the localization to start over; Success once it
/// answered.
struct Relocalize;

impl<C: 'static> ServiceSpec<C> for Relocalize {
    type Service = EmptyService;

    fn request(&mut self, _h: &mut Handle<'_, C>) -> Result<EmptyRequest, String> {
        Ok(EmptyRequest::default())
    }

    fn on_response(&mut self, _h: &mut Handle<'_, C>, _: &EmptyResponse) -> Status {
        Status::Success
    }
}
