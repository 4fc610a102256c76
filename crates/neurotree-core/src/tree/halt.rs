//! Halting a tree from another thread: the [`HaltHandle`].
//!
//! The thread that ticks a tree owns it (`&mut`), so another thread cannot halt it directly.
//! It asks instead: [`HaltHandle::request`] raises a flag the tree reads at its next **tick
//! boundary**, never in the middle of a node:
//!
//! - at the start of every [`Tree::tick_once`](crate::Tree::tick_once) and
//!   [`Tree::tick_exactly_once`](crate::Tree::tick_exactly_once) call;
//! - between two passes of one `tick_once` (a pass that was in progress when the request
//!   came completes normally first).
//!
//! At a boundary with a request pending, the tree does what [`Tree::halt`](crate::Tree::halt)
//! does (every Running node halted, children first, each Running stateful action getting
//! exactly one `on_halted`, every async action's future dropped), clears the request, and
//! the call returns [`TickError::HaltRequested`] without
//! ticking anything more. The next call starts afresh. A request made while nothing runs is
//! served the same way: the halt changes nothing, and the call still returns the error, so
//! a loop that ticks ends either way. A halt that takes ticks
//! ([`slow_halt`]) goes on in the next calls, which return Running
//! without ticking the root until it is done, or with [`Tree::tick_halt`](crate::Tree::tick_halt).
//!
//! A request made during a pass of `tick_once` that leaves the root Running is served right
//! after that pass: the request wakes the tree, which asks for another pass, and the
//! boundary before it serves the request. One made during a pass that completes the root,
//! or during `tick_exactly_once`'s only pass, waits for the next call, which serves it
//! before ticking. Requests do not queue: any number made before a boundary are served by
//! one halt.
//!
//! Loops that wait between ticks end their wait early:
//! [`Tree::tick_while_running`](crate::Tree::tick_while_running) and the toolkit's runners.
//! A request also sets the tree's [`WakeSignal`], so a runner awaiting
//! it ticks at once.
//!
//! The handle costs nothing until it is made: the flag lives in the tree's wake signal,
//! which trees without async actions make only on demand, and a tree without one checks
//! for a request with a single branch per call.

use core::fmt;

use super::{slow_halt, Tree, WakeSignal};
use crate::{NodeId, NodeStatus, Status, TickError};

/// Asks a [`Tree`] to halt at its next tick boundary, from any thread; clones
/// ask the same tree. Made by [`Tree::halt_handle`](crate::Tree::halt_handle).
///
/// ```
/// use std::sync::Arc;
/// use neurotree_core::{Blueprint, ManualClock, Status, TickError, Tree};
///
/// let blueprint = Blueprint::<()>::builder()
///     .sleep("nap", core::time::Duration::from_secs(60))
///     .build_shared()
///     .unwrap();
/// let mut tree = Tree::with_clock(blueprint, ManualClock::new());
/// let handle = tree.halt_handle();
/// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
///
/// std::thread::spawn(move || handle.request()).join().unwrap();
/// assert_eq!(tree.tick_once(&mut ()), Err(TickError::HaltRequested));
/// // Served: the tree was halted and the next tick starts afresh.
/// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
/// ```
#[derive(Clone)]
pub struct HaltHandle {
    signal: WakeSignal,
}

impl HaltHandle {
    pub(crate) fn new(signal: WakeSignal) -> Self {
        Self { signal }
    }

    /// Asks the tree to halt at its next tick boundary, and wakes a runner waiting on the
    /// tree's wake signal. Returns at once; the tick thread serves the request.
    pub fn request(&self) {
        self.signal.request_halt();
    }

    /// `true` while a request waits to be served.
    pub fn is_pending(&self) -> bool {
        self.signal.halt_requested()
    }
}

impl fmt::Debug for HaltHandle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("HaltHandle")
            .field("pending", &self.is_pending())
            .finish()
    }
}

