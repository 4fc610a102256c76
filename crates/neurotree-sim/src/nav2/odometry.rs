//! What the robot's motion says: IsStuck, DistanceTraveled, TimeExpired, CheckStopStatus,
//! TransformAvailable and InitialPoseReceived.
//!
//! Nav2 reads the robot's pose from TF and its speed from odometry; here they are the
//! world's pose and the speed and turn rate over the last step
//! ([`Nav2Sim::robot_speed`](crate::nav2::Nav2Sim::robot_speed),
//! [`Nav2Sim::turn_rate`](crate::nav2::Nav2Sim::turn_rate),
//! [`Nav2Sim::acceleration`](crate::nav2::Nav2Sim::acceleration)).
//!
//! - **IsStuck**: a condition, no ports. Success when the robot slowed down faster than
//!   10 m/s² over the last step (Nav2's `brake_accel_limit` of -10), else Failure, as
//!   `is_stuck_condition.cpp` judges the last two odometry messages.
//! - **DistanceTraveled**: a condition. Ports `distance` (default 1.0), `global_frame`,
//!   `robot_base_frame`. As `distance_traveled_condition.cpp`: on the tick from Idle it
//!   reads `distance`, remembers the robot's pose: Failure. Later: Failure while the robot
//!   is less than `distance` (straight line) from that pose; else it remembers the new pose:
//!   Success.
//! - **TimeExpired**: a condition. Port `seconds` (default 1.0). As
//!   `time_expired_condition.cpp`: on the tick from Idle it reads `seconds`, starts its
//!   timer: Failure. Later: Failure until `seconds` have passed, then Success and the
//!   timer starts again.
//! - **CheckStopStatus**: an action. Ports `velocity_threshold` (default 0.01),
//!   `duration_stopped` (ms, default 1000). As `check_stop_status_action.cpp`: while the
//!   speed and the turn rate are both under the threshold, Running until the robot has been
//!   still for more than `duration_stopped`, then Success (and the count starts again);
//!   moving: Failure. The time it has been still is kept across halts, as Nav2 keeps it in
//!   the node.
//! - **TransformAvailable**: a condition. Ports `child`, `parent`. On the tick from Idle
//!   either frame empty is an error of the tick, as Nav2's node throws. The simulated
//!   robot's transforms are always there: Success (remembered, as Nav2 does).
//! - **InitialPoseReceived**: a condition. Port `initial_pose_received`, or the blackboard
//!   entry of that name when the port is not given (Nav2's `getInputOrBlackboard`): Success
//!   when it is true; absent or false: Failure.

use std::time::Duration;

use neurotree_core::{
    Arity, Category, CustomNode, Handle, NodeCtx, NodeStatus, StatefulAction, Status,
};

use super::{ports, Nav2Context};
use neurotree_nav2::robotics::Pose2D;
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

/// Nav2's `brake_accel_limit`, in m/s².
const BRAKE_ACCEL_LIMIT: f64 = -10.0;

fn frame(name: &str) -> PortSpec {
    PortSpec::input::<String>(name).describe("Frame name (unused: the world has one frame).")
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    register_pose_and_clock(r)?;
    r.register_condition("IsStuck", vec![], |h: &Handle<'_, C>| {
        h.ctx().nav2().acceleration() < BRAKE_ACCEL_LIMIT
    })?;
    r.describe(
        "IsStuck",
        "Succeeds when the robot braked harder than 10 m/s².",
    );
    r.register_stateful(
        "CheckStopStatus",
        vec![
            PortSpec::input::<f64>("velocity_threshold")
                .default_value("0.01")
                .describe("Speed (m/s, rad/s) under which the robot counts as still."),
            PortSpec::input::<u64>("duration_stopped")
                .default_value("1000")
                .describe("Milliseconds the robot must be still."),
        ],
        CheckStopStatus::default,
    )?;
    r.describe(
        "CheckStopStatus",
        "Runs while the robot is still, succeeds once it was still for `duration_stopped`.",
    );
    Ok(())
}

