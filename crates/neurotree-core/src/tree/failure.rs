//! Why the root failed: reasons given with failures, and the chain that explains a tick.
//!
//! A node may attach a [`Reason`] to the Failure it returns ([`Handle::fail_with`]); a few
//! built-ins give their own: a Timeout that fired ("timed out after 100 ms"), a
//! RetryUntilSuccessful that ran out of attempts ("gave up after 3 attempts") and a
//! `_failureIf` precondition that held ("failed by its precondition").
//!
//! # What is recorded, and what it costs
//!
//! Nothing, until a reason is given: a tick in which no node gives one runs exactly as
//! before. The first reason of a tick is written to the tree's record and from then on, for
//! the rest of that [`Tree::tick_once`](crate::Tree::tick_once) call, the engine notes
//! every status write to Failure (it ticks as if an observer were attached). The record is
//! emptied when the next call starts; a static reason allocates nothing once there is room
//! for it.
//!
//! The record is a list of 32-bit words: a Failure takes one (the node), a reason two (the
//! reason packed in 32 bits, then the node). The built-ins' reasons fit those bits (a
//! Retry's attempts, a Timeout's whole milliseconds, a precondition); any other reason (a
//! leaf's) is kept apart, in one box with the pass's error, and its word holds its place.
//!
//! A tree has no record until one of its nodes first gives a reason: that tick makes it,
//! with room for 16 words (80 bytes with its head, counted in
//! [`Tree::state_bytes`](crate::Tree::state_bytes)), and the first tick that notes more
//! doubles it to 32, the most it holds: at most two allocations in a tree's life. Reasons
//! kept apart take three more at most: the box, room for 4, then for 16. The same box keeps
//! a tick call's error ([`Tree::last_error`](crate::Tree::last_error)): made by the first
//! of an error, a reason kept apart and `reserve_failure_record` (120 bytes, counted in
//! `state_bytes` too) and kept, and each error returned is copied into it (its text
//! allocated again). So a tree that never fails with a reason
//! and never errs carries nothing, and 100,000 game agents keep their state
//! together in memory (a record made with each tree spread it out and made a frame of them
//! 2.7 times as long); a tick of the benchmark's 50-node agent notes at most 13 words, a
//! Retry's reason and the failures after it, and its record stays at 80 bytes (a quarter
//! of those agents make one, BENCHMARKS.md). A program that must not allocate even once
//! while ticking makes it up front, with room for 32 words and 16 reasons kept apart, with
//! [`Tree::reserve_failure_record`](crate::Tree::reserve_failure_record).
//!
//! Apart from reasons, every write of Failure to a node's status in a tick sets that node's
//! bit in a set the tree keeps (one bit a node, cleared when the next tick starts): one
//! store, no allocation, and no observer needed. The conditions a Sequence or Fallback calls
//! straight from its child list, whose statuses are never stored, are marked there too.
//!
//! # Which failures decided the root
//!
//! [`Tree::last_failure`](crate::Tree::last_failure) builds the [`Failure`] after the tick,
//! only when asked, from those bits and the record. It starts at the root and, at each node,
//! goes down to the children that failed in the tick. A Fallback (Fallback, AsyncFallback,
//! ReactiveFallback), whose failure means every child it tried failed, lists each of them
//! with its own chain, and the chain goes on through the last. Any other node (a Sequence, a
//! decorator, a SubTree) goes on through its failing child; when it ran more than once in the
//! tick (a Retry's attempts) and several children failed, through the one whose Failure was
//! noted last, else the last in order. A link carries the node's own reason: the one it gave
//! during the run that ended in the Failure being explained (a leaf's, a Timeout's, a
//! Retry's). The chain ends at a node with no failing child: a leaf, a Timeout that halted
//! its child, an Inverter whose child succeeded (which says so as its reason).
//!
//! [`Handle::fail_with`]: crate::Handle::fail_with

use alloc::borrow::Cow;
use alloc::boxed::Box;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;
use core::time::Duration;

use thin_vec::ThinVec;

use crate::blueprint::Blueprint;
use crate::nodes::built_in::Family;
use crate::{NodeId, TickError, THIN_HEAD};

/// Why a node failed: a small code and a message.
///
/// A static message allocates nothing once its tree has room for it (the first makes room
/// for 4 a tick, a tick with more room for 16: see the [module docs](self)); [`Reason::owned`] carries text made at run time
/// (and allocates for it). The built-ins' own reasons keep their numbers and are put into
/// words only when shown, so they allocate nothing either. Code 0 means "no code": the
/// built-ins' reasons use it, and the [`Display`](fmt::Display) form then shows the
/// message alone.
///
/// ```
/// use neurotree_core::Reason;
///
/// const BLOCKED: Reason = Reason::new(106, "blocked");
/// assert_eq!(BLOCKED.to_string(), "blocked (error 106)");
/// assert_eq!(Reason::owned(0, format!("{} m short", 2)).to_string(), "2 m short");
/// ```
#[derive(Clone, Debug)]
pub struct Reason {
    code: u32,
    message: Message,
}

