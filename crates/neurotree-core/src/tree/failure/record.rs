//! A tree's record of the reasons and failures of a tick, in 32-bit words, and what it
//! keeps beside it: the reasons that do not fit a word and the tick calls' errors (see the
//! [failure module docs](super)).

use alloc::borrow::Cow;
use alloc::boxed::Box;
use alloc::vec::Vec;
use core::time::Duration;

use thin_vec::ThinVec;

use super::{Message, Reason};
use crate::{NodeId, TickError, THIN_HEAD};

/// What a node gives the record: a reason for its coming Failure, or the Failure itself.
#[derive(Debug)]
pub(crate) enum Note {
    /// A node gave this reason for its coming Failure (a leaf's, or a built-in's own).
    Gave(Reason),
    /// The node's status was written Failure.
    Failed,
}

/// One entry of a tick's record: the node, and what it noted, packed in 32 bits. The
/// built-ins' reasons (a Retry's attempts, a Timeout's whole milliseconds, a precondition)
/// fit in those bits; any other reason is kept apart, in the record's [`Spill`], and the
/// entry holds its place there.
///
/// The record holds an entry in one word, a Failure's (the node), or two, a reason's (the
/// reason packed, then the node marked with [`MARK`]): a tick of failures notes many
/// failures and few reasons. It is read from its newest word back, where a marked word says
/// that the word before it is its reason.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Entry {
    node: NodeId,
    what: u32,
}

/// `Entry::what` of a Failure.
const FAILED: u32 = 0;
/// `Entry::what` of a `_failureIf` precondition's reason.
const HELD: u32 = 1;
/// The top two bits of `Entry::what` say which reason the low 30 carry.
const KIND: u32 = 3 << 30;
/// A Retry gave up after the low bits' attempts.
const GAVE_UP: u32 = 1 << 30;
/// A Timeout fired after the low bits' milliseconds.
const TIMED_OUT: u32 = 2 << 30;
/// The low bits are the reason's place among the spilled ones.
const SPILLED: u32 = 3 << 30;
/// The largest value the low bits carry.
const LOW: u32 = !KIND;
/// Marks a record's word as a reason's node, the word before it being what the reason is.
/// A failure's word is its node alone: node ids stay below it (a blueprint holds at most
/// [`MAX_NODES`](crate::blueprint::MAX_NODES)).
const MARK: u32 = 1 << 31;

// Every node id leaves the mark free.
const _: () = assert!(crate::blueprint::MAX_NODES <= MARK);

impl Entry {
    /// The node the entry is about.
    pub(crate) fn node(self) -> NodeId {
        self.node
    }

    /// `true` for a Failure, `false` for a reason.
    pub(crate) fn failed(self) -> bool {
        self.what == FAILED
    }

    /// The entry's `what` for a built-in's reason, `None` for one kept apart.
    fn packed(reason: &Reason) -> Option<u32> {
        if reason.code != 0 {
            return None;
        }
        let low = |n: u128| u32::try_from(n).ok().filter(|&n| n <= LOW);
        match reason.message {
            Message::Precondition => Some(HELD),
            Message::GaveUp(n) => low(u128::from(n)).map(|n| GAVE_UP | n),
            Message::TimedOut(after) if after.subsec_nanos() % 1_000_000 == 0 => {
                low(after.as_millis()).map(|ms| TIMED_OUT | ms)
            }
            _ => None,
        }
    }
}

/// What a tree keeps apart from its record: the pass's error, the last tick's, and the
/// reasons that do not fit an entry. Boxed together, behind the one pointer a tree had for
/// its error alone, made on the first of them and kept: no later error or reason allocates
/// for it.
#[derive(Default)]
struct Spill {
    /// The first error of this pass.
    fault: Option<TickError>,
    /// The error the last tick call returned ([`Tree::last_error`](crate::Tree::last_error)).
    last: Option<TickError>,
    /// The reasons whose places the record's entries hold, oldest first.
    reasons: ThinVec<Reason>,
}