/// Halting a tree from the thread that ticks it, and the halts that take ticks.
impl<C> Tree<C> {
    /// Halts every Running node (children before parents) and resets the whole tree to
    /// Idle, as BehaviorTree.CPP's `haltTree` does: stateful actions that were Running get
    /// `on_halted`, and completed statuses a control had left in place (a two-child
    /// IfThenElse keeps its failed condition's) are cleared too, so the next tick starts
    /// afresh. RunOnce and Cooldown keep their memory, SequenceWithMemory its place.
    ///
    /// Returns `true` when the tree is fully halted. An action whose halt takes several
    /// ticks ([`HaltProgress::Halting`](crate::HaltProgress::Halting), or an async action's
    /// [`HaltFuture`](crate::HaltFuture) not ready at its first poll, or a TryCatch's catch
    /// waiting for them) makes it `false`: such halts, and those that were in progress, now
    /// wait for the tree. Call
    /// [`tick_halt`](Self::tick_halt) until it returns `true` (or keep ticking:
    /// [`tick_once`](Self::tick_once) continues them first, and ticks the root only once
    /// they are done). See [`slow_halt`].
    pub fn halt(&mut self, ctx: &mut C) -> bool {
        self.resting = None;
        self.wake_up();
        let mut t = self.ticker(ctx);
        t.halt_node(NodeId::ROOT);
        // Nothing is Running any more, so this only resets what a control left behind.
        for id in t.bp.ids() {
            t.halt_node(id);
        }
        self.out.halts.count == 0
    }

    /// Continues every halt in progress (one [`on_halting`](crate::StatefulAction::on_halting)
    /// or poll of its halt future for each action still halting, whoever waits for it, then
    /// the catch of each TryCatch whose try block has stopped) without ticking the root;
    /// returns `true` when the tree is fully halted. A runner that halts a tree calls it,
    /// a tick period apart, until it does.
    ///
    /// ```
    /// use neurotree_core::{Blueprint, HaltProgress, Handle, ManualClock, StatefulAction, Status, Tree};
    ///
    /// /// Runs until halted, then takes `ticks` more ticks to stop.
    /// struct Arm { ticks: u32, left: u32 }
    /// impl StatefulAction<()> for Arm {
    ///     fn on_start(&mut self, _h: &mut Handle<'_, ()>) -> Status { Status::Running }
    ///     fn on_running(&mut self, _h: &mut Handle<'_, ()>) -> Status { Status::Running }
    ///     fn on_halt_requested(&mut self, _h: &mut Handle<'_, ()>) -> HaltProgress {
    ///         self.left = self.ticks;
    ///         HaltProgress::Halting
    ///     }
    ///     fn on_halting(&mut self, _h: &mut Handle<'_, ()>) -> HaltProgress {
    ///         self.left -= 1;
    ///         if self.left == 0 { HaltProgress::Done } else { HaltProgress::Halting }
    ///     }
    /// }
    /// let bp = Blueprint::<()>::builder()
    ///     .stateful("arm", || Arm { ticks: 2, left: 0 })
    ///     .build_shared()
    ///     .unwrap();
    /// let mut tree = Tree::with_clock(bp, ManualClock::new());
    /// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    /// assert!(!tree.halt(&mut ()));
    /// assert!(tree.is_halting());
    /// assert!(!tree.tick_halt(&mut ()));
    /// assert!(tree.tick_halt(&mut ()));
    /// assert!(!tree.is_halting());
    /// ```
    pub fn tick_halt(&mut self, ctx: &mut C) -> bool {
        if self.out.halts.count != 0 {
            // A panic in `on_halting` ends that action's halt; the halt has no error to give.
            let _ = self.continue_halt(ctx, slow_halt::Waiter::Any);
        }
        let done = self.out.halts.count == 0;
        if done {
            self.finish_reload();
        }
        done
    }

    /// `true` while a halt is in progress: an action whose halt takes ticks, or a TryCatch
    /// whose catch waits for one (see [`slow_halt`]).
    pub fn is_halting(&self) -> bool {
        self.out.halts.count != 0
    }

    /// Continues the halts `waiter` selects: `Ok(true)` while any is left.
    #[cold]
    #[inline(never)]
    pub(super) fn continue_halt(
        &mut self,
        ctx: &mut C,
        waiter: slow_halt::Waiter,
    ) -> Result<bool, TickError> {
        // As a pass does: this call polls every halt future it continues, so earlier wakes
        // are answered by it.
        if let Some(w) = self.wake() {
            w.signal.take();
        }
        let mut t = self.ticker(ctx);
        let left = t.continue_halts(waiter);
        match t.out.take_fault() {
            Some(fault) => Err(fault),
            None => Ok(left),
        }
    }

    /// Before a tick call: continues the halts that wait for the tree. `Some` (Running, or
    /// the error of a panic in `on_halting`) while any is left: the root is not ticked.
    #[cold]
    #[inline(never)]
    pub(super) fn tree_waits(&mut self, ctx: &mut C) -> Option<Result<Status, TickError>> {
        match self.continue_halt(ctx, slow_halt::Waiter::Owner(None)) {
            Ok(false) => {
                self.finish_reload();
                None
            }
            Ok(true) => {
                self.last_root = NodeStatus::Running;
                Some(Ok(Status::Running))
            }
            Err(fault) => Some(Err(fault)),
        }
    }
}
