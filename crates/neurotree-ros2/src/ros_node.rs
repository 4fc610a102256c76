//! The bridge's ROS 2 node: one DDS participant and one ros2-client node that every
//! NeuroTree ROS node of a process shares.
//!
//! Discovery is standard RTPS (SPDP then SEDP), with one choice about the network:
//!
//! - [`Network::Loopback`]: the participant uses 127.0.0.1 only. Participants find each other
//!   by unicast SPDP to the well-known ports of 127.0.0.1 (RustDDS's same-host discovery, the
//!   same thing as Cyclone DDS's `<Peers><Peer address="127.0.0.1"/></Peers>` or Fast DDS's
//!   initial peers). Linux's `lo` has no multicast, so multicast SPDP alone finds nothing
//!   there: this is what works on a machine without a network, and in the tests.
//! - [`Network::All`]: RustDDS's defaults, multicast SPDP on every interface as ROS 2's own
//!   middlewares do, plus the unicast localhost peers.
//!
//! The node runs no spinner: the tree's nodes poll their endpoints on their ticks, and a
//! server's presence is read from the participant's discovery data.

use std::net::{IpAddr, Ipv4Addr};
use std::sync::{Arc, Mutex, MutexGuard};

use ros2_client::action::{
    ActionClient, ActionClientQosPolicies, ActionServer, ActionServerQosPolicies,
};
use ros2_client::qos::{Durability, History, WhenFull};
use ros2_client::service::{Client, Server};
/// How service requests carry their ids on DDS (see [`RosOptions::service_mapping`]).
pub use ros2_client::ServiceMapping;
use ros2_client::{
    ActionTypeName, Context, MessageTypeName, Name, NodeName, NodeOptions, Publisher, QosProfile,
    ServiceTypeName, Subscription,
};
use rustdds::{DomainParticipant, DomainParticipantBuilder};

use crate::{Ros2Error, RosAction, RosMessage, RosService};

/// Which network interfaces the node's participant uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Network {
    /// 127.0.0.1 only, unicast discovery: processes of one machine.
    #[default]
    Loopback,
    /// Every interface, multicast discovery as well: a robot's network.
    All,
}

/// How to start a [`RosNode`].
#[derive(Clone, Debug)]
pub struct RosOptions {
    /// The DDS domain (`ROS_DOMAIN_ID`); 0 by default.
    pub domain_id: u16,
    /// The interfaces used.
    pub network: Network,
    /// How service and action requests carry their ids: it depends on the peer's
    /// middleware. `Enhanced` (the default) is `rmw_fastrtps`'s, ROS 2's default;
    /// `Cyclone` is `rmw_cyclonedds`'s.
    pub service_mapping: ServiceMapping,
}

impl Default for RosOptions {
    fn default() -> Self {
        Self {
            domain_id: 0,
            network: Network::Loopback,
            service_mapping: ServiceMapping::Enhanced,
        }
    }
}

impl RosOptions {
    /// Domain `domain_id` on 127.0.0.1 only.
    pub fn loopback(domain_id: u16) -> Self {
        Self {
            domain_id,
            ..Self::default()
        }
    }
}

/// ros2-client's client of action type `A`.
pub type RosActionClient<A> =
    ActionClient<<A as RosAction>::Goal, <A as RosAction>::Result, <A as RosAction>::Feedback>;

/// ros2-client's server of action type `A`.
pub type RosActionServer<A> =
    ActionServer<<A as RosAction>::Goal, <A as RosAction>::Result, <A as RosAction>::Feedback>;

/// ROS 2's default QoS for topics and services: reliable, volatile, the last 10 kept.
pub fn default_qos() -> QosProfile {
    QosProfile::publisher_default()
        .reliability_reliable(WhenFull::DEFAULT)
        .durability(Durability::Volatile)
        .history(History::KeepLast { depth: 10 })
}

/// A ROS 2 node for the bridge; cheap to clone, every clone is the same node.
///
/// ```no_run
/// use neurotree_ros2::{RosNode, RosOptions};
///
/// let node = RosNode::new("neurotree", &RosOptions::loopback(0)).unwrap();
/// assert_eq!(node.domain_id(), 0);
/// ```
#[derive(Clone)]
pub struct RosNode {
    inner: Arc<Inner>,
}

struct Inner {
    node: Mutex<ros2_client::Node>,
    name: NodeName,
    participant: DomainParticipant,
    service_mapping: ServiceMapping,
}

impl RosNode {
    /// Starts a participant on `options.domain_id` and a node named `name` in the root
    /// namespace.
    pub fn new(name: &str, options: &RosOptions) -> Result<Self, Ros2Error> {
        let fail = |message: String| Ros2Error::Node {
            node: name.to_owned(),
            message,
        };
        let mut builder = DomainParticipantBuilder::new(options.domain_id);
        if options.network == Network::Loopback {
            builder = builder.with_only_networks([IpAddr::V4(Ipv4Addr::LOCALHOST)]);
        }
        let participant = builder.build().map_err(|e| fail(e.to_string()))?;
        let context = Context::from_domain_participant(participant.clone())
            .map_err(|e| fail(e.to_string()))?;
        let node_name = NodeName::new("/", name).map_err(|e| fail(e.to_string()))?;
        let node = context
            .new_node(node_name.clone(), NodeOptions::new())
            .map_err(|e| fail(format!("{e:?}")))?;
        Ok(Self {
            inner: Arc::new(Inner {
                node: Mutex::new(node),
                name: node_name,
                participant,
                service_mapping: options.service_mapping,
            }),
        })
    }

