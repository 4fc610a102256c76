//! RateController: let the child start again at most `hz` times per second.

use std::time::Duration;

use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeStatus};

use super::port_or;
use neurotree_core::nodes::semantics::{first, Order, Semantics, Statuses};

/// RateController's semantics: its child's statuses, and RUNNING while it waits.
pub const SEMANTICS: Semantics =
    Semantics::new(Order::again(Statuses::ANY, Statuses::ANY), |l, c| {
        let read = Statuses::FAILURE.when(l.text("hz").is_none());
        first(c).or(Statuses::RUNNING).or(read)
    });

/// RateController: let the child start again at most `hz` times per second.
///
/// Port `hz` (default 10).
///
/// - On the tick from Idle, start a period timer and tick the child at once.
/// - Later: tick the child if it is Running or the period has elapsed since the last child
///   Success; otherwise return Running without ticking it.
/// - Child Success restarts the timer.
///
/// The period is `1/hz` seconds on the tree's [`Clock`](neurotree_toolkit::Clock), read from
/// `hz` on the tick from Idle. The child's status passes through, and a completed child is
/// reset, so that the next period starts it afresh. As in Nav2, `hz = 0` makes the period
/// endless (the child runs once per run of the node) and a negative `hz` makes it always
/// elapsed.
///
/// "Later" needs a parent that keeps the completed node as it is: a PipelineSequence does,
/// which is how Nav2 replans at a fixed rate while the path is followed. A parent that resets
/// the node after each Success (a Sequence that completes, a root) starts a new run, and a
/// new run ticks the child at once.
#[derive(Debug, Default)]
pub struct RateController {
    /// Time from one start of the child to the next; `None` never elapses.
    period: Option<Duration>,
    /// When the current period began: the run's first tick, or the child's last Success.
    since: Duration,
    /// The run's first tick is under way: tick the child whatever the time.
    first: bool,
}

impl RateController {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder); bind `hz` with `.ports(..)`
    /// first thing in the child closure (10 when left out).
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "RateController",
            Arity::One,
            Box::new(|| Box::new(RateController::default())),
        )
    }
}

/// The period of a rate, as Nav2 computes it (`1/hz` seconds): zero or NaN never elapses,
/// a negative rate always has, a rate so small that its period overflows never elapses.
fn period_of(hz: f64) -> Option<Duration> {
    if hz < 0.0 {
        return Some(Duration::ZERO);
    }
    if hz.is_nan() || hz == 0.0 {
        return None;
    }
    Duration::try_from_secs_f64(1.0 / hz).ok()
}

