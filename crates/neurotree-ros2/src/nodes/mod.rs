//! The tree's ROS 2 nodes, BehaviorTree.ROS2's four kinds.
//!
//! | node | ROS 2 side | ports besides the node's own |
//! |---|---|---|
//! | [`RosActionNode`] | action client: Running while the goal runs | `action_name`, `server_timeout`, `wait_for_server_timeout`, `error_msg` |
//! | [`RosServiceNode`] | service client: Running until the response | `service_name`, `server_timeout`, `wait_for_server_timeout`, `error_msg` |
//! | [`RosTopicSubNode`] | subscription: Success with the latest message | `topic_name` |
//! | [`RosTopicPubNode`] | publisher: Success once published | `topic_name` |
//!
//! Each is generic over the message types through a small trait the user implements (what to
//! send from the ports, what a reply means), as BehaviorTree.ROS2's nodes are subclassed.
//! None blocks the tick: endpoints are polled, and a wait is a deadline checked on later
//! ticks. Deadlines are wall-clock ([`Instant`]), not the tree's clock: they measure the
//! network, which a manual clock does not drive.

pub mod action;
pub mod publisher;
pub mod service;
pub mod subscriber;

pub use action::{ActionError, ActionSpec, RosActionNode};
pub use publisher::{PublisherSpec, RosTopicPubNode};
pub use service::{RosServiceNode, ServiceError, ServiceSpec};
pub use subscriber::{RosTopicSubNode, SubscriberSpec};

use std::time::{Duration, Instant};

use neurotree_toolkit::{Handle, PortError, PortSpec};

/// BehaviorTree.ROS2's default `server_timeout`, in milliseconds.
pub const DEFAULT_SERVER_TIMEOUT_MS: u64 = 1000;
/// BehaviorTree.ROS2's default `wait_for_server_timeout`, in milliseconds.
pub const DEFAULT_WAIT_FOR_SERVER_TIMEOUT_MS: u64 = 500;

/// How long a server must have been discovered before a client's first request goes out.
///
/// Discovery (SEDP) is two one-way announcements: seeing the server's reader does not mean
/// the server has seen this client's writer yet. A request written before it has is only
/// repaired at the writer's next heartbeat, up to 1 s later with RustDDS, which can outlast
/// `server_timeout`. Waiting this long once per client lets the other announcement land.
pub const DISCOVERY_SETTLE: Duration = Duration::from_millis(200);

/// Tells whether a server is ready for requests: discovered, and for [`DISCOVERY_SETTLE`].
#[derive(Debug, Default)]
pub(crate) struct ServerPresence {
    seen_since: Option<Instant>,
}

impl ServerPresence {
    /// `discovered` is this tick's reading of the discovery data.
    pub(crate) fn ready(&mut self, discovered: bool) -> bool {
        if !discovered {
            self.seen_since = None;
            return false;
        }
        self.seen_since.get_or_insert_with(Instant::now).elapsed() >= DISCOVERY_SETTLE
    }
}

/// The ports of a client node (action or service): the name port `name_port` (default
/// `default_name`), the two timeouts and the failure reason.
pub(crate) fn client_ports(name_port: &str, default_name: &str) -> Vec<PortSpec> {
    vec![
        PortSpec::input::<String>(name_port)
            .default_value(default_name)
            .describe("the ROS 2 name of the server"),
        PortSpec::input::<u64>("server_timeout")
            .default_value(&DEFAULT_SERVER_TIMEOUT_MS.to_string())
            .describe("milliseconds to wait for the server to answer a request"),
        PortSpec::input::<u64>("wait_for_server_timeout")
            .default_value(&DEFAULT_WAIT_FOR_SERVER_TIMEOUT_MS.to_string())
            .describe("milliseconds to wait for the server to be discovered"),
        PortSpec::output::<String>("error_msg").describe("why the node last failed"),
    ]
}

/// Reads input `port`, or `default` when the node has no such port (a node made with the
/// builder binds only the ports it was given; the XML loader binds every declared default).
pub(crate) fn input_or<C, T>(h: &Handle<'_, C>, port: &str, default: T) -> Result<T, PortError>
where
    T: neurotree_toolkit::FromPortStr + std::any::Any + Clone,
{
    match h.input::<T>(port) {
        Err(PortError::NoSuchPort { .. }) => Ok(default),
        other => other,
    }
}

/// A client's name and timeouts, read from its ports when it starts.
pub(crate) struct ClientPorts {
    pub name: String,
    pub server_timeout: Duration,
    pub wait_for_server_timeout: Duration,
}

impl ClientPorts {
    pub(crate) fn read<C>(
        h: &Handle<'_, C>,
        name_port: &str,
        default_name: &str,
    ) -> Result<Self, PortError> {
        Ok(Self {
            name: input_or(h, name_port, default_name.to_owned())?,
            server_timeout: Duration::from_millis(input_or(
                h,
                "server_timeout",
                DEFAULT_SERVER_TIMEOUT_MS,
            )?),
            wait_for_server_timeout: Duration::from_millis(input_or(
                h,
                "wait_for_server_timeout",
                DEFAULT_WAIT_FOR_SERVER_TIMEOUT_MS,
            )?),
        })
    }
}

/// Writes the reason of a failure to `error_msg` when that port is bound to an entry.
pub(crate) fn report<C>(h: &mut Handle<'_, C>, reason: String) {
    // An unbound or literal `error_msg` is the user's choice not to read the reason.
    let _ = h.output("error_msg", reason);
}

/// A point in wall-clock time `after` from now.
pub(crate) fn deadline(after: Duration) -> Instant {
    Instant::now() + after
}
