//! Sleeping trees: a tree whose Running leaves all wait for something is not ticked until
//! that something can have happened.
//!
//! A leaf says what it waits on when it returns Running: a moment on the tree's clock
//! ([`Handle::sleep_until`](crate::Handle::sleep_until)) or a write to the blackboard
//! ([`Handle::wake_on`](crate::Handle::wake_on)); a custom control or decorator says it
//! through [`NodeCtx`](crate::NodeCtx) in the same words. The built-in timers declare their
//! own deadlines: Sleep, Delay while it waits, Timeout while its child runs.
//!
//! After a pass whose root is Running, the tree falls asleep when all of these hold:
//!
//! - every stateful action that returned Running in the pass declared what it waits on;
//! - no async action returned Running, and every custom node ticked declared;
//! - no node asked for another pass, no halt waits for a slow halt, no observer that
//!   sees every tick is attached
//!   ([`Observer::lets_tree_sleep`](crate::Observer::lets_tree_sleep)), and the pass wrote nothing to the blackboard;
//! - every child a Running ReactiveSequence, ReactiveFallback or WhileDoElse re-checks
//!   reads only what wakes the tree: a condition whose kind reads only the blackboard
//!   ([`Condition::reads_only_blackboard`](crate::Condition::reads_only_blackboard), the
//!   toolkit's scripts), or that declared its wake in the tick
//!   ([`Handle::wake_on`](crate::Handle::wake_on),
//!   [`Handle::wake_on_handle`](crate::Handle::wake_on_handle)); a closure of the
//!   context, a node that would answer otherwise when ticked again (a Sleep that just
//!   completed), and every other leaf keep it awake (as does KeepRunningUntilFailure after
//!   its child succeeded: its next tick starts it again), and so does an action halted in
//!   the pass while Running (its branch failed under it), which the re-check would start
//!   again.
//!
//! [`Tree::why_awake`] names the first thing that kept the tree awake.
//!
//! A sleeping tree's [`tick_once`](crate::Tree::tick_once) and
//! [`tick_exactly_once`](crate::Tree::tick_exactly_once) return Running at once, without a
//! pass, until it wakes: the clock reaches the earliest deadline declared, the blackboard is
//! written (any entry: the tree does not tell entries apart), its [`WakeHandle`] or
//! [`WakeSignal`] fires, a halt is requested, an observer that sees every tick is attached,
//! or the tree is halted, reloaded or restored. Since a sleeping tree skips only passes
//! whose result would have been the same, statuses, halts and the blackboard are those of
//! a tree ticked every frame; only the calls of the waiting leaves are saved.
//!
//! A leaf that declares nothing keeps the tree awake: it is ticked every frame, as before.

use core::sync::atomic::{AtomicU8, Ordering};
use core::time::Duration;

use super::why_awake::AwakeReason;
use crate::clock::duration_to_nanos;
use crate::tree::WakeSignal;
use crate::{NodeId, Tree};

/// What the nodes ticked in one pass said they wait on.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Waits {
    /// The earliest deadline declared, in clock nanoseconds; `u64::MAX`: none.
    pub(crate) deadline: u64,
    /// The stateful action ticked last declared a wait.
    pub(crate) declared: bool,
    /// A node ticked in the pass waits on nothing it declared: the tree stays awake.
    pub(crate) awake: bool,
    /// Some node declared a wait (a deadline or an event) in the pass: a Running root
    /// with none is Running for some other reason, and stays awake.
    pub(crate) any: bool,
    /// A leaf ticked (since a reactive node last looked) may read more than the
    /// blackboard: its context, the world. A reactive node that re-checks it every tick
    /// keeps the tree awake.
    pub(crate) opaque: bool,
    /// The last leaf that may read more than the blackboard.
    pub(crate) opaque_node: NodeId,
    /// Why the tree stays awake after this pass: the first reason given, and its node.
    pub(crate) reason: Option<(AwakeReason, NodeId)>,
}

impl Waits {
    /// Nothing declared, nothing keeping the tree awake.
    pub(crate) const fn new() -> Self {
        Self {
            deadline: u64::MAX,
            declared: false,
            awake: false,
            any: false,
            opaque: false,
            opaque_node: NodeId(0),
            reason: None,
        }
    }

    /// Keeps the tree awake after this pass, for `reason` at `node` (the first one given
    /// is kept).
    #[inline]
    pub(crate) fn keep_awake(&mut self, reason: AwakeReason, node: NodeId) {
        if !self.awake {
            self.awake = true;
            self.reason = Some((reason, node));
        }
    }

    /// Notes that `node`, a leaf, may read more than the blackboard.
    #[inline]
    pub(crate) fn opaque(&mut self, node: NodeId) {
        // Two plain stores, no branch: conditions of the context are the commonest leaves.
        self.opaque = true;
        self.opaque_node = node;
    }

    /// Declares a deadline at `at`.
    #[inline]
    pub(crate) fn until(&mut self, at: Duration) {
        self.deadline = self.deadline.min(duration_to_nanos(at));
        self.declared = true;
        self.any = true;
    }