/// What a pass leaves behind in the tree: its error, the tick's record of reasons, and the
/// halts still in progress.
///
/// One place for them, so that a leaf's [`Handle`](crate::Handle) reaches them through one
/// pointer, and the ticker carries no other for halts (which keeps their cost out of every
/// pass of a tree that never halts slowly).
pub(crate) struct Outcome {
    /// The pass's error and the reasons kept apart from the record: boxed, since both are
    /// rare and every tree would otherwise carry their size.
    spill: Option<Box<Spill>>,
    /// Halts that take ticks (see [`slow_halt`](crate::tree::slow_halt)).
    pub(crate) halts: crate::tree::slow_halt::Halts,
    /// Why the tree stayed awake after its last pass, and the node it is about (see
    /// [`why_awake`](crate::tree::why_awake)); what the nodes waited on in the pass is the
    /// pass's own ([`Waits`](crate::tree::sleep::Waits)), not kept.
    pub(crate) reason: Option<(crate::tree::why_awake::AwakeReason, NodeId)>,
    /// The stateful action ticked last in the last pass declared a wait.
    pub(crate) declared: bool,
    /// What the leaf being ticked declared through a shared handle.
    pub(crate) reads: crate::tree::sleep::Reads,
    /// The tick's record, oldest first, one or two words an entry ([`Entry`]): no room
    /// until a node gives a reason (see the module docs); a pointer, its length and room
    /// beside its words.
    record: ThinVec<u32>,
    /// The words in `record`: read without following its pointer, as every tick asks
    /// whether a reason was given.
    noted: u8,
}

/// Words the record holds before it drops its older half. The chain needs only the
/// tick's last failures: a full record keeps its newer half.
const RECORD: usize = 32;

/// Words the record has room for when the tree's first reason makes it: a tick of the
/// benchmark's 50-node agent notes at most 13 (a Retry's reason and 11 failures).
const FIRST_ROOM: usize = 16;

/// Reasons kept apart a tree first has room for.
const FIRST_SPILLED: usize = 4;

/// Reasons kept apart the record can hold: one an entry of two words.
const SPILLED_MOST: usize = RECORD / 2;

// A record grows once, from `FIRST_ROOM` straight to `RECORD`; so do the spilled reasons.
const _: () = assert!(FIRST_ROOM < RECORD && FIRST_SPILLED < SPILLED_MOST);

/// Bytes of a `ThinVec` with room for `room` items of `T`: none without room.
fn thin_bytes<T>(room: usize) -> usize {
    match room {
        0 => 0,
        room => THIN_HEAD + room * core::mem::size_of::<T>(),
    }
}

/// Gives `list` room for `first`, then for `most`, when it has no room for `more`: two
/// allocations at most in its life, as long as it never holds more than `most`.
fn make_room<T>(list: &mut ThinVec<T>, more: usize, first: usize, most: usize) {
    if list.capacity() - list.len() < more {
        // Room asked for exactly, rather than by the vector's own growth, so that a list
        // is made once and grown once: no tick allocates for it after.
        let room = if list.capacity() == 0 { first } else { most };
        list.reserve_exact(room.saturating_sub(list.len()));
    }
}

impl Outcome {
    /// The outcome of a fresh tree: no record until a reason is given.
    pub(crate) fn new() -> Self {
        Self {
            spill: None,
            halts: crate::tree::slow_halt::Halts::default(),
            reason: None,
            declared: false,
            reads: crate::tree::sleep::Reads::default(),
            record: ThinVec::new(),
            noted: 0,
        }
    }

    /// Keeps what the pass that waited on `waits` says of why the tree stays awake.
    #[inline]
    pub(crate) fn keep(&mut self, waits: &crate::tree::sleep::Waits) {
        self.reason = waits.reason;
        self.declared = waits.declared;
    }

    /// `true` once the pass has an error.
    #[inline]
    pub(crate) fn faulted(&self) -> bool {
        self.spill.as_ref().is_some_and(|s| s.fault.is_some())
    }

    /// Records the pass's error made by `error`, unless it has one: the first wins.
    #[cold]
    pub(crate) fn fault(&mut self, error: impl FnOnce() -> TickError) {
        let spill = self.spill.get_or_insert_with(Box::default);
        if spill.fault.is_none() {
            spill.fault = Some(error());
        }
    }

    /// Takes the pass's error: for a tree that never had one, a load and a branch, inlined
    /// at the end of every pass.
    #[inline(always)]
    pub(crate) fn take_fault(&mut self) -> Option<TickError> {
        match self.spill.as_deref_mut() {
            None => None,
            Some(spill) => spill.fault.take(),
        }
    }