#[derive(Clone, Debug)]
enum Message {
    Static(&'static str),
    Owned(String),
    /// A Timeout fired after this long.
    TimedOut(Duration),
    /// A RetryUntilSuccessful ran out after this many attempts.
    GaveUp(u64),
    /// A `_failureIf` precondition held.
    Precondition,
}

impl Reason {
    /// A reason with a static message.
    pub const fn new(code: u32, message: &'static str) -> Self {
        Self {
            code,
            message: Message::Static(message),
        }
    }

    /// A reason with a message made at run time.
    pub fn owned(code: u32, message: impl Into<String>) -> Self {
        Self {
            code,
            message: Message::Owned(message.into()),
        }
    }

    /// A Timeout's reason: "timed out after 100 ms".
    pub(crate) const fn timed_out(after: Duration) -> Self {
        Self {
            code: 0,
            message: Message::TimedOut(after),
        }
    }

    /// A Retry's reason: "gave up after 3 attempts".
    pub(crate) const fn gave_up(attempts: u64) -> Self {
        Self {
            code: 0,
            message: Message::GaveUp(attempts),
        }
    }

    /// The reason of a `_failureIf` precondition that held.
    pub(crate) const PRECONDITION: Reason = Reason {
        code: 0,
        message: Message::Precondition,
    };

    /// The code (0: none).
    pub fn code(&self) -> u32 {
        self.code
    }

    /// The message (put into words now for a built-in's reason).
    pub fn message(&self) -> Cow<'_, str> {
        match &self.message {
            Message::Static(text) => Cow::Borrowed(text),
            Message::Owned(text) => Cow::Borrowed(text),
            Message::Precondition => Cow::Borrowed(HELD_WORDS),
            _ => Cow::Owned(alloc::format!("{}", Words(&self.message))),
        }
    }
}

/// Two reasons are equal when their codes and their messages, in words, are.
impl PartialEq for Reason {
    fn eq(&self, other: &Self) -> bool {
        self.code == other.code && self.message() == other.message()
    }
}

impl Eq for Reason {}

/// A precondition's reason in words.
const HELD_WORDS: &str = "failed by its precondition";

/// A message in words.
struct Words<'a>(&'a Message);

impl fmt::Display for Words<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Message::Static(text) => f.write_str(text),
            Message::Owned(text) => f.write_str(text),
            Message::Precondition => f.write_str(HELD_WORDS),
            Message::TimedOut(after) => write!(f, "timed out after {}", Span(*after)),
            Message::GaveUp(n) => {
                write!(
                    f,
                    "gave up after {n} attempt{}",
                    if *n == 1 { "" } else { "s" }
                )
            }
        }
    }
}

impl fmt::Display for Reason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        Words(&self.message).fmt(f)?;
        if self.code != 0 {
            write!(f, " (error {})", self.code)?;
        }
        Ok(())
    }
}

/// A duration as people write it: whole seconds as `2 s`, anything else in milliseconds.
struct Span(Duration);

impl fmt::Display for Span {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let ms = self.0.as_millis();
        if ms != 0 && ms % 1000 == 0 {
            write!(f, "{} s", ms / 1000)
        } else {
            write!(f, "{ms} ms")
        }
    }
}

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
    /// Halts that take ticks (see [`slow_halt`](super::slow_halt)).
    pub(crate) halts: super::slow_halt::Halts,
    /// Why the tree stayed awake after its last pass, and the node it is about (see
    /// [`why_awake`](super::why_awake)); what the nodes waited on in the pass is the
    /// pass's own ([`Waits`](super::sleep::Waits)), not kept.
    pub(crate) reason: Option<(super::why_awake::AwakeReason, NodeId)>,
    /// The stateful action ticked last in the last pass declared a wait.
    pub(crate) declared: bool,
    /// What the leaf being ticked declared through a shared handle.
    pub(crate) reads: super::sleep::Reads,
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
            halts: super::slow_halt::Halts::default(),
            reason: None,
            declared: false,
            reads: super::sleep::Reads::default(),
            record: ThinVec::new(),
            noted: 0,
        }
    }

    /// Keeps what the pass that waited on `waits` says of why the tree stays awake.
    #[inline]
    pub(crate) fn keep(&mut self, waits: &super::sleep::Waits) {
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

/// Why the root failed on the last tick: the chain from the root down to the node whose
/// failure decided it, and, for each Fallback on it, every child it tried with that child's
/// own chain (see the [module docs](self)). Together they are the tree of the tick's
/// failures: every node on it failed in that tick.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure {
    /// From the root down; never empty.
    pub links: Vec<FailureLink>,
}

