//! `nav_msgs`: paths.

use serde::{Deserialize, Serialize};

use super::geometry_msgs::PoseStamped;
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

messages!("nav_msgs": Path);
