//! PipelineSequence: a sequence whose earlier children keep running while later ones start.

use neurotree_core::nodes::semantics::{chain, Order, Semantics, Statuses};
use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeStatus};

/// PipelineSequence's semantics: a chain through successes and skips, ticked again from the
/// first on every tick.
pub const SEMANTICS: Semantics = Semantics::new(
    Order::again(Statuses::SUCCESS.or(Statuses::SKIPPED), Statuses::ANY),
    |_, c| chain(c, Statuses::SUCCESS),
);

/// PipelineSequence: a sequence whose earlier children keep running while later ones start.
///
/// Every tick, tick children from the first.
///
/// - Failure: halt all, Failure.
/// - Success or Skipped: go on.
/// - Running: if this child is at or past the furthest child that has run so far, remember it
///   and return Running; an earlier child still Running is passed over (it keeps running "in
///   the pipeline").
/// - All done: halt all, reset, Success (Skipped if all were skipped).
///
/// Nav2 uses it to plan and follow at once: `PipelineSequence(RateController(Plan), Follow)`
/// re-ticks the planner's branch every tick and, once a first path exists, follows it while
/// the planner runs again. A child that succeeded is ticked again on every tick too (a
/// stateful leaf that completed repeats its result until the pipeline resets it).
#[derive(Debug, Default)]
pub struct PipelineSequence {
    /// The furthest child that returned Running in this run.
    furthest: usize,
}

impl PipelineSequence {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder):
    /// `builder.custom("navigate", PipelineSequence::spec(), |c| ...)`.
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "PipelineSequence",
            Arity::AtLeast(1),
            Box::new(|| Box::new(PipelineSequence::default())),
        )
    }

    fn finish<C>(&mut self, node: &mut NodeCtx<'_, '_, C>, status: NodeStatus) -> NodeStatus {
        node.reset_children();
        self.furthest = 0;
        status
    }
}

