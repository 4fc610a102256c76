//! A tree's node state in one block of words: the tick's failure bits, the nodes' slots,
//! and their statuses a byte each. One allocation rather than three, one pointer in the
//! tree rather than three, and one stretch of memory for a runner to prefetch: what a
//! crowd of many small trees saves in bytes and in cache lines.
//!
//! The block's first word says where the parts end (the nodes, and the slots), so that the
//! block alone says how to read it: `[shape | failure bits | slots | statuses]`.

use alloc::boxed::Box;
use alloc::vec;

use crate::NodeStatus;

/// The failure bits, slots and statuses of a tree's nodes (see the [module docs](self)).
pub(crate) struct NodeState {
    words: Box<[u64]>,
}

/// The parts of a [`NodeState`], borrowed side by side.
pub(crate) struct Parts<'a> {
    pub(crate) statuses: &'a mut [NodeStatus],
    pub(crate) failed: &'a mut [u64],
    pub(crate) aux: &'a mut [u64],
}

impl NodeState {
    /// The state of `nodes` nodes with `aux` slots: every node Idle, every slot and bit 0.
    pub(crate) fn new(nodes: usize, aux: usize) -> Self {
        let (n, a) = (
            u32::try_from(nodes).expect("a blueprint has fewer than 2^32 nodes"),
            u32::try_from(aux).expect("a blueprint has fewer than 2^32 slots"),
        );
        let mut words = vec![0; 1 + nodes.div_ceil(64) + aux + nodes.div_ceil(8)];
        words[0] = u64::from(n) | (u64::from(a) << 32);
        Self {
            words: words.into_boxed_slice(),
        }
    }

    /// The nodes, and the slots.
    #[inline(always)]
    fn shape(&self) -> (usize, usize) {
        let shape = self.words[0];
        ((shape as u32) as usize, (shape >> 32) as usize)
    }

    /// Bytes the block takes.
    pub(crate) fn bytes(&self) -> usize {
        self.words.len() * core::mem::size_of::<u64>()
    }

    /// The block, for [`prefetch`](crate::hint::prefetch).
    #[inline]
    pub(crate) fn words(&self) -> &[u64] {
        &self.words
    }

    /// The parts, to change.
    #[inline(always)]
    pub(crate) fn parts(&mut self) -> Parts<'_> {
        let (nodes, aux) = self.shape();
        let (_, rest) = self.words.split_at_mut(1);
        let (failed, rest) = rest.split_at_mut(nodes.div_ceil(64));
        let (aux, statuses) = rest.split_at_mut(aux);
        debug_assert!(statuses.len() * 8 >= nodes);
        let nodes = nodes.min(statuses.len() * 8);
        // SAFETY: `NodeStatus` is `repr(u8)` with `Idle = 0`, and the status words were
        // zeroed (`new`) and are written only through this view, as `NodeStatus` values:
        // their first `nodes` bytes always hold valid statuses. The view stays within the
        // words (`nodes` bytes of at least that many), a `u8`'s alignment is 1, and it
        // borrows them mutably, apart from the other parts, for as long as `self`.
        let statuses = unsafe {
            core::slice::from_raw_parts_mut(statuses.as_mut_ptr().cast::<NodeStatus>(), nodes)
        };
        Parts {
            statuses,
            failed,
            aux,
        }
    }

    /// The statuses, indexed by node.
    #[inline]
    pub(crate) fn statuses(&self) -> &[NodeStatus] {
        let (nodes, aux) = self.shape();
        let statuses = &self.words[1 + nodes.div_ceil(64) + aux..];
        let nodes = nodes.min(statuses.len() * 8);
        // SAFETY: as in `parts`, shared.
        unsafe { core::slice::from_raw_parts(statuses.as_ptr().cast::<NodeStatus>(), nodes) }
    }

    /// The failure bits.
    #[inline]
    pub(crate) fn failed(&self) -> &[u64] {
        let (nodes, _) = self.shape();
        &self.words[1..1 + nodes.div_ceil(64)]
    }

    /// The slots.
    #[inline]
    pub(crate) fn aux(&self) -> &[u64] {
        let (nodes, aux) = self.shape();
        let at = 1 + nodes.div_ceil(64);
        &self.words[at..at + aux]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_are_apart_and_keep_what_is_written() {
        for (nodes, aux) in [
            (0, 0),
            (1, 0),
            (7, 3),
            (8, 1),
            (9, 2),
            (64, 0),
            (65, 5),
            (130, 17),
        ] {
            let mut state = NodeState::new(nodes, aux);
            assert_eq!(
                state.bytes(),
                8 * (1 + nodes.div_ceil(64) + aux + nodes.div_ceil(8))
            );
            let p = state.parts();
            assert_eq!(
                (p.statuses.len(), p.failed.len(), p.aux.len()),
                (nodes, nodes.div_ceil(64), aux)
            );
            assert!(p.statuses.iter().all(|s| *s == NodeStatus::Idle));
            for (i, s) in p.statuses.iter_mut().enumerate() {
                *s = [
                    NodeStatus::Running,
                    NodeStatus::Failure,
                    NodeStatus::Skipped,
                ][i % 3];
            }
            p.failed.fill(u64::MAX);
            for (i, a) in p.aux.iter_mut().enumerate() {
                *a = u64::MAX - i as u64;
            }
            for (i, s) in state.statuses().iter().enumerate() {
                assert_eq!(
                    *s,
                    [
                        NodeStatus::Running,
                        NodeStatus::Failure,
                        NodeStatus::Skipped
                    ][i % 3]
                );
            }
            assert!(state.failed().iter().all(|w| *w == u64::MAX));
            assert!(state
                .aux()
                .iter()
                .enumerate()
                .all(|(i, a)| *a == u64::MAX - i as u64));
            assert_eq!(state.shape(), (nodes, aux));
        }
    }
}
