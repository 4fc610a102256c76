//! What makes a Rust type a ROS 2 interface: its ROS 2 name.
//!
//! A message is a serde struct whose fields are those of the `.msg` file, in order: ROS 2's
//! CDR encoding is serde's field order. The traits add the name the type has on the wire:
//! `std_msgs/msg/String` is the DDS type `std_msgs::msg::dds_::String_`. A service pairs a
//! request with a response, an action a goal, a result and a feedback.
//!
//! ```
//! use neurotree_ros2::{RosMessage, msg::std_msgs};
//!
//! assert_eq!(std_msgs::String::TYPE, ("std_msgs", "String"));
//! ```

use ros2_client::Message;

/// A ROS 2 message type: a serde struct (fields in the order of its `.msg` file) and its name.
pub trait RosMessage: Message + Clone + std::fmt::Debug + Send + Sync + 'static {
    /// Package and type name: `("std_msgs", "String")` for `std_msgs/msg/String`.
    const TYPE: (&'static str, &'static str);
}

/// A ROS 2 service type: its request, its response and its name.
pub trait RosService: Send + Sync + 'static {
    /// The request message.
    type Request: Message + Clone + Send + Sync + 'static;
    /// The response message.
    type Response: Message + Clone + Send + Sync + 'static;
    /// Package and type name: `("nav2_msgs", "ClearEntireCostmap")` for
    /// `nav2_msgs/srv/ClearEntireCostmap`.
    const TYPE: (&'static str, &'static str);
}

/// A ROS 2 action type: its goal, result and feedback messages and its name.
pub trait RosAction: Send + Sync + 'static {
    /// What the client asks for.
    type Goal: Message + Clone + Send + Sync + 'static;
    /// What the server answers when the goal ends.
    type Result: Message + Clone + Send + Sync + 'static;
    /// What the server reports while it works.
    type Feedback: Message + Clone + Send + Sync + 'static;
    /// Package and type name: `("nav2_msgs", "Spin")` for `nav2_msgs/action/Spin`.
    const TYPE: (&'static str, &'static str);
}
