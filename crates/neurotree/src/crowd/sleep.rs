//! Sleeping members: a member whose tree [sleeps](crate::tree::sleep) costs a frame nothing
//! until it wakes: the frame neither visits its schedule nor looks at its tree or context.
//!
//! The crowd keeps one bit per slot, set while the slot's member is awake, and a frame
//! walks the set bits only (64 slots per word read; a word of sleepers is skipped in one
//! comparison). A member that falls asleep in a tick clears its bit; if its tree wakes on
//! its own at a deadline (the earliest its nodes declared), the deadline goes into a
//! binary heap of timers, which the start of every frame pops up to the clock's reading,
//! setting those members' bits again: a member wakes in the first frame whose clock
//! reaches its deadline, exactly as a tree ticked every frame would. A member woken early
//! leaves its timer in the heap; the timer is dropped when it comes up (its member no
//! longer sleeps until that moment), and the heap is compacted when stale timers outnumber
//! the slots.
//!
//! Each chunk of [`CHUNK`](super::schedule::CHUNK) slots has a heap of its own, and the
//! members that fell asleep in a frame are noted in a second set of bits by the thread
//! that ticked them: the start of the next frame marks them asleep, times them and pops the
//! deadlines chunk by chunk on all the crowd's threads, so that a crowd that mostly sleeps
//! keeps every core busy rather than waiting on one.
//!
//! A sleeping member wakes when the crowd's clock reaches its deadline, or earlier when:
//!
//! - the program changes its tree between frames ([`MemberMut::tree_mut`] and
//!   [`MemberMut::tree_and_context_mut`] wake it, since the blackboard may be written);
//! - the program wakes it: [`MemberMut::wake`], [`Crowd::wake`], or from any thread a
//!   [`CrowdWaker`], whose wakes the next frame applies;
//! - the crowd halts its tree ([`Crowd::halt_all`], [`MemberMut::replace_tree`]): a halted
//!   tree starts over at its next tick;
//! - its tree's own [`HaltHandle`](crate::HaltHandle) asks for a halt, from any thread: the
//!   member's next due frame ticks it, and the tick serves the request, as a tree ticked
//!   every frame would. The crowd registers a waker of its own on the wake signal of each
//!   sleeping tree that has a halt handle, which queues the member's wake as a
//!   [`CrowdWaker`] does (it replaces a waker registered there by other code).
//!
//! A tree's own [`WakeHandle`](crate::WakeHandle) is not seen by a crowd until the member
//! is ticked again, unless the tree has a halt handle: in a crowd, wake members through the
//! crowd. Writing a member's context
//! does not wake it: a leaf that declared what it waits on promised that its result does
//! not depend on anything else.
//!
//! A sleeping member's [`FrameStatus`] is [`Asleep`](FrameStatus::Asleep) from the frame
//! after the tick that put it to sleep until it is ticked again, whatever its interval.
//!
//! [`MemberMut::tree_mut`]: super::MemberMut::tree_mut
//! [`MemberMut::tree_and_context_mut`]: super::MemberMut::tree_and_context_mut
//! [`MemberMut::wake`]: super::MemberMut::wake
//! [`MemberMut::replace_tree`]: super::MemberMut::replace_tree

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::task::{Wake, Waker};
use std::time::Duration;

use rayon::prelude::*;

use super::member::{FrameStatus, Plan};
use super::schedule::CHUNK;
use super::{Crowd, MemberId};
use crate::Tree;

/// `Plan::sleeps_until` of a member that is awake.
pub(super) const AWAKE: u64 = 0;

/// Bits of the awake set per word.
pub(super) const BITS: usize = 64;

/// When a member whose tree was just ticked wakes: [`AWAKE`] if its tree is awake, the
/// clock reading in nanoseconds of its earliest deadline, `u64::MAX` if it waits only for
/// a wake.
pub(super) fn sleeps_until<C>(tree: &Tree<C>) -> u64 {
    if !tree.is_asleep() {
        return AWAKE;
    }
    tree.wakes_at().map_or(u64::MAX, nanos).max(1)
}

/// A clock reading in nanoseconds.
pub(super) fn nanos(d: Duration) -> u64 {
    u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)
}

/// A member that fell asleep, and when it wakes on its own.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct Timer {
    /// Clock nanoseconds; `u64::MAX`: only a wake wakes it.
    pub(super) until: u64,
    pub(super) slot: u32,
    pub(super) generation: u32,
}

