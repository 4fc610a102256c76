//! Nav2 over ROS 2: the navigator's ROS-backed leaves, the navigator itself, and the grid
//! world served as the Nav2 servers it calls.
//!
//! | piece | what it is |
//! |---|---|
//! | [`register_nav2_ros_leaves`] | every Nav2 node that calls a server, a service or a topic, with `nav2_tree_nodes.xml`'s ports: the actions (ComputePathToPose, ComputePathThroughPoses, SmoothPath, NavigateToPose, NavigateThroughPoses, FollowPath, Spin, BackUp, DriveOnHeading, Wait, AssistedTeleop, ComputeRoute, ComputeAndTrackRoute, DockRobot, UndockRobot, FollowObject) as ROS 2 action clients; the four costmap clearings, CheckPoseOccupancy, RemoveInCollisionGoals, ToggleCollisionMonitor and ReinitializeGlobalLocalization as service clients; the eight cancel nodes ([`register_cancel_nodes`]); IsBatteryLow, IsBatteryCharging ([`register_battery_conditions`]), IsStuck and CheckStopStatus ([`register_odometry_conditions`]) as subscribers |
//! | [`Navigator`] | the `navigate_to_pose` action server: ticks a tree per goal, feedback, result, cancel halts; generic over the program's context, its tree loaded from the program's registry: Nav2's nodes ([`register_navigator_nodes`]) beside the robot's own leaves |
//! | `Navigator::on_map` (feature `sim`) | the navigator of every node type of Nav2 main: the rest are the simulator's checks on its own view of the map (`neurotree_sim::nav2::register_nav2_checks`) |
//! | `SimServers` (feature `sim`) | a `neurotree_sim::GridWorld` as the planner, smoother, controller, behavior, route, docking, following and costmap servers, the navigator through poses, the collision monitor, the localization and the odometry, stepping on its own clock |
//! | [`convert`] | between the blackboard's `Pose2D` / `Path` and their messages |
//!
//! Nav2's navigator (`navigate_to_pose_w_replanning_and_recovery.xml`) runs unchanged: a
//! `Navigator::on_map` on one ROS node, a `SimServers` on another (in another process, or
//! in the same one), and a goal sent to `navigate_to_pose`. See `tests/navigator.rs`. A
//! robot's own program builds without the `sim` feature, registers its leaves beside
//! Nav2's and runs [`Navigator::new`] over its own context: see `tests/robot.rs`.
//!
//! # Where it is simpler than Nav2
//!
//! - A navigator runs one tree; a goal naming another `behavior_tree` is aborted with
//!   FAILED_TO_LOAD_BEHAVIOR_TREE.
//! - One goal at a time: a cancel applies to the running goal (ros2-client does not give
//!   the goal id of a cancel request).
//! - The feedback's `number_of_recoveries` counts every run of a recovery branch of the
//!   tree, clearing a costmap included (Nav2 counts spin, wait and back-up);
//!   `estimated_time_remaining` is always zero.
//! - The navigator follows the robot from a pose topic ([`ROBOT_POSE_TOPIC`] by default,
//!   which the simulator publishes) rather than from TF.
//! - RemoveInCollisionGoals keeps no waypoint statuses (`output_waypoint_statuses` is not
//!   written), as in the simulator.

mod battery;
mod cancels;
mod clearing;
pub mod convert;
mod goal_server;
mod leaves;
mod navigator;
mod odometry;
#[cfg(feature = "sim")]
mod sim;

pub use battery::{register_battery_conditions, BATTERY_TOPIC};
pub use cancels::register_cancel_nodes;
pub use leaves::{
    register_nav2_ros_leaves, register_nav2_ros_leaves_for, GET_COST_GLOBAL_COSTMAP,
    REINITIALIZE_GLOBAL_LOCALIZATION, TOGGLE_COLLISION_MONITOR, WAIT_FOR_SERVER_MS,
};
pub use navigator::{
    register_navigator_nodes, Navigator, NavigatorContext, NavigatorError, NavigatorOptions,
    NavigatorStats, ROBOT_POSE_TOPIC,
};
pub use odometry::{register_odometry_conditions, ODOM_TOPIC};
#[cfg(feature = "sim")]
pub use sim::{
    ServerCounts, SimOptions, SimServers, SimStats, SimStatsHandle, CLEAR_GLOBAL_COSTMAP,
    CLEAR_LOCAL_COSTMAP, GET_COST_LOCAL_COSTMAP, OBJECT_POSE_TOPIC, PREEMPT_TELEOP_TOPIC,
};
