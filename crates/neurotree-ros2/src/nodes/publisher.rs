//! `RosTopicPubNode`: a ROS 2 publisher as an action (BehaviorTree.ROS2's
//! `RosTopicPubNode`).
//!
//! Each tick asks [`PublisherSpec::message`] for a message and publishes it: Success once
//! written, Failure when there is no message or the write fails. The node never runs.
//! Like any DDS publisher's, a message written before a subscriber is discovered reaches no
//! one: publishing is not delivery.

use std::marker::PhantomData;

use neurotree_toolkit::{Handle, PortSpec, Registry, RegistryError, StatefulAction, Status};
use ros2_client::Publisher;

use super::{input_or, report};
use crate::{RosMessage, RosNode};

/// What a publisher node sends: BehaviorTree.ROS2's `setMessage`.
pub trait PublisherSpec<C>: Send + 'static {
    /// The message type.
    type Message: RosMessage;

    /// The node's own ports, besides `topic_name` and `error_msg`.
    fn ports() -> Vec<PortSpec>
    where
        Self: Sized,
    {
        Vec::new()
    }

    /// The message to publish, from the ports; an error fails the node.
    fn message(&mut self, h: &mut Handle<'_, C>) -> Result<Self::Message, String>;
}

/// A ROS 2 publisher as an action; see the [module](self) for its semantics.
pub struct RosTopicPubNode<C, S: PublisherSpec<C>> {
    ros: RosNode,
    default_name: String,
    spec: S,
    publisher: Option<(String, Publisher<S::Message>)>,
    _context: PhantomData<fn(&mut C)>,
}

impl<C: 'static, S: PublisherSpec<C>> RosTopicPubNode<C, S> {
    /// A node on `ros` whose `topic_name` defaults to `default_name`; it makes its publisher
    /// now, so that subscribers are discovered before the first tick.
    pub fn new(ros: RosNode, default_name: &str, spec: S) -> Self {
        let mut node = Self {
            ros,
            default_name: default_name.to_owned(),
            spec,
            publisher: None,
            _context: PhantomData,
        };
        let _ = node.advertise(default_name);
        node
    }

    /// The ports the node reads: the spec's, `topic_name` and `error_msg`.
    pub fn ports(default_name: &str) -> Vec<PortSpec> {
        let mut ports = S::ports();
        ports.push(
            PortSpec::input::<String>("topic_name")
                .default_value(default_name)
                .describe("the ROS 2 topic"),
        );
        ports.push(PortSpec::output::<String>("error_msg").describe("why the node last failed"));
        ports
    }

    /// Registers the node type `type_name` for XML.
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
        registry.register_stateful(type_name, Self::ports(default_name), move || {
            Self::new(ros.clone(), &name, make())
        })
    }

    fn advertise(&mut self, topic: &str) -> Result<(), crate::Ros2Error> {
        if self.publisher.as_ref().is_none_or(|(t, _)| t != topic) {
            self.publisher = Some((topic.to_owned(), self.ros.publisher(topic)?));
        }
        Ok(())
    }

    fn publish(&mut self, h: &mut Handle<'_, C>) -> Result<(), String> {
        let topic =
            input_or(h, "topic_name", self.default_name.clone()).map_err(|e| e.to_string())?;
        self.advertise(&topic).map_err(|e| e.to_string())?;
        let message = self.spec.message(h)?;
        let Some((_, publisher)) = &self.publisher else {
            return Err("no publisher".to_owned());
        };
        publisher
            .publish(message)
            .map_err(|e| format!("cannot publish on `{topic}`: {e:?}"))
    }
}

impl<C: 'static, S: PublisherSpec<C>> StatefulAction<C> for RosTopicPubNode<C, S> {
    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        match self.publish(h) {
            Ok(()) => Status::Success,
            Err(reason) => {
                report(h, reason);
                Status::Failure
            }
        }
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.on_start(h)
    }

    /// A publication is done within its tick: nothing is kept between ticks.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(Vec::new())
    }
}