impl Timer {
    /// The timer of the member `plan` schedules, in `slot`, asleep now.
    pub(super) fn of(plan: &Plan, slot: usize) -> Self {
        Self {
            until: plan.sleeps_until,
            slot: slot as u32,
            generation: plan.generation,
        }
    }

    /// `true` if the member `plan` schedules (in the timer's slot) still sleeps as it did
    /// when the timer was set.
    fn holds(&self, plan: &Plan) -> bool {
        plan.present() && plan.generation == self.generation && plan.sleeps_until == self.until
    }
}

/// Which members are awake: a bit per slot. Atomic, so that members handed out together by
/// [`Crowd::iter_mut`] or [`Crowd::for_each_mut`] can each wake their own. The members
/// asleep are those present whose bit is clear, counted when asked rather than kept in a
/// count that every thread waking a member would write.
#[derive(Debug, Default)]
pub(super) struct Awake {
    pub(super) bits: Vec<AtomicU64>,
}

impl Awake {
    /// Makes room for `slots` slots.
    pub(super) fn grow(&mut self, slots: usize) {
        let words = slots.div_ceil(BITS);
        if self.bits.len() < words {
            self.bits.resize_with(words, AtomicU64::default);
        }
    }

    /// Marks the member in `slot` awake (a member that joins, or one woken).
    pub(super) fn set(&self, slot: usize) {
        let bit = 1u64 << (slot % BITS);
        self.bits[slot / BITS].fetch_or(bit, Ordering::Relaxed);
    }

    /// Marks the member in `slot` asleep, or no longer there.
    pub(super) fn clear(&self, slot: usize) {
        Self::clear_in(&self.bits, slot);
    }

    /// Clears the bit of `slot` in `words`, a part of the set.
    pub(super) fn clear_in(words: &[AtomicU64], slot: usize) {
        let bit = 1u64 << (slot % BITS);
        words[slot / BITS].fetch_and(!bit, Ordering::Relaxed);
    }

    /// Wakes the sleeping member `plan` schedules in `slot`: sets its bit.
    pub(super) fn wake(&self, plan: &mut Plan, slot: usize) {
        if plan.sleeps_until == AWAKE {
            return;
        }
        plan.sleeps_until = AWAKE;
        self.set(slot);
    }

    /// Members awake: the bits set.
    pub(super) fn count(&self) -> usize {
        self.bits
            .iter()
            .map(|w| w.load(Ordering::Relaxed).count_ones() as usize)
            .sum()
    }
}

/// Calls `tick` with the index (in `words`' slots) of each member whose bit is set, in slot
/// order; `tick` returns `false` when the member fell asleep, which clears its bit.
#[inline]
pub(super) fn for_each_awake(words: &mut [AtomicU64], mut tick: impl FnMut(usize) -> bool) {
    for (w, word) in words.iter_mut().enumerate() {
        let bits = word.get_mut();
        let mut left = *bits;
        while left != 0 {
            let b = left.trailing_zeros() as usize;
            left &= left - 1;
            if !tick(w * BITS + b) {
                *bits &= !(1u64 << b);
            }
        }
    }
}

/// What [`for_each_awake_ahead`] asks of its visitor for a member.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Ahead {
    /// The member comes [`FAR`] members later: start loading its schedule, its tree's own
    /// bytes and its context.
    Far,
    /// The member comes [`NEAR`] members later, its tree's bytes loaded by now: start
    /// loading the node state and the blackboard's root entries they point to.
    Near,
    /// Tick the member (if due): `false` when it fell asleep, which clears its bit.
    Tick,
}

/// How many awake members ahead of the one ticked a frame asks for their schedules, trees
/// and contexts; a trip to memory takes about as long as a few ticks.
pub(super) const FAR: usize = 4;

/// How many members ahead a frame asks for their node state, whose address it reads in
/// their tree, asked for [`FAR`] members ahead.
pub(super) const NEAR: usize = 2;

