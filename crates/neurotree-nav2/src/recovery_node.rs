//! RecoveryNode: run an action; when it fails, run a recovery and try the action again.

use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeStatus};

use super::port_or;
use neurotree_core::nodes::semantics::{Literals, Order, Semantics, Statuses};

/// RecoveryNode's semantics: the recovery after the action fails, the action again after the
/// recovery succeeds.
pub const SEMANTICS: Semantics =
    Semantics::new(Order::again(Statuses::FAILURE, Statuses::SUCCESS), outcomes);

/// What a RecoveryNode can return: the action's SUCCESS, RUNNING and SKIPPED, FAILURE once it
/// failed (the retries run out, or the recovery fails or is skipped), the recovery's
/// RUNNING; FAILURE at once for a negative `number_of_retries`.
fn outcomes(l: &Literals<'_>, c: &[Statuses]) -> Statuses {
    let (Some(n), [action, recovery]) = (l.int("number_of_retries"), c) else {
        return Statuses::ANY;
    };
    if n < 0 {
        return Statuses::FAILURE;
    }
    let recovers = action.can_fail() && n > 0;
    action
        .without(Statuses::FAILURE)
        .or(Statuses::FAILURE.when(action.can_fail()))
        .or(Statuses::RUNNING.when(recovers && recovery.can_run()))
}

const ACTION: usize = 0;
const RECOVERY: usize = 1;

/// RecoveryNode: run an action; when it fails, run a recovery and try the action again.
///
/// Port `number_of_retries` (N, default 1). Exactly 2 children: action, recovery.
///
/// - Action Success: halt recovery, reset, Success.
/// - Action Running: Running.
/// - Action Failure: if retries < N, halt action and tick recovery in the same tick; else
///   reset, Failure.
/// - Recovery Success: retries+1, tick the action again in the same tick; Running: Running;
///   Failure: reset, Failure; Skipped: Failure (not counted as a retry).
/// - Action Skipped: Skipped.
///
/// "Reset" clears the retry count and halts and resets both children; a skipped action
/// resets the node too, since a node that returns Skipped is Idle again. A negative
/// `number_of_retries` fails at once without ticking anything, as in Nav2. The port is read
/// on every tick, so it may be bound to a blackboard entry.
#[derive(Debug, Default)]
pub struct RecoveryNode {
    /// The child being run: the action, or the recovery.
    current: usize,
    /// Recoveries that succeeded in this run.
    retries: i32,
}

impl RecoveryNode {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder); bind `number_of_retries` with
    /// `.ports(..)` first thing in the children closure (1 when left out).
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "RecoveryNode",
            Arity::Range { min: 2, max: 2 },
            Box::new(|| Box::new(RecoveryNode::default())),
        )
    }

    fn finish<C>(&mut self, node: &mut NodeCtx<'_, '_, C>, status: NodeStatus) -> NodeStatus {
        node.reset_children();
        self.current = ACTION;
        self.retries = 0;
        status
    }
}