    /// `true` once the box that keeps the last tick call's error is made: one load and a
    /// branch, for the tick calls to begin with, on the tree's own line.
    #[inline(always)]
    pub(crate) fn holds_error(&self) -> bool {
        self.spill.is_some()
    }

    /// Keeps a copy of the error a tick call returns, until the next call.
    #[cold]
    #[inline(never)]
    pub(crate) fn keep_error(&mut self, error: &TickError) {
        self.spill.get_or_insert_with(Box::default).last = Some(error.clone());
    }

    /// Keeps a copy of `error`, which a tick call returns, and gives it back.
    #[cold]
    #[inline(never)]
    pub(crate) fn kept(&mut self, error: TickError) -> TickError {
        self.keep_error(&error);
        error
    }

    /// Forgets the last tick call's error, at the start of the next.
    #[cold]
    #[inline(never)]
    pub(crate) fn forget_error(&mut self) {
        if let Some(spill) = self.spill.as_deref_mut() {
            spill.last = None;
        }
    }

    /// The error the last tick call returned.
    pub(crate) fn last_error(&self) -> Option<&TickError> {
        self.spill.as_ref().and_then(|s| s.last.as_ref())
    }

    /// Makes the record now with room for the most it holds, and for as many reasons kept
    /// apart, if it has not that room yet.
    pub(crate) fn reserve(&mut self) {
        self.record.reserve_exact(RECORD - self.record.len());
        let reasons = &mut self.spill.get_or_insert_with(Box::default).reasons;
        reasons.reserve_exact(SPILLED_MOST - reasons.len());
    }

    /// Bytes the record takes (none until the tree's first reason): its head and its
    /// room, and what holds the reasons kept apart, if any is.
    pub(crate) fn record_bytes(&self) -> usize {
        let spilled = self.spill.as_ref().map_or(0, |s| {
            core::mem::size_of::<Spill>() + thin_bytes::<Reason>(s.reasons.capacity())
        });
        thin_bytes::<u32>(self.record.capacity()) + spilled
    }