/// As [`for_each_awake`] over at most [`CHUNK`](super::schedule::CHUNK) slots, but asking
/// `visit` to start loading each member's memory before its turn ([`Ahead`]): the awake
/// members of a crowd that mostly sleeps lie far apart, and each would otherwise wait
/// for memory, one after another.
///
/// `slots` is room for the chunk's awake slots, lent by the caller so that a frame does not
/// clear 2 KiB for each chunk of a million members, most of them asleep.
#[inline]
pub(super) fn for_each_awake_ahead(
    words: &mut [AtomicU64],
    slots: &mut [u16; super::schedule::CHUNK],
    mut visit: impl FnMut(usize, Ahead) -> bool,
) {
    let mut n = 0;
    for (w, word) in words.iter_mut().enumerate() {
        let mut left = *word.get_mut();
        while left != 0 {
            slots[n] = (w * BITS + left.trailing_zeros() as usize) as u16;
            n += 1;
            left &= left - 1;
        }
    }
    let slots = &slots[..n];
    // The first members are asked for at once: the loop asks for each member a few ahead
    // of its turn, and the first ones of every chunk (and of every leaf of a frame on two
    // threads, which starts a chunk of its own) would otherwise each wait for memory.
    for &first in &slots[..FAR.min(n)] {
        visit(usize::from(first), Ahead::Far);
    }
    for (k, &slot) in slots.iter().enumerate() {
        if let Some(&far) = slots.get(k + FAR) {
            visit(usize::from(far), Ahead::Far);
        }
        if let Some(&near) = slots.get(k + NEAR) {
            visit(usize::from(near), Ahead::Near);
        }
        let i = usize::from(slot);
        if !visit(i, Ahead::Tick) {
            *words[i / BITS].get_mut() &= !(1u64 << (i % BITS));
        }
    }
}

/// The timers of sleeping members, and those that fell asleep in the last frame.
#[derive(Debug, Default)]
pub(super) struct Timers {
    /// Per chunk of slots, the deadlines of its sleepers.
    heaps: Vec<BinaryHeap<Reverse<Timer>>>,
    /// A bit per slot, set for a member that fell asleep in the last frame, by the
    /// frame's threads; the start of the next frame handles and clears them.
    pub(super) fallen: Vec<u64>,
    /// Per chunk of slots, members just marked asleep whose tree has a halt handle, whose
    /// wake signal the crowd is to watch (see [`watch_signal`]).
    watch: Vec<Vec<Timer>>,
    /// The waker's queue, swapped out at the start of a frame, kept for its room.
    woken: Vec<MemberId>,
    /// Per slot, the waker registered on its sleeping tree's wake signal (see
    /// [`watch_signal`]), kept for the slot's member so that falling asleep again
    /// allocates nothing.
    signals: Vec<Option<(u32, Waker)>>,
}

impl Timers {
    /// Forgets that the member in `slot` fell asleep in the last frame: it was held, or it
    /// left.
    pub(super) fn forget_fallen(&mut self, slot: usize) {
        if let Some(word) = self.fallen.get_mut(slot / BITS) {
            *word &= !(1 << (slot % BITS));
        }
    }
}

/// Queues its member's wake on the crowd's [`CrowdWaker`] when woken: registered on the
/// wake signal of a sleeping tree with a [`HaltHandle`](crate::HaltHandle), so that a
/// request wakes the member.
struct SignalWake {
    waker: CrowdWaker,
    id: MemberId,
}

impl Wake for SignalWake {
    fn wake(self: Arc<Self>) {
        self.waker.wake(self.id);
    }

    fn wake_by_ref(self: &Arc<Self>) {
        self.waker.wake(self.id);
    }
}

/// Has the crowd hear of what wakes the signal of `tree`, asleep in member `id`: a halt
/// request from its [`HaltHandle`](crate::HaltHandle). A request made before the waker is
/// registered (between the tick that put the member to sleep and this) queues the wake
/// at once.
fn watch_signal<C>(
    signals: &mut Vec<Option<(u32, Waker)>>,
    crowd: &CrowdWaker,
    id: MemberId,
    tree: &mut Tree<C>,
) {
    let slot = id.index as usize;
    if signals.len() <= slot {
        signals.resize_with(slot + 1, || None);
    }
    let waker = match &signals[slot] {
        Some((generation, waker)) if *generation == id.generation => waker,
        _ => {
            let waker = Waker::from(Arc::new(SignalWake {
                waker: crowd.clone(),
                id,
            }));
            &signals[slot].insert((id.generation, waker)).1
        }
    };
    let pending = tree.halt_requested();
    let signal = tree.wake_signal();
    signal.register(waker);
    if pending || signal.is_woken() {
        crowd.wake(id);
    }
}

/// Wakes members of a crowd from any thread: the next frame ticks them whatever they wait
/// on. Clones share one queue.
#[derive(Clone, Debug, Default)]
pub struct CrowdWaker {
    queue: Arc<Mutex<Vec<MemberId>>>,
}

