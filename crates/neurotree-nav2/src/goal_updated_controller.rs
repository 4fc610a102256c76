//! GoalUpdatedController: start the child again only for a new goal.

use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeStatus};

use super::goals::SeenGoals;
use neurotree_core::nodes::semantics::{first, Order, Semantics, Statuses};

/// GoalUpdatedController's semantics: its child's statuses, and RUNNING while no new goal
/// comes.
pub const SEMANTICS: Semantics =
    Semantics::new(Order::again(Statuses::ANY, Statuses::ANY), |_, c| {
        first(c).or(Statuses::RUNNING).or(Statuses::FAILURE)
    });

/// GoalUpdatedController: start the child again only for a new goal.
///
/// Ports `goal` and `goals`.
///
/// - On the tick from Idle: remember the goals and tick the child.
/// - Later: tick the child if it is Running or `goal` or `goals` changed since the last look;
///   otherwise return Running without ticking it.
///
/// The child's status passes through, and a completed child is reset, so that the next new
/// goal starts it afresh. As with the RateController, "later" needs a parent that keeps the
/// completed node as it is, such as a PipelineSequence: Nav2 plans a path once per goal
/// with `PipelineSequence(GoalUpdatedController(Plan), Follow)`. How goals are read and
/// compared is told in the [catalog](super#goals).
#[derive(Debug, Default)]
pub struct GoalUpdatedController {
    seen: SeenGoals,
    /// A new goal (or a new run) waits for the child to be ticked.
    pending: bool,
}

impl GoalUpdatedController {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder):
    /// `builder.custom("plan_once_per_goal", GoalUpdatedController::spec(), |c| ...)`.
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "GoalUpdatedController",
            Arity::One,
            Box::new(|| Box::new(GoalUpdatedController::default())),
        )
    }

    /// Looks at the goals: remembers them on a new run, compares them later.
    fn look<C>(&mut self, node: &mut NodeCtx<'_, '_, C>) -> Result<(), String> {
        if !node.previous_status().is_active() {
            self.seen.remember(node)?;
            self.pending = true;
        }
        if self.seen.update(node)? {
            self.pending = true;
        }
        Ok(())
    }
}

impl<C> CustomNode<C> for GoalUpdatedController {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(&self.seen, self.pending)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(seen, pending)| {
                self.seen = seen;
                self.pending = pending;
            })
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        if let Err(message) = self.look(node) {
            node.fail(message);
            node.reset_children();
            return NodeStatus::Failure;
        }
        // Nav2's `setStatus(RUNNING)` before the child ticks.
        node.set_running();
        if !(self.pending || node.child_status(0) == NodeStatus::Running) {
            return NodeStatus::Running;
        }
        self.pending = false;
        let status = node.tick_child(0);
        if status.is_completed() {
            node.reset_children();
        }
        status
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robotics::Pose2D;
    use crate::testing::*;
    use crate::PipelineSequence;

    const A: Pose2D = Pose2D::new(1.0, 2.0, 0.0);
    const B: Pose2D = Pose2D::new(3.0, 4.0, 0.5);

    /// PipelineSequence(GoalUpdatedController(plan = leaf 0), follow = leaf 1).
    fn plan_per_goal(lab: &Lab) -> Tree<Lab> {
        lab.tree(|b| {
            b.custom("navigate", PipelineSequence::spec(), |p| {
                p.custom("per_goal", GoalUpdatedController::spec(), |c| c.scripted(0))
                    .scripted(1)
            })
        })
    }

    #[test]
    fn ticks_the_child_on_a_new_run_and_on_each_new_goal() {
        let mut lab = Lab::new(&[&[R, S, R, S], &[R]]);
        let mut tree = plan_per_goal(&lab);
        tree.blackboard_mut().set("goal", A).unwrap();
        // New run: plan at once; it runs.
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 0]);
        // A running child is ticked on: plan succeeds, follow starts.
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2, 1]);
        assert_eq!(tree.status(NodeId(1)), S);
        // Same goal: the controller answers Running without ticking plan.
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2, 3]);
        assert_eq!(tree.status(NodeId(1)), R);
        // A new goal: plan starts afresh while follow goes on in the pipeline.
        tree.blackboard_mut().set("goal", B).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [3, 4]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [4, 5]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [4, 6]);
        assert_eq!(lab.halts, [0, 0]);
    }

    #[test]
    fn a_change_while_the_child_runs_is_consumed_by_that_tick() {
        let mut lab = Lab::new(&[&[R, R, S], &[R]]);
        let mut tree = plan_per_goal(&lab);
        tree.blackboard_mut().set("goals", vec![A]).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        tree.blackboard_mut().set("goals", vec![A, B]).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [3, 1]);
        // The change was seen while plan ran: no second plan after it succeeded.
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [3, 2]);
    }

    #[test]
    fn completion_passes_and_the_next_run_ticks_at_once() {
        let mut lab = Lab::new(&[&[F, S]]);
        let mut tree =
            lab.tree(|b| b.custom("per_goal", GoalUpdatedController::spec(), |c| c.scripted(0)));
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [2]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn a_skipped_child_is_skipped() {
        let mut lab = Lab::new(&[&[K]]);
        let mut tree = lab.tree(|b| {
            b.custom("per_goal", GoalUpdatedController::spec(), |c| {
                c.skippable(0)
            })
        });
        assert_eq!(lab.tick(&mut tree), K);
        assert_eq!(lab.tick(&mut tree), K);
        assert_eq!(lab.ticks, [2]);
    }

    #[test]
    fn halt_from_a_parent_halts_the_child_once_and_the_next_run_ticks_at_once() {
        let mut lab = Lab::new(&[&[S, F, S], &[R]]);
        let mut tree = lab.tree(|b| {
            b.reactive_sequence("guarded", |r| {
                r.check(0)
                    .custom("per_goal", GoalUpdatedController::spec(), |c| c.scripted(1))
            })
        });
        tree.blackboard_mut().set("goal", A).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.halts, [0, 1]);
        // Same goal, but a new run: the child is ticked at once.
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [3, 2]);
    }

    #[test]
    fn a_goal_of_another_type_is_a_tick_error() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree =
            lab.tree(|b| b.custom("per_goal", GoalUpdatedController::spec(), |c| c.scripted(0)));
        tree.blackboard_mut().set("goal", 3_u8).unwrap();
        let err = tree.tick_once(&mut lab).unwrap_err();
        assert!(err.to_string().contains("u8"), "{err}");
        assert_eq!(lab.ticks, [0]);
    }
}
