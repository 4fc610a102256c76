//! GoalUpdated: a condition that succeeds when the goal changed while its parent ran.

use neurotree_core::{Arity, Category, CustomNode, CustomSpec, NodeCtx, NodeStatus};

use super::goals::SeenGoals;

/// GoalUpdated: a condition that succeeds when the goal changed while its parent ran.
///
/// A condition, with ports `goal` and `goals`.
///
/// - On the tick from Idle: remember the goals, Failure.
/// - Later: Success if `goal` or `goals` differs from what it remembered (and remember the new
///   ones), else Failure.
///
/// "Later" means a tick that finds the condition's last result still stored: its parent has
/// not reset it since. A WhileDoElse keeps its condition's result while a branch runs, so
/// `WhileDoElse(GoalUpdated, replan, follow)` replans on each new goal. A ReactiveFallback
/// resets its other children whenever one runs, so there GoalUpdated starts afresh on every
/// tick and never succeeds, as it does in Nav2 on BehaviorTree.CPP 4 (see
/// [GlobalUpdatedGoal](super::GlobalUpdatedGoal)). How goals are read and compared is told
/// in the [catalog](super#goals).
#[derive(Debug, Default)]
pub struct GoalUpdated {
    seen: SeenGoals,
}

impl GoalUpdated {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder), a leaf:
    /// `builder.custom("new_goal", GoalUpdated::spec(), |c| c)`.
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "GoalUpdated",
            Arity::Leaf,
            Box::new(|| Box::new(GoalUpdated::default())),
        )
        .in_category(Category::Condition)
    }
}

impl<C> CustomNode<C> for GoalUpdated {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(&self.seen,)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(seen,)| {
                self.seen = seen;
            })
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let updated = if node.previous_status().is_active() {
            self.seen.update(node)
        } else {
            self.seen.remember(node).map(|()| false)
        };
        match updated {
            Ok(true) => NodeStatus::Success,
            Ok(false) => NodeStatus::Failure,
            Err(message) => {
                node.fail(message);
                NodeStatus::Failure
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robotics::Pose2D;
    use crate::testing::*;

    const A: Pose2D = Pose2D::new(1.0, 2.0, 0.0);
    const B: Pose2D = Pose2D::new(3.0, 4.0, 0.5);

    /// WhileDoElse(GoalUpdated, replan = leaf 0, follow = leaf 1).
    fn replan_on_new_goal(lab: &Lab) -> Tree<Lab> {
        lab.tree(|b| {
            b.while_do_else("navigate", |w| {
                w.custom("new_goal", GoalUpdated::spec(), |c| c)
                    .scripted(0)
                    .scripted(1)
            })
        })
    }

    #[test]
    fn succeeds_once_per_change_of_goal() {
        let mut lab = Lab::new(&[&[R], &[R]]);
        let mut tree = replan_on_new_goal(&lab);
        tree.blackboard_mut().set("goal", A).unwrap();
        // From Idle: remember A, Failure: follow.
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(tree.status(NodeId(1)), F);
        assert_eq!(lab.ticks, [0, 1]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [0, 2]);
        // A new goal: Success once: follow is halted, replan starts.
        tree.blackboard_mut().set("goal", B).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(tree.status(NodeId(1)), S);
        assert_eq!(lab.ticks, [1, 2]);
        assert_eq!(lab.halts, [0, 1]);
        // Same goal again: Failure: replan is halted, follow starts again.
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(tree.status(NodeId(1)), F);
        assert_eq!(lab.ticks, [1, 3]);
        assert_eq!(lab.halts, [1, 1]);
        // Writing the same value is no update.
        tree.blackboard_mut().set("goal", B).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 4]);
    }

    #[test]
    fn a_change_of_the_goal_list_counts_too() {
        let mut lab = Lab::new(&[&[R], &[R]]);
        let mut tree = replan_on_new_goal(&lab);
        tree.blackboard_mut().set("goals", vec![A]).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        tree.blackboard_mut().set("goals", vec![A, B]).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(tree.status(NodeId(1)), S);
        assert_eq!(lab.ticks, [1, 1]);
    }

    #[test]
    fn every_tick_from_idle_only_remembers() {
        // Under a ReactiveFallback whose next child runs, the condition is reset on every
        // tick: each tick is a tick from Idle, so even a new goal is no Success.
        let mut lab = Lab::new(&[&[R]]);
        let mut tree = lab.tree(|b| {
            b.reactive_fallback("recover", |f| {
                f.custom("new_goal", GoalUpdated::spec(), |c| c).scripted(0)
            })
        });
        tree.blackboard_mut().set("goal", A).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        tree.blackboard_mut().set("goal", B).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2]);
        assert_eq!(lab.halts, [0]);
    }

    #[test]
    fn a_missing_goal_is_the_empty_one_and_remembering_it_keeps_the_old() {
        let mut lab = Lab::new(&[&[R], &[R]]);
        let mut tree = replan_on_new_goal(&lab);
        // Nothing written: remembered as the origin.
        assert_eq!(lab.tick(&mut tree), R);
        tree.blackboard_mut().set("goal", A).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(tree.status(NodeId(1)), S);
        // Halting resets the condition; with the entry gone, remembering keeps A, and the
        // next look reads the origin: a change.
        lab.halt(&mut tree);
        assert!(tree.blackboard_mut().unset("goal"));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(tree.status(NodeId(1)), F);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(tree.status(NodeId(1)), S);
    }

    #[test]
    fn a_bound_port_is_read_before_the_entry_named_goal() {
        let mut lab = Lab::new(&[&[R], &[R]]);
        let mut tree = lab.tree(|b| {
            b.while_do_else("navigate", |w| {
                w.custom("new_goal", GoalUpdated::spec(), |c| {
                    c.ports([Port::entry("goal", "target")])
                })
                .scripted(0)
                .scripted(1)
            })
        });
        tree.blackboard_mut().set("target", A).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        // The `goal` entry is not the port's: no change.
        tree.blackboard_mut().set("goal", B).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(tree.status(NodeId(1)), F);
        tree.blackboard_mut().set("target", B).unwrap();
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(tree.status(NodeId(1)), S);
    }

    #[test]
    fn a_goal_of_another_type_is_a_tick_error() {
        let mut lab = Lab::new(&[&[R], &[R]]);
        let mut tree = replan_on_new_goal(&lab);
        tree.blackboard_mut().set("goal", 1.5_f64).unwrap();
        let err = tree.tick_once(&mut lab).unwrap_err();
        assert!(err.to_string().contains("new_goal"), "{err}");
        assert!(err.to_string().contains("f64"), "{err}");
        // The condition failed, so the pass went on to `follow`; the tree was then halted.
        assert_eq!(lab.ticks, [0, 1]);
        assert_eq!(lab.halts, [0, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }
}
