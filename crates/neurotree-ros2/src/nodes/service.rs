//! `RosServiceNode`: a ROS 2 service client as a leaf (BehaviorTree.ROS2's `RosServiceNode`).
//!
//! | tick | what happens | status |
//! |---|---|---|
//! | from Idle | reads the ports, asks the [`ServiceSpec`] for the request | Failure (`InvalidRequest`) if it has none |
//! | while the server is not discovered | waits up to `wait_for_server_timeout` (and [`DISCOVERY_SETTLE`](super::DISCOVERY_SETTLE) after the first discovery) | Running, then Failure (`ServerUnreachable`) |
//! | server discovered | sends the request, waits up to `server_timeout` | Running, then Failure (`TimedOut`) |
//! | response | `on_response` | its status |
//! | halted while Running | forgets the request (a service call cannot be cancelled) | (Idle) |
//!
//! Failures go through [`ServiceSpec::on_failure`] (Failure by default), their reason to the
//! `error_msg` port when bound.

use std::fmt;
use std::time::{Duration, Instant};

use neurotree_toolkit::{Handle, PortSpec, Registry, RegistryError, StatefulAction, Status};
use ros2_client::service::{Client, RmwRequestId};

use super::{client_ports, deadline, report, ClientPorts, ServerPresence};
use crate::ros_node::parse_name;
use crate::{RosNode, RosService};

type Request<S, C> = <<S as ServiceSpec<C>>::Service as RosService>::Request;

/// What a service node does with its service: BehaviorTree.ROS2's `setRequest`,
/// `onResponseReceived` and `onFailure`.
pub trait ServiceSpec<C>: Send + 'static {
    /// The service type.
    type Service: RosService;

    /// The node's own ports, besides `service_name`, `server_timeout`,
    /// `wait_for_server_timeout` and `error_msg`.
    fn ports() -> Vec<PortSpec>
    where
        Self: Sized,
    {
        Vec::new()
    }

    /// The request to send, from the ports; an error fails the node (`InvalidRequest`).
    fn request(
        &mut self,
        h: &mut Handle<'_, C>,
    ) -> Result<<Self::Service as RosService>::Request, String>;

    /// The response arrived: the node's status.
    fn on_response(
        &mut self,
        h: &mut Handle<'_, C>,
        response: &<Self::Service as RosService>::Response,
    ) -> Status;

    /// The node failed for `error`. Failure by default.
    fn on_failure(&mut self, _h: &mut Handle<'_, C>, _error: &ServiceError) -> Status {
        Status::Failure
    }
}

/// Why a service node failed (BehaviorTree.ROS2's `ServiceNodeErrorCode`).
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ServiceError {
    /// No server was discovered within `wait_for_server_timeout`.
    ServerUnreachable {
        /// The service name.
        service: String,
        /// How long the node waited.
        waited: Duration,
    },
    /// No response within `server_timeout`.
    TimedOut {
        /// The service name.
        service: String,
        /// How long the node waited.
        waited: Duration,
    },
    /// [`ServiceSpec::request`] gave no request.
    InvalidRequest(String),
    /// A port could not be read, or the client could not be made or used.
    Client(String),
}

impl fmt::Display for ServiceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::ServerUnreachable { service, waited } => {
                write!(f, "service `{service}` not found within {waited:?}")
            }
            Self::TimedOut { service, waited } => {
                write!(f, "service `{service}` did not answer within {waited:?}")
            }
            Self::InvalidRequest(reason) => write!(f, "no request to send: {reason}"),
            Self::Client(reason) => write!(f, "service client: {reason}"),
        }
    }
}

struct ServiceClient<S: RosService> {
    name: String,
    /// The DDS topic the server's request reader is on: its presence is the server's.
    request_topic: String,
    presence: ServerPresence,
    client: Client<S::Request, S::Response>,
}

enum Phase<R> {
    Idle,
    WaitingForServer {
        request: R,
        since: Instant,
        until: Instant,
    },
    WaitingForResponse {
        id: RmwRequestId,
        since: Instant,
        until: Instant,
    },
}

/// A ROS 2 service client as a [`StatefulAction`]; see the [module](self) for its semantics.
pub struct RosServiceNode<C, S: ServiceSpec<C>> {
    ros: RosNode,
    default_name: String,
    spec: S,
    client: Option<ServiceClient<S::Service>>,
    phase: Phase<Request<S, C>>,
    server_timeout: Duration,
}