    /// Declares a wait for an event: a blackboard write or a wake.
    #[inline]
    pub(crate) fn on_event(&mut self) {
        self.declared = true;
        self.any = true;
    }
}

/// What the leaf being ticked declared through a shared handle: a condition's
/// [`check`](crate::Condition::check) sees `&Handle`, and may still say what wakes it.
///
/// Atomics only so that a tree stays `Sync`: one thread ticks a tree, so relaxed loads and
/// stores are plain ones.
#[derive(Debug, Default)]
pub(crate) struct Reads(AtomicU8);

/// The leaf said it waits for a write or a wake ([`Handle::wake_on`](crate::Handle::wake_on),
/// [`Handle::wake_on_handle`](crate::Handle::wake_on_handle)).
const EVENT: u8 = 1;
/// The leaf's kind reads only the blackboard and its ports.
const PURE: u8 = 2;
/// A condition called from a run (a guard's loop) may read more than the blackboard:
/// kept until the caller takes it.
const SEEN_OPAQUE: u8 = 4;

impl Reads {
    /// Before a leaf's call: nothing declared yet; `pure` if its kind says it reads only
    /// the blackboard.
    #[inline(always)]
    pub(crate) fn declare(&self, pure: bool) {
        let seen = self.0.load(Ordering::Relaxed) & SEEN_OPAQUE;
        self.0
            .store(seen | if pure { PURE } else { 0 }, Ordering::Relaxed);
    }

    /// After a condition's call from a run: notes it if it may read more than the
    /// blackboard, for [`take_opaque`](Self::take_opaque).
    #[inline(always)]
    pub(crate) fn settle(&self) {
        let v = self.0.load(Ordering::Relaxed);
        if v & (EVENT | PURE) == 0 {
            self.0.store(v | SEEN_OPAQUE, Ordering::Relaxed);
        }
    }

    /// After a run of conditions: `true` if one may read more than the blackboard.
    #[inline(always)]
    pub(crate) fn take_opaque(&self) -> bool {
        let v = self.0.load(Ordering::Relaxed);
        if v & SEEN_OPAQUE == 0 {
            return false;
        }
        self.0.store(v & !SEEN_OPAQUE, Ordering::Relaxed);
        true
    }

    /// The leaf said it waits for a write or a wake.
    #[inline(always)]
    pub(crate) fn on_event(&self) {
        self.0
            .store(self.0.load(Ordering::Relaxed) | EVENT, Ordering::Relaxed);
    }

    /// After the call: `true` if the leaf declared a wait for an event.
    #[inline(always)]
    pub(crate) fn event(&self) -> bool {
        self.0.load(Ordering::Relaxed) & EVENT != 0
    }

    /// After the call: `true` if the leaf reads only what wakes the tree.
    #[inline(always)]
    pub(crate) fn known(&self) -> bool {
        self.0.load(Ordering::Relaxed) & (EVENT | PURE) != 0
    }
}

/// A sleeping tree's wake conditions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Asleep {
    /// The earliest deadline, in clock nanoseconds; `u64::MAX`: none.
    until: u64,
    /// The blackboard's write count when the tree fell asleep.
    writes: u64,
}

impl Asleep {
    /// What an awake tree keeps in the place.
    pub(crate) const NONE: Self = Self {
        until: u64::MAX,
        writes: 0,
    };
}

/// Wakes a sleeping tree from anywhere (another thread, a game event): the tree's next
/// tick is a pass. Clones wake the same tree.
///
/// ```
/// use neurotree_core::{Blueprint, Handle, ManualClock, Status, StatefulAction, Tree};
///
/// /// Waits for a door that someone else opens, and says so.
/// struct WaitForDoor;
/// impl StatefulAction<bool> for WaitForDoor {
///     fn on_start(&mut self, h: &mut Handle<'_, bool>) -> Status { self.on_running(h) }
///     fn on_running(&mut self, h: &mut Handle<'_, bool>) -> Status {
///         if *h.ctx() { return Status::Success; }
///         h.wake_on_handle();
///         Status::Running
///     }
/// }
/// let bp = Blueprint::<bool>::builder()
///     .stateful("door", || WaitForDoor)
///     .build_shared()
///     .unwrap();
/// let mut tree = Tree::with_clock(bp, ManualClock::new());
/// let door = tree.wake_handle();
/// let mut open = false;
/// assert_eq!(tree.tick_once(&mut open), Ok(Status::Running));
/// assert!(tree.is_asleep());
/// open = true;
/// // Asleep: the door is not looked at until the handle fires.
/// assert_eq!(tree.tick_once(&mut open), Ok(Status::Running));
/// door.wake();
/// assert_eq!(tree.tick_once(&mut open), Ok(Status::Success));
/// ```
#[derive(Clone, Debug)]
pub struct WakeHandle {
    signal: WakeSignal,
}

impl WakeHandle {
    /// Wakes the tree: its next tick is a pass.
    pub fn wake(&self) {
        self.signal.wake();
    }
}