impl CrowdWaker {
    /// Wakes member `id` at the start of the crowd's next frame (nothing if it has left).
    pub fn wake(&self, id: MemberId) {
        self.queue
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(id);
    }
}

impl<C: Send> Crowd<C> {
    /// A waker for this crowd's members, to hand to other threads or event handlers.
    pub fn waker(&self) -> CrowdWaker {
        self.waker.clone()
    }

    /// Wakes member `id`: its next due frame ticks it. `false` if `id` names no member.
    pub fn wake(&mut self, id: MemberId) -> bool {
        match self.get_mut(id) {
            Some(mut member) => {
                member.wake();
                true
            }
            None => false,
        }
    }

    /// Members whose tree sleeps now (or that are [held](Self::hold)).
    pub fn asleep(&self) -> usize {
        self.len - self.awake.count()
    }

    /// Readies the frame's sleepers: the wakes queued through [`CrowdWaker`]s wake their
    /// members; the members that fell asleep in the last frame are marked asleep and their
    /// deadlines set; the deadlines the clock reached wake their members. Runs on the
    /// frame's threads (call it in the pool), or with `inline` on the caller's alone (see
    /// [`Crowd::runs_inline`]).
    pub(super) fn start_sleep_frame(&mut self, inline: bool) {
        let chunks = self.plans.len().div_ceil(CHUNK);
        let timers = &mut self.timers;
        if timers.fallen.len() < self.awake.bits.len() {
            timers.fallen.resize(self.awake.bits.len(), 0);
        }
        if timers.watch.len() < chunks {
            timers.watch.resize_with(chunks, Vec::new);
        }
        if timers.heaps.len() < chunks {
            timers.heaps.resize_with(chunks, BinaryHeap::new);
        }
        self.apply_wakes();
        let Self {
            plans,
            bodies,
            awake,
            timers,
            waker,
            clock,
            ..
        } = self;
        let now = nanos(clock.now());
        // The members that fell asleep are marked from their schedules alone: their trees,
        // elsewhere in memory, are read only for those to watch (below).
        // The same chunks either way; rayon's parallel iterators and the standard ones are
        // different types, so the walk is written out for each.
        if inline {
            plans
                .chunks_mut(CHUNK)
                .zip(awake.bits.chunks_mut(CHUNK / BITS))
                .zip(timers.fallen.chunks_mut(CHUNK / BITS))
                .zip(timers.heaps.iter_mut())
                .zip(timers.watch.iter_mut())
                .enumerate()
                .for_each(|(c, chunk)| ready_chunk(c, chunk, now));
        } else {
            plans
                .par_chunks_mut(CHUNK)
                .zip(awake.bits.par_chunks_mut(CHUNK / BITS))
                .zip(timers.fallen.par_chunks_mut(CHUNK / BITS))
                .zip(timers.heaps.par_iter_mut())
                .zip(timers.watch.par_iter_mut())
                .enumerate()
                // At most 8 chunks per job: the members that fell asleep bunch (those alerted
                // together) and the threads must share a bunch, but a job per chunk cost a
                // crowd that mostly sleeps more in handing out a thousand jobs than their work.
                .with_max_len(8)
                .for_each(|(c, chunk)| ready_chunk(c, chunk, now));
        }
        let mut watched = false;
        for timer in timers.watch.iter_mut().flat_map(|w| w.drain(..)) {
            if let Some(body) = &mut bodies[timer.slot as usize] {
                let id = MemberId {
                    index: timer.slot,
                    generation: timer.generation,
                };
                watch_signal(&mut timers.signals, waker, id, &mut body.tree);
                watched = true;
            }
        }
        if watched {
            // A halt asked for before its signal was watched queued a wake just now.
            self.apply_wakes();
        }
        self.keep_held();
    }

    /// Wakes the members the [`CrowdWaker`]s named since the last frame. A member that fell
    /// asleep in the last frame is marked asleep first, as the frame's start would have
    /// marked it, so that its status does not depend on whether it was woken.
    fn apply_wakes(&mut self) {
        let Self {
            plans,
            bodies,
            awake,
            timers,
            waker,
            ..
        } = self;
        std::mem::swap(
            &mut *waker.queue.lock().unwrap_or_else(PoisonError::into_inner),
            &mut timers.woken,
        );
        for id in timers.woken.drain(..) {
            let slot = id.index as usize;
            if let Some(plan) = plans.get_mut(slot)
                && plan.present()
                && plan.generation == id.generation
            {
                if plan.sleeps_until != AWAKE {
                    plan.status = FrameStatus::Asleep;
                }
                awake.wake(plan, slot);
                if let Some(body) = &mut bodies[slot] {
                    body.tree.wake_up();
                }
            }
        }
    }
}

