//! Asking the processor ahead for what a tick of a tree reads: for runners that tick many
//! trees in an order they know, such as a crowd's awake members (see [`hint`](crate::hint)).

use super::Tree;

impl<C> Tree<C> {
    /// Asks the processor to start loading the node state a tick of this tree reads (its
    /// statuses, slots, objects and its blackboard's root entries, values of small plain
    /// types included), for a runner that ticks many trees and knows which comes next: see
    /// [`hint`](crate::hint). Changes nothing.
    #[inline]
    pub fn prefetch_state(&self) {
        // The block's size from the blueprint, which every member shares and the cache
        // holds, not from the block's own head, which is what is being asked for.
        let bytes = self.blueprint.instance_state_bytes();
        crate::hint::prefetch_bytes(self.state.block(), bytes);
        self.blackboard.prefetch();
    }

    /// Asks the processor to start loading the boxed values of the first blackboard entries
    /// of the tree's root scope (values of other types than `bool`, numbers and `Duration`),
    /// whose addresses are in the entries [`prefetch_state`](Self::prefetch_state) loads:
    /// call it a little later than that. A tree whose root values are all held inline has
    /// nothing more to load. Changes nothing.
    #[inline]
    pub fn prefetch_entries(&self) {
        self.blackboard.prefetch_entries();
    }
}
