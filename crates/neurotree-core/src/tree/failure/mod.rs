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
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;
use core::time::Duration;

use crate::blueprint::Blueprint;
use crate::nodes::built_in::Family;
use crate::{NodeId, NodeStatus, TickError};

mod record;

use record::Entry;
pub(crate) use record::{Note, Notes, Outcome};

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

/// What the tree keeps of why its last tick failed or erred.
impl<C> super::Tree<C> {
    /// Makes the record of failure reasons now, with room for the most it holds, rather than
    /// in the first tick in which a node gives a reason (see the [module docs](self)): after it, no tick
    /// of this tree allocates for reasons. For programs that must not allocate while ticking
    /// at all; it costs 792 bytes (a record made by a tick has room for half as many words
    /// until a tick needs more, and no room for reasons other than the built-ins' until a
    /// node gives one). It makes the box that keeps the tree's errors and the reasons kept
    /// apart too, so that an error then allocates only for its own text.
    pub fn reserve_failure_record(&mut self) {
        self.out.reserve();
    }

    /// Why the root failed on the last tick: the chain from the root to the node whose
    /// failure decided it, with the reasons nodes gave on the way; `None` unless the last
    /// [`tick_once`](Self::tick_once) or [`tick_exactly_once`](Self::tick_exactly_once)
    /// returned Failure. Built now, from the tick's record; see the [module docs](self) for which
    /// failure "decided" the root. When no node gave a reason during the tick, the chain
    /// is the root alone, with no reason.
    ///
    /// ```
    /// use neurotree_core::{Action, Blueprint, Handle, ManualClock, Status, Tree};
    ///
    /// struct FollowPath;
    /// impl Action<()> for FollowPath {
    ///     fn tick(&self, h: &mut Handle<'_, ()>) -> Status {
    ///         h.fail_with(106, "blocked")
    ///     }
    /// }
    /// let bp = Blueprint::<()>::builder()
    ///     .sequence("go", |s| s.action_node("follow_path", FollowPath))
    ///     .build_shared()
    ///     .unwrap();
    /// let mut tree = Tree::with_clock(bp, ManualClock::new());
    /// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Failure));
    /// let failure = tree.last_failure().unwrap();
    /// assert_eq!(failure.leaf().path, "go/follow_path");
    /// assert_eq!(failure.reason().unwrap().to_string(), "blocked (error 106)");
    /// ```
    pub fn last_failure(&self) -> Option<Failure> {
        (self.last_root == NodeStatus::Failure)
            .then(|| build(&self.blueprint, self.state.failed(), self.out.notes()))
    }

    /// The error the last [`tick_once`](Self::tick_once) or
    /// [`tick_exactly_once`](Self::tick_exactly_once) returned, kept until the next of
    /// them starts; `None` when it returned a status. Other calls (a halt) leave it as it
    /// is.
    ///
    /// ```
    /// use neurotree_core::{Blueprint, ManualClock, Status, TickError, Tree};
    ///
    /// // A sync action may not return Running.
    /// let bp = Blueprint::<()>::builder()
    ///     .action("bad", |_: &mut ()| Status::Running)
    ///     .build_shared()
    ///     .unwrap();
    /// let mut tree = Tree::with_clock(bp, ManualClock::new());
    /// assert!(tree.tick_once(&mut ()).is_err());
    /// assert!(matches!(tree.last_error(), Some(TickError::LeafRunning { .. })));
    /// ```
    pub fn last_error(&self) -> Option<&TickError> {
        self.out.last_error()
    }

    /// Keeps a copy of the error a tick call returns, and gives it back. The tree rests
    /// nowhere after an error: it was halted, and the next call's pass starts at the root
    /// (the calls' paths for a resting tree keep and forget no error).
    #[cold]
    #[inline(never)]
    pub(super) fn kept(&mut self, error: TickError) -> TickError {
        self.resting = None;
        self.out.kept(error)
    }
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
