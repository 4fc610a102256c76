//! Fallback (the textbook's Selector) and AsyncFallback: try children in order until one
//! succeeds.
//!
//! | node | semantics |
//! |---|---|
//! | Fallback (Selector) | Mirror of Sequence: resume at the stored child index. Child Success: halt/reset children, index 0, Success. Failure: move on. Running: Running. All failed: reset, Failure. |
//! | AsyncFallback | As Fallback, but yields (Running + wake-up) after each child that failed from Idle within this tick, while children remain. |
//!
//! Skipped children count as absent; if all were skipped, the node is Skipped.

use super::{pack, unpack};
use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

/// `YIELDS` selects AsyncFallback; a const parameter so that Fallback's loop carries no check.
#[inline(never)]
pub(crate) fn tick<C, const YIELDS: bool>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
) -> NodeStatus {
    if t.observed() {
        run::<C, YIELDS, true>(t, id, def)
    } else {
        run::<C, YIELDS, false>(t, id, def)
    }
}

#[inline(always)]
fn run<C, const YIELDS: bool, const OBSERVED: bool>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
) -> NodeStatus {
    let bp = t.bp;
    let children = bp.children_of(def);
    let hot = bp.hot_children_of(def);
    let slot = t.bp.slot(id);
    let n = def.child_count;
    let (mut cursor, mut skipped) = unpack(t.aux[slot]);
    if !t.status(id).is_active() {
        skipped = 0;
    }
    t.set_status(id, NodeStatus::Running);
    while let Some(child) = hot.get(cursor as usize) {
        let prev = if YIELDS {
            t.status(child.id)
        } else {
            NodeStatus::Running
        };
        // An if-chain rather than a match: see `sequence`.
        let status = t.tick_child::<OBSERVED>(child);
        if status == NodeStatus::Failure {
            cursor += 1;
            if YIELDS && prev == NodeStatus::Idle && cursor < n {
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
            // Success (Idle never leaves `Ticker::tick`).
            // Children past the cursor are Idle already.
            t.reset_completed(&children[..=cursor as usize]);
            t.aux[slot] = pack(0, skipped);
            return NodeStatus::Success;
        }
    }
    let all_skipped = skipped == n;
    t.reset_completed(children);
    t.aux[slot] = 0;
    if all_skipped {
        NodeStatus::Skipped
    } else {
        NodeStatus::Failure
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn first_success_wins() {
        let mut lab = Lab::new(&[&[F], &[S], &[S]]);
        let mut tree = lab.tree(|b| b.fallback("fb", |f| f.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 1, 0]);
    }

    #[test]
    fn resumes_at_the_running_child() {
        let mut lab = Lab::new(&[&[F], &[R, F], &[F]]);
        let mut tree = lab.tree(|b| b.fallback("fb", |f| f.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1, 2, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn async_yields_after_an_immediate_failure() {
        let mut lab = Lab::new(&[&[F], &[F], &[S]]);
        let mut tree =
            lab.tree(|b| b.async_fallback("fb", |f| f.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [1, 0, 0]);
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 1, 1]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [2, 2, 2]);
    }

    #[test]
    fn halt_restarts_from_the_first_child() {
        let mut lab = Lab::new(&[&[F], &[R]]);
        let mut tree = lab.tree(|b| b.fallback("fb", |f| f.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [0, 1]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [2, 2]);
    }
}
