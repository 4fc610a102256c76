//! The ROS 2 messages, services and actions the Nav2 navigator needs, as Rust types with
//! their ROS 2 names (ROS 2 Jazzy's definitions).
//!
//! | package | types |
//! |---|---|
//! | [`builtin_interfaces`] | `Time`, `Duration` |
//! | [`std_msgs`] | `Header`, `String`, `Empty` |
//! | [`geometry_msgs`] | `Point`, `Quaternion`, `Pose`, `PoseStamped`, `Vector3`, `Twist` |
//! | [`nav_msgs`] | `Path` |
//! | [`nav2_msgs`] | actions `ComputePathToPose`, `FollowPath`, `Spin`, `BackUp`, `Wait`; service `ClearEntireCostmap` |
//!
//! Field order is the wire format: each struct lists the fields of its `.msg` file in order.
//! A definition with no field (`std_msgs/Empty`, an empty feedback) carries the one byte
//! that ROS 2's code generators add, `structure_needs_at_least_one_member`.

pub mod builtin_interfaces;
pub mod geometry_msgs;
pub mod nav2_msgs;
pub mod nav_msgs;
pub mod std_msgs;
