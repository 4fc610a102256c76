//! The loop shared by Sequence and Fallback, which mirror each other: a Sequence moves on
//! while its children succeed and stops at the first failure, a Fallback moves on while they
//! fail and stops at the first success. See [`sequence`](super::sequence) and
//! [`fallback`](super::fallback) for the semantics.

use super::{pack, unpack};
use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

/// Which member of a family is ticking.
pub(crate) type Flavor = u8;
/// Sequence, Fallback.
pub(crate) const PLAIN: Flavor = 0;
/// SequenceWithMemory: a failure and a halt keep the cursor; yields.
pub(crate) const MEMORY: Flavor = 1;
/// AsyncSequence, AsyncFallback: yields after each child that completed from Idle.
pub(crate) const ASYNC: Flavor = 2;

/// Ticks a Sequence (`SEQUENCE`) or a Fallback (`!SEQUENCE`) of the given flavor; the
/// parameters are constants so that each node compiles to its own loop.
#[inline(never)]
pub(crate) fn tick<C, const SEQUENCE: bool, const FLAVOR: Flavor>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
) -> NodeStatus {
    if t.observed() {
        run::<C, SEQUENCE, FLAVOR, true>(t, id, def)
    } else {
        run::<C, SEQUENCE, FLAVOR, false>(t, id, def)
    }
}

#[inline(always)]
fn run<C, const SEQUENCE: bool, const FLAVOR: Flavor, const OBSERVED: bool>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
) -> NodeStatus {
    // The outcome that moves the loop on, and the one that ends it.
    let (go_on, stop) = if SEQUENCE {
        (NodeStatus::Success, NodeStatus::Failure)
    } else {
        (NodeStatus::Failure, NodeStatus::Success)
    };
    let bp = t.bp;
    let children = bp.children_of(def);
    let hot = bp.hot_children_of(def);
    let slot = t.bp.slot(id);
    let n = children.len() as u32;
    let (mut cursor, mut skipped) = unpack(t.aux[slot]);
    if !t.status(id).is_active() {
        skipped = 0;
    }
    t.set_status(id, NodeStatus::Running);
    while let Some(child) = hot.get(cursor as usize) {
        let prev = if FLAVOR == PLAIN {
            NodeStatus::Running
        } else {
            t.status(child.id)
        };
        // An if-chain rather than a match: the common case costs one predictable compare
        // instead of an indirect jump through a table.
        let status = t.tick_child::<OBSERVED>(child);
        if status == go_on {
            cursor += 1;
            if FLAVOR != PLAIN && prev == NodeStatus::Idle && cursor < n {
                t.wake = Some(id);
                t.aux[slot] = pack(cursor, skipped);
                return NodeStatus::Running;
            }
        } else if status == NodeStatus::Running {
            t.aux[slot] = pack(cursor, skipped);
            return NodeStatus::Running;
        } else if status == NodeStatus::Skipped {
            cursor += 1;
            skipped += 1;
        } else {
            // `stop` (Idle never leaves `Ticker::tick`).
            if FLAVOR == MEMORY {
                t.halt_children_from(def, cursor);
            } else {
                // Children past the cursor are Idle already.
                t.reset_completed(&children[..=cursor as usize]);
                cursor = 0;
            }
            t.aux[slot] = pack(cursor, skipped);
            return stop;
        }
    }
    let all_skipped = skipped == n;
    t.reset_completed(children);
    t.aux[slot] = 0;
    if all_skipped {
        NodeStatus::Skipped
    } else {
        go_on
    }
}