impl<C> Tree<C> {
    /// A handle that wakes this tree when it sleeps (see [`sleep`](self)). Makes the tree's
    /// [`WakeSignal`] if it had none.
    pub fn wake_handle(&mut self) -> WakeHandle {
        WakeHandle {
            signal: self.wake_signal().clone(),
        }
    }

    /// With `false`, the tree never sleeps: it is ticked every frame whatever its leaves
    /// declare (a reference to compare a sleeping tree with, or a runner that counts
    /// passes). `true` by default; `false` also wakes a sleeping tree.
    pub fn set_sleep_allowed(&mut self, allowed: bool) {
        self.sleep_allowed = allowed;
        if !allowed {
            self.set_asleep(None);
        }
    }

    /// `true` while the tree sleeps: its ticks return Running without a pass until it wakes.
    pub fn is_asleep(&self) -> bool {
        self.sleeping
    }

    /// What wakes the tree, while it sleeps.
    #[inline]
    pub(crate) fn asleep(&self) -> Option<Asleep> {
        self.sleeping.then_some(self.asleep)
    }

    /// Puts the tree to sleep until `asleep`, or wakes it (`None`).
    #[inline]
    fn set_asleep(&mut self, asleep: Option<Asleep>) {
        self.sleeping = asleep.is_some();
        self.asleep = asleep.unwrap_or(Asleep::NONE);
    }

    /// When the sleeping tree wakes on its own: the earliest deadline its nodes declared.
    /// `None` if it is awake, or waits only for a write or a wake.
    pub fn wakes_at(&self) -> Option<Duration> {
        self.asleep()
            .filter(|a| a.until != u64::MAX)
            .map(|a| Duration::from_nanos(a.until))
    }

    /// `true` if the tree is awake, or sleeps and something it waits on happened: its next
    /// tick will be a pass. A runner ticking many trees asks this to skip the others.
    pub fn is_due(&self) -> bool {
        match self.asleep() {
            None => true,
            Some(a) => {
                duration_to_nanos(self.clock.now()) >= a.until
                    || self.blackboard.writes() != a.writes
                    || self.keeps_awake_observer()
                    || self.wake().is_some_and(|w| w.signal.is_woken())
            }
        }
    }

    /// At the start of a tick: `true` if the tree sleeps on (the tick returns Running with
    /// no pass), else it is awake from now on.
    #[inline]
    pub(crate) fn sleeps_on(&mut self) -> bool {
        if !self.sleeping {
            return false;
        }
        if self.is_due() {
            self.set_asleep(None);
            return false;
        }
        true
    }

    /// `true` with an observer attached that sees every tick (most do: see
    /// [`Observer::lets_tree_sleep`](crate::Observer::lets_tree_sleep)).
    #[inline]
    pub(crate) fn keeps_awake_observer(&self) -> bool {
        self.observer().is_some_and(|o| !o.lets_tree_sleep())
    }

    /// Wakes the tree if it sleeps: its next tick is a pass, whatever its nodes wait on.
    pub fn wake_up(&mut self) {
        self.set_asleep(None);
    }

    /// Before a pass: nothing declared yet. Returns the blackboard's write count, for
    /// [`fall_asleep`](Self::fall_asleep).
    #[inline]
    pub(crate) fn start_waits(&mut self) -> u64 {
        self.out.keep(&Waits::new());
        self.blackboard.writes()
    }

    /// After a pass that left the root Running with no node asking for another, its nodes
    /// waiting on `waits`: falls asleep if everything ticked waits (see the
    /// [module docs](self)). `writes`: the blackboard's write count before the pass.
    pub(crate) fn fall_asleep(&mut self, writes: u64, waits: &Waits) {
        let sleeps = !waits.awake
            && waits.any
            && self.sleep_allowed
            && !self.keeps_awake_observer()
            && self.out.halts.count == 0
            && self.out.is_quiet()
            && self.blackboard.writes() == writes;
        if sleeps {
            self.set_asleep(Some(Asleep {
                until: waits.deadline,
                writes,
            }));
        } else if waits.reason.is_none() {
            self.out.reason = Some((self.awake_for(writes), NodeId::ROOT));
        }
    }

    /// Why a pass that kept the tree awake, with no node to blame, did (see
    /// [`why_awake`](super::why_awake)).
    #[cold]
    fn awake_for(&self, writes: u64) -> AwakeReason {
        if self.out.halts.count != 0 || !self.out.is_quiet() {
            AwakeReason::AnotherPass
        } else if self.blackboard.writes() != writes {
            AwakeReason::WroteBlackboard
        } else {
            AwakeReason::NothingDeclared
        }
    }

    /// After the action the tree rests in answered Running again without a pass, waiting
    /// on `waits`: the tree falls asleep if the action declared a wait.
    pub(crate) fn rest_asleep(&mut self, leaf: NodeId, writes: u64, waits: &Waits) {
        let _ = leaf;
        if waits.declared {
            self.fall_asleep(writes, waits);
        }
    }
}

#[cfg(test)]
mod tests;
