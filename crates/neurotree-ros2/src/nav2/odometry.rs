//! Nav2's odometry nodes over ROS 2: IsStuck and CheckStopStatus, each subscribed to the
//! robot's odometry (`odom`, `nav_msgs/msg/Odometry`; port `topic_name`, which Nav2's
//! nodes do not have: they read the navigator's `odom` subscription).
//!
//! - **IsStuck** (a condition, no ports), as Nav2's `is_stuck_condition.cpp`: from the
//!   third message on, each message gives the acceleration since the one before (the
//!   change of `twist.linear.x` over the change of stamp); Success while the last one was
//!   a harder deceleration than the brake limit, -10 m/s², Failure otherwise.
//! - **CheckStopStatus** (an action), as Nav2's `check_stop_status_action.cpp` reading the
//!   newest odometry: a twist with `linear.x`, `linear.y` and `angular.z` all below
//!   `velocity_threshold` (default 0.01) is stopped; the first stopped reading is stamped,
//!   and the node is Running until it has been stopped for more than `duration_stopped` ms
//!   (default 1000), then Success (and the stamp is forgotten). A reading of motion: Failure.
//!   Before any message the twist is zero, as Nav2's odometry smoother's is. Nav2 takes
//!   "now" from the node's clock, on which (with `use_sim_time`) the odometry is stamped;
//!   this node has no `/clock`, so the newest reading's stamp is its "now", and an
//!   unstamped reading is stamped with the tree's clock, as Nav2 stamps one with its own
//!   (a stopped time counted on one of the two clocks starts again on the other).
//!
//! [`SimServers`](super::SimServers) publishes the world's odometry on [`ODOM_TOPIC`],
//! stamped with the simulated time.

use std::collections::VecDeque;
use std::time::Duration;

use neurotree_toolkit::{Category, Handle, PortSpec, Registry, RegistryError, Status};

use crate::msg::nav_msgs::Odometry;
use crate::nodes::subscriber::SubscriberSpec;
use crate::{RosNode, RosTopicSubNode};

/// Where Nav2's odometry readers listen.
pub const ODOM_TOPIC: &str = "odom";

/// Registers IsStuck (a condition) and CheckStopStatus (an action) as subscribers of
/// [`ODOM_TOPIC`] on `ros`. Fails if one of the names is taken.
pub fn register_odometry_conditions<C: 'static>(
    registry: &mut Registry<C>,
    ros: &RosNode,
) -> Result<(), RegistryError> {
    let node = ros.clone();
    registry.register_stateful_as(
        "IsStuck",
        Category::Condition,
        RosTopicSubNode::<C, Stuck>::ports(ODOM_TOPIC),
        move || RosTopicSubNode::new(node.clone(), ODOM_TOPIC, Stuck::default()),
    )?;
    registry.describe(
        "IsStuck",
        "Succeeds while the odometry last said the robot braked harder than 10 m/s².",
    );
    let node = ros.clone();
    registry.register_stateful_as(
        "CheckStopStatus",
        Category::Action,
        RosTopicSubNode::<C, StopStatus>::ports(ODOM_TOPIC),
        move || RosTopicSubNode::new(node.clone(), ODOM_TOPIC, StopStatus::default()),
    )?;
    registry.describe(
        "CheckStopStatus",
        "Running while the odometry says the robot stands still, Success once it has for `duration_stopped` ms.",
    );
    Ok(())
}

/// Seconds of a message's stamp.
fn stamp_secs(odometry: &Odometry) -> f64 {
    let stamp = odometry.header.stamp;
    f64::from(stamp.sec) + f64::from(stamp.nanosec) * 1e-9
}

fn is_unstamped(odometry: &Odometry) -> bool {
    odometry.header.stamp.sec == 0 && odometry.header.stamp.nanosec == 0
}

/// Nav2's `odom_history_size_`.
const HISTORY: usize = 10;
/// Nav2's `brake_accel_limit_`, in m/s².
const BRAKE_ACCEL_LIMIT: f64 = -10.0;

/// IsStuck: see the [module documentation](self).
#[derive(Default)]
struct Stuck {
    history: VecDeque<Odometry>,
    acceleration: f64,
    stuck: bool,
}

impl<C> SubscriberSpec<C> for Stuck {
    type Message = Odometry;

    fn on_message(&mut self, message: &Odometry) {
        while self.history.len() >= HISTORY {
            self.history.pop_front();
        }
        self.history.push_back(message.clone());
        let n = self.history.len();
        if n > 2 {
            let (previous, current) = (&self.history[n - 2], &self.history[n - 1]);
            let dt = stamp_secs(current) - stamp_secs(previous);
            let dv = current.twist.twist.linear.x - previous.twist.twist.linear.x;
            self.acceleration = dv / dt;
        }
        self.stuck = self.acceleration < BRAKE_ACCEL_LIMIT;
    }

    fn on_tick(&mut self, _h: &mut Handle<'_, C>, _latest: Option<&Odometry>) -> Status {
        if self.stuck {
            Status::Success
        } else {
            Status::Failure
        }
    }
}

/// CheckStopStatus: see the [module documentation](self).
#[derive(Default)]
struct StopStatus {
    /// The newest reading, stamped (in seconds).
    newest: Option<(Odometry, f64)>,
    /// When the robot was first read stopped, in seconds, and whether on the stamps'
    /// clock (else the tree's).
    stopped_since: Option<(f64, bool)>,
}

impl<C> SubscriberSpec<C> for StopStatus {
    type Message = Odometry;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<f64>("velocity_threshold")
                .default_value("0.01")
                .describe("The speed under which the robot counts as stopped."),
            PortSpec::input::<u64>("duration_stopped")
                .default_value("1000")
                .describe("Milliseconds the robot must stay stopped."),
        ]
    }

    fn on_tick(&mut self, h: &mut Handle<'_, C>, latest: Option<&Odometry>) -> Status {
        let threshold = h.input::<f64>("velocity_threshold").unwrap_or(0.01);
        let needed = Duration::from_millis(h.input::<u64>("duration_stopped").unwrap_or(1000));
        let clock = h.now().as_secs_f64();
        if let Some(message) = latest {
            let stamp = if is_unstamped(message) {
                clock
            } else {
                stamp_secs(message)
            };
            self.newest = Some((message.clone(), stamp));
        }
        let (twist, stamp, now, stamped) = match &self.newest {
            // An unstamped reading's time is the tree's: "now" goes on with the clock.
            Some((m, stamp)) if is_unstamped(m) => (m.twist.twist, *stamp, clock, false),
            Some((m, stamp)) => (m.twist.twist, *stamp, *stamp, true),
            None => (Default::default(), clock, clock, false),
        };
        let still = twist.linear.x.abs() < threshold
            && twist.linear.y.abs() < threshold
            && twist.angular.z.abs() < threshold;
        if !still {
            self.stopped_since = None;
            return Status::Failure;
        }
        // Two clocks cannot be compared: a reading on the other one starts the count again.
        if self.stopped_since.is_some_and(|(_, on)| on != stamped) {
            self.stopped_since = None;
        }
        let (since, _) = *self.stopped_since.get_or_insert((stamp, stamped));
        if now - since > needed.as_secs_f64() {
            self.stopped_since = None;
            Status::Success
        } else {
            Status::Running
        }
    }
}