impl<C> CustomNode<C> for RateController {
    /// The period too: it is read from `hz` on the tick from Idle only, so a node restored
    /// while running would otherwise never let its child start again.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(
            self.period,
            self.since,
            self.first,
        )))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(period, since, first)| {
                self.period = period;
                self.since = since;
                self.first = first;
            })
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        if !node.previous_status().is_active() {
            let Some(hz) = port_or(node, "hz", 10.0) else {
                return NodeStatus::Failure;
            };
            self.period = period_of(hz);
            self.since = node.now();
            self.first = true;
        }
        // Nav2's `setStatus(RUNNING)` before the child ticks.
        node.set_running();
        let elapsed = node.now().saturating_sub(self.since);
        let due = self.period.is_some_and(|period| elapsed >= period);
        if !(self.first || due || node.child_status(0) == NodeStatus::Running) {
            return NodeStatus::Running;
        }
        self.first = false;
        let status = node.tick_child(0);
        if status == NodeStatus::Success {
            self.since = node.now();
        }
        if status.is_completed() {
            node.reset_children();
        }
        status
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::*;
    use crate::PipelineSequence;

    /// PipelineSequence(RateController(leaf 0), leaf 1): the controller keeps its status
    /// while leaf 1 runs, as in Nav2's navigators.
    fn replanning(lab: &Lab, hz: Option<&str>) -> Tree<Lab> {
        lab.tree(|b| {
            b.custom("navigate", PipelineSequence::spec(), |p| {
                p.custom("rate", RateController::spec(), |r| match hz {
                    Some(hz) => r.ports([Port::literal("hz", hz)]).scripted(0),
                    None => r.scripted(0),
                })
                .scripted(1)
            })
        })
    }

    #[test]
    fn ticks_the_child_at_once_then_once_per_period() {
        // 10 Hz by default: every 100 ms.
        let mut lab = Lab::new(&[&[S], &[R]]);
        let mut tree = replanning(&lab, None);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 1]);
        assert_eq!(tree.status(NodeId(1)), S);
        lab.advance(ms(50));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 2]);
        lab.advance(ms(50));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2, 3]);
        lab.advance(ms(99));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2, 4]);
        lab.advance(ms(1));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [3, 5]);
        assert_eq!(lab.halts, [0, 0]);
    }

    #[test]
    fn reads_the_rate_from_its_port() {
        let mut lab = Lab::new(&[&[S], &[R]]);
        let mut tree = replanning(&lab, Some("2"));
        assert_eq!(lab.tick(&mut tree), R);
        lab.advance(ms(499));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 2]);
        lab.advance(ms(1));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2, 3]);
    }

    #[test]
    fn a_running_child_is_ticked_every_tick() {
        let mut lab = Lab::new(&[&[R, R, S], &[R]]);
        let mut tree = replanning(&lab, None);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 0]);
        // No time passes: the child runs, so it is ticked anyway.
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2, 0]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [3, 1]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [3, 2]);
    }

    #[test]
    fn the_period_runs_from_the_last_success() {
        let mut lab = Lab::new(&[&[R, S], &[R]]);
        let mut tree = replanning(&lab, None);
        assert_eq!(lab.tick(&mut tree), R);
        lab.advance(ms(80));
        assert_eq!(lab.tick(&mut tree), R); // child succeeds at 80 ms
        assert_eq!(lab.ticks, [2, 1]);
        lab.advance(ms(50));
        assert_eq!(lab.tick(&mut tree), R); // 130 ms: only 50 since the success
        assert_eq!(lab.ticks, [2, 2]);
        lab.advance(ms(50));
        assert_eq!(lab.tick(&mut tree), R); // 180 ms: 100 since the success
        assert_eq!(lab.ticks, [3, 3]);
    }

    #[test]
    fn its_saved_state_keeps_the_period_read_on_the_tick_from_idle() {
        let running = RateController {
            period: Some(ms(500)),
            since: ms(1200),
            first: false,
        };
        let saved = CustomNode::<Lab>::save_state(&running).unwrap();
        let mut fresh = RateController::default();
        assert!(CustomNode::<Lab>::restore_state(&mut fresh, &saved));
        assert_eq!(
            (fresh.period, fresh.since, fresh.first),
            (Some(ms(500)), ms(1200), false)
        );
        // Bytes of another node's state are refused.
        assert!(!CustomNode::<Lab>::restore_state(&mut fresh, &[1]));
    }

    #[test]
    fn failure_passes_and_the_next_run_ticks_at_once() {
        let mut lab = Lab::new(&[&[F, S]]);
        let mut tree = lab.tree(|b| b.custom("rate", RateController::spec(), |r| r.scripted(0)));
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [2]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn a_skipped_child_is_skipped_and_the_next_tick_starts_a_run() {
        let mut lab = Lab::new(&[&[K, S]]);
        let mut tree = lab.tree(|b| b.custom("rate", RateController::spec(), |r| r.skippable(0)));
        assert_eq!(lab.tick(&mut tree), K);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [2]);
    }

    #[test]
    fn zero_hz_ticks_the_child_once_per_run() {
        let mut lab = Lab::new(&[&[S], &[R]]);
        let mut tree = replanning(&lab, Some("0"));
        assert_eq!(lab.tick(&mut tree), R);
        lab.advance(Duration::from_secs(3600));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 2]);

        let mut lab = Lab::new(&[&[S], &[R]]);
        let mut tree = replanning(&lab, Some("-1"));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2, 2]);
    }

    #[test]
    fn halt_from_a_parent_halts_the_child_once_and_the_next_run_ticks_at_once() {
        let mut lab = Lab::new(&[&[S, F, S], &[R]]);
        let mut tree = lab.tree(|b| {
            b.reactive_sequence("guarded", |r| {
                r.check(0)
                    .custom("rate", RateController::spec(), |c| c.scripted(1))
            })
        });
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.halts, [0, 1]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [3, 2]);
    }

    #[test]
    fn periods_from_rates() {
        assert_eq!(period_of(10.0), Some(ms(100)));
        assert_eq!(period_of(0.5), Some(Duration::from_secs(2)));
        assert_eq!(period_of(0.0), None);
        assert_eq!(period_of(f64::NAN), None);
        assert_eq!(period_of(-3.0), Some(Duration::ZERO));
        assert_eq!(period_of(f64::MIN_POSITIVE), None);
        assert_eq!(period_of(f64::INFINITY), Some(Duration::ZERO));
    }
}