/// One node on a [`Failure`] chain.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FailureLink {
    /// The node.
    pub node: NodeId,
    /// Its path in the blueprint (`root/fallback/leaf`).
    pub path: String,
    /// Its own reason, if it gave one (a leaf's, a Timeout's, a Retry's, a precondition's),
    /// or, for a node that failed with no child failing, what it did (an Inverter whose
    /// child succeeded).
    pub reason: Option<Reason>,
    /// For a Fallback: every child it tried in the tick, in order, each with its own chain.
    /// Empty for other nodes.
    pub tried: Vec<Tried>,
}

/// A child a Fallback tried.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Tried {
    /// The child.
    pub node: NodeId,
    /// Its path in the blueprint.
    pub path: String,
    /// The deepest reason on its own chain, if any node below gave one.
    pub reason: Option<Reason>,
    /// Its own failure: the chain from it down to the node that decided it (its first link
    /// is the child itself).
    pub chain: Vec<FailureLink>,
}

impl Failure {
    /// The node where the chain ends: the one whose failure decided the root.
    pub fn leaf(&self) -> &FailureLink {
        // Invariant: `build` always pushes the root's link.
        self.links.last().expect("a failure chain holds the root")
    }

    /// The deepest reason on the chain: what, in the end, went wrong.
    pub fn reason(&self) -> Option<&Reason> {
        deepest(&self.links)
    }

    /// Every node of the failure, once each, from the root down: the chain's links and
    /// those of the chains of what each Fallback tried.
    pub fn all_links(&self) -> Vec<&FailureLink> {
        fn walk<'f>(links: &'f [FailureLink], out: &mut Vec<&'f FailureLink>) {
            for link in links {
                if !out.iter().any(|l| l.node == link.node) {
                    out.push(link);
                }
                for tried in &link.tried {
                    walk(&tried.chain, out);
                }
            }
        }
        let mut out = Vec::new();
        walk(&self.links, &mut out);
        out
    }
}

fn deepest(links: &[FailureLink]) -> Option<&Reason> {
    links.iter().rev().find_map(|l| l.reason.as_ref())
}

/// One link per line, indented by depth: `path: reason`; below a Fallback each child it
/// tried (`tried path: reason`) and, for all but the one the chain goes on through, that
/// child's own chain.
impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write_chain(f, &self.links, 0, false)
    }
}

fn write_chain(
    f: &mut fmt::Formatter<'_>,
    links: &[FailureLink],
    base: usize,
    headless: bool,
) -> fmt::Result {
    for (depth, link) in links.iter().enumerate() {
        let indent = base + depth * 2;
        if !(headless && depth == 0) {
            if depth > 0 || base > 0 {
                f.write_str("\n")?;
            }
            write!(f, "{:indent$}{}", "", link.path)?;
            if let Some(reason) = &link.reason {
                write!(f, ": {reason}")?;
            }
        }
        let next = links.get(depth + 1).map(|l| l.node);
        for tried in &link.tried {
            write!(f, "\n{:width$}tried {}", "", tried.path, width = indent + 2)?;
            match &tried.reason {
                Some(reason) => write!(f, ": {reason}")?,
                None => f.write_str(": no reason given")?,
            }
            if Some(tried.node) != next {
                write_chain(f, &tried.chain, indent + 2, true)?;
            }
        }
    }
    Ok(())
}

fn is_marked(failed: &[u64], node: NodeId) -> bool {
    let i = node.index();
    failed.get(i / 64).is_some_and(|w| w & (1 << (i % 64)) != 0)
}

/// Builds the chain of a tick whose root failed, from the nodes marked failed in the tick
/// and the tick's record of reasons.
pub(crate) fn build<C>(bp: &Blueprint<C>, failed: &[u64], notes: Notes<'_>) -> Failure {
    Failure {
        links: chain(bp, failed, &notes, NodeId::ROOT),
    }
}

/// The chain from `node`, which failed in the tick, down to the node that decided it.
fn chain<C>(
    bp: &Blueprint<C>,
    failed: &[u64],
    notes: &Notes<'_>,
    node: NodeId,
) -> Vec<FailureLink> {
    let mut links = Vec::new();
    let mut node = Some(node);
    while let Some(at) = node {
        let (link, next) = explain(bp, failed, notes, at);
        links.push(link);
        node = next;
    }
    links
}

