//! The ids a caller names for [`Crowd::for_each_mut`](super::Crowd::for_each_mut), sorted
//! by the word of 64 slots they fall in, so that the crowd's threads can share them out by
//! [`Span`](super::span::Span)s.
//!
//! A counting sort: two passes over the ids and one over the words, so that naming a few
//! members of a large crowd costs little more than the few. Within a word the ids keep the
//! caller's order, so that a member named twice is visited in that order.
//!
//! Members named are far apart in memory as often as not: each visit asks for the memory
//! of the member [`FAR`] ids later, and for the blackboard of the one [`NEAR`] ids later,
//! so that the visits' trips to memory overlap.

use neurotree_core::hint::prefetch;

use super::member::{Body, Plan};
use super::sleep::{BITS, FAR, NEAR};
use super::span::Span;
use super::{Crowd, FrameReport, MemberId, MemberMut};

impl<C: Send> Crowd<C> {
    /// Calls `f` on each member `ids` names, in parallel on the crowd's threads: to deliver
    /// what happened to many members between frames (an alert written to each one's
    /// blackboard, which wakes it), where [`get_mut`](Self::get_mut) one by one would do it
    /// on one thread. Ids of members that left are skipped; a member named twice is visited
    /// twice, one visit after the other, in the order of `ids`. Shared among threads, the
    /// members are visited by words of 64 slots in slot order, and within a word in the
    /// order of `ids`, so that each thread walks its share of memory in order: `f` must not
    /// depend on the order of members far apart. Fewer than [`SHARED_VISITS`] ids, or a
    /// crowd on one thread, are visited on the calling thread in the order of `ids`, since
    /// handing them to the pool would cost more than the visits.
    ///
    /// To deliver a frame's events and then run the frame, [`frame_with`](Self::frame_with)
    /// does both in one trip to the crowd's threads.
    pub fn for_each_mut(&mut self, ids: &[MemberId], f: impl Fn(MemberMut<'_, C>) + Send + Sync) {
        if ids.len() < SHARED_VISITS || self.threads() == 1 {
            self.visit_in_order(ids, &f);
            return;
        }
        self.in_pool(|crowd| crowd.visit_shared(ids, &f));
    }

    /// Calls `f` on each member `ids` names, then runs a frame: the same visits, ticks and
    /// report as [`for_each_mut`](Self::for_each_mut) followed by [`frame`](Self::frame),
    /// in one trip to the crowd's threads rather than two. As a game delivers a frame's
    /// events (a blackboard write that wakes a sleeping agent) just before the frame.
    ///
    /// The visits follow `for_each_mut`'s order, except that on a crowd with more than one
    /// thread they are shared among its threads from [`SHARED_IN_FRAME`] ids on (the
    /// frame's threads are at work already), visited by words of 64 slots in slot order:
    /// `f` must not depend on the order of members far apart.
    pub fn frame_with(
        &mut self,
        ids: &[MemberId],
        f: impl Fn(MemberMut<'_, C>) + Send + Sync,
    ) -> FrameReport {
        let shared = ids.len() >= SHARED_IN_FRAME && self.threads() > 1;
        self.frame_after(move |crowd: &mut Self, inline: bool| {
            if shared && !inline {
                crowd.visit_shared(ids, &f);
            } else {
                crowd.visit_in_order(ids, &f);
            }
        })
    }

    /// Visits the members `ids` names on this thread, in the order of `ids`.
    fn visit_in_order(&mut self, ids: &[MemberId], f: &(impl Fn(MemberMut<'_, C>) + Sync)) {
        for (k, &id) in ids.iter().enumerate() {
            ahead(&self.plans, &self.bodies, &self.contexts, ids, k);
            if let Some(member) = self.get_mut(id) {
                f(member);
            }
        }
    }

    /// Visits the members `ids` names on the crowd's threads (call it in the pool), by
    /// words in slot order.
    fn visit_shared(&mut self, ids: &[MemberId], f: &(impl Fn(MemberMut<'_, C>) + Sync)) {
        let Self {
            plans,
            bodies,
            contexts,
            awake,
            clock,
            visits,
            ..
        } = self;
        visits.sort(ids, plans.len());
        let (awake, clock, named) = (&*awake, &*clock, &visits.ids);
        let whole = Span::whole(plans, bodies, contexts, None, &visits.starts);
        let visit = |span: Span<'_, C>| {
            let first = span.first;
            let named = &named[span.work_range()];
            for (k, &id) in named.iter().enumerate() {
                // The span's own slots, counted from its first.
                let local = |id: MemberId| MemberId {
                    index: id.index - first as u32,
                    ..id
                };
                if let Some(&far) = named.get(k + FAR) {
                    ask_far(span.plans, span.bodies, span.contexts, local(far));
                }
                if let Some(&near) = named.get(k + NEAR) {
                    ask_near(span.bodies, local(near));
                }
                let i = id.index as usize - first;
                let (plan, body, ctx) = (
                    &mut span.plans[i],
                    &mut span.bodies[i],
                    &mut span.contexts[i],
                );
                if let Some(member) = MemberMut::of(id, plan, body, ctx, awake, clock) {
                    f(member);
                }
            }
        };
        whole.fold_leaves(&visit, &|(), ()| ());
    }
}

/// Before the visit of `ids[k]`, asks for the memory of the members visited a little later.
#[inline]
fn ahead<C>(
    plans: &[Plan],
    bodies: &[Option<Body<C>>],
    contexts: &[Option<C>],
    ids: &[MemberId],
    k: usize,
) {
    if let Some(&far) = ids.get(k + FAR) {
        ask_far(plans, bodies, contexts, far);
    }
    if let Some(&near) = ids.get(k + NEAR) {
        ask_near(bodies, near);
    }
}

/// Starts loading the schedule, the tree's own bytes and the context of member `id` (its
/// slot counted in the tables given); nothing for a slot past them.
#[inline]
fn ask_far<C>(plans: &[Plan], bodies: &[Option<Body<C>>], contexts: &[Option<C>], id: MemberId) {
    let i = id.index as usize;
    if let (Some(plan), Some(body), Some(ctx)) = (plans.get(i), bodies.get(i), contexts.get(i)) {
        prefetch(plan);
        prefetch(body);
        prefetch(ctx);
    }
}

/// Starts loading the blackboard's root entries of member `id`, whose tree [`ask_far`]
/// asked for. Not its node state: a visit that writes the blackboard does not read it,
/// and the frame's ticks ask for it in time; asked for here too, it crowded the trips to
/// memory of the visits that came next (BENCHMARKS.md, "Visits ask for less").
#[inline]
fn ask_near<C>(bodies: &[Option<Body<C>>], id: MemberId) {
    if let Some(Some(body)) = bodies.get(id.index as usize) {
        body.tree.prefetch_blackboard();
    }
}

/// The fewest ids [`Crowd::frame_with`] shares among the crowd's threads: a split costs
/// about what a few visits do once the frame's threads are at work.
pub const SHARED_IN_FRAME: usize = 64;

/// The fewest ids [`Crowd::for_each_mut`] shares among the crowd's threads: a few thousand
/// visits take about as long as waking a thread of the pool.
pub const SHARED_VISITS: usize = 4096;

/// Ids sorted by word, and where each word's begin; kept between calls for their room.
#[derive(Debug, Default)]
pub(super) struct Visits {
    pub(super) ids: Vec<MemberId>,
    /// `starts[w]..starts[w + 1]`: word `w`'s ids in `ids`, which is also the count of ids
    /// before each word that a [`Span`](super::span::Span) splits by.
    pub(super) starts: Vec<u32>,
}

impl Visits {
    /// Sorts `ids` by word, for a crowd of `slots` slots; ids past them are dropped.
    pub(super) fn sort(&mut self, ids: &[MemberId], slots: usize) {
        let words = slots.div_ceil(BITS);
        self.starts.clear();
        self.starts.resize(words + 1, 0);
        for id in ids {
            if (id.index as usize) < slots {
                self.starts[id.index as usize / BITS + 1] += 1;
            }
        }
        for c in 0..words {
            self.starts[c + 1] += self.starts[c];
        }
        self.ids.clear();
        let blank = MemberId {
            index: 0,
            generation: 0,
        };
        self.ids.resize(self.starts[words] as usize, blank);
        // `starts[c]` moves along chunk `c`'s share as it is filled, ending where chunk
        // `c + 1`'s begins; one shift puts them back.
        for &id in ids {
            if (id.index as usize) < slots {
                let at = &mut self.starts[id.index as usize / BITS];
                self.ids[*at as usize] = id;
                *at += 1;
            }
        }
        self.starts.copy_within(0..words, 1);
        self.starts[0] = 0;
    }

    /// Each word's ids, in word order.
    #[cfg(test)]
    fn parts(&self) -> Vec<Vec<MemberId>> {
        self.starts
            .windows(2)
            .map(|w| self.ids[w[0] as usize..w[1] as usize].to_vec())
            .filter(|part| !part.is_empty())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn id(index: u32) -> MemberId {
        MemberId {
            index,
            generation: index % 3,
        }
    }

    #[test]
    fn ids_are_grouped_by_word_keeping_their_order_within_one() {
        let mut visits = Visits::default();
        let named = [id(130), id(5), id(70), id(3), id(5), id(9000), id(129)];
        visits.sort(&named, 140);
        assert_eq!(visits.starts, [0, 3, 4, 6]);
        assert_eq!(
            visits.parts(),
            [
                vec![id(5), id(3), id(5)],
                vec![id(70)],
                vec![id(130), id(129)]
            ]
        );
        // Sorted again, the room is reused and nothing of the last call is left.
        visits.sort(&[id(7)], 10);
        assert_eq!(visits.parts(), [vec![id(7)]]);
    }
}