    /// The tick's record, oldest first, read out of its words: for the chain, built
    /// after the tick.
    pub(crate) fn notes(&self) -> Notes<'_> {
        let mut entries: Vec<Entry> = Entries(&self.record).collect();
        entries.reverse();
        Notes {
            entries,
            spilled: self.spill.as_ref().map_or(&[], |s| &s.reasons[..]),
        }
    }

    /// `true` when no reason was given in this tick.
    #[inline(always)]
    pub(crate) fn is_quiet(&self) -> bool {
        self.noted == 0
    }

    /// Empties the record, dropping the reasons it held and keeping its room.
    pub(crate) fn forget(&mut self) {
        // A quiet tick leaves the record's memory untouched.
        if core::mem::take(&mut self.noted) == 0 {
            return;
        }
        self.record.clear();
        if let Some(spill) = self.spill.as_deref_mut() {
            spill.reasons.clear();
        }
    }

    /// Adds to the record. When the entry's words would not fit in [`RECORD`], it first
    /// drops its older entries, keeping the newest that fit in half of it, rather than grow:
    /// ticking allocates at most twice in a tree's life for the record, and three times for
    /// the reasons kept apart (the box, room for 4, room for 16; see the module docs). The
    /// chain is built from the newest entries (the root's failure is the last), so only a
    /// chain longer than half the record loses its far end.
    pub(crate) fn push(&mut self, node: NodeId, note: Note) {
        // Node ids stay below `MARK`: a blueprint holds at most `MAX_NODES`.
        debug_assert!(node.0 < MARK);
        let words = if matches!(note, Note::Failed) { 1 } else { 2 };
        // First, so that the reasons kept apart are those of the entries kept.
        if self.record.len() + words > RECORD {
            self.drop_older_half();
        }
        let what = match note {
            Note::Failed => None,
            Note::Gave(reason) => Some(match Entry::packed(&reason) {
                Some(what) => what,
                None => {
                    let reasons = &mut self.spill.get_or_insert_with(Box::default).reasons;
                    make_room(reasons, 1, FIRST_SPILLED, SPILLED_MOST);
                    // Fewer than `SPILLED_MOST` (one per entry of two words), which fit the
                    // low bits.
                    let place = reasons.len() as u32;
                    reasons.push(reason);
                    SPILLED | place
                }
            }),
        };
        make_room(&mut self.record, words, FIRST_ROOM, RECORD);
        match what {
            None => self.record.push(node.0),
            Some(what) => {
                self.record.push(what);
                self.record.push(MARK | node.0);
            }
        }
        // At most `RECORD`, which fits.
        self.noted = self.record.len() as u8;
    }

    /// Drops the record's older entries, keeping the newest that fit in half of it, and
    /// the reasons kept apart only they held.
    fn drop_older_half(&mut self) {
        let len = self.record.len();
        let mut start = len;
        let mut places = [0usize; RECORD / 2];
        let mut spilled = 0;
        for entry in Entries(&self.record) {
            let words = if entry.failed() { 1 } else { 2 };
            if len - (start - words) > RECORD / 2 {
                break;
            }
            start -= words;
            if entry.what & KIND == SPILLED {
                // The reason's word, from the newest back.
                places[spilled] = start;
                spilled += 1;
            }
        }
        self.record.drain(..start);
        let Some(spill) = self.spill.as_deref_mut() else {
            return;
        };
        // The places left rise with the entries, and none is below its new place: each
        // reason moves down to its new place, oldest first, and those of dropped entries
        // fall off the end.
        for (kept, &at) in places[..spilled].iter().rev().enumerate() {
            let what = &mut self.record[at - start];
            spill.reasons.swap(kept, (*what & LOW) as usize);
            *what = SPILLED | kept as u32;
        }
        spill.reasons.truncate(spilled);
    }

    /// The reason the newest entry gives, if it is a reason given by `node`.
    pub(crate) fn last_reason_of(&self, node: NodeId) -> Option<Cow<'_, Reason>> {
        let last = Entries(&self.record).next()?;
        let spilled = self.spill.as_ref().map_or(&[][..], |s| &s.reasons[..]);
        (last.node == node).then(|| reason(last, spilled)).flatten()
    }
}

/// A record's entries, read from its newest word back.
struct Entries<'a>(&'a [u32]);

impl Iterator for Entries<'_> {
    type Item = Entry;

    fn next(&mut self) -> Option<Entry> {
        let (&last, rest) = self.0.split_last()?;
        if last & MARK == 0 {
            self.0 = rest;
            return Some(Entry {
                node: NodeId(last),
                what: FAILED,
            });
        }
        // Invariant: a marked word follows the word of what its reason is (`push`).
        let (&what, rest) = rest.split_last()?;
        self.0 = rest;
        Some(Entry {
            node: NodeId(last & !MARK),
            what,
        })
    }
}

/// The reason `entry` gives, `None` for a Failure, with `spilled` the reasons kept apart.
/// A built-in's is made anew (no allocation); another is borrowed from where it was kept.
fn reason(entry: Entry, spilled: &[Reason]) -> Option<Cow<'_, Reason>> {
    let low = entry.what & LOW;
    Some(match entry.what & KIND {
        _ if entry.what == FAILED => return None,
        _ if entry.what == HELD => Cow::Owned(Reason::PRECONDITION),
        GAVE_UP => Cow::Owned(Reason::gave_up(u64::from(low))),
        TIMED_OUT => Cow::Owned(Reason::timed_out(Duration::from_millis(u64::from(low)))),
        // Invariant: a spilled entry's place is among the reasons kept (`push`).
        _ => Cow::Borrowed(&spilled[low as usize]),
    })
}

/// A tick's record as the chain reads it: its entries, oldest first, and the reasons kept
/// apart from them.
pub(crate) struct Notes<'a> {
    entries: Vec<Entry>,
    spilled: &'a [Reason],
}

impl<'a> Notes<'a> {
    /// The entries, oldest first.
    pub(crate) fn entries(&self) -> &[Entry] {
        &self.entries
    }

    /// The reason `entry` gives, `None` for a Failure (see [`reason`]).
    pub(crate) fn reason(&self, entry: Entry) -> Option<Cow<'a, Reason>> {
        reason(entry, self.spilled)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::string::{String, ToString};

