//! `RosActionNode`: a ROS 2 action client as a leaf (BehaviorTree.ROS2's `RosActionNode`).
//!
//! | tick | what happens | status |
//! |---|---|---|
//! | from Idle | reads the ports, asks the [`ActionSpec`] for the goal | Failure (`InvalidGoal`) if it has none |
//! | while the server is not discovered | waits up to `wait_for_server_timeout` (and [`DISCOVERY_SETTLE`](super::DISCOVERY_SETTLE) after the first discovery) | Running, then Failure (`ServerUnreachable`) |
//! | server discovered | sends the goal, waits up to `server_timeout` for the answer | Running, then Failure (`SendGoalTimeout`) |
//! | goal rejected | | Failure (`GoalRejected`) |
//! | goal accepted | asks for the result; each feedback goes to `on_feedback` | Running, or what `on_feedback` returns (the goal is then cancelled) |
//! | goal running, and [`ActionSpec::updated_goal`] gives a new one | sends it in the running goal's place, waits for its acceptance | Running |
//! | result | Succeeded → `on_result`; Aborted / Canceled → `on_failure` | their status |
//! | halted while Running | sends a cancel request for the goal | (Idle) |
//!
//! Every failure goes through [`ActionSpec::on_failure`] (Failure by default) and its reason
//! is written to the `error_msg` port when bound. The tick never waits on the network: each
//! tick polls the client's readers and compares deadlines.
//!
//! ```no_run
//! use neurotree_ros2::msg::{builtin_interfaces::Duration, nav2_msgs};
//! use neurotree_ros2::{ActionSpec, RosActionNode, RosNode, RosOptions};
//! use neurotree_toolkit::{Handle, PortSpec, Registry, Status};
//!
//! /// Nav2's Wait: the `wait_duration` port, in seconds.
//! struct Wait;
//! impl ActionSpec<()> for Wait {
//!     type Action = nav2_msgs::Wait;
//!     fn ports() -> Vec<PortSpec> {
//!         vec![PortSpec::input::<f64>("wait_duration").default_value("1.0")]
//!     }
//!     fn goal(&mut self, h: &mut Handle<'_, ()>) -> Result<nav2_msgs::WaitGoal, String> {
//!         let secs: f64 = h.input("wait_duration").map_err(|e| e.to_string())?;
//!         Ok(nav2_msgs::WaitGoal { time: std::time::Duration::from_secs_f64(secs).into() })
//!     }
//!     fn on_result(&mut self, _h: &mut Handle<'_, ()>, _r: &nav2_msgs::WaitResult) -> Status {
//!         Status::Success
//!     }
//! }
//!
//! let ros = RosNode::new("bt", &RosOptions::loopback(0)).unwrap();
//! let mut registry = Registry::<()>::new();
//! RosActionNode::register(&mut registry, "Wait", &ros, "wait", || Wait).unwrap();
//! ```

use std::fmt;
use std::time::{Duration, Instant};

use neurotree_toolkit::{Handle, PortSpec, Registry, RegistryError, StatefulAction, Status};
use ros2_client::action::{GoalId, GoalStatusEnum};
use ros2_client::service::RmwRequestId;

use super::{client_ports, deadline, report, ClientPorts, ServerPresence};
use crate::ros_node::{parse_name, RosActionClient};
use crate::{RosAction, RosNode};

type Goal<S, C> = <<S as ActionSpec<C>>::Action as RosAction>::Goal;
type Outcome<S, C> = <<S as ActionSpec<C>>::Action as RosAction>::Result;