/// After a member's tick: `true` if it is still awake, else its bit is set in `fallen`
/// (the words of the slots `i` counts from), for the next frame to mark and to time.
#[inline]
pub(super) fn stays_awake(plan: &Plan, i: usize, fallen: &mut [u64]) -> bool {
    if plan.sleeps_until == AWAKE {
        return true;
    }
    fallen[i / BITS] |= 1 << (i % BITS);
    false
}

/// The slots of one chunk, `c`, and its timers, as the start of a frame readies them.
type Chunk<'a> = (
    (
        ((&'a mut [Plan], &'a mut [AtomicU64]), &'a mut [u64]),
        &'a mut BinaryHeap<Reverse<Timer>>,
    ),
    &'a mut Vec<Timer>,
);

/// Readies chunk `c` for a frame at `now`: its members that fell asleep in the last frame
/// are marked asleep and timed, and the deadlines `now` reached wake their members.
fn ready_chunk(c: usize, chunk: Chunk<'_>, now: u64) {
    let ((((plans, words), fallen), heap), watch) = chunk;
    let base = c * CHUNK;
    for (w, word) in fallen.iter_mut().enumerate() {
        let mut left = std::mem::take(word);
        while left != 0 {
            let i = w * BITS + left.trailing_zeros() as usize;
            left &= left - 1;
            fell_asleep(&mut plans[i], base + i, heap, watch);
        }
    }
    while let Some(&Reverse(timer)) = heap.peek() {
        if timer.until > now {
            break;
        }
        heap.pop();
        let i = timer.slot as usize - base;
        if timer.holds(&plans[i]) {
            plans[i].sleeps_until = AWAKE;
            *words[i / BITS].get_mut() |= 1u64 << (i % BITS);
        }
    }
    // Each sleeper holds one timer at most: past twice the slots, most are stale.
    if heap.len() > 2 * plans.len() + 64 {
        heap.retain(|Reverse(t)| t.holds(&plans[t.slot as usize - base]));
    }
}

