//! `RosTopicSubNode`: a ROS 2 subscription as a condition (BehaviorTree.ROS2's
//! `RosTopicSubNode`).
//!
//! Each tick takes every message that arrived since the last one (each one to
//! [`SubscriberSpec::on_message`]) and calls [`SubscriberSpec::on_tick`] with the newest,
//! or with `None` when none came; its answer is the node's status (Success or Failure for
//! a condition; an action spec may answer Running).
//!
//! [`LatestMessage`] is the spec most trees want: it writes the newest message to the
//! `message` port and succeeds once any message has arrived.

use std::marker::PhantomData;

use neurotree_toolkit::{
    Category, Handle, PortSpec, Registry, RegistryError, StatefulAction, Status,
};
use ros2_client::Subscription;

use super::input_or;
use crate::{RosMessage, RosNode};

/// What a subscriber node makes of its topic: BehaviorTree.ROS2's `onTick`.
pub trait SubscriberSpec<C>: Send + 'static {
    /// The message type.
    type Message: RosMessage;

    /// The node's own ports, besides `topic_name`.
    fn ports() -> Vec<PortSpec>
    where
        Self: Sized,
    {
        Vec::new()
    }

    /// Each message that arrived since the last tick, oldest first, before
    /// [`on_tick`](Self::on_tick): for a spec that follows every message (a history), not
    /// only the newest. Nothing by default.
    fn on_message(&mut self, _message: &Self::Message) {}

    /// The node's status, given the newest message since the last tick (`None`: none came).
    fn on_tick(&mut self, h: &mut Handle<'_, C>, latest: Option<&Self::Message>) -> Status;
}

/// Writes the newest message to output port `message`; Success once a message has arrived
/// (the last one is written again on ticks that bring none), Failure before.
pub struct LatestMessage<M> {
    last: Option<M>,
}

impl<M> Default for LatestMessage<M> {
    fn default() -> Self {
        Self { last: None }
    }
}

impl<C, M: RosMessage> SubscriberSpec<C> for LatestMessage<M> {
    type Message = M;

    fn ports() -> Vec<PortSpec> {
        vec![PortSpec::output::<M>("message").describe("the newest message")]
    }

    fn on_tick(&mut self, h: &mut Handle<'_, C>, latest: Option<&M>) -> Status {
        if let Some(message) = latest {
            self.last = Some(message.clone());
        }
        match &self.last {
            Some(message) => {
                // An unbound `message` port is the user's choice to only test for traffic.
                let _ = h.output("message", message.clone());
                Status::Success
            }
            None => Status::Failure,
        }
    }
}

/// A ROS 2 subscription as a condition; see the [module](self) for its semantics.
pub struct RosTopicSubNode<C, S: SubscriberSpec<C>> {
    ros: RosNode,
    /// The port that names the topic: `topic_name`, or another name a library gives it.
    name_port: &'static str,
    default_name: String,
    spec: S,
    subscription: Option<(String, Subscription<S::Message>)>,
    _context: PhantomData<fn(&mut C)>,
}

impl<C: 'static, S: SubscriberSpec<C>> RosTopicSubNode<C, S> {
    /// A node on `ros` whose `topic_name` defaults to `default_name`; it subscribes now, so
    /// that messages published before the first tick are kept.
    pub fn new(ros: RosNode, default_name: &str, spec: S) -> Self {
        let mut node = Self {
            ros,
            name_port: "topic_name",
            default_name: default_name.to_owned(),
            spec,
            subscription: None,
            _context: PhantomData,
        };
        let _ = node.subscribe(default_name);
        node
    }

    /// The same node reading the topic's name from port `name_port` instead of
    /// `topic_name`, as Nav2's battery conditions name it `battery_topic`.
    pub fn with_name_port(mut self, name_port: &'static str) -> Self {
        self.name_port = name_port;
        self
    }

    /// The ports the node reads: the spec's and `topic_name`.
    pub fn ports(default_name: &str) -> Vec<PortSpec> {
        let mut ports = S::ports();
        ports.push(
            PortSpec::input::<String>("topic_name")
                .default_value(default_name)
                .describe("the ROS 2 topic"),
        );
        ports
    }

    /// Registers the node type `type_name` for XML, as a condition.
    pub fn register<F>(
        registry: &mut Registry<C>,
        type_name: &str,
        ros: &RosNode,
        default_name: &str,
        make: F,
    ) -> Result<(), RegistryError>
    where
        F: Fn() -> S + Send + Sync + 'static,
    {
        let ros = ros.clone();
        let name = default_name.to_owned();
        registry.register_stateful_as(
            type_name,
            Category::Condition,
            Self::ports(default_name),
            move || Self::new(ros.clone(), &name, make()),
        )
    }

    fn subscribe(&mut self, topic: &str) -> Result<(), crate::Ros2Error> {
        if self.subscription.as_ref().is_none_or(|(t, _)| t != topic) {
            self.subscription = Some((topic.to_owned(), self.ros.subscription(topic)?));
        }
        Ok(())
    }

    fn tick(&mut self, h: &mut Handle<'_, C>) -> Status {
        let topic = match input_or(h, self.name_port, self.default_name.clone()) {
            Ok(topic) => topic,
            Err(_) => return Status::Failure,
        };
        if self.subscribe(&topic).is_err() {
            return Status::Failure;
        }
        let Some((_, subscription)) = &self.subscription else {
            return Status::Failure;
        };
        let mut latest = None;
        // A read error is a message lost, not a reason to stop reading the next ones.
        while let Ok(Some((message, _))) = subscription.take() {
            self.spec.on_message(&message);
            latest = Some(message);
        }
        self.spec.on_tick(h, latest.as_ref())
    }
}

impl<C: 'static, S: SubscriberSpec<C>> StatefulAction<C> for RosTopicSubNode<C, S> {
    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.tick(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.tick(h)
    }

    /// The messages it read are the world's, not the tree's: a restored node reads the
    /// topic afresh.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(Vec::new())
    }
}
