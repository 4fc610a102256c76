//! Sequence, SequenceWithMemory and AsyncSequence: do all children, in order.
//!
//! | node | semantics |
//! |---|---|
//! | Sequence | Resume at the stored child index (earlier successes are not re-ticked). Child Failure: halt/reset children, index 0, Failure. Running: Running. All succeeded: reset, Success. |
//! | SequenceWithMemory | As Sequence, but a Failure keeps the index (the failed child is retried next tick) and halt keeps it too; yields after each child success. |
//! | AsyncSequence | As Sequence, but yields (Running + wake-up) after each child that completes. |
//!
//! "Yields" follows BehaviorTree.CPP: only after a child that went from Idle to Success within
//! this tick, and only when children remain; [`Tree::tick_once`](crate::Tree::tick_once) then
//! ticks again at once, [`Tree::tick_exactly_once`](crate::Tree::tick_exactly_once) returns
//! Running. Skipped children count as absent; if all were skipped, the node is Skipped.

use super::{pack, unpack};
use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

/// Which member of the family is ticking; a const parameter so that each member compiles to
/// its own loop without the others' checks.
pub(crate) type Flavor = u8;
/// Sequence.
pub(crate) const PLAIN: Flavor = 0;
/// SequenceWithMemory.
pub(crate) const MEMORY: Flavor = 1;
/// AsyncSequence.
pub(crate) const ASYNC: Flavor = 2;

#[inline(never)]
pub(crate) fn tick<C, const FLAVOR: Flavor>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
) -> NodeStatus {
    if t.observed() {
        run::<C, FLAVOR, true>(t, id, def)
    } else {
        run::<C, FLAVOR, false>(t, id, def)
    }
}

#[inline(always)]
fn run<C, const FLAVOR: Flavor, const OBSERVED: bool>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
) -> NodeStatus {
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
        if status == NodeStatus::Success {
            cursor += 1;
            if FLAVOR != PLAIN && prev == NodeStatus::Idle && cursor < n {
                t.wake = true;
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
            // Failure (Idle never leaves `Ticker::tick`).
            if FLAVOR == MEMORY {
                t.halt_children_from(def, cursor);
            } else {
                // Children past the cursor are Idle already.
                t.reset_completed(&children[..=cursor as usize]);
                cursor = 0;
            }
            t.aux[slot] = pack(cursor, skipped);
            return NodeStatus::Failure;
        }
    }
    let all_skipped = skipped == n;
    t.reset_completed(children);
    t.aux[slot] = 0;
    if all_skipped {
        NodeStatus::Skipped
    } else {
        NodeStatus::Success
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn resumes_at_the_running_child() {
        let mut lab = Lab::new(&[&[S], &[R, S], &[S]]);
        let mut tree = lab.tree(|b| b.sequence("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 2, 1]);
        assert_eq!(lab.halts, [0, 0, 0]);
    }

    #[test]
    fn failure_resets_to_the_first_child() {
        let mut lab = Lab::new(&[&[S], &[F, S], &[S]]);
        let mut tree = lab.tree(|b| b.sequence("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1, 1, 0]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [2, 2, 1]);
    }

    #[test]
    fn memory_retries_the_failed_child() {
        let mut lab = Lab::new(&[&[S], &[F, S], &[S]]);
        let mut tree =
            lab.tree(|b| b.sequence_with_memory("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        // Child 0 is not ticked again: the sequence remembered its place.
        assert_eq!(lab.ticks, [1, 2, 1]);
    }

    #[test]
    fn memory_keeps_its_place_across_a_halt() {
        let mut lab = Lab::new(&[&[S], &[R, R, S], &[S]]);
        let mut tree =
            lab.tree(|b| b.sequence_with_memory("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [0, 1, 0]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 3, 1]);
    }

    #[test]
    fn memory_yields_after_each_success() {
        let mut lab = Lab::new(&[&[S], &[S], &[S]]);
        let mut tree =
            lab.tree(|b| b.sequence_with_memory("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [1, 0, 0]);
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 1, 1]);
        // tick_once re-ticks while woken: one call does all three.
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [2, 2, 2]);
    }

    #[test]
    fn async_yields_only_after_an_immediate_completion() {
        let mut lab = Lab::new(&[&[R, S], &[S], &[S]]);
        let mut tree =
            lab.tree(|b| b.async_sequence("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        // Child 0 was Running before its success, so no yield: child 1 runs in the same tick
        // and yields because it completed from Idle.
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [2, 1, 0]);
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [2, 1, 1]);
    }

    #[test]
    fn plain_sequence_never_yields() {
        let mut lab = Lab::new(&[&[S], &[S], &[S]]);
        let mut tree = lab.tree(|b| b.sequence("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 1, 1]);
    }

    #[test]
    fn all_children_skipped_is_skipped() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| {
            b.sequence("root", |r| {
                r.sequence("inner", |s| s.run_once("once", true, |o| o.scripted(0)))
                    .always_success("after")
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1]);
        let mut lab2 = Lab::new(&[&[S]]);
        let mut solo =
            lab2.tree(|b| b.sequence("inner", |s| s.run_once("once", true, |o| o.scripted(0))));
        assert_eq!(lab2.tick(&mut solo), Ok(Status::Success));
        assert_eq!(lab2.tick(&mut solo), Err(TickError::RootSkipped));
    }

    #[test]
    fn children_are_reset_to_idle_on_completion() {
        let mut lab = Lab::new(&[&[S], &[S]]);
        let mut tree = lab.tree(|b| b.sequence("seq", |s| s.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }
}