impl<C> CustomNode<C> for PipelineSequence {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(self.furthest,)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(furthest,)| {
                self.furthest = furthest;
            })
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let count = node.child_count();
        let mut skipped = 0;
        for i in 0..count {
            match node.tick_child(i) {
                NodeStatus::Failure => return self.finish(node, NodeStatus::Failure),
                NodeStatus::Skipped => skipped += 1,
                NodeStatus::Running if i >= self.furthest => {
                    self.furthest = i;
                    return NodeStatus::Running;
                }
                // Success, an earlier child still running, or Idle, which a child never
                // returns (the engine turns it into a reported Failure).
                _ => {}
            }
        }
        let done = if skipped == count {
            NodeStatus::Skipped
        } else {
            NodeStatus::Success
        };
        self.finish(node, done)
    }

    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {
        self.furthest = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::*;

    fn pipeline(
        b: Builder<Lab>,
        children: impl FnOnce(Builder<Lab>) -> Builder<Lab>,
    ) -> Builder<Lab> {
        b.custom("pipe", PipelineSequence::spec(), children)
    }

    #[test]
    fn all_succeed_in_one_tick() {
        let mut lab = Lab::new(&[&[S], &[S], &[S]]);
        let mut tree = lab.tree(|b| pipeline(b, |p| p.scripted(0).check(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [1, 1, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn earlier_children_keep_running_in_the_pipeline() {
        // Plan runs, then succeeds; Follow starts; Plan is ticked again (a check, re-run
        // each tick) while Follow runs; a planner that runs again is passed over.
        let mut lab = Lab::new(&[&[R, S], &[R, R, R, S]]);
        let mut tree = lab.tree(|b| pipeline(b, |p| p.scripted(0).scripted(1)));
        // Tick 1: child 0 runs and is the furthest.
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 0]);
        // Tick 2: child 0 succeeds, child 1 starts running.
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2, 1]);
        // Ticks 3, 4: child 0 completed and is not reset, so it repeats Success uncalled.
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2, 3]);
        // Tick 5: child 1 succeeds: Success, everything reset, no halts.
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [2, 4]);
        assert_eq!(lab.halts, [0, 0]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn a_running_earlier_child_is_passed_over_and_ticked_each_tick() {
        // Child 0 is a skippable leaf re-ticked every tick: Success, then Running twice,
        // then Success. While it runs, child 1 (already the furthest) is ticked on.
        let mut lab = Lab::new(&[&[S, R, R, S], &[R, R, R, R, S]]);
        let mut tree = lab.tree(|b| pipeline(b, |p| p.skippable(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 1]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2, 2]);
        assert_eq!(tree.status(NodeId(1)), R);
        assert_eq!(tree.status(NodeId(2)), R);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [3, 3]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [4, 4]);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [5, 5]);
        assert_eq!(lab.halts, [0, 0]);
    }

    #[test]
    fn running_at_or_past_the_furthest_child_returns_at_once() {
        // Child 1 runs (furthest = 1); then child 0 runs again: it is before the furthest,
        // so it is passed over, and child 1 returns Running; child 2 is not reached.
        let mut lab = Lab::new(&[&[S, R], &[R], &[S]]);
        let mut tree = lab.tree(|b| pipeline(b, |p| p.skippable(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [1, 1, 0]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [2, 2, 0]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [3, 3, 0]);
    }

    #[test]
    fn failure_halts_all_and_fails() {
        // Child 0 runs in the pipeline while child 1 runs; child 1 fails: child 0 is halted.
        let mut lab = Lab::new(&[&[S, R], &[R, F], &[S]]);
        let mut tree = lab.tree(|b| pipeline(b, |p| p.skippable(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [2, 2, 0]);
        assert_eq!(lab.halts, [1, 0, 0]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn an_earlier_child_failing_halts_the_running_later_one() {
        let mut lab = Lab::new(&[&[S, F], &[R]]);
        let mut tree = lab.tree(|b| pipeline(b, |p| p.check(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [2, 1]);
        assert_eq!(lab.halts, [0, 1]);
    }

    #[test]
    fn the_furthest_child_is_forgotten_when_the_run_ends() {
        // Run 1 ends with child 1 running (furthest = 1), then failing. In run 2, child 0
        // running must return at once: child 1 is not ticked.
        let mut lab = Lab::new(&[&[S, S, R], &[R, F, S]]);
        let mut tree = lab.tree(|b| pipeline(b, |p| p.skippable(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [2, 2]);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [3, 2]);
    }

    #[test]
    fn an_earlier_child_still_running_when_the_last_succeeds_is_halted() {
        let mut lab = Lab::new(&[&[S, R], &[R, S]]);
        let mut tree = lab.tree(|b| pipeline(b, |p| p.skippable(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [2, 2]);
        assert_eq!(lab.halts, [1, 0]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn skipped_children_are_passed_and_all_skipped_is_skipped() {
        let mut lab = Lab::new(&[&[K], &[S], &[K]]);
        let mut tree = lab.tree(|b| pipeline(b, |p| p.skippable(0).scripted(1).skippable(2)));
        assert_eq!(lab.tick(&mut tree), S);
        assert_eq!(lab.ticks, [1, 1, 1]);

        let mut lab = Lab::new(&[&[K], &[K]]);
        let mut tree = lab.tree(|b| pipeline(b, |p| p.skippable(0).skippable(1)));
        assert_eq!(lab.tick(&mut tree), K);
        assert_eq!(lab.ticks, [1, 1]);
        assert_eq!(tree.status(NodeId(0)), NodeStatus::Idle);
    }

    #[test]
    fn halt_from_a_parent_halts_running_children_once_and_forgets_the_furthest() {
        // ReactiveSequence(guard, pipeline(A, B)): the guard fails while A and B both run.
        let mut lab = Lab::new(&[&[S, S, S, F, S], &[S, R, R, R], &[R, R, R, R, R]]);
        let mut tree = lab.tree(|b| {
            b.reactive_sequence("guarded", |r| {
                r.check(0).custom("pipe", PipelineSequence::spec(), |p| {
                    p.skippable(1).scripted(2)
                })
            })
        });
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [3, 3, 3]);
        assert_eq!(lab.tick(&mut tree), F);
        assert_eq!(lab.ticks, [4, 3, 3]);
        assert_eq!(lab.halts, [0, 1, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
        // Next run: child 1 runs again; with the furthest forgotten, child 2 is not ticked.
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.ticks, [5, 4, 3]);
    }

    #[test]
    fn halting_the_tree_halts_each_running_child_once() {
        let mut lab = Lab::new(&[&[S, R], &[R]]);
        let mut tree = lab.tree(|b| pipeline(b, |p| p.skippable(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), R);
        assert_eq!(lab.tick(&mut tree), R);
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [1, 1]);
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [1, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }
}
