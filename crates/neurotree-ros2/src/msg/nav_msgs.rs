//! `nav_msgs`: paths, lists of goals and odometry.

use serde::{Deserialize, Serialize};

use super::geometry_msgs::{PoseStamped, PoseWithCovariance, TwistWithCovariance};
use super::std_msgs::Header;
use crate::interface::messages;

/// `nav_msgs/msg/Path`: poses for a robot to follow.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Path {
    /// Frame and time of the path.
    pub header: Header,
    /// The poses, in order.
    pub poses: Vec<PoseStamped>,
}

/// `nav_msgs/msg/Goals`: goals to reach in order (Nav2 main's lists of goals).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Goals {
    /// When and in which frame the goals were computed.
    pub header: Header,
    /// The goals, in order.
    pub goals: Vec<PoseStamped>,
}

/// `nav_msgs/msg/Odometry`: where the robot thinks it is and how fast it moves.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Odometry {
    /// When, and the frame of the pose (`odom`).
    pub header: Header,
    /// The frame of the twist (`base_link`).
    pub child_frame_id: String,
    /// The pose, in `header.frame_id`.
    pub pose: PoseWithCovariance,
    /// The velocity, in `child_frame_id`.
    pub twist: TwistWithCovariance,
}

messages!("nav_msgs": Path, Goals, Odometry);