impl<C> CustomNode<C> for RecoveryNode {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(self.current, self.retries)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(current, retries)| {
                self.current = current;
                self.retries = retries;
            })
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let Some(max_retries) = port_or(node, "number_of_retries", 1_i32) else {
            return self.finish(node, NodeStatus::Failure);
        };
        // Nav2's `setStatus(RUNNING)` before the children tick.
        node.set_running();
        while self.retries <= max_retries {
            if self.current == ACTION {
                match node.tick_child(ACTION) {
                    NodeStatus::Success => return self.finish(node, NodeStatus::Success),
                    NodeStatus::Running => return NodeStatus::Running,
                    NodeStatus::Skipped => return self.finish(node, NodeStatus::Skipped),
                    // Failure (a child never returns Idle: the engine reports it as Failure).
                    _ if self.retries < max_retries => {
                        node.halt_child(ACTION);
                        self.current = RECOVERY;
                    }
                    _ => return self.finish(node, NodeStatus::Failure),
                }
            } else {
                match node.tick_child(RECOVERY) {
                    NodeStatus::Success => {
                        node.halt_child(RECOVERY);
                        self.retries += 1;
                        self.current = ACTION;
                    }
                    NodeStatus::Running => return NodeStatus::Running,
                    // Failure, or Skipped: a recovery that did not run helps nothing.
                    _ => return self.finish(node, NodeStatus::Failure),
                }
            }
        }
        self.finish(node, NodeStatus::Failure)
    }

    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {
        self.current = ACTION;
        self.retries = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::*;

    /// RecoveryNode(action = leaf 0, recovery = leaf 1), with `retries` if given.
    fn recovery(lab: &Lab, retries: Option<&str>, skippable: bool) -> Tree<Lab> {
        lab.tree(|b| {
            b.custom("recover", RecoveryNode::spec(), |c| {
                let c = match retries {
                    Some(n) => c.ports([Port::literal("number_of_retries", n)]),
                    None => c,
                };
                if skippable {
                    c.skippable(0).skippable(1)
                } else {
                    c.scripted(0).scripted(1)
                }
            })
        })
    }

    #[test]
    fn action_success_is_success() {
        let mut lab = Lab::new(&[&[R, S], &[S]]);
        let mut tree = recovery(&lab, None, false);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [2, 0]);
        assert_eq!(lab.halts, [0, 0]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn failure_runs_the_recovery_and_the_action_again_in_the_same_tick() {
        // Default: one retry. Action fails, recovery succeeds, action succeeds: one tick.
        let mut lab = Lab::new(&[&[F, S], &[S]]);
        let mut tree = recovery(&lab, None, false);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [2, 1]);
        assert_eq!(lab.halts, [0, 0]);
    }

    #[test]
    fn retries_are_counted_until_the_limit() {
        // Two retries: fail, recover, fail, recover, fail → Failure, in one tick.
        let mut lab = Lab::new(&[&[F], &[S]]);
        let mut tree = recovery(&lab, Some("2"), false);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [3, 2]);
        // The count was reset: the next run has its two retries again.
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [6, 4]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn zero_retries_fails_on_the_first_failure() {
        let mut lab = Lab::new(&[&[F], &[S]]);
        let mut tree = recovery(&lab, Some("0"), false);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [1, 0]);
    }

    #[test]
    fn negative_retries_fail_without_a_tick() {
        let mut lab = Lab::new(&[&[S], &[S]]);
        let mut tree = recovery(&lab, Some("-1"), false);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [0, 0]);
    }

    #[test]
    fn a_running_recovery_is_ticked_on_and_a_running_action_too() {
        // Action runs, fails; recovery runs twice, succeeds; action runs, succeeds.
        let mut lab = Lab::new(&[&[R, F, R, S], &[R, R, S]]);
        let mut tree = recovery(&lab, None, false);
        assert_eq!(lab.tick(&mut tree), R); // action running
        assert_eq!(lab.tick(&mut tree), R); // action failed, recovery running
        assert_eq!(lab.ticks, [2, 1]);
        assert_eq!(lab.tick(&mut tree), R); // recovery running
        assert_eq!(lab.tick(&mut tree), R); // recovery succeeded, action running again
        assert_eq!(lab.ticks, [3, 3]);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [4, 3]);
        assert_eq!(lab.halts, [0, 0]);
    }

    #[test]
    fn recovery_failure_is_failure() {
        let mut lab = Lab::new(&[&[F], &[R, F]]);
        let mut tree = recovery(&lab, Some("5"), false);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [1, 2]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn a_skipped_recovery_fails_without_counting_a_retry() {
        // With retries counted, the third tick of the action would be allowed; a skipped
        // recovery ends the run at once instead.
        let mut lab = Lab::new(&[&[F], &[K]]);
        let mut tree = recovery(&lab, Some("3"), true);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [1, 1]);
    }

    #[test]
    fn a_skipped_action_is_skipped_and_starts_afresh() {
        // Fail, recover, then skipped: Skipped. The next run has its retry again.
        let mut lab = Lab::new(&[&[F, K, F, S], &[S]]);
        let mut tree = recovery(&lab, None, true);
        assert_eq!(lab.tick(&mut tree), K);
        assert_eq!(lab.ticks, [2, 1]);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [4, 2]);
    }

    #[test]
    fn halt_from_a_parent_halts_the_running_child_and_resets_the_count() {
        // ReactiveSequence(guard, RecoveryNode(action, recovery)): the guard fails while the
        // action runs again after a recovery (one retry used).
        let mut lab = Lab::new(&[&[S, F, S], &[F, R, F, S], &[S]]);
        let mut tree = lab.tree(|b| {
            b.reactive_sequence("guarded", |r| {
                r.check(0).custom("recover", RecoveryNode::spec(), |c| {
                    c.ports([Port::literal("number_of_retries", "1")])
                        .scripted(1)
                        .scripted(2)
                })
            })
        });
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 2, 1]);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [2, 2, 1]);
        assert_eq!(lab.halts, [0, 1, 0]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
        // The retry used before the halt is given back: fail, recover, succeed.
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [3, 4, 2]);
    }

    #[test]
    fn a_retry_count_that_does_not_read_is_a_tick_error() {
        let mut lab = Lab::new(&[&[S], &[S]]);
        let mut tree = lab.tree(|b| {
            b.custom("recover", RecoveryNode::spec(), |c| {
                c.ports([Port::entry("number_of_retries", "tries")])
                    .scripted(0)
                    .scripted(1)
            })
        });
        let err = tree.tick_once(&mut lab).unwrap_err();
        assert!(err.to_string().contains("number_of_retries"), "{err}");
        assert_eq!(lab.ticks, [0, 0]);
        tree.blackboard_mut().set("tries", 0_i32).unwrap();
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [1, 0]);
    }
}
