//! A run of slots and their tables, shared among the crowd's threads by the work in it
//! rather than by its length.
//!
//! The members a frame ticks often bunch: those alerted together sit in neighbouring slots,
//! and a crowd cut into equal runs of slots would hand one thread all of them. A [`Span`]
//! splits where half its work lies, from a count of the work before each word of 64 slots
//! (the awake members, or the ids a caller named): always down to spans of at most
//! [`most_work`] (or a single word), so that a thread held up in one (its core taken by
//! another process, or a slower core) holds up that span alone while the other threads take
//! the rest; below that, as rayon splits (a few leaves a span, and more whenever it gives
//! work to an idle thread), down to [`LEAST_WORK`], so that a few members with costly trees
//! are still shared.

use std::ops::Range;
use std::sync::atomic::AtomicU64;

use rayon::iter::ParallelIterator;

use super::member::{Body, Plan};
use super::sleep::BITS;

/// A span with less work than this is not split: a split costs about what a few ticks do.
const LEAST_WORK: u32 = 16;

/// A span with more work than this is always split. rayon's own splitting stops at a few
/// leaves per thread, and a thread whose core was taken for a millisecond in a leaf of a
/// quarter of the crowd held up the frame by that millisecond while the others waited.
/// Below it, rayon still cuts a span into four leaves or more on two threads; each leaf
/// costs a few hundred nanoseconds (the split, and its first members ticked before their
/// memory was asked for), and with spans of 256 a frame of 100,000 members all awake had
/// 1,562 leaves where 1,024 gives 514 and a frame 1-2 % shorter on two threads, 2,048 258
/// (BENCHMARKS.md, "Fewer leaves").
const MOST_WORK: u32 = 2048;

/// The most work a span of a frame with `work` in all holds on `threads` threads: a
/// sixteenth of a thread's share, so that the last leaves, which the threads cannot share,
/// are a small part of a short frame (spans of 2,048 made a frame of 3,500 awake members on
/// two threads 2-6 % longer than spans of 256); kept from [`FEWEST_MOST_WORK`] to
/// [`MOST_WORK`].
fn most_work(work: u32, threads: usize) -> u32 {
    let spans = u32::try_from(threads.max(1) * 16).unwrap_or(u32::MAX);
    (work / spans).clamp(FEWEST_MOST_WORK, MOST_WORK)
}

/// The least [`most_work`] gives.
const FEWEST_MOST_WORK: u32 = 256;

/// Slots `first..` of a crowd and their tables, with the crowd's count of work.
pub(super) struct Span<'a, C> {
    /// The crowd's index of the first slot, a multiple of [`BITS`].
    pub(super) first: usize,
    pub(super) plans: &'a mut [Plan],
    pub(super) bodies: &'a mut [Option<Body<C>>],
    pub(super) contexts: &'a mut [Option<C>],
    /// The slots' words of the awake set and of the fell-asleep set, for a frame's ticks.
    pub(super) bits: Option<Bits<'a>>,
    /// For the whole crowd, the work before each word: `work[w + 1] - work[w]` is word
    /// `w`'s.
    work: &'a [u32],
}

/// The words of a span's slots in the awake set and in the fell-asleep set.
pub(super) struct Bits<'a> {
    pub(super) awake: &'a mut [AtomicU64],
    pub(super) fallen: &'a mut [u64],
}

impl<'a, C: Send> Span<'a, C> {
    /// The whole crowd, its work counted in `work` (see [`count_awake`]): a word's work
    /// for each word of its slots, and one more entry.
    pub(super) fn whole(
        plans: &'a mut [Plan],
        bodies: &'a mut [Option<Body<C>>],
        contexts: &'a mut [Option<C>],
        bits: Option<Bits<'a>>,
        work: &'a [u32],
    ) -> Self {
        let words = plans.len().div_ceil(BITS);
        debug_assert_eq!(work.len(), words + 1);
        Self {
            first: 0,
            plans,
            bodies,
            contexts,
            bits: bits.map(|b| Bits {
                awake: &mut b.awake[..words],
                fallen: &mut b.fallen[..words],
            }),
            work,
        }
    }

    /// Runs `leaf` on each leaf of the span, on the threads of the pool it is called in,
    /// and sums the results with `add` (from `R::default()` where rayon splits on its own).
    pub(super) fn fold_leaves<R: Send + Default>(
        self,
        leaf: &(impl Fn(Self) -> R + Sync),
        add: &(impl Fn(R, R) -> R + Sync),
    ) -> R {
        let most = most_work(self.total_work(), rayon::current_num_threads());
        self.fold_within(most, leaf, add)
    }