/// What an action node does with its action: BehaviorTree.ROS2's `setGoal`,
/// `onFeedback`, `onResultReceived` and `onFailure`.
pub trait ActionSpec<C>: Send + 'static {
    /// The action type.
    type Action: RosAction;

    /// The node's own ports, besides `action_name`, `server_timeout`,
    /// `wait_for_server_timeout` and `error_msg`.
    fn ports() -> Vec<PortSpec>
    where
        Self: Sized,
    {
        Vec::new()
    }

    /// The goal to send, from the ports; an error fails the node (`InvalidGoal`).
    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<<Self::Action as RosAction>::Goal, String>;

    /// A feedback arrived: Running to go on, Success or Failure to end the node now (the
    /// goal is then cancelled).
    fn on_feedback(
        &mut self,
        _h: &mut Handle<'_, C>,
        _feedback: &<Self::Action as RosAction>::Feedback,
    ) -> Status {
        Status::Running
    }

    /// The goal succeeded with `result`: the node's status.
    fn on_result(
        &mut self,
        h: &mut Handle<'_, C>,
        result: &<Self::Action as RosAction>::Result,
    ) -> Status;

    /// While the goal runs, at each tick: a goal to send in its place when the ports now ask
    /// for another one (Nav2's `on_wait_for_result` setting `goal_updated_`); the server
    /// then preempts the running goal. `None`, the default, goes on with it.
    fn updated_goal(
        &mut self,
        _h: &mut Handle<'_, C>,
    ) -> Option<<Self::Action as RosAction>::Goal> {
        None
    }

    /// The node was halted while it ran (its goal, if sent, is then cancelled). Nothing by
    /// default.
    fn on_halt(&mut self, _h: &mut Handle<'_, C>) {}

    /// The node failed for `error`; `result` is the server's when it aborted or cancelled
    /// the goal. Failure by default.
    fn on_failure(
        &mut self,
        _h: &mut Handle<'_, C>,
        _error: &ActionError,
        _result: Option<&<Self::Action as RosAction>::Result>,
    ) -> Status {
        Status::Failure
    }
}

/// Why an action node failed (BehaviorTree.ROS2's `ActionNodeErrorCode`).
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ActionError {
    /// No server was discovered within `wait_for_server_timeout`.
    ServerUnreachable {
        /// The action name.
        action: String,
        /// How long the node waited.
        waited: Duration,
    },
    /// The server did not answer the goal within `server_timeout`.
    SendGoalTimeout {
        /// The action name.
        action: String,
        /// How long the node waited.
        waited: Duration,
    },
    /// The server rejected the goal.
    GoalRejected {
        /// The action name.
        action: String,
    },
    /// The server aborted the goal.
    Aborted {
        /// The action name.
        action: String,
    },
    /// The goal was cancelled, by someone else than this node.
    Canceled {
        /// The action name.
        action: String,
    },
    /// [`ActionSpec::goal`] gave no goal.
    InvalidGoal(String),
    /// A port could not be read, or the client could not be made or used.
    Client(String),
}

impl fmt::Display for ActionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::ServerUnreachable { action, waited } => {
                write!(f, "action server `{action}` not found within {waited:?}")
            }
            Self::SendGoalTimeout { action, waited } => {
                write!(
                    f,
                    "action server `{action}` did not answer the goal within {waited:?}"
                )
            }
            Self::GoalRejected { action } => {
                write!(f, "action server `{action}` rejected the goal")
            }
            Self::Aborted { action } => write!(f, "action server `{action}` aborted the goal"),
            Self::Canceled { action } => write!(f, "the goal of `{action}` was cancelled"),
            Self::InvalidGoal(reason) => write!(f, "no goal to send: {reason}"),
            Self::Client(reason) => write!(f, "action client: {reason}"),
        }
    }
}

/// An action client per node instance: replies are read by request id, and a client shared
/// by two nodes would take the other's replies off its readers.
struct Client<A: RosAction> {
    name: String,
    /// The DDS topic the server's goal reader is on: its presence is the server's.
    goal_topic: String,
    presence: ServerPresence,
    client: RosActionClient<A>,
}

/// Where a run of the node is.
enum Phase<G> {
    Idle,
    WaitingForServer {
        goal: G,
        since: Instant,
        until: Instant,
    },
    WaitingForAcceptance {
        goal_id: GoalId,
        request: RmwRequestId,
        since: Instant,
        until: Instant,
    },
    Executing {
        goal_id: GoalId,
        result_request: RmwRequestId,
    },
}

/// A ROS 2 action client as a [`StatefulAction`]; see the [module](self) for its semantics.
pub struct RosActionNode<C, S: ActionSpec<C>> {
    ros: RosNode,
    default_name: String,
    spec: S,
    client: Option<Client<S::Action>>,
    phase: Phase<Goal<S, C>>,
    server_timeout: Duration,
}

