//! Nav2's cancel nodes over ROS 2: CancelControl, CancelSpin, CancelBackUp,
//! CancelDriveOnHeading, CancelWait, CancelAssistedTeleop, CancelComputeAndTrackRoute and
//! CancelFollowObject, each asking its action server to cancel every goal.
//!
//! As Nav2's `BtCancelActionNode`: the tick from Idle sends the server a request to cancel
//! all its goals (a zero goal id and stamp), once the server is discovered (within
//! `wait_for_server_timeout`): Running until the server answers, then Success; no server,
//! or no answer within `server_timeout`: Failure (the reason in `error_msg`). The
//! action goes by `action_name`, as the other ROS 2 leaves name it (Nav2's `server_name` is
//! declared and not read). The cancelled goal's own node then ends with Success, as Nav2's
//! `on_cancelled`.

use std::time::{Duration, Instant};

use neurotree_toolkit::{Handle, PortSpec, Registry, RegistryError, StatefulAction, Status};
use ros2_client::service::RmwRequestId;

use crate::msg::nav2_msgs::{
    AssistedTeleop, BackUp, ComputeAndTrackRoute, DriveOnHeading, FollowObject, FollowPath, Spin,
    Wait,
};
use crate::nodes::{client_ports, deadline, report, ClientPorts, ServerPresence};
use crate::ros_node::parse_name;
use crate::{RosAction, RosActionClient, RosNode};

/// Registers the eight cancel nodes on `ros`. Fails if one of the names is taken.
pub fn register_cancel_nodes<C: 'static>(
    registry: &mut Registry<C>,
    ros: &RosNode,
) -> Result<(), RegistryError> {
    register::<C, FollowPath>(registry, "CancelControl", ros, "follow_path")?;
    register::<C, Spin>(registry, "CancelSpin", ros, "spin")?;
    register::<C, BackUp>(registry, "CancelBackUp", ros, "backup")?;
    register::<C, DriveOnHeading>(registry, "CancelDriveOnHeading", ros, "drive_on_heading")?;
    register::<C, Wait>(registry, "CancelWait", ros, "wait")?;
    register::<C, AssistedTeleop>(registry, "CancelAssistedTeleop", ros, "assisted_teleop")?;
    register::<C, ComputeAndTrackRoute>(
        registry,
        "CancelComputeAndTrackRoute",
        ros,
        "compute_and_track_route",
    )?;
    register::<C, FollowObject>(registry, "CancelFollowObject", ros, "follow_object")
}

fn register<C: 'static, A: RosAction>(
    registry: &mut Registry<C>,
    type_name: &str,
    ros: &RosNode,
    default_name: &'static str,
) -> Result<(), RegistryError> {
    let ros = ros.clone();
    let mut ports = vec![PortSpec::input::<String>("server_name")
        .describe("Nav2's name port (unused: `action_name`).")];
    ports.extend(client_ports("action_name", default_name));
    registry.register_stateful(type_name, ports, move || {
        CancelAll::<A>::new(ros.clone(), default_name)
    })?;
    registry.describe(
        type_name,
        &format!("Asks the action server `{default_name}` to cancel all its goals."),
    );
    Ok(())
}

/// Where a cancel node's run is.
enum Phase {
    Idle,
    /// Waiting for the server to be discovered, until the first instant; then the answer
    /// may take the duration.
    WaitingForServer(Instant, Duration),
    /// The request sent, and when the answer is due.
    Sent(RmwRequestId, Instant),
}

/// The node's client: the action's name, the DDS topic the server's cancel service reads,
/// whether the server was seen, and the client.
struct Client<A: RosAction> {
    name: String,
    cancel_topic: String,
    presence: ServerPresence,
    client: RosActionClient<A>,
}

/// A cancel node: see the [module documentation](self).
struct CancelAll<A: RosAction> {
    ros: RosNode,
    default_name: &'static str,
    client: Option<Client<A>>,
    phase: Phase,
}

impl<A: RosAction> CancelAll<A> {
    /// A node whose client is made now, so that it finds its server before the first tick.
    fn new(ros: RosNode, default_name: &'static str) -> Self {
        let mut node = Self {
            ros,
            default_name,
            client: None,
            phase: Phase::Idle,
        };
        let _ = node.client(default_name);
        node
    }

    fn client(&mut self, name: &str) -> Result<(), String> {
        if self.client.as_ref().is_none_or(|c| c.name != name) {
            let client = self
                .ros
                .action_client::<A>(name)
                .map_err(|e| e.to_string())?;
            let ros_name = parse_name(name).map_err(|e| e.to_string())?;
            self.client = Some(Client {
                name: name.to_owned(),
                cancel_topic: self
                    .ros
                    .dds_name(&ros_name, "rq", "/_action/cancel_goalRequest"),
                presence: ServerPresence::default(),
                client,
            });
        }
        Ok(())
    }

    fn fail<C>(&mut self, h: &mut Handle<'_, C>, reason: String) -> Status {
        self.phase = Phase::Idle;
        report(h, reason);
        Status::Failure
    }

    /// One step of the run.
    fn step<C>(&mut self, h: &mut Handle<'_, C>) -> Status {
        let Some(client) = &mut self.client else {
            return self.fail(h, "no client".into());
        };
        match std::mem::replace(&mut self.phase, Phase::Idle) {
            Phase::Idle => Status::Failure,
            Phase::WaitingForServer(until, answer_within) => {
                let discovered = self.ros.has_remote_reader(&client.cancel_topic);
                if !client.presence.ready(discovered) {
                    if Instant::now() >= until {
                        let name = client.name.clone();
                        return self.fail(h, format!("no server of `{name}` was discovered"));
                    }
                    self.phase = Phase::WaitingForServer(until, answer_within);
                    return Status::Running;
                }
                match client.client.cancel_all_goals() {
                    Ok(request) => {
                        self.phase = Phase::Sent(request, deadline(answer_within));
                        Status::Running
                    }
                    Err(e) => {
                        let name = client.name.clone();
                        self.fail(h, format!("cannot ask `{name}` to cancel: {e:?}"))
                    }
                }
            }
            Phase::Sent(request, due) => match client.client.receive_cancel_response(request) {
                Ok(Some(_)) => Status::Success,
                _ if Instant::now() >= due => {
                    let name = client.name.clone();
                    self.fail(
                        h,
                        format!("`{name}` did not answer the cancel request in time"),
                    )
                }
                _ => {
                    self.phase = Phase::Sent(request, due);
                    Status::Running
                }
            },
        }
    }
}

impl<C: 'static, A: RosAction> StatefulAction<C> for CancelAll<A> {
    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        let ports = match ClientPorts::read(h, "action_name", self.default_name) {
            Ok(ports) => ports,
            Err(e) => return self.fail(h, e.to_string()),
        };
        if let Err(e) = self.client(&ports.name) {
            return self.fail(h, e);
        }
        self.phase = Phase::WaitingForServer(
            deadline(ports.wait_for_server_timeout),
            ports.server_timeout,
        );
        self.step(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.step(h)
    }

    fn on_halted(&mut self, _h: &mut Handle<'_, C>) {
        self.phase = Phase::Idle;
    }

    /// Between its runs the node keeps nothing a restored tree needs; while its cancel
    /// request is on its way, the tree cannot be saved until it is answered.
    fn save_state(&self) -> Option<Vec<u8>> {
        matches!(self.phase, Phase::Idle).then(Vec::new)
    }
}