impl<C: 'static, S: ServiceSpec<C>> RosServiceNode<C, S> {
    /// A node on `ros` whose `service_name` defaults to `default_name`; its client is made
    /// now so that discovery runs before the first tick.
    pub fn new(ros: RosNode, default_name: &str, spec: S) -> Self {
        let mut node = Self {
            ros,
            default_name: default_name.to_owned(),
            spec,
            client: None,
            phase: Phase::Idle,
            server_timeout: Duration::ZERO,
        };
        let _ = node.client(default_name);
        node
    }

    /// The ports the node reads: the spec's and the client's.
    pub fn ports(default_name: &str) -> Vec<PortSpec> {
        let mut ports = S::ports();
        ports.extend(client_ports("service_name", default_name));
        ports
    }

    /// Registers the node type `type_name` for XML: one node per instance, made by `make`.
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

    fn client(&mut self, name: &str) -> Result<(), ServiceError> {
        if self.client.as_ref().is_none_or(|c| c.name != name) {
            let client = self
                .ros
                .service_client::<S::Service>(name)
                .map_err(|e| ServiceError::Client(e.to_string()))?;
            let ros_name = parse_name(name).map_err(|e| ServiceError::Client(e.to_string()))?;
            self.client = Some(ServiceClient {
                name: name.to_owned(),
                request_topic: self.ros.dds_name(&ros_name, "rq", "Request"),
                presence: ServerPresence::default(),
                client,
            });
        }
        Ok(())
    }

    fn fail(&mut self, h: &mut Handle<'_, C>, error: ServiceError) -> Status {
        self.phase = Phase::Idle;
        report(h, error.to_string());
        self.spec.on_failure(h, &error)
    }

    fn step(&mut self, h: &mut Handle<'_, C>) -> Status {
        let Some(client) = &mut self.client else {
            return Status::Failure;
        };
        let service = client.name.clone();
        match std::mem::replace(&mut self.phase, Phase::Idle) {
            Phase::Idle => Status::Failure,
            Phase::WaitingForServer {
                request,
                since,
                until,
            } => {
                let discovered = self.ros.has_remote_reader(&client.request_topic);
                if !client.presence.ready(discovered) {
                    if Instant::now() >= until {
                        let waited = since.elapsed();
                        return self.fail(h, ServiceError::ServerUnreachable { service, waited });
                    }
                    self.phase = Phase::WaitingForServer {
                        request,
                        since,
                        until,
                    };
                    return Status::Running;
                }
                match client.client.send_request(request) {
                    Ok(id) => {
                        self.phase = Phase::WaitingForResponse {
                            id,
                            since: Instant::now(),
                            until: deadline(self.server_timeout),
                        };
                        Status::Running
                    }
                    Err(e) => {
                        let error = ServiceError::Client(format!("cannot send the request: {e:?}"));
                        self.fail(h, error)
                    }
                }
            }
            Phase::WaitingForResponse { id, since, until } => loop {
                match client.client.receive_response() {
                    Ok(Some((answered, response))) if answered == id => {
                        break self.spec.on_response(h, &response);
                    }
                    // A late answer to a request this node has given up on.
                    Ok(Some(_)) => continue,
                    Ok(None) if Instant::now() >= until => {
                        let waited = since.elapsed();
                        break self.fail(h, ServiceError::TimedOut { service, waited });
                    }
                    Ok(None) => {
                        self.phase = Phase::WaitingForResponse { id, since, until };
                        break Status::Running;
                    }
                    Err(e) => {
                        let error =
                            ServiceError::Client(format!("cannot read the response: {e:?}"));
                        break self.fail(h, error);
                    }
                }
            },
        }
    }
}

impl<C: 'static, S: ServiceSpec<C>> StatefulAction<C> for RosServiceNode<C, S> {
    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        let ports = match ClientPorts::read(h, "service_name", &self.default_name) {
            Ok(ports) => ports,
            Err(e) => return self.fail(h, ServiceError::Client(e.to_string())),
        };
        if let Err(error) = self.client(&ports.name) {
            return self.fail(h, error);
        }
        let request = match self.spec.request(h) {
            Ok(request) => request,
            Err(reason) => return self.fail(h, ServiceError::InvalidRequest(reason)),
        };
        self.server_timeout = ports.server_timeout;
        self.phase = Phase::WaitingForServer {
            request,
            since: Instant::now(),
            until: deadline(ports.wait_for_server_timeout),
        };
        self.step(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.step(h)
    }

    fn on_halted(&mut self, _h: &mut Handle<'_, C>) {
        self.phase = Phase::Idle;
    }

    /// Between its calls the node keeps nothing a restored tree needs; while a request is
    /// on its way to the server, the tree cannot be saved until the call ends.
    fn save_state(&self) -> Option<Vec<u8>> {
        matches!(self.phase, Phase::Idle).then(Vec::new)
    }
}