    /// Pushes `n` entries noting failures of node 1.
    fn push(out: &mut Outcome, n: usize) {
        for _ in 0..n {
            out.push(NodeId(1), Note::Failed);
        }
    }

    /// The entries' nodes, oldest first.
    fn nodes(out: &Outcome) -> Vec<u32> {
        out.notes().entries().iter().map(|e| e.node().0).collect()
    }

    /// The entries as `node` for a Failure and `node: reason` for a reason, oldest first.
    fn read(out: &Outcome) -> Vec<String> {
        let notes = out.notes();
        notes
            .entries()
            .iter()
            .map(|&e| match notes.reason(e) {
                Some(reason) => alloc::format!("{}: {reason}", e.node().0),
                None => alloc::format!("{}", e.node().0),
            })
            .collect()
    }

    #[test]
    fn a_record_has_room_for_16_words_then_32_and_never_more() {
        let mut out = Outcome::new();
        assert_eq!((out.record.capacity(), out.record_bytes()), (0, 0));
        push(&mut out, 16);
        assert_eq!((out.record.capacity(), out.record.len()), (16, 16));
        assert_eq!(out.record_bytes(), 16 + 16 * 4);
        push(&mut out, 1);
        assert_eq!((out.record.capacity(), out.record.len()), (32, 17));
        assert_eq!(out.record_bytes(), 16 + 32 * 4);
        // Full, it keeps its newer half and its room.
        push(&mut out, 15);
        assert_eq!(out.record.len(), 32);
        out.push(NodeId(2), Note::Failed);
        assert_eq!((out.record.capacity(), out.record.len()), (32, 17));
        assert_eq!(nodes(&out).last(), Some(&2));
        // A new tick starts empty, with the room kept.
        out.forget();
        assert_eq!((out.record.capacity(), out.record.len()), (32, 0));
        assert!(out.is_quiet());
    }

    #[test]
    fn a_reason_takes_two_words_and_a_failure_one() {
        let mut out = Outcome::new();
        out.push(NodeId(5), Note::Gave(Reason::gave_up(3)));
        out.push(NodeId(5), Note::Failed);
        out.push(NodeId(4), Note::Failed);
        assert_eq!(out.record.len(), 4);
        assert_eq!(read(&out), ["5: gave up after 3 attempts", "5", "4"]);
        // A reason that would not fit the room left makes the room at once: 15 words, then
        // two more.
        push(&mut out, 11);
        assert_eq!((out.record.capacity(), out.record.len()), (16, 15));
        out.push(NodeId(6), Note::Gave(Reason::PRECONDITION));
        assert_eq!((out.record.capacity(), out.record.len()), (32, 17));
        assert_eq!(
            out.last_reason_of(NodeId(6)).unwrap().to_string(),
            "failed by its precondition"
        );
        assert_eq!(out.last_reason_of(NodeId(1)), None);
    }

    #[test]
    fn a_full_record_never_keeps_half_an_entry() {
        let mut out = Outcome::new();
        // 15 reasons and a failure, 31 words, then a reason of two: the newest 16 words
        // would begin with the node word of a reason, without the word of what it is, so
        // the newest 15 are kept.
        for i in 0..15 {
            out.push(NodeId(10 + i), Note::Gave(Reason::gave_up(u64::from(i))));
        }
        push(&mut out, 1);
        assert_eq!(out.record.len(), 31);
        out.push(NodeId(99), Note::Gave(Reason::gave_up(99)));
        assert_eq!(out.record.len(), 15 + 2);
        let kept = read(&out);
        assert_eq!(kept.len(), 9);
        assert_eq!(kept[0], "18: gave up after 8 attempts");
        assert_eq!(kept[6], "24: gave up after 14 attempts");
        assert_eq!(kept[7..], ["1", "99: gave up after 99 attempts"]);
    }

