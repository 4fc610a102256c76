//! GlobalUpdatedGoal: a condition that succeeds when the goal changed since it last looked,
//! however its parents reset it in between.

use neurotree_core::{Arity, Category, CustomNode, CustomSpec, NodeCtx, NodeStatus};

use super::goals::SeenGoals;

/// GlobalUpdatedGoal: a condition that succeeds when the goal changed since it last looked,
/// however its parents reset it in between.
///
/// A condition, with ports `goal` and `goals`.
///
/// - On its first tick ever: remember the goals, Success.
/// - Later (whatever its parents did meanwhile): Success if `goal` or `goals` differs from what
///   it remembered (and remember the new ones), else Failure.
///
/// Its memory lives as long as the tree instance: neither a reset nor a halt of the tree
/// clears it. Nav2 puts it under an Inverter in "is a new path needed?" checks, so that the
/// first tick and every new goal force a plan. How goals are read and compared is told in
/// the [catalog](super#goals).
#[derive(Debug)]
pub struct GlobalUpdatedGoal {
    seen: SeenGoals,
    first: bool,
}

impl Default for GlobalUpdatedGoal {
    fn default() -> Self {
        Self {
            seen: SeenGoals::default(),
            first: true,
        }
    }
}

impl GlobalUpdatedGoal {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder), a leaf:
    /// `builder.custom("new_goal", GlobalUpdatedGoal::spec(), |c| c)`.
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "GlobalUpdatedGoal",
            Arity::Leaf,
            Box::new(|| Box::new(GlobalUpdatedGoal::default())),
        )
        .in_category(Category::Condition)
    }
}

impl<C> CustomNode<C> for GlobalUpdatedGoal {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(&self.seen, self.first)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(seen, first)| {
                self.seen = seen;
                self.first = first;
            })
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let updated = if self.first {
            self.first = false;
            self.seen.remember(node).map(|()| true)
        } else {
            self.seen.update(node)
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

    #[test]
    fn succeeds_first_then_on_each_change_even_when_reset_every_tick() {
        // ReactiveFallback(GlobalUpdatedGoal, run): the fallback resets the condition on
        // every tick in which `run` runs, which this condition does not mind.
        let mut lab = Lab::new(&[&[R]]);
        let mut tree = lab.tree(|b| {
            b.reactive_fallback("recover", |f| {
                f.custom("new_goal", GlobalUpdatedGoal::spec(), |c| c)
                    .scripted(0)
            })
        });
        tree.blackboard_mut().set("goal", A).unwrap();
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [0]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2]);
        tree.blackboard_mut().set("goal", B).unwrap();
        // A new goal: Success, and the running child is halted.
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [2]);
        assert_eq!(lab.halts, [1]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [3]);
    }

    #[test]
    fn a_halt_of_the_tree_keeps_its_memory() {
        let mut lab = Lab::new(&[&[R]]);
        let mut tree = lab.tree(|b| {
            b.reactive_fallback("recover", |f| {
                f.custom("new_goal", GlobalUpdatedGoal::spec(), |c| c)
                    .scripted(0)
            })
        });
        tree.blackboard_mut().set("goals", vec![A]).unwrap();
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.tick(&mut tree), R);
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [1]);
        // Not a first tick again: the goals did not change, so the child runs.
        assert_eq!(lab.tick(&mut tree), R);
        tree.blackboard_mut().set("goals", vec![B]).unwrap();
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [2]);
        assert_eq!(lab.halts, [2]);
    }

    #[test]
    fn a_goal_of_another_type_is_a_tick_error() {
        let mut lab = Lab::new(&[&[R]]);
        let mut tree = lab.tree(|b| b.custom("new_goal", GlobalUpdatedGoal::spec(), |c| c));
        tree.blackboard_mut()
            .set("goals", String::from("north"))
            .unwrap();
        let err = tree.tick_once(&mut lab).unwrap_err();
        assert!(err.to_string().contains("north"), "{err}");
    }
}
