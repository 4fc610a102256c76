//! Nav2 over ROS 2: the navigator's ROS-backed leaves, the navigator itself, and the grid
//! world served as the Nav2 servers it calls.
//!
//! | piece | what it is |
//! |---|---|
//! | [`register_nav2_ros_leaves`] | ComputePathToPose, FollowPath, Spin, BackUp, Wait and ClearEntireCostmap as ROS 2 clients, with `nav2_tree_nodes.xml`'s ports |
//! | [`Navigator`] | the `navigate_to_pose` action server: ticks a tree per goal, feedback, result, cancel halts |
//! | [`SimServers`] | a [`GridWorld`](neurotree_sim::GridWorld) as the planner, controller, behavior and costmap servers, stepping on its own clock |
//! | [`convert`] | between the blackboard's `Pose2D` / `Path` and their messages |
//!
//! Nav2's navigator (`navigate_to_pose_w_replanning_and_recovery.xml`) runs unchanged: a
//! [`Navigator`] on one ROS node, a [`SimServers`] on another (in another process, or in
//! the same one), and a goal sent to `navigate_to_pose`. See `tests/navigator.rs`.

pub mod convert;
mod goal_server;
mod leaves;
mod navigator;
mod sim_servers;

pub use leaves::{register_nav2_ros_leaves, WAIT_FOR_SERVER_MS};
pub use navigator::{
    Navigator, NavigatorError, NavigatorOptions, NavigatorStats, ROBOT_POSE_TOPIC,
};
pub use sim_servers::{
    ServerCounts, SimOptions, SimServers, SimStats, SimStatsHandle, CLEAR_GLOBAL_COSTMAP,
    CLEAR_LOCAL_COSTMAP,
};