    #[test]
    fn the_built_ins_reasons_are_packed_and_read_back_the_same() {
        let mut out = Outcome::new();
        let given = [
            Reason::gave_up(3),
            Reason::gave_up(u64::from(LOW)),
            Reason::timed_out(Duration::from_millis(100)),
            Reason::timed_out(Duration::from_secs(2)),
            Reason::PRECONDITION,
        ];
        for (i, reason) in given.iter().enumerate() {
            out.push(NodeId(i as u32), Note::Gave(reason.clone()));
        }
        assert!(out.spill.is_none(), "nothing kept apart");
        assert_eq!(out.record_bytes(), 16 + 16 * 4);
        assert_eq!(
            read(&out),
            [
                "0: gave up after 3 attempts",
                "1: gave up after 1073741823 attempts",
                "2: timed out after 100 ms",
                "3: timed out after 2 s",
                "4: failed by its precondition",
            ]
        );
        let notes = out.notes();
        assert_eq!(
            *notes.reason(notes.entries()[4]).unwrap(),
            Reason::PRECONDITION
        );
    }

    #[test]
    fn other_reasons_are_kept_apart_and_read_back_the_same() {
        let mut out = Outcome::new();
        let given = [
            Reason::new(106, "blocked"),
            Reason::owned(0, "2 m short"),
            // Too many attempts, or a part of a millisecond, for an entry's bits.
            Reason::gave_up(u64::from(LOW) + 1),
            Reason::timed_out(Duration::from_micros(1_500)),
            // A built-in's words with a code: not a built-in's.
            Reason::new(7, "failed by its precondition"),
        ];
        for reason in &given {
            out.push(NodeId(1), Note::Gave(reason.clone()));
            out.push(NodeId(1), Note::Failed);
        }
        let notes = out.notes();
        let back: Vec<Reason> = notes
            .entries()
            .iter()
            .filter_map(|&e| notes.reason(e).map(Cow::into_owned))
            .collect();
        assert_eq!(back, given);
        assert_eq!(back[3].message(), "timed out after 1 ms");
        assert_eq!(out.spill.as_ref().unwrap().reasons.len(), 5);
        // Room for 16 words, and for 16 reasons kept apart once 4 were not enough.
        assert_eq!(
            out.record_bytes(),
            16 + 16 * 4 + core::mem::size_of::<Spill>() + 16 + 16 * 32
        );
        // The next tick drops them and keeps the room.
        out.forget();
        assert!(out.spill.as_ref().unwrap().reasons.is_empty());
        assert_eq!(out.spill.as_ref().unwrap().reasons.capacity(), SPILLED_MOST);
    }

    #[test]
    fn a_full_record_keeps_the_reasons_its_newer_half_gives_and_no_more() {
        let mut out = Outcome::new();
        // 60 words: each node gives a reason of its own (two words), then fails (one).
        for i in 0..20u32 {
            out.push(
                NodeId(i),
                Note::Gave(Reason::owned(i, alloc::format!("reason {i}"))),
            );
            out.push(NodeId(i), Note::Failed);
        }
        // Each drop keeps the newest five nodes' entries (15 words), and the reasons they
        // hold.
        let kept: Vec<(u32, u32)> = {
            let notes = out.notes();
            notes
                .entries()
                .iter()
                .filter_map(|&e| notes.reason(e).map(|r| (e.node().0, r.code())))
                .collect()
        };
        let first = kept[0].0;
        let want: Vec<(u32, u32)> = (first..20).map(|i| (i, i)).collect();
        assert_eq!(kept, want);
        assert_eq!(out.spill.as_ref().unwrap().reasons.len(), kept.len());
        // Every entry whole: each reason followed by its node's failure, the newest last,
        // after, at most, the failure of the node before (whose reason was dropped).
        let all = read(&out);
        assert_eq!(all.last().map(String::as_str), Some("19"));
        let lone = all.len() - 2 * kept.len();
        assert!(lone <= 1, "{all:?}");
        if lone == 1 {
            assert_eq!(all[0], (first - 1).to_string());
        }
        assert_eq!(
            all[lone],
            alloc::format!("{first}: reason {first} (error {first})")
        );
        assert_eq!(
            out.last_reason_of(NodeId(19)),
            None,
            "the newest is a Failure"
        );
        out.push(NodeId(20), Note::Gave(Reason::new(20, "last")));
        assert_eq!(out.last_reason_of(NodeId(20)).unwrap().code(), 20);
        assert_eq!(out.last_reason_of(NodeId(19)), None);
    }