/// DistanceTraveled, TimeExpired, TransformAvailable and InitialPoseReceived: they read only
/// the robot's pose, the clock and the blackboard, so a navigator whose world is elsewhere
/// (over ROS 2) has them too.
pub(super) fn register_pose_and_clock<C: Nav2Context>(
    r: &mut Registry<C>,
) -> Result<(), RegistryError> {
    r.register_custom_as(
        "DistanceTraveled",
        Category::Condition,
        Arity::Leaf,
        vec![
            PortSpec::input::<f64>("distance")
                .default_value("1.0")
                .describe("Metres after which it succeeds."),
            frame("global_frame"),
            frame("robot_base_frame"),
        ],
        || Box::new(DistanceTraveled::default()),
    )?;
    r.describe(
        "DistanceTraveled",
        "Succeeds each time the robot is `distance` from where it last succeeded.",
    );
    r.register_custom_as(
        "TimeExpired",
        Category::Condition,
        Arity::Leaf,
        vec![PortSpec::input::<f64>("seconds")
            .default_value("1.0")
            .describe("Seconds after which it succeeds.")],
        || Box::new(TimeExpired::default()),
    )?;
    r.describe("TimeExpired", "Succeeds each time `seconds` have passed.");
    r.register_custom_as(
        "TransformAvailable",
        Category::Condition,
        Arity::Leaf,
        vec![
            PortSpec::input::<String>("child")
                .default_value("")
                .describe("The child frame."),
            PortSpec::input::<String>("parent")
                .default_value("")
                .describe("The parent frame."),
        ],
        || Box::new(TransformAvailable::default()),
    )?;
    r.describe(
        "TransformAvailable",
        "Succeeds when the transform between two frames is known (always, here).",
    );
    r.register_condition(
        "InitialPoseReceived",
        vec![PortSpec::input::<bool>("initial_pose_received")
            .describe("Whether the initial pose was received.")],
        |h: &Handle<'_, C>| initial_pose_received(h),
    )?;
    r.describe(
        "InitialPoseReceived",
        "Succeeds when `initial_pose_received` is true.",
    );
    Ok(())
}

/// DistanceTraveled: see the [module documentation](self).
#[derive(Debug, Default)]
struct DistanceTraveled {
    distance: f64,
    start: Pose2D,
}

impl<C: Nav2Context> CustomNode<C> for DistanceTraveled {
    /// The distance and the pose it counts from, as the tick from Idle read them.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(self.distance, self.start)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(distance, start)| (self.distance, self.start) = (distance, start))
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let robot = node.ctx().nav2().world.robot();
        if !node.previous_status().is_active() {
            match ports::absent_as_none(node.input::<f64>("distance")) {
                Ok(distance) => self.distance = distance.unwrap_or(1.0),
                Err(e) => {
                    node.fail(e.to_string());
                    return NodeStatus::Failure;
                }
            }
            self.start = robot;
            return NodeStatus::Failure;
        }
        if robot.distance(&self.start) < self.distance {
            return NodeStatus::Failure;
        }
        self.start = robot;
        NodeStatus::Success
    }
}

/// TimeExpired: see the [module documentation](self).
#[derive(Debug, Default)]
struct TimeExpired {
    period: f64,
    start: Duration,
}

impl<C: Nav2Context> CustomNode<C> for TimeExpired {
    /// The period and the timer's start, on the tree's clock (which a rewind sets back
    /// with the world).
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(self.period, self.start)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(period, start)| (self.period, self.start) = (period, start))
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let now = node.now();
        if !node.previous_status().is_active() {
            match ports::absent_as_none(node.input::<f64>("seconds")) {
                Ok(seconds) => self.period = seconds.unwrap_or(1.0),
                Err(e) => {
                    node.fail(e.to_string());
                    return NodeStatus::Failure;
                }
            }
            self.start = now;
            return NodeStatus::Failure;
        }
        if now.saturating_sub(self.start).as_secs_f64() < self.period {
            return NodeStatus::Failure;
        }
        self.start = now;
        NodeStatus::Success
    }
}

/// CheckStopStatus: see the [module documentation](self).
#[derive(Debug, Default)]
struct CheckStopStatus {
    /// When the robot was first seen still, while it stays still.
    still_since: Option<Duration>,
}

impl<C: Nav2Context> StatefulAction<C> for CheckStopStatus {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&self.still_since))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode::<Option<Duration>>(state)
            .map(|saved| self.still_since = saved)
            .is_some()
    }

    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        let read = ports::or(h, "velocity_threshold", 0.01)
            .and_then(|t| Ok((t, ports::or(h, "duration_stopped", 1000_u64)?)));
        let Ok((threshold, stopped_ms)) = read else {
            return Status::Failure;
        };
        let sim = h.ctx().nav2();
        let still = sim.robot_speed().abs() < threshold && sim.turn_rate().abs() < threshold;
        if !still {
            self.still_since = None;
            return Status::Failure;
        }
        let now = h.now();
        let since = *self.still_since.get_or_insert(now);
        if now.saturating_sub(since) > Duration::from_millis(stopped_ms) {
            self.still_since = None;
            Status::Success
        } else {
            Status::Running
        }
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.on_start(h)
    }
}

/// TransformAvailable: see the [module documentation](self).
#[derive(Debug, Default)]
struct TransformAvailable {
    found: bool,
}

impl<C: Nav2Context> CustomNode<C> for TransformAvailable {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&self.found))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|found| self.found = found)
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        if !node.previous_status().is_active() {
            let child = node.input::<String>("child").unwrap_or_default();
            let parent = node.input::<String>("parent").unwrap_or_default();
            if child.is_empty() || parent.is_empty() {
                node.fail(format!(
                    "TransformAvailable: child frame `{child}` or parent frame `{parent}` is empty"
                ));
                return NodeStatus::Failure;
            }
        }
        self.found = true;
        NodeStatus::Success
    }
}