    /// The DDS domain.
    pub fn domain_id(&self) -> u16 {
        self.inner.participant.domain_id()
    }

    /// The node's name, `/name`.
    pub fn name(&self) -> String {
        self.inner.name.fully_qualified_name()
    }

    fn node(&self) -> MutexGuard<'_, ros2_client::Node> {
        // A panic while the node was borrowed left nothing half-made: each use is one call.
        self.inner.node.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// `true` when another participant has a reader on the DDS topic `dds_topic`.
    pub(crate) fn has_remote_reader(&self, dds_topic: &str) -> bool {
        self.inner
            .participant
            .discovered_readers()
            .iter()
            .any(|r| r.subscription_topic_data.topic_name() == dds_topic)
    }

    /// The DDS topic name of ROS name `name` with `prefix` and `suffix` (`rq`, `Request`).
    pub(crate) fn dds_name(&self, name: &Name, prefix: &str, suffix: &str) -> String {
        name.to_dds_name(prefix, &self.inner.name, suffix)
    }

    /// A publisher on topic `topic` with ROS 2's default QoS.
    pub fn publisher<M: RosMessage>(&self, topic: &str) -> Result<Publisher<M>, Ros2Error> {
        let name = parse_name(topic)?;
        let fail = endpoint_error("publisher", topic);
        let mut node = self.node();
        let t = node
            .create_topic(&name, message_type::<M>(), &default_qos())
            .map_err(fail)?;
        node.create_publisher(&t, None).map_err(fail)
    }

    /// A subscription to topic `topic` with ROS 2's default QoS.
    pub fn subscription<M: RosMessage>(&self, topic: &str) -> Result<Subscription<M>, Ros2Error> {
        let name = parse_name(topic)?;
        let fail = endpoint_error("subscription", topic);
        let mut node = self.node();
        let t = node
            .create_topic(&name, message_type::<M>(), &default_qos())
            .map_err(fail)?;
        node.create_subscription(&t, None).map_err(fail)
    }

    /// A client of service `service`.
    pub fn service_client<S: RosService>(
        &self,
        service: &str,
    ) -> Result<Client<S::Request, S::Response>, Ros2Error> {
        let name = parse_name(service)?;
        let (package, type_name) = S::TYPE;
        self.node()
            .create_client(
                self.inner.service_mapping,
                &name,
                &ServiceTypeName::new(package, type_name),
                default_qos(),
                default_qos(),
            )
            .map_err(endpoint_error("service client", service))
    }

    /// A server of service `service`.
    pub fn service_server<S: RosService>(
        &self,
        service: &str,
    ) -> Result<Server<S::Request, S::Response>, Ros2Error> {
        let name = parse_name(service)?;
        let (package, type_name) = S::TYPE;
        self.node()
            .create_server(
                self.inner.service_mapping,
                &name,
                &ServiceTypeName::new(package, type_name),
                default_qos(),
                default_qos(),
            )
            .map_err(endpoint_error("service server", service))
    }

    /// A client of action `action`.
    pub fn action_client<A: RosAction>(
        &self,
        action: &str,
    ) -> Result<RosActionClient<A>, Ros2Error> {
        let name = parse_name(action)?;
        let (package, type_name) = A::TYPE;
        let qos = ActionClientQosPolicies {
            goal_service: default_qos(),
            result_service: default_qos(),
            cancel_service: default_qos(),
            feedback_subscription: default_qos(),
            status_subscription: default_qos(),
        };
        self.node()
            .create_action_client(
                self.inner.service_mapping,
                &name,
                &ActionTypeName::new(package, type_name),
                qos,
            )
            .map_err(endpoint_error("action client", action))
    }

    /// A server of action `action`.
    pub fn action_server<A: RosAction>(
        &self,
        action: &str,
    ) -> Result<RosActionServer<A>, Ros2Error> {
        let name = parse_name(action)?;
        let (package, type_name) = A::TYPE;
        let qos = ActionServerQosPolicies {
            goal_service: default_qos(),
            result_service: default_qos(),
            cancel_service: default_qos(),
            feedback_publisher: default_qos(),
            status_publisher: default_qos()
                .durability(Durability::TransientLocal)
                .history(History::KeepLast { depth: 1 }),
        };
        self.node()
            .create_action_server(
                self.inner.service_mapping,
                &name,
                &ActionTypeName::new(package, type_name),
                qos,
            )
            .map_err(endpoint_error("action server", action))
    }
}

/// A topic, service or action name: `chatter`, `/chatter` or `/ns/chatter`.
pub(crate) fn parse_name(text: &str) -> Result<Name, Ros2Error> {
    let absolute = if text.starts_with('/') {
        text.to_owned()
    } else {
        format!("/{text}")
    };
    Name::parse(&absolute).map_err(|e| Ros2Error::Name {
        name: text.to_owned(),
        message: format!("{e:?}"),
    })
}

fn message_type<M: RosMessage>() -> MessageTypeName {
    let (package, type_name) = M::TYPE;
    MessageTypeName::new(package, type_name)
}

fn endpoint_error<'n, E: std::fmt::Debug>(
    kind: &'static str,
    name: &'n str,
) -> impl Fn(E) -> Ros2Error + Copy + 'n {
    move |e| Ros2Error::Endpoint {
        kind,
        name: name.to_owned(),
        message: format!("{e:?}"),
    }
}
