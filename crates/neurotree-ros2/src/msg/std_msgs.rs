//! `std_msgs`: the header and the plain messages.

use serde::{Deserialize, Serialize};

use super::builtin_interfaces::Time;
use crate::interface::messages;

/// `std_msgs/msg/Header`: when and in which frame a stamped message was taken.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// When.
    pub stamp: Time,
    /// The coordinate frame (`map`, `odom`, `base_link`).
    pub frame_id: std::string::String,
}

/// `std_msgs/msg/String`: one text.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct String {
    /// The text.
    pub data: std::string::String,
}

/// `std_msgs/msg/Empty`: no data (one placeholder byte on the wire).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Empty {
    /// The byte ROS 2's code generators add to a struct without fields; always 0.
    pub structure_needs_at_least_one_member: u8,
}

messages!("std_msgs": Header, String, Empty);

impl From<&str> for String {
    fn from(text: &str) -> Self {
        Self {
            data: text.to_owned(),
        }
    }
}
