//! A ROS 2 bridge for NeuroTree in pure Rust: BehaviorTree.ROS2's four node kinds and the
//! message types of Nav2's navigator, over [ros2-client] and [RustDDS], so that it builds
//! with `cargo` alone (no ROS 2 installation, no C++ middleware).
//!
//! | piece | what it is |
//! |---|---|
//! | [`RosNode`] | one DDS participant and ROS 2 node, shared by the tree's ROS nodes |
//! | [`RosActionNode`] | action client: sends the goal on start, Running with feedback, Success / Failure from the result, cancels on halt |
//! | [`RosServiceNode`] | service client: Running until the response |
//! | [`RosTopicSubNode`] | subscription as a condition; [`LatestMessage`] puts the newest message on the blackboard |
//! | [`RosTopicPubNode`] | publisher as an action |
//! | [`nav2`] | Nav2 over ROS 2: the navigator's ROS leaves, a [`Navigator`](nav2::Navigator) serving `navigate_to_pose` over the program's own context and leaves, and (feature `sim`) `SimServers`, the grid world as Nav2's servers |
//! | [`msg`] | `builtin_interfaces`, `std_msgs`, `geometry_msgs`, `nav_msgs` and `nav2_msgs` types with their ROS 2 names |
//!
//! Each node is generic over its messages through a small trait ([`ActionSpec`],
//! [`ServiceSpec`], [`SubscriberSpec`], [`PublisherSpec`]), registered for XML with
//! BehaviorTree.ROS2's ports (`action_name` / `service_name` / `topic_name`,
//! `server_timeout`, `wait_for_server_timeout`) by `register`, or placed with the builder's
//! `stateful`. No tick waits on the network: the nodes poll their DDS readers and compare
//! deadlines.
//!
//! # Discovery
//!
//! [`Network::Loopback`] (the default) keeps a participant on 127.0.0.1 and finds the others
//! by unicast SPDP to the well-known ports of 127.0.0.1; [`Network::All`] adds multicast on
//! every interface, as ROS 2's middlewares do by default. Measured on a machine whose only
//! usable interface is `lo` (two participants of one process, a `std_msgs/String`):
//!
//! | set-up | result |
//! |---|---|
//! | 127.0.0.1 only, unicast SPDP to localhost ports | message after ~0.25 s; every datagram to 127.0.0.1 |
//! | multicast SPDP only, `lo` alone | nothing in 20 s: Linux's `lo` has no `MULTICAST` flag |
//! | multicast SPDP only, `lo` given `MULTICAST` and a 239/8 route | message after ~0.2 s |
//!
//! Cyclone DDS (`<Peers><Peer address="127.0.0.1"/></Peers>`, multicast off) interoperates
//! with the loopback set-up: see `tests/cyclonedds.rs`.
//!
//! # Compatibility
//!
//! Messages follow ROS 2 Jazzy's definitions (Nav2's results carry `error_msg` since Jazzy).
//! Services and actions use the `Enhanced` mapping of request ids by default, the one of
//! `rmw_fastrtps` (ROS 2's default middleware); [`RosOptions::service_mapping`] picks
//! `rmw_cyclonedds`'s.
//!
//! [ros2-client]: https://crates.io/crates/ros2-client
//! [RustDDS]: https://crates.io/crates/rustdds
//!
//! ```no_run
//! use neurotree_ros2::msg::std_msgs;
//! use neurotree_ros2::{LatestMessage, RosNode, RosOptions, RosTopicSubNode};
//! use neurotree_toolkit::{Registry, Tree, XmlLoader};
//!
//! let ros = RosNode::new("bt", &RosOptions::loopback(0))?;
//! let mut registry = Registry::<()>::new();
//! RosTopicSubNode::register(&mut registry, "Chatter", &ros, "chatter", || {
//!     LatestMessage::<std_msgs::String>::default()
//! })?;
//! let mut loader = XmlLoader::new(&registry);
//! loader.load_str(
//!     r#"<root BTCPP_format="4"><BehaviorTree ID="T">
//!          <Chatter topic_name="chatter" message="{heard}"/>
//!        </BehaviorTree></root>"#,
//!     "t.xml",
//! )?;
//! let mut tree = Tree::new(std::sync::Arc::new(loader.build_main()?));
//! tree.tick_once(&mut ())?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![forbid(unsafe_code)]

mod error;
mod interface;
pub mod msg;
pub mod nav2;
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
pub use ros_node::{
    default_qos, Network, RosActionClient, RosActionServer, RosNode, RosOptions, ServiceMapping,
};

/// The ROS 2 chapter of the guide, whose examples compile as this crate's doctests.
#[cfg(doctest)]
#[doc = include_str!("../guide/ros2.md")]
struct GuideRos2;
