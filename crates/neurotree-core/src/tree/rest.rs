//! Resting: a tree whose last pass ended Running in a stateful action, with only nodes
//! that pass a Running child's tick straight through above it, starts its next pass at
//! that action rather than at the root.

use super::sleep::Waits;
use super::ticker::Object;
use super::{root::recover, TickError, Tree};
use crate::{NodeId, NodeStatus};

/// What [`Tree::rest`] did.
pub(super) enum Rest {
    /// The tree does not rest, or may not be resumed: a pass from the root is due.
    No,
    /// The action returned Running again: the pass is over, and the tree still rests.
    Running,
    /// The action returned this: the pass from the root is to be run with it.
    Answered(NodeId, NodeStatus),
    /// The action panicked; the tree has been halted as after a panic in a pass.
    Failed(TickError),
}

impl<C> Tree<C> {
    /// If the last pass rested in a stateful action and nothing since (a halt, a slow
    /// halt under way, an observer attached, a reason given) stands in the way, calls the
    /// action as a pass from the root would. A halt, a reload and a restore forget the
    /// action.
    // Inlined in the tick calls always: a crowd's trees mostly do not rest, and for them
    // this is a load and a branch, which a call would triple.
    #[inline(always)]
    pub(super) fn rest(&mut self, ctx: &mut C, writes: u64) -> Rest {
        let Some(leaf) = self.resting else {
            return Rest::No;
        };
        let rests = self.observer().is_none()
            && self.out.is_quiet()
            && self.out.halts.count == 0
            && self.state.statuses()[leaf.index()] == NodeStatus::Running;
        if !rests {
            self.resting = None;
            return Rest::No;
        }
        let mut waits = Waits::new();
        let answer = self.resting_answer(leaf, ctx, &mut waits);
        if self.out.reads.event() {
            waits.on_event();
        }
        self.out.keep(&waits);
        match answer {
            Some(Ok(NodeStatus::Running)) if !self.out.faulted() => {
                self.rest_asleep(leaf, writes, &waits);
                Rest::Running
            }
            // The pass from the root, with the answer; a fault ends it.
            Some(Ok(answer)) => {
                self.resting = None;
                Rest::Answered(leaf, answer)
            }
            Some(Err(panicked)) => Rest::Failed(self.rest_panicked(ctx, leaf, panicked)),
            None => {
                self.resting = None;
                Rest::No
            }
        }
    }

    /// After `leaf`, the action the tree rested in, panicked: the tree recovered as from a
    /// pass's panic. Out of line, so that the inlined resting path stays short.
    #[cold]
    #[inline(never)]
    fn rest_panicked(&mut self, ctx: &mut C, leaf: NodeId, panicked: TickError) -> TickError {
        self.resting = None;
        let mut t = self.ticker(ctx);
        t.current = leaf;
        recover(&mut t, panicked)
    }

    /// The answer of `leaf`, the stateful action the last pass rested in, called as a pass
    /// from the root would call it: its ancestors up to the root pass a Running child's
    /// tick straight through, so such a pass would tick it and nothing else, and, if it
    /// returns Running, change nothing else. `None` if its object is not at hand (an
    /// action still halting); `Err` for a panic, caught and named as a pass names it. What
    /// the action says it waits on goes in `waits`, fresh.
    #[inline]
    fn resting_answer(
        &mut self,
        leaf: NodeId,
        ctx: &mut C,
        waits: &mut Waits,
    ) -> Option<Result<NodeStatus, TickError>> {
        let bp = &*self.blueprint;
        let Some(Object::Stateful(action)) = self.state.objects_mut().get_mut(bp.slot(leaf)) else {
            return None;
        };
        self.out.reads.declare(false);
        let mut h = crate::Handle {
            ctx,
            blackboard: &mut self.blackboard,
            clock: &*self.clock,
            node: leaf,
            bp,
            out: &mut self.out,
            waits,
        };
        #[cfg(feature = "std")]
        {
            let call =
                core::panic::AssertUnwindSafe(|| NodeStatus::from(action.on_running(&mut h)));
            Some(
                std::panic::catch_unwind(call).map_err(|payload| TickError::Panicked {
                    node: leaf,
                    path: bp.path(leaf),
                    message: super::ticker::panic_message(&*payload),
                }),
            )
        }
        #[cfg(not(feature = "std"))]
        {
            Some(Ok(NodeStatus::from(action.on_running(&mut h))))
        }
    }
}