/// InitialPoseReceived: see the [module documentation](self).
fn initial_pose_received<C>(h: &Handle<'_, C>) -> bool {
    match ports::optional::<bool, C>(h, "initial_pose_received") {
        Ok(Some(received)) => received,
        Ok(None) => h.get::<bool>("initial_pose_received").unwrap_or(false),
        Err(_) => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::{watched, Bench};
    use Status::{Failure as F, Running as R, Success as S};

    /// Ticks, stepping the world after each.
    fn ticks(b: &mut Bench, n: usize) -> Vec<Status> {
        (0..n)
            .map(|_| {
                let s = b.tick();
                b.sim.step();
                s
            })
            .collect()
    }

    #[test]
    fn time_expired_succeeds_once_its_period_passed_and_starts_again_from_idle() {
        let mut b = Bench::new("R", &watched(r#"<TimeExpired seconds="0.3"/>"#));
        // From Idle at 0 s: Failure; 0.1 s, 0.2 s: Failure; 0.3 s: Success. The tree's
        // Success resets it: from Idle again at 0.4 s.
        assert_eq!(ticks(&mut b, 8), [R, R, R, S, R, R, R, S]);
        // Alone, the root's reset makes every tick a tick from Idle.
        let mut b = Bench::new("R", r#"<TimeExpired seconds="0.3"/>"#);
        assert_eq!(ticks(&mut b, 5), [F, F, F, F, F]);
    }

    #[test]
    fn distance_traveled_succeeds_every_metre() {
        let mut b = Bench::new("R.....", &watched(r#"<DistanceTraveled distance="1.0"/>"#));
        let path = b
            .sim
            .world
            .plan(b.sim.world.robot(), Pose2D::new(5.5, 0.5, 0.0))
            .unwrap();
        b.sim.world.follow(path, 0.5);
        // 0.05 m per step: a metre after 20 steps, seen at tick 21 (index 20); the tree's
        // Success resets it, so tick 22 starts counting again from there.
        let run = ticks(&mut b, 45);
        let successes: Vec<usize> = run
            .iter()
            .enumerate()
            .filter(|(_, s)| **s == S)
            .map(|(i, _)| i)
            .collect();
        // (Twenty more steps, and a rounding hair.)
        assert_eq!(successes, [20, 42]);
    }

    #[test]
    fn check_stop_status_runs_while_still_and_fails_when_moving() {
        let mut b = Bench::new(
            "R.....",
            r#"<CheckStopStatus velocity_threshold="0.1" duration_stopped="250"/>"#,
        );
        // Still from the start: more than 250 ms at the fourth tick (300 ms).
        assert_eq!(ticks(&mut b, 5), [R, R, R, S, R]);
        let path = b
            .sim
            .world
            .plan(b.sim.world.robot(), Pose2D::new(5.5, 0.5, 0.0))
            .unwrap();
        b.sim.world.follow(path, 1.0);
        b.sim.step();
        assert_eq!(b.tick(), F);
        // Spinning is moving too.
        b.sim.world.spin(3.0, 1.0);
        b.sim.step();
        assert_eq!(b.tick(), F);
    }

    #[test]
    fn is_stuck_when_braking_harder_than_ten_metres_per_second_squared() {
        let mut b = Bench::new("R..#..", r#"<IsStuck/>"#);
        assert_eq!(b.tick(), F);
        let path = b
            .sim
            .world
            .plan(b.sim.world.robot(), Pose2D::new(2.5, 0.5, 0.0))
            .unwrap();
        // 1.5 m/s for a step, then still: -15 m/s².
        b.sim.world.follow(path, 1.5);
        b.sim.step();
        assert_eq!(b.tick(), F);
        b.sim.world.stop();
        b.sim.step();
        assert_eq!(b.tick(), S);
        b.sim.step();
        assert_eq!(b.tick(), F);
    }

    #[test]
    fn transforms_are_available_unless_a_frame_is_empty() {
        let mut b = Bench::new(
            "R",
            r#"<TransformAvailable child="base_link" parent="map"/>"#,
        );
        assert_eq!(b.tick(), S);
        let mut b = Bench::new("R", r#"<TransformAvailable child="base_link"/>"#);
        let error = b.tree.tick_once(&mut b.sim).unwrap_err();
        assert!(error.to_string().contains("is empty"), "{error}");
    }

    #[test]
    fn the_initial_pose_is_read_from_the_port_or_the_entry_of_its_name() {
        let mut b = Bench::new("R", r#"<InitialPoseReceived/>"#);
        assert_eq!(b.tick(), F);
        b.set("initial_pose_received", true);
        assert_eq!(b.tick(), S);
        let mut b = Bench::new(
            "R",
            r#"<InitialPoseReceived initial_pose_received="{got}"/>"#,
        );
        b.set("initial_pose_received", true);
        b.set("got", false);
        assert_eq!(b.tick(), F);
    }
}