    /// What a record holds after `entries` are pushed, worked out apart: each entry takes
    /// its words; one that would not fit in `RECORD` first drops the oldest entries until
    /// the rest fit in half of it.
    fn kept_by_a_model(entries: &[(u32, usize)]) -> Vec<(u32, usize)> {
        let mut kept: Vec<(u32, usize)> = Vec::new();
        for &entry in entries {
            let words = |k: &[(u32, usize)]| k.iter().map(|e| e.1).sum::<usize>();
            if words(&kept) + entry.1 > RECORD {
                while words(&kept) > RECORD / 2 {
                    kept.remove(0);
                }
            }
            kept.push(entry);
        }
        kept
    }

    #[test]
    fn a_full_record_of_packed_kept_apart_and_failure_entries_keeps_what_a_model_keeps() {
        let mut out = Outcome::new();
        let mut pushed = Vec::new();
        // Each node: a reason kept apart, a Retry's, and its failure: 5 words; 60 in all.
        for i in 0..12u32 {
            out.push(
                NodeId(i),
                Note::Gave(Reason::owned(100 + i, alloc::format!("r{i}"))),
            );
            out.push(NodeId(i), Note::Gave(Reason::gave_up(u64::from(i))));
            out.push(NodeId(i), Note::Failed);
            pushed.extend([(i, 2), (i, 2), (i, 1)]);
            let model = kept_by_a_model(&pushed);
            let words: usize = model.iter().map(|e| e.1).sum();
            assert_eq!(out.record.len(), words);
            let want: Vec<String> = model
                .iter()
                .enumerate()
                .map(|(k, &(node, w))| {
                    let at = pushed.len() - model.len() + k;
                    match (w, at % 3) {
                        (1, _) => alloc::format!("{node}"),
                        (_, 0) => alloc::format!("{node}: r{node} (error {})", 100 + node),
                        _ => alloc::format!(
                            "{node}: gave up after {node} attempt{}",
                            if node == 1 { "" } else { "s" }
                        ),
                    }
                })
                .collect();
            assert_eq!(read(&out), want, "after node {i}");
            // One reason kept apart for each such entry left, no more.
            let apart = model
                .iter()
                .enumerate()
                .filter(|&(k, e)| e.1 == 2 && (pushed.len() - model.len() + k) % 3 == 0);
            assert_eq!(out.spill.as_ref().unwrap().reasons.len(), apart.count());
        }
    }

    #[test]
    #[cfg(target_pointer_width = "64")]
    fn the_box_of_errors_and_reasons_takes_120_bytes() {
        // Two errors of 56 bytes and a pointer: what the docs and `state_bytes` say.
        assert_eq!(core::mem::size_of::<Spill>(), 120);
    }

    #[test]
    fn an_error_is_taken_once_and_kept_until_the_next_call_in_a_box_made_once() {
        let mut out = Outcome::new();
        assert!(!out.faulted() && !out.holds_error());
        out.fault(|| TickError::HaltRequested);
        out.fault(|| unreachable!("the first error wins"));
        assert!(out.faulted());
        let error = out.take_fault().unwrap();
        assert_eq!(error, TickError::HaltRequested);
        assert_eq!(out.take_fault(), None);
        assert!(!out.faulted());
        out.keep_error(&error);
        assert_eq!(out.last_error(), Some(&TickError::HaltRequested));
        // The next call forgets it; the box stays, for the next error.
        assert!(out.holds_error());
        out.forget_error();
        assert_eq!(out.last_error(), None);
        assert!(out.holds_error());
        assert_eq!(out.record_bytes(), core::mem::size_of::<Spill>());
    }

    #[test]
    fn reserving_a_record_made_with_room_for_16_gives_room_for_32() {
        let mut out = Outcome::new();
        push(&mut out, 3);
        out.reserve();
        assert_eq!((out.record.capacity(), out.record.len()), (32, 3));
        let spill = core::mem::size_of::<Spill>() + 16 + 16 * 32;
        assert_eq!(out.record_bytes(), 16 + 32 * 4 + spill);
        push(&mut out, 40);
        for i in 0..40 {
            out.push(NodeId(i), Note::Gave(Reason::new(i, "kept apart")));
        }
        assert_eq!(out.record.capacity(), 32);
        assert_eq!(out.spill.as_ref().unwrap().reasons.capacity(), 16);
        assert_eq!(out.record_bytes(), 16 + 32 * 4 + spill);
    }
}
