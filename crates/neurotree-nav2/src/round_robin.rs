//! RoundRobin: each use of the node runs the next child, so that recoveries take turns.

use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeStatus};

use super::port_or;
use neurotree_core::nodes::semantics::{union, Order, Semantics, Statuses};

/// RoundRobin's semantics: it starts at the child after the last one used, so no order
/// between its children holds; FAILURE once each had its turn.
pub const SEMANTICS: Semantics =
    Semantics::new(Order::AllAtOnce, |_, c| union(c).or(Statuses::FAILURE));

/// RoundRobin: each use of the node runs the next child, so that recoveries take turns, as
/// Nav2's `round_robin_node.cpp` does.
///
/// Port `wrap_around` (default false). Starting at the stored child, tick; a child that
/// completes advances the index.
///
/// - Success: halt the others, Success; the next tick starts at the child after it.
/// - Running: Running.
/// - Failure: try the next; when every child has failed since the last success: reset,
///   Failure.
/// - Without wrap-around, once the last child has completed, whatever it returned (Success
///   too): reset (the next use starts at the first child), Failure (Skipped if every child
///   was skipped in this tick). With wrap-around the index goes back to the first child.
/// - Halt resets the index.
///
/// The index survives the node's completion: a parent that resets the node after a Success
/// does not halt it, so the next use starts at the next child. That is what makes Nav2's
/// recovery list (clear costmaps, spin, wait, back up) try a different recovery each time,
/// and, without wrap-around, give up once each has had its turn. A skipped child is passed
/// like a failed one without counting as a failure; when every child was skipped in one tick
/// the node returns Skipped.
#[derive(Debug, Default)]
pub struct RoundRobin {
    /// The child to tick next.
    next: usize,
    /// Children that failed since the last success.
    failed: usize,
}

impl RoundRobin {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder); bind `wrap_around` with
    /// `.ports(..)` first thing in the children closure (false when left out).
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "RoundRobin",
            Arity::AtLeast(1),
            Box::new(|| Box::new(RoundRobin::default())),
        )
    }

    fn restart(&mut self) {
        self.next = 0;
        self.failed = 0;
    }
}

