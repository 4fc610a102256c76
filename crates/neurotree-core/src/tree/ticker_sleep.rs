//! What a pass tells a sleeping tree: when it may wake, and what keeps it awake.

use super::ticker::Ticker;
use crate::NodeId;

impl<C> Ticker<'_, C> {
    /// Declares, for a sleeping tree, that the pass's result may change at `at` (nanoseconds
    /// on the clock): the time-based built-ins call it while they wait.
    #[inline]
    pub(crate) fn wake_at(&mut self, at: u64) {
        let waits = &mut self.waits;
        waits.deadline = waits.deadline.min(at);
        waits.any = true;
    }

    /// Keeps the tree awake after this pass: a node returns Running with nothing under it
    /// waiting (KeepRunningUntilFailure after its child succeeded), or re-checks its
    /// children every tick (the reactive controls).
    #[inline]
    pub(crate) fn stay_awake(&mut self, reason: crate::AwakeReason, node: NodeId) {
        self.waits.keep_awake(reason, node);
    }

    /// After a sync leaf's call: unless its kind reads only the blackboard or it declared
    /// what wakes it, it may read anything (see [`Waits::opaque`](super::sleep::Waits)).
    #[inline(always)]
    pub(super) fn note_reads(&mut self, id: NodeId) {
        if !self.out.reads.known() {
            self.waits.opaque(id);
        }
    }

    /// Says that node `id`, which completed in this pass, would not answer the same if
    /// ticked again (it starts afresh: a Sleep sleeps again): a reactive node re-checking it
    /// keeps the tree awake.
    #[inline]
    pub(crate) fn answers_otherwise_next(&mut self, id: NodeId) {
        self.waits.opaque(id);
    }
}
