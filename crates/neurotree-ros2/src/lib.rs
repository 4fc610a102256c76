//! spike
mod error;
mod interface;
pub mod msg;
pub mod nodes;
mod ros_node;

pub use error::Ros2Error;
pub use interface::{RosAction, RosMessage, RosService};
pub use nodes::subscriber::LatestMessage;
pub use nodes::{
    ActionError, ActionSpec, PublisherSpec, RosActionNode, RosServiceNode, RosTopicPubNode,
    RosTopicSubNode, ServiceError, ServiceSpec, SubscriberSpec, DISCOVERY_SETTLE,
};
/// The ROS 2 client library underneath, for servers and types the nodes do not wrap.
pub use ros2_client;
pub use ros_node::{default_qos, Network, RosActionClient, RosActionServer, RosNode, RosOptions};