impl<C> CustomNode<C> for RoundRobin {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(self.next, self.failed)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(next, failed)| {
                self.next = next;
                self.failed = failed;
            })
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let Some(wrap_around) = port_or(node, "wrap_around", false) else {
            node.reset_children();
            self.restart();
            return NodeStatus::Failure;
        };
        // Nav2's `setStatus(RUNNING)` before the children tick.
        node.set_running();
        let count = node.child_count();
        let mut skipped = 0;
        while self.failed + skipped < count {
            let status = node.tick_child(self.next);
            if status == NodeStatus::Running {
                return NodeStatus::Running;
            }
            self.next += 1;
            if self.next == count {
                if !wrap_around {
                    // Nav2 breaks out here, after the last child, and fails even when that
                    // child succeeded.
                    match status {
                        NodeStatus::Skipped => skipped += 1,
                        NodeStatus::Success => {}
                        _ => self.failed += 1,
                    }
                    break;
                }
                self.next = 0;
            }
            match status {
                NodeStatus::Success => {
                    self.failed = 0;
                    node.reset_children();
                    return NodeStatus::Success;
                }
                NodeStatus::Skipped => skipped += 1,
                // Failure (a child never returns Idle: the engine reports it as Failure).
                _ => self.failed += 1,
            }
        }
        node.reset_children();
        self.restart();
        if skipped == count {
            NodeStatus::Skipped
        } else {
            NodeStatus::Failure
        }
    }

    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {
        self.restart();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::*;

    /// A RoundRobin over leaves 0..n (skippable ones if `skippable`).
    fn round_robin(lab: &Lab, wrap: Option<&str>, skippable: bool) -> Tree<Lab> {
        let n = lab.scripts.len();
        lab.tree(|b| {
            b.custom("turns", RoundRobin::spec(), |mut c| {
                if let Some(w) = wrap {
                    c = c.ports([Port::literal("wrap_around", w)]);
                }
                for i in 0..n {
                    c = if skippable {
                        c.skippable(i)
                    } else {
                        c.scripted(i)
                    };
                }
                c
            })
        })
    }

    #[test]
    fn each_success_moves_to_the_next_child() {
        let mut lab = Lab::new(&[&[S], &[S], &[S]]);
        let mut tree = round_robin(&lab, Some("true"), false);
        for expected in [[1, 0, 0], [1, 1, 0], [1, 1, 1], [2, 1, 1]] {
            assert_eq!(lab.tick(&mut tree), S);
            assert_eq!(lab.ticks, expected);
        }
        assert_eq!(lab.halts, [0, 0, 0]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn without_wrap_around_the_last_childs_success_is_failure() {
        // The default: the last child succeeds, yet the node halts itself and fails, as
        // Nav2's `round_robin_node.cpp` breaks out after the last child; the next use
        // starts again at the first child.
        let mut lab = Lab::new(&[&[S], &[S]]);
        let mut tree = round_robin(&lab, None, false);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [1, 0]);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [1, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [2, 1]);
        assert_eq!(lab.halts, [0, 0]);
    }

    #[test]
    fn without_wrap_around_a_skipped_last_child_ends_the_turns() {
        // 0 fails, 1 (the last) is skipped: Failure, not Skipped, as one child failed.
        let mut lab = Lab::new(&[&[F, K], &[K]]);
        let mut tree = round_robin(&lab, Some("false"), true);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [1, 1]);
        // Both skipped: Skipped.
        assert_eq!(lab.tick(&mut tree), K);
        assert_eq!(lab.ticks, [2, 2]);
    }

    #[test]
    fn a_failure_tries_the_next_child_in_the_same_tick() {
        let mut lab = Lab::new(&[&[F], &[F, S], &[S]]);
        let mut tree = round_robin(&lab, Some("true"), false);
        // 0 fails, 1 fails, 2 succeeds.
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [1, 1, 1]);
        // Next use starts after 2, wraps to 0: fails, then 1 succeeds.
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [2, 2, 1]);
    }

    #[test]
    fn all_failing_since_the_last_success_is_failure() {
        let mut lab = Lab::new(&[&[S, F], &[F], &[F]]);
        let mut tree = round_robin(&lab, Some("true"), false);
        assert_eq!(lab.tick(&mut tree), S);
        // From child 1: 1, 2, then 0 fail: three failures since the success.
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [2, 1, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
        // Reset: the next use starts at child 0.
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [3, 2, 2]);
    }

    #[test]
    fn without_wrap_around_failing_to_the_end_is_failure() {
        let mut lab = Lab::new(&[&[S], &[F], &[F]]);
        let mut tree = round_robin(&lab, Some("false"), false);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [1, 1, 1]);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [2, 1, 1]);
    }

    #[test]
    fn failures_are_counted_across_ticks_while_a_child_runs() {
        let mut lab = Lab::new(&[&[F], &[R, F], &[F]]);
        let mut tree = round_robin(&lab, Some("true"), false);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 1, 0]);
        // 1 fails (two failures), 2 fails (three): Failure without ticking 0 again.
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [1, 2, 1]);
    }

    #[test]
    fn a_running_child_keeps_its_turn() {
        let mut lab = Lab::new(&[&[R, R, S], &[R, S]]);
        let mut tree = round_robin(&lab, None, false);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [3, 0]);
        assert_eq!(lab.tick(&mut tree), R);
        // The last child succeeds: without wrap-around that ends the turns with Failure.
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [3, 2]);
    }

    #[test]
    fn skipped_children_are_passed_without_counting_as_failures() {
        let mut lab = Lab::new(&[&[K], &[F, S], &[K]]);
        let mut tree = round_robin(&lab, Some("true"), true);
        // 0 skipped, 1 fails, 2 skipped: each child had its pass (one failure and two
        // skips make three), so the tick ends with Failure.
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [1, 1, 1]);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [2, 2, 1]);

        let mut lab = Lab::new(&[&[K], &[K]]);
        let mut tree = round_robin(&lab, Some("true"), true);
        assert_eq!(lab.tick(&mut tree), K);
        assert_eq!(lab.ticks, [1, 1]);
    }

    #[test]
    fn the_turn_survives_a_reset_by_the_parent_but_not_a_halt() {
        // Sequence(RoundRobin(A, B), C): C runs after A succeeded, then the tree is halted:
        // the RoundRobin completed, so its parent only resets it, and B has the next turn.
        let mut lab = Lab::new(&[&[S], &[R], &[R, S, R]]);
        let mut tree = lab.tree(|b| {
            b.sequence("seq", |s| {
                s.custom("turns", RoundRobin::spec(), |c| c.scripted(0).scripted(1))
                    .scripted(2)
            })
        });
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 0, 1]);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [1, 0, 2]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 1, 2]);
        // B is Running inside the RoundRobin: a halt stops it once and resets the turn.
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [0, 1, 0]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2, 1, 3]);
    }

    #[test]
    fn halt_from_a_parent_resets_the_turn_and_the_failures() {
        // ReactiveSequence(guard, RoundRobin(A, B, C)): A fails, B runs; the guard fails.
        let mut lab = Lab::new(&[&[S, F, S], &[F, S], &[R], &[F]]);
        let mut tree = lab.tree(|b| {
            b.reactive_sequence("guarded", |r| {
                r.check(0).custom("turns", RoundRobin::spec(), |c| {
                    c.ports([Port::literal("wrap_around", "true")])
                        .scripted(1)
                        .scripted(2)
                        .scripted(3)
                })
            })
        });
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.halts, [0, 0, 1, 0]);
        // Starts again at A with no failures counted: A succeeds.
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [3, 2, 1, 0]);
    }
}