impl<C: 'static, S: ActionSpec<C>> RosActionNode<C, S> {
    /// A node on `ros` whose `action_name` defaults to `default_name`.
    ///
    /// The client for `default_name` is made now, so that discovery runs before the first
    /// tick; a failure here is met again, and reported, on that tick.
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

    /// The ports the node reads: the spec's and the client's, `action_name` defaulting to
    /// `default_name`.
    pub fn ports(default_name: &str) -> Vec<PortSpec> {
        let mut ports = S::ports();
        ports.extend(client_ports("action_name", default_name));
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

    /// The client for action `name`, made on first use or when the name changed.
    fn client(&mut self, name: &str) -> Result<&Client<S::Action>, ActionError> {
        if self.client.as_ref().is_none_or(|c| c.name != name) {
            let client = self
                .ros
                .action_client::<S::Action>(name)
                .map_err(|e| ActionError::Client(e.to_string()))?;
            let ros_name = parse_name(name).map_err(|e| ActionError::Client(e.to_string()))?;
            self.client = Some(Client {
                name: name.to_owned(),
                goal_topic: self
                    .ros
                    .dds_name(&ros_name, "rq", "/_action/send_goalRequest"),
                presence: ServerPresence::default(),
                client,
            });
        }
        // Set just above when it was absent or stale.
        self.client
            .as_ref()
            .ok_or_else(|| ActionError::Client("no client".to_owned()))
    }

    /// Ends the run with `error`.
    fn fail(
        &mut self,
        h: &mut Handle<'_, C>,
        error: ActionError,
        result: Option<&Outcome<S, C>>,
    ) -> Status {
        self.phase = Phase::Idle;
        report(h, error.to_string());
        self.spec.on_failure(h, &error, result)
    }

    /// One step of the run: what this tick's polling finds.
    fn step(&mut self, h: &mut Handle<'_, C>) -> Status {
        match std::mem::replace(&mut self.phase, Phase::Idle) {
            Phase::Idle => Status::Failure,
            Phase::WaitingForServer { goal, since, until } => {
                self.wait_for_server(h, goal, since, until)
            }
            Phase::WaitingForAcceptance {
                goal_id,
                request,
                since,
                until,
            } => self.wait_for_acceptance(h, goal_id, request, since, until),
            Phase::Executing {
                goal_id,
                result_request,
            } => self.execute(h, goal_id, result_request),
        }
    }

    fn wait_for_server(
        &mut self,
        h: &mut Handle<'_, C>,
        goal: Goal<S, C>,
        since: Instant,
        until: Instant,
    ) -> Status {
        let Some(client) = &mut self.client else {
            return Status::Failure;
        };
        let discovered = self.ros.has_remote_reader(&client.goal_topic);
        if !client.presence.ready(discovered) {
            if Instant::now() >= until {
                let error = ActionError::ServerUnreachable {
                    action: client.name.clone(),
                    waited: since.elapsed(),
                };
                return self.fail(h, error, None);
            }
            self.phase = Phase::WaitingForServer { goal, since, until };
            return Status::Running;
        }
        match client.client.send_goal(goal) {
            Ok((request, goal_id)) => {
                self.phase = Phase::WaitingForAcceptance {
                    goal_id,
                    request,
                    since: Instant::now(),
                    until: deadline(self.server_timeout),
                };
                Status::Running
            }
            Err(e) => {
                let error = ActionError::Client(format!("cannot send the goal: {e:?}"));
                self.fail(h, error, None)
            }
        }
    }

    fn wait_for_acceptance(
        &mut self,
        h: &mut Handle<'_, C>,
        goal_id: GoalId,
        request: RmwRequestId,
        since: Instant,
        until: Instant,
    ) -> Status {
        let Some(client) = &self.client else {
            return Status::Failure;
        };
        let action = client.name.clone();
        match client.client.receive_goal_response(request) {
            Ok(Some(response)) if response.accepted => {
                match client.client.request_result(goal_id) {
                    Ok(result_request) => {
                        self.phase = Phase::Executing {
                            goal_id,
                            result_request,
                        };
                        Status::Running
                    }
                    Err(e) => {
                        let error =
                            ActionError::Client(format!("cannot ask for the result: {e:?}"));
                        self.fail(h, error, None)
                    }
                }
            }
            Ok(Some(_)) => self.fail(h, ActionError::GoalRejected { action }, None),
            Ok(None) if Instant::now() >= until => {
                // The goal may still be accepted later: withdraw it.
                let _ = client.client.cancel_goal(goal_id);
                let waited = since.elapsed();
                self.fail(h, ActionError::SendGoalTimeout { action, waited }, None)
            }
            Ok(None) => {
                self.phase = Phase::WaitingForAcceptance {
                    goal_id,
                    request,
                    since,
                    until,
                };
                Status::Running
            }
            Err(e) => {
                let error = ActionError::Client(format!("cannot read the goal response: {e:?}"));
                self.fail(h, error, None)
            }
        }
    }

    fn execute(
        &mut self,
        h: &mut Handle<'_, C>,
        goal_id: GoalId,
        result_request: RmwRequestId,
    ) -> Status {
        let Some(client) = &self.client else {
            return Status::Failure;
        };
        let action = client.name.clone();
        // Feedback first: a result ends the run, and feedback sent before it still counts.
        loop {
            match client.client.receive_feedback(goal_id) {
                Ok(Some(feedback)) => {
                    let status = self.spec.on_feedback(h, &feedback);
                    if status != Status::Running {
                        let _ = client.client.cancel_goal(goal_id);
                        return status;
                    }
                }
                Ok(None) => break,
                Err(e) => {
                    let error = ActionError::Client(format!("cannot read feedback: {e:?}"));
                    return self.fail(h, error, None);
                }
            }
        }
        if let Some(goal) = self.spec.updated_goal(h) {
            return match client.client.send_goal(goal) {
                Ok((request, goal_id)) => {
                    self.phase = Phase::WaitingForAcceptance {
                        goal_id,
                        request,
                        since: Instant::now(),
                        until: deadline(self.server_timeout),
                    };
                    Status::Running
                }
                Err(e) => {
                    let error = ActionError::Client(format!("cannot send the new goal: {e:?}"));
                    self.fail(h, error, None)
                }
            };
        }
        match client.client.receive_result(result_request) {
            Ok(None) => {
                self.phase = Phase::Executing {
                    goal_id,
                    result_request,
                };
                Status::Running
            }
            Ok(Some((GoalStatusEnum::Succeeded, result))) => self.spec.on_result(h, &result),
            Ok(Some((GoalStatusEnum::Canceled, result))) => {
                self.fail(h, ActionError::Canceled { action }, Some(&result))
            }
            Ok(Some((_, result))) => self.fail(h, ActionError::Aborted { action }, Some(&result)),
            Err(e) => {
                let error = ActionError::Client(format!("cannot read the result: {e:?}"));
                self.fail(h, error, None)
            }
        }
    }
}