/// The link of `node`, which failed in the tick, and the child that decided it, if one
/// failed.
fn explain<C>(
    bp: &Blueprint<C>,
    failed: &[u64],
    notes: &Notes<'_>,
    node: NodeId,
) -> (FailureLink, Option<NodeId>) {
    let children = bp.children(node);
    let failing: Vec<NodeId> = children
        .iter()
        .copied()
        .filter(|&c| is_marked(failed, c))
        .collect();
    let fallback = bp.kind(node).built_in().and_then(|n| n.family()) == Some(Family::Alternative);
    let mut tried = Vec::new();
    let next = if fallback {
        for &child in &failing {
            let chain = chain(bp, failed, notes, child);
            tried.push(Tried {
                node: child,
                path: bp.path(child),
                reason: deepest(&chain).cloned(),
                chain,
            });
        }
        // A failed Fallback's children all failed: the last one decided it.
        failing.last().copied()
    } else {
        // Several children failed in one tick when the node ran more than once in it (a
        // Retry's attempts, a reactive control's passes): the one whose Failure was
        // noted last decided it; unnoted, the last in order.
        failing.iter().copied().max_by_key(|&c| {
            let entries = notes.entries();
            (last_failed(entries, c, entries.len()), c.index())
        })
    };
    let mut reason = own_reason(notes, node);
    if reason.is_none() && next.is_none() && !children.is_empty() {
        let alone = bp.kind(node).built_in().and_then(|n| n.failed_alone());
        reason = Some(Reason::new(
            0,
            alone.unwrap_or("failed with no child failing"),
        ));
    }
    let link = FailureLink {
        node,
        path: bp.path(node),
        reason,
        tried,
    };
    (link, next)
}

/// The reason `node` gave during the run that ended in its last noted Failure.
fn own_reason(notes: &Notes<'_>, node: NodeId) -> Option<Reason> {
    let entries = notes.entries();
    let end = last_failed(entries, node, entries.len())?;
    let start = last_failed(entries, node, end).map_or(0, |i| i + 1);
    entries[start..end]
        .iter()
        .rev()
        .filter(|e| e.node() == node)
        .find_map(|&e| notes.reason(e))
        .map(Cow::into_owned)
}

/// The index of the last Failure of `node` among `notes[..before]`.
fn last_failed(entries: &[Entry], node: NodeId, before: usize) -> Option<usize> {
    entries[..before]
        .iter()
        .rposition(|e| e.node() == node && e.failed())
}

/// The observer the engine attaches to a tick once a reason was given, when the user
/// attached none: it hears nothing, but with it attached every status write goes through
/// the path that notes failures.
struct StandIn;

impl crate::Observer for StandIn {}

/// A stand-in observer. It has no size, so making one allocates nothing.
pub(crate) fn stand_in() -> &'static mut dyn crate::Observer {
    alloc::boxed::Box::leak(alloc::boxed::Box::new(StandIn))
}

/// Noting why nodes fail while a pass runs.
impl<C> super::ticker::Ticker<'_, C> {
    /// Records why node `id` fails (a reason it gave, or a built-in's own cause), and
    /// notes every Failure for the rest of the tick (see [`failure`](super::failure)).
    #[cold]
    #[inline(never)]
    pub(crate) fn note(&mut self, id: NodeId, note: Note) {
        self.out.push(id, note);
        self.watch();
    }

    /// After a leaf that held a handle: if it gave a reason, note every Failure from now
    /// on. A leaf that gave none pays a load and a branch.
    #[inline(always)]
    pub(crate) fn watch_if_noted(&mut self) {
        if self.observer.is_none() && !self.out.is_quiet() {
            self.watch();
        }
    }

    /// Attaches the engine's stand-in observer, unless one is attached: status writes then
    /// go through [`set_status_observed`](Self::set_status_observed), which notes failures.
    #[cold]
    #[inline(never)]
    pub(crate) fn watch(&mut self) {
        if self.observer.is_none() {
            self.observer = Some(stand_in());
            self.watching = true;
        }
    }

    /// Notes node `id`'s Failure, telling the user's observer first of the reason the node
    /// gave for it, if it gave one just before.
    #[cold]
    #[inline(never)]
    pub(super) fn note_failed(&mut self, id: NodeId) {
        if !self.watching {
            if let (Some(reason), Some(o)) =
                (self.out.last_reason_of(id), self.observer.as_deref_mut())
            {
                o.on_failure_reason(id, &reason);
            }
        }
        self.out.push(id, Note::Failed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::string::ToString;

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