/// At the start of the frame after its member (in `slot`) fell asleep: unless something
/// woke it or took it away since, marks it asleep, times it in `heap`, and notes in
/// `watch` a tree whose halt handle is to wake it.
fn fell_asleep(
    plan: &mut Plan,
    slot: usize,
    heap: &mut BinaryHeap<Reverse<Timer>>,
    watch: &mut Vec<Timer>,
) {
    if !plan.present() || plan.sleeps_until == AWAKE {
        return;
    }
    plan.status = FrameStatus::Asleep;
    let timer = Timer::of(plan, slot);
    if plan.fell_asleep_with_halt_handle() {
        watch.push(timer);
    }
    if timer.until != u64::MAX {
        heap.push(Reverse(timer));
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;
    use std::time::Duration;

    use crate::crowd::{Crowd, FrameStatus};
    use crate::{Blueprint, Handle, ManualClock, StatefulAction, Status};

    /// Counts its calls; Running, asleep for ten seconds from each call.
    struct Nap;

    impl StatefulAction<u32> for Nap {
        fn on_start(&mut self, h: &mut Handle<'_, u32>) -> Status {
            self.on_running(h)
        }
        fn on_running(&mut self, h: &mut Handle<'_, u32>) -> Status {
            *h.ctx_mut() += 1;
            let at = h.now() + Duration::from_secs(10);
            h.sleep_until(at);
            Status::Running
        }
    }

    /// Every awake slot is ticked once, in slot order, across words; each is asked for
    /// FAR and NEAR members ahead of its tick, in that order, when that many come
    /// before it, and the first FAR ones for their memory before any tick; a tick that
    /// returns `false` clears the slot's bit and no other.
    #[test]
    fn awake_slots_are_ticked_in_order_each_asked_for_ahead_of_its_tick() {
        use super::{for_each_awake_ahead, Ahead, FAR, NEAR};
        use std::sync::atomic::AtomicU64;
        let set = [0usize, 3, 63, 64, 65, 200, 201, 255, 700, 1023];
        for n in 0..=set.len() {
            let slots = &set[..n];
            let mut words: Vec<AtomicU64> = (0..16).map(|_| AtomicU64::new(0)).collect();
            for &s in slots {
                *words[s / 64].get_mut() |= 1 << (s % 64);
            }
            let mut seen = Vec::new();
            // Room left over from another chunk's slots, as a frame lends it.
            let mut room = [1023u16; 1024];
            // Odd slots fall asleep.
            for_each_awake_ahead(&mut words, &mut room, |i, step| {
                seen.push((i, step));
                step != Ahead::Tick || i % 2 == 0
            });
            let ticks: Vec<usize> = seen
                .iter()
                .filter(|(_, s)| *s == Ahead::Tick)
                .map(|(i, _)| *i)
                .collect();
            assert_eq!(ticks, slots);
            for (k, &slot) in slots.iter().enumerate() {
                let at = |step: Ahead| seen.iter().position(|&e| e == (slot, step));
                let tick = at(Ahead::Tick).unwrap();
                for (ahead, step) in [(FAR, Ahead::Far), (NEAR, Ahead::Near)] {
                    // Asked for when the member `ahead` before it was ticked; the first FAR
                    // for their memory before the first tick; the first NEAR not otherwise.
                    let asked = at(step);
                    match k.checked_sub(ahead) {
                        Some(before) => {
                            let prior =
                                seen.iter().position(|&e| e == (slots[before], Ahead::Tick));
                            let asked = asked.expect("asked for");
                            assert!(asked < prior.unwrap() && asked < tick, "{slot} {step:?}");
                        }
                        None if step == Ahead::Far => {
                            let first = seen.iter().position(|e| e.1 == Ahead::Tick);
                            assert!(asked.expect("asked for") < first.unwrap(), "{slot}");
                        }
                        None => assert_eq!(asked, None, "{slot} {step:?}"),
                    }
                    // Asked for once at most.
                    let times = seen.iter().filter(|&&e| e == (slot, step)).count();
                    assert_eq!(times, usize::from(asked.is_some()), "{slot} {step:?}");
                }
            }
            for s in 0..1024 {
                let bit = *words[s / 64].get_mut() >> (s % 64) & 1 == 1;
                assert_eq!(bit, slots.contains(&s) && s % 2 == 0, "slot {s}");
            }
        }
    }

    /// Members woken early leave a stale timer each time: the heap is compacted
    /// before it passes twice the slots, and the timers that hold still wake their members
    /// exactly at their deadlines.
    #[test]
    fn stale_timers_are_dropped_and_live_ones_still_fire_on_time() {
        let clock = ManualClock::new();
        let mut crowd = Crowd::new(clock.clone()).with_threads(1).unwrap();
        let nap = Blueprint::<u32>::builder()
            .stateful("nap", || Nap)
            .build_shared()
            .unwrap();
        let ids: Vec<_> = (0..10).map(|_| crowd.add(Arc::clone(&nap), 0)).collect();
        assert_eq!(crowd.frame().ticked, 10);
        clock.advance(Duration::from_millis(20));
        let mut most = 0;
        for frame in 1..=200 {
            // Members 0 to 4 are woken every other frame, after their timers went into the
            // heap; 5 to 9 sleep on.
            let woken = frame % 2 == 0;
            if woken {
                for &id in &ids[..5] {
                    crowd.wake(id);
                }
            }
            let report = crowd.frame();
            let expected = if woken { (5, 5) } else { (0, 10) };
            assert_eq!((report.ticked, report.asleep), expected, "{report:?}");
            most = most.max(crowd.timers.heaps.iter().map(|h| h.len()).sum());
            clock.advance(Duration::from_millis(20));
        }
        assert!(most <= 2 * 10 + 64 + 5, "{most} timers for 10 members");
        // Frames of 20 ms: the sleepers' deadlines, 10 s after frame 0, come at frame 500;
        // those of the members last woken at frame 200, at frame 700.
        let calls = |crowd: &Crowd<u32>, i: usize| *crowd.get(ids[i]).unwrap().context();
        assert_eq!((calls(&crowd, 0), calls(&crowd, 9)), (101, 1));
        for frame in 201..=500 {
            let report = crowd.frame();
            let expected = if frame == 500 { 5 } else { 0 };
            assert_eq!(report.ticked, expected, "frame {frame}");
            clock.advance(Duration::from_millis(20));
        }
        assert_eq!(calls(&crowd, 9), 2);
        assert_eq!(
            crowd.get(ids[9]).unwrap().status(),
            FrameStatus::Ticked(Status::Running)
        );
    }
}