impl<C: 'static, S: ActionSpec<C>> StatefulAction<C> for RosActionNode<C, S> {
    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        let ports = match ClientPorts::read(h, "action_name", &self.default_name) {
            Ok(ports) => ports,
            Err(e) => return self.fail(h, ActionError::Client(e.to_string()), None),
        };
        if let Err(error) = self.client(&ports.name) {
            return self.fail(h, error, None);
        }
        let goal = match self.spec.goal(h) {
            Ok(goal) => goal,
            Err(reason) => return self.fail(h, ActionError::InvalidGoal(reason), None),
        };
        self.server_timeout = ports.server_timeout;
        self.phase = Phase::WaitingForServer {
            goal,
            since: Instant::now(),
            until: deadline(ports.wait_for_server_timeout),
        };
        self.step(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.step(h)
    }

    fn on_halted(&mut self, h: &mut Handle<'_, C>) {
        self.spec.on_halt(h);
        let goal_id = match std::mem::replace(&mut self.phase, Phase::Idle) {
            Phase::WaitingForAcceptance { goal_id, .. } | Phase::Executing { goal_id, .. } => {
                goal_id
            }
            Phase::Idle | Phase::WaitingForServer { .. } => return,
        };
        if let Some(client) = &self.client {
            // Fire and forget: the tree does not wait for the server to confirm.
            let _ = client.client.cancel_goal(goal_id);
        }
    }

    /// Between its runs the node keeps nothing a restored tree needs (its client is made
    /// again); while a goal is on its way or on the server, the goal lives there, where no
    /// saved state can reach it: the tree cannot be saved until the run ends.
    fn save_state(&self) -> Option<Vec<u8>> {
        matches!(self.phase, Phase::Idle).then(Vec::new)
    }
}

impl<C, S: ActionSpec<C>> fmt::Debug for RosActionNode<C, S> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RosActionNode")
            .field("default_name", &self.default_name)
            .finish_non_exhaustive()
    }
}
