//! ReactiveSequence and ReactiveFallback: re-check every child from the first, every tick.
//!
//! - **ReactiveSequence**: restart at child 0 every tick.
//!   - A child Running: halt (and reset) every other child, return Running.
//!   - Failure: halt/reset all, Failure.
//!   - All succeeded: reset, Success.
//! - **ReactiveFallback**: mirror of ReactiveSequence: Success ends it, Failure moves on, all
//!   failed → Failure.
//!
//! This is what makes a tree reactive: a condition placed before a long action is checked on
//! every tick, and when it flips, the running action is halted in the same tick. A skipped
//! child is reset so that it can be skipped (or run) afresh next tick; all skipped → Skipped.

use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus, Status};

/// `goal` is the outcome that lets the node move on: Success for the sequence, Failure for
/// the fallback.
#[inline(never)]
pub(crate) fn tick<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
    goal: Status,
) -> NodeStatus {
    let bp = t.bp;
    let children = bp.children_of(def);
    let hot = bp.hot_children_of(def);
    let go_on = NodeStatus::from(goal);
    let mut all_skipped = true;
    t.set_status(id, NodeStatus::Running);
    for (index, hot_child) in hot.iter().enumerate() {
        let child = hot_child.id;
        let status = t.tick_child::<true>(hot_child);
        all_skipped &= status == NodeStatus::Skipped;
        if status == NodeStatus::Running {
            for (other, &c) in children.iter().enumerate() {
                if other != index {
                    t.halt_child(c);
                }
            }
            return NodeStatus::Running;
        }
        if status == NodeStatus::Skipped {
            t.halt_child(child);
        } else if status != go_on {
            t.reset_children(id);
            return status;
        }
    }
    t.reset_children(id);
    if all_skipped {
        NodeStatus::Skipped
    } else {
        go_on
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn rechecks_conditions_every_tick() {
        let mut lab = Lab::new(&[&[S], &[R, R, S]]);
        let mut tree = lab.tree(|b| b.reactive_sequence("rs", |s| s.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [3, 3]);
        assert_eq!(lab.halts, [0, 0]);
    }

    #[test]
    fn failing_condition_halts_the_running_action() {
        let mut lab = Lab::new(&[&[S, S, F], &[R]]);
        let mut tree = lab.tree(|b| b.reactive_sequence("rs", |s| s.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [3, 2]);
        assert_eq!(lab.halts, [0, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn fallback_halts_its_running_action_when_a_condition_flips() {
        // BehaviorTree.CPP's case: ReactiveFallback(condition, action); the condition turns
        // true while the action runs, so the action is halted and the node succeeds.
        let mut lab = Lab::new(&[&[F, F, S], &[R]]);
        let mut tree = lab.tree(|b| b.reactive_fallback("rf", |f| f.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [3, 2]);
        assert_eq!(lab.halts, [0, 1]);
        assert_eq!(lab.log_of(1), ["start", "running", "halted"]);
    }

    #[test]
    fn a_later_running_child_halts_an_earlier_one() {
        // Child 0 runs, then succeeds; child 1 starts running in the same tick and child 0,
        // completed, is reset to Idle without a halt.
        let mut lab = Lab::new(&[&[R, S], &[R]]);
        let mut tree = lab.tree(|b| b.reactive_sequence("rs", |s| s.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [1, 0]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [2, 1]);
        // Child 0 succeeded this tick, and was reset to Idle when child 1 ran.
        assert_eq!(lab.halts, [0, 0]);
        assert_eq!(tree.status(NodeId(1)), NodeStatus::Idle);
        assert_eq!(tree.status(NodeId(2)), NodeStatus::Running);
    }
}
