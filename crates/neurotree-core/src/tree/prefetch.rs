//! Asking the processor ahead for what a tick of a tree reads: for runners that tick many
//! trees in an order they know, such as a crowd's awake members (see [`hint`](crate::hint)).

use super::Tree;

impl<C> Tree<C> {
    /// Asks the processor to start loading the node state a tick of this tree reads (its
    /// statuses, slots, objects and its blackboard's root entries, values of small plain
    /// types included), for a runner that ticks many trees and knows which comes next: see
    /// [`hint`](crate::hint). Changes nothing.
    ///
    /// Boxed values (of types other than `bool`, numbers and `Duration`) are not asked for:
    /// their addresses are in the entries asked for here, and reading them a member later
    /// waited for those entries to arrive, which cost a crowd's frames more than the ticks
    /// that read a boxed value then waited for it (BENCHMARKS.md, "The tally in place, no
    /// values asked ahead").
    #[inline]
    pub fn prefetch_state(&self) {
        // The block's size from the blueprint, which every member shares and the cache
        // holds, not from the block's own head, which is what is being asked for.
        let bytes = self.blueprint.instance_state_bytes();
        crate::hint::prefetch_bytes(self.state.block(), bytes);
        self.blackboard.prefetch();
    }

    /// Asks the processor to start loading the blackboard's root entries only, values of
    /// small plain types included: for a runner that writes many trees' blackboards
    /// between ticks, such as a crowd delivering alerts, whose writes read nothing of the
    /// node state. Changes nothing.
    #[inline]
    pub fn prefetch_blackboard(&self) {
        self.blackboard.prefetch();
    }
}
