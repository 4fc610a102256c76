//! SpeedController: tick the child at a rate that grows with the robot's speed.

use std::time::Duration;

use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeStatus};

use super::goals::SeenGoals;
use neurotree_core::nodes::semantics::{first, Order, Semantics, Statuses};

/// SpeedController's semantics: its child's statuses, and RUNNING while it waits.
pub const SEMANTICS: Semantics =
    Semantics::new(Order::again(Statuses::ANY, Statuses::ANY), |_, c| {
        first(c).or(Statuses::RUNNING).or(Statuses::FAILURE)
    });

/// The blackboard entry the SpeedController reads the robot's speed from.
pub const ROBOT_SPEED: &str = "robot_speed";

/// SpeedController: tick the child at a rate between `min_rate` and `max_rate`, scaled by the
/// robot's speed between `min_speed` and `max_speed`, as Nav2's `speed_controller.cpp`
/// does.
///
/// Ports `min_rate` (0.1), `max_rate` (1.0), `min_speed` (0.0), `max_speed` (0.5), `goal`
/// and `goals` (read as the [goal nodes](super#goals) read them).
///
/// Nav2 reads the speed from its odometry smoother; here it is the blackboard entry
/// `robot_speed` ([`ROBOT_SPEED`]), an `f64` in m/s (Nav2's `hypot` of the linear twist)
/// that the world writes. Without that entry the speed is 0, as a smoother that has had
/// no odometry gives, so under `neurotree run` the child is ticked at `min_rate`.
///
/// - On the tick from Idle, and whenever `goal` or `goals` changed: the period is
///   `1/max_rate`, restarted now, and the child is ticked this tick.
/// - Otherwise the child is ticked while it is Running or once the period has elapsed;
///   when it has, the next period is `1/rate` for the rate the current speed gives, from
///   now. Else Running without ticking the child.
///
/// The child's status passes through, and a completed child is reset. A rate that is not
/// above 0 is an error of the tick (Nav2 throws when it builds the node). The rates are
/// read on the tick from Idle; Nav2 reads them once, when the node is built.
#[derive(Debug, Default)]
pub struct SpeedController {
    seen: SeenGoals,
    rates: Rates,
    /// Seconds from `start` to the next tick of the child.
    period: f64,
    start: Duration,
    first: bool,
}

/// The four bounds of a [`SpeedController`].
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
struct Rates {
    min_rate: f64,
    max_rate: f64,
    min_speed: f64,
    max_speed: f64,
}

impl Rates {
    /// Nav2's `getScaledRate`: the rate for `speed`, linear between the bounds and clamped.
    fn scaled(&self, speed: f64) -> f64 {
        let d_rate = self.max_rate - self.min_rate;
        let d_speed = self.max_speed - self.min_speed;
        let rate = ((speed - self.min_speed) / d_speed) * d_rate + self.min_rate;
        rate.min(self.max_rate).max(self.min_rate)
    }
}

impl SpeedController {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder).
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "SpeedController",
            Arity::One,
            Box::new(|| Box::new(SpeedController::default())),
        )
    }

    fn read_rates<C>(node: &mut NodeCtx<'_, '_, C>) -> Option<Rates> {
        let rates = Rates {
            min_rate: super::port_or(node, "min_rate", 0.1)?,
            max_rate: super::port_or(node, "max_rate", 1.0)?,
            min_speed: super::port_or(node, "min_speed", 0.0)?,
            max_speed: super::port_or(node, "max_speed", 0.5)?,
        };
        if rates.min_rate <= 0.0 || rates.max_rate <= 0.0 {
            node.fail("SpeedController node cannot have rate <= 0.0");
            return None;
        }
        Some(rates)
    }

    fn restart(&mut self, now: Duration) {
        self.period = 1.0 / self.rates.max_rate;
        self.start = now;
        self.first = true;
    }
}

impl<C> CustomNode<C> for SpeedController {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(
            &self.seen,
            self.rates,
            self.period,
            self.start,
            self.first,
        )))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(seen, rates, period, start, first)| {
                self.seen = seen;
                self.rates = rates;
                self.period = period;
                self.start = start;
                self.first = first;
            })
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        node.reset_completed_children_after_tick();
        if !node.previous_status().is_active() {
            let Some(rates) = Self::read_rates(node) else {
                return NodeStatus::Failure;
            };
            self.rates = rates;
            if let Err(e) = self.seen.remember(node) {
                node.fail(e);
                return NodeStatus::Failure;
            }
            self.restart(node.now());
        }
        match self.seen.update(node) {
            Ok(true) => self.restart(node.now()),
            Ok(false) => {}
            Err(e) => {
                node.fail(e);
                return NodeStatus::Failure;
            }
        }
        node.set_running();
        let elapsed = node.now().saturating_sub(self.start).as_secs_f64();
        let due = elapsed >= self.period;
        if !(self.first || due || node.child_status(0) == NodeStatus::Running) {
            return NodeStatus::Running;
        }
        self.first = false;
        if due {
            let speed = match super::goals::entry_owned::<C, f64>(node, ROBOT_SPEED) {
                Ok(speed) => speed.unwrap_or(0.0),
                Err(e) => {
                    node.fail(e);
                    return NodeStatus::Failure;
                }
            };
            self.period = 1.0 / self.rates.scaled(speed.abs());
            self.start = node.now();
        }
        node.tick_child(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rate_is_linear_in_the_speed_and_clamped() {
        let rates = Rates {
            min_rate: 0.1,
            max_rate: 1.0,
            min_speed: 0.0,
            max_speed: 0.5,
        };
        assert!((rates.scaled(0.25) - 0.55).abs() < 1e-12);
        assert_eq!(rates.scaled(0.0), 0.1);
        assert_eq!(rates.scaled(3.0), 1.0);
        assert_eq!(rates.scaled(-1.0), 0.1);
    }
}