    /// [`fold_leaves`](Self::fold_leaves), splitting spans of more than `most` work.
    fn fold_within<R: Send + Default>(
        self,
        most: u32,
        leaf: &(impl Fn(Self) -> R + Sync),
        add: &(impl Fn(R, R) -> R + Sync),
    ) -> R {
        if self.total_work() <= most {
            return rayon::iter::split(self, Self::halve)
                .map(leaf)
                .reduce(R::default, add);
        }
        match self.halve() {
            (left, Some(right)) => {
                let (a, b) = rayon::join(
                    || left.fold_within(most, leaf, add),
                    || right.fold_within(most, leaf, add),
                );
                add(a, b)
            }
            (whole, None) => leaf(whole),
        }
    }

    /// The work in the span.
    fn total_work(&self) -> u32 {
        let Range { start, end } = self.words();
        self.work[end] - self.work[start]
    }

    /// The span's words in the crowd's count.
    fn words(&self) -> Range<usize> {
        let w0 = self.first / BITS;
        w0..w0 + self.plans.len().div_ceil(BITS)
    }

    /// Where the span's work lies in the order it was counted: for the ids of
    /// [`Visits`](super::visit::Visits), the span's ids.
    pub(super) fn work_range(&self) -> Range<usize> {
        let words = self.words();
        self.work[words.start] as usize..self.work[words.end] as usize
    }

    /// Splits off the second half of the span's work, at a word boundary; `None` for a
    /// span too small to split.
    fn halve(self) -> (Self, Option<Self>) {
        let Range { start, end } = self.words();
        let (before, after) = (self.work[start], self.work[end]);
        if after - before < LEAST_WORK || end - start < 2 {
            return (self, None);
        }
        let half = before + (after - before) / 2;
        // The first word past the start at which half the work is done, leaving a word or
        // more on each side.
        let at = start + 1 + self.work[start + 1..end].partition_point(|&w| w < half);
        let at = at.min(end - 1);
        let slots = (at - start) * BITS;
        let (plans, plans2) = self.plans.split_at_mut(slots);
        let (bodies, bodies2) = self.bodies.split_at_mut(slots);
        let (contexts, contexts2) = self.contexts.split_at_mut(slots);
        let (bits, bits2) = match self.bits {
            Some(b) => {
                let (awake, awake2) = b.awake.split_at_mut(at - start);
                let (fallen, fallen2) = b.fallen.split_at_mut(at - start);
                (
                    Some(Bits { awake, fallen }),
                    Some(Bits {
                        awake: awake2,
                        fallen: fallen2,
                    }),
                )
            }
            None => (None, None),
        };
        let first = self.first;
        let work = self.work;
        (
            Self {
                first,
                plans,
                bodies,
                contexts,
                bits,
                work,
            },
            Some(Self {
                first: first + slots,
                plans: plans2,
                bodies: bodies2,
                contexts: contexts2,
                bits: bits2,
                work,
            }),
        )
    }
}

/// Counts the awake members before each word of `awake` into `work` (one more entry than
/// words), kept between frames for its room.
pub(super) fn count_awake(awake: &mut [AtomicU64], work: &mut Vec<u32>) {
    work.clear();
    work.push(0);
    let mut sum = 0u32;
    for word in awake {
        sum += word.get_mut().count_ones();
        work.push(sum);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Splits `span` as far as it goes, giving each leaf's first slot and slot count.
    fn leaves(span: Span<'_, ()>, out: &mut Vec<(usize, usize)>) {
        match span.halve() {
            (left, Some(right)) => {
                leaves(left, out);
                leaves(right, out);
            }
            (leaf, None) => out.push((leaf.first, leaf.plans.len())),
        }
    }

    #[test]
    fn spans_split_where_the_work_is_and_cover_every_slot_once() {
        let slots: usize = 64 * 40 + 10;
        let words = slots.div_ceil(BITS);
        let mut plans: Vec<Plan> = (0..slots).map(|_| Plan::new(0)).collect();
        let mut bodies: Vec<Option<Body<()>>> = (0..slots).map(|_| None).collect();
        let mut contexts: Vec<Option<()>> = vec![None; slots];
        // A bunch of awake members in words 30 to 33, nothing elsewhere.
        let mut awake: Vec<AtomicU64> = (0..words)
            .map(|w| AtomicU64::new(if (30..34).contains(&w) { u64::MAX } else { 0 }))
            .collect();
        let mut fallen = vec![0u64; words];
        let mut work = Vec::new();
        count_awake(&mut awake, &mut work);
        assert_eq!((work.len(), work[words]), (words + 1, 4 * 64));
        let bits = Bits {
            awake: &mut awake,
            fallen: &mut fallen,
        };
        let span = Span::whole(&mut plans, &mut bodies, &mut contexts, Some(bits), &work);
        let mut out = Vec::new();
        leaves(span, &mut out);
        // Every slot once, in order.
        let mut next = 0;
        for &(first, len) in &out {
            assert_eq!(first, next);
            next += len;
        }
        assert_eq!(next, slots);
        // The bunch is split word by word: each of its words is a leaf of its own, whatever
        // the length of the idle runs beside it.
        for w in 30..34 {
            assert!(out.contains(&(w * 64, 64)), "{out:?}");
        }
    }

    /// Folds `work` (the work before each word, one more entry than words) over a crowd
    /// of `slots` empty slots on two threads: the sum, and each leaf's first slot, slot
    /// count and work, in slot order.
    fn fold(slots: usize, work: &[u32]) -> (u32, Vec<(usize, usize, u32)>) {
        let mut plans: Vec<Plan> = (0..slots).map(|_| Plan::new(0)).collect();
        let mut bodies: Vec<Option<Body<()>>> = (0..slots).map(|_| None).collect();
        let mut contexts: Vec<Option<()>> = vec![None; slots];
        let span = Span::whole(&mut plans, &mut bodies, &mut contexts, None, work);
        let seen = std::sync::Mutex::new(Vec::new());
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let summed = pool.install(|| {
            span.fold_leaves(
                &|leaf: Span<'_, ()>| {
                    let work = leaf.work_range().len() as u32;
                    seen.lock()
                        .unwrap()
                        .push((leaf.first, leaf.plans.len(), work));
                    work
                },
                &|a, b| a + b,
            )
        });
        let mut seen = seen.into_inner().unwrap();
        seen.sort_unstable();
        // Every slot once, in order.
        let mut next = 0;
        for &(first, len, _) in &seen {
            assert_eq!(first, next, "{seen:?}");
            next += len;
        }
        assert_eq!(next, slots);
        (summed, seen)
    }

    #[test]
    fn leaves_hold_at_most_the_most_work_and_their_sums_add_up() {
        let slots: usize = 64 * 400 + 7;
        let words = slots.div_ceil(BITS);
        // Every slot of words 0 to 199 awake, one in two of words 200 to 299, none after.
        let mut awake: Vec<AtomicU64> = (0..words)
            .map(|w| {
                AtomicU64::new(match w {
                    0..200 => u64::MAX,
                    200..300 => 0x5555_5555_5555_5555,
                    _ => 0,
                })
            })
            .collect();
        let mut work = Vec::new();
        count_awake(&mut awake, &mut work);
        let total = 200 * 64 + 100 * 32;
        assert_eq!(work[words], total);
        let (summed, seen) = fold(slots, &work);
        assert_eq!(summed, total);
        let most = most_work(total, 2);
        assert_eq!(most, total / 32);
        for &(_, len, work) in &seen {
            assert!(work <= most || len <= BITS, "{seen:?}");
        }
        assert!(seen.len() >= 32, "{seen:?}");

        // The most work a span holds, from 256 to 2,048.
        assert_eq!(
            [0, 3_500, 100_000, 1_000_000].map(|w| most_work(w, 2)),
            [256, 256, 2048, 2048]
        );
        assert_eq!(most_work(1_000_000, 64), 976);

        // One word with more than the most work (ids named many times over): a leaf of its
        // own, whatever its work.
        let much = MOST_WORK + 44;
        let (summed, seen) = fold(3 * 64, &[0, much, much, much]);
        assert_eq!(summed, much);
        assert!(seen.contains(&(0, 64, much)), "{seen:?}");

        // Little work in all: the sum is the same however rayon splits it.
        let (summed, seen) = fold(8 * 64, &[0, 10, 30, 30, 60, 100, 100, 140, 200]);
        assert_eq!((summed, seen.iter().map(|l| l.2).sum::<u32>()), (200, 200));
    }
}
