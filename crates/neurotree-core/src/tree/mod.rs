//! An instance of a blueprint: the per-run state, and the ways to tick it.
//!
//! A [`Tree`] holds only what changes while ticking: one status byte per node, a 32-bit slot
//! for each node whose kind keeps a cursor, a counter or a flag (two for a moment), the
//! stateful leaves' objects (all of it in one block behind one pointer), and its blackboard.
//! The structure stays in the shared [`Blueprint`].
//!
//! Two ways to tick, as in BehaviorTree.CPP:
//! - [`Tree::tick_exactly_once`]: one pass of the root;
//! - [`Tree::tick_once`]: a pass, repeated at once while a node yielded and asked to be
//!   woken (Repeat, RetryUntilSuccessful, SequenceWithMemory and the Async composites do so
//!   after a child that completed within the tick), or the future of an async action woke
//!   during the pass (see [`WakeSignal`]).
//!
//! A root that completes is reset to Idle, so the next tick starts afresh.
//!
//! A wake-up request counts only within the call that received it. (BehaviorTree.CPP keeps a
//! request made during `tickExactlyOnce`, or during a pass whose root completed, pending
//! until the next `tickOnce`, which then runs one extra pass; NeuroTree drops it, so the work
//! of one call never leaks into the next.)
//!
//! Another thread halts the tree through a [`HaltHandle`]: the request is served at the next
//! tick boundary (the start of a call, or between two passes of `tick_once`), and that call
//! returns [`TickError::HaltRequested`]; see [`halt`] for the exact rules.

pub(crate) mod calls;
mod contain;
mod error;
pub mod failure;
pub mod halt;
mod new_blackboard;
mod objects;
mod params;
mod persist;
mod prefetch;
mod rare;
mod reload;
mod rest;
mod root;
pub mod sleep;
pub mod slow_halt;
mod state;
pub(crate) mod ticker;
mod ticker_sleep;
mod wake;
pub mod why_awake;

pub use error::TickError;
pub use failure::{Failure, FailureLink, Reason, Tried};
pub use halt::HaltHandle;
pub use reload::{ReloadError, ReloadReport};
pub use sleep::WakeHandle;
pub(crate) use ticker::Ticker;
pub use wake::{WakeSignal, Woken};
pub use why_awake::{AwakeCounts, AwakeReason, WhyAwake};

use alloc::boxed::Box;
use alloc::sync::Arc;
use alloc::vec::Vec;
use core::time::Duration;

use crate::blackboard::{Blackboard, ScopeId};
use crate::blueprint::{Blueprint, NodeKind};
use crate::{Clock, NodeId, NodeStatus, Status};
use new_blackboard::new_blackboard;
use rare::Rare;
use rest::Rest;
use root::{recover, tick_root, to_result};
use state::NodeState;
use ticker::Object;
use wake::TreeWake;

/// A running instance of a [`Blueprint`], ticked with a user context `C`.
pub struct Tree<C> {
    blueprint: Arc<Blueprint<C>>,
    /// The nodes' statuses and slots, a bit per node (its status was written Failure in the
    /// last tick, see [`failure`]), and the stateful leaves' objects: one block behind one
    /// pointer (see [`state`]).
    state: NodeState<C>,
    blackboard: Blackboard,
    clock: Arc<dyn Clock>,
    /// What few trees use (an observer, a wake signal, a pass bound of their own, a reload
    /// in progress): boxed, made on first use, so that the many trees of a crowd pay one
    /// pointer for all of it.
    rare: Option<Box<Rare<C>>>,
    /// The passes the last `tick_once` made.
    last_passes: u32,
    /// A second Running child of a reactive control is an error
    /// ([`reject_multiple_running`](Self::reject_multiple_running)).
    reject_multiple_running: bool,
    /// The pass's error, and the record of reasons given during the last tick.
    out: failure::Outcome,
    /// What the root returned on the last tick (Idle after an error).
    last_root: NodeStatus,
    /// The stateful action the last pass rested in: it returned Running under a chain of
    /// nodes up to the root that pass a Running child's tick straight through, and which
    /// all returned Running. The next pass starts at it rather than at the root
    /// ([`resting_answer`](Self::resting_answer)).
    resting: Option<NodeId>,
    /// While the tree sleeps (see [`sleep`]), what wakes it; apart from its flag, so that
    /// the two fit in 17 bytes rather than 24.
    asleep: sleep::Asleep,
    /// The tree sleeps.
    sleeping: bool,
    /// The tree may sleep ([`Tree::set_sleep_allowed`]).
    sleep_allowed: bool,
}

/// Bytes of the node state block of a tree of `nodes` nodes, `slots` slots and `objects`
/// objects (see [`state`]).
pub(crate) fn node_state_bytes<C>(nodes: usize, slots: usize, objects: usize) -> usize {
    NodeState::<C>::bytes_for(nodes, slots, objects)
}

/// Passes one [`Tree::tick_once`] makes at most, unless [`Tree::set_max_passes`] says
/// otherwise: enough for a `Repeat` of a million quick cycles, finite for one of `-1`.
pub const DEFAULT_MAX_PASSES: u32 = 1_000_000;

/// The longest stretch of the clock's time a wait between ticks sleeps before looking for a
/// halt request again, once the tree has a [`HaltHandle`]: how late, at most, a request ends
/// [`Tree::tick_while_running`]'s wait (and the toolkit's `FixedRate` sleep).
pub const HALT_POLL_PERIOD: Duration = Duration::from_millis(10);

/// Who asked for another pass of the root.
#[derive(Clone, Copy)]
enum Waker {
    /// A node that yielded (a Repeat between cycles, an async Sequence between children).
    Node(NodeId),
    /// The future of an async action.
    Future,
}

impl<C> Tree<C> {
    /// A fresh instance whose time-based nodes read `clock`.
    pub fn with_clock(blueprint: Arc<Blueprint<C>>, clock: impl Clock + 'static) -> Self {
        Self::with_shared_clock(blueprint, Arc::new(clock))
    }

    /// A fresh instance sharing `clock` with other trees.
    pub fn with_shared_clock(blueprint: Arc<Blueprint<C>>, clock: Arc<dyn Clock>) -> Self {
        let mut objects = Vec::with_capacity(blueprint.objects as usize);
        let mut wake = None;
        for def in blueprint.nodes.iter() {
            match &def.kind {
                NodeKind::Stateful(make) => objects.push(Object::Stateful(make())),
                NodeKind::Custom(spec) => objects.push(Object::Custom((spec.factory)())),
                NodeKind::Async(_) => {
                    objects.push(Object::Async(None));
                    wake.get_or_insert_with(|| Box::new(TreeWake::new()));
                }
                _ => {}
            }
        }
        let blackboard = new_blackboard(&blueprint);
        let rare = wake.map(|wake| {
            Box::new(Rare {
                wake: Some(wake),
                ..Rare::new()
            })
        });
        Self {
            state: NodeState::new(blueprint.len(), blueprint.aux_slots as usize, objects),
            blackboard,
            clock,
            rare,
            last_passes: 0,
            reject_multiple_running: false,
            out: failure::Outcome::new(),
            last_root: NodeStatus::Idle,
            resting: None,
            asleep: sleep::Asleep::NONE,
            sleeping: false,
            sleep_allowed: true,
            blueprint,
        }
    }

    /// A fresh instance on the system clock.
    #[cfg(feature = "std")]
    pub fn new(blueprint: Arc<Blueprint<C>>) -> Self {
        Self::with_clock(blueprint, crate::SystemClock::new())
    }

    /// The blueprint this tree instantiates.
    pub fn blueprint(&self) -> &Arc<Blueprint<C>> {
        &self.blueprint
    }

    /// The stored status of a node.
    pub fn status(&self, id: NodeId) -> NodeStatus {
        self.state.statuses()[id.index()]
    }

    /// The stored status of every node, indexed by [`NodeId`].
    pub fn statuses(&self) -> &[NodeStatus] {
        self.state.statuses()
    }

    /// The tree's blackboard.
    pub fn blackboard(&self) -> &Blackboard {
        &self.blackboard
    }

    /// The tree's blackboard, to seed or inspect entries between ticks.
    pub fn blackboard_mut(&mut self) -> &mut Blackboard {
        &mut self.blackboard
    }

    /// The scope a SubTree node opened for its child, if `id` is a SubTree.
    pub fn subtree_scope(&self, id: NodeId) -> Option<ScopeId> {
        match self.blueprint.kind(id) {
            NodeKind::SubTree(_) => self
                .blueprint
                .children(id)
                .first()
                .map(|c| self.blueprint.scope(*c)),
            _ => None,
        }
    }

    /// The clock the tree reads.
    pub fn clock(&self) -> &dyn Clock {
        &*self.clock
    }

    /// Moves the tree onto `clock`, shared with other trees, and wakes it if it slept: its
    /// sleep's deadline was a reading of the old clock. Time-based nodes that are Running
    /// keep the readings they took (a Delay's start), so move a tree while it is Idle or
    /// halted, or between clocks that read the same.
    pub fn set_shared_clock(&mut self, clock: Arc<dyn Clock>) {
        self.clock = clock;
        self.wake_up();
    }

    /// `true` while a [`HaltHandle`]'s request waits to be served by the next tick call; a
    /// runner waiting between ticks reads it to stop waiting.
    #[inline]
    pub fn halt_requested(&self) -> bool {
        match self.wake() {
            Some(w) => w.signal.halt_requested(),
            None => false,
        }
    }

    /// Serves a pending halt request: clears it, halts the tree, and names why.
    #[cold]
    fn serve_halt_request(&mut self, ctx: &mut C) -> TickError {
        if let Some(w) = self.wake() {
            w.signal.take_halt();
        }
        // A halt that takes ticks goes on in the next tick calls (see `slow_halt`).
        let _ = self.halt(ctx);
        TickError::HaltRequested
    }

    /// Bytes this instance keeps on the heap for node state: the block of its nodes' slots,
    /// statuses, failure bits and stateful leaves' objects
    /// ([`Blueprint::instance_state_bytes`]), the failure reasons' record once a node has
    /// given a reason, and the box that keeps the reasons that do not fit it and the tick's
    /// error once the tree has needed it; not counting what the stateful leaves' objects
    /// point to, an error's own text, or blackboard entries.
    pub fn state_bytes(&self) -> usize {
        self.state.bytes() + self.out.record_bytes()
    }

    fn ticker<'t>(&'t mut self, ctx: &'t mut C) -> Ticker<'t, C> {
        let watching = !self.out.is_quiet() && self.observer().is_none();
        let (observer, waker) = match self.rare.as_deref_mut() {
            Some(rare) => (
                rare.observer.as_deref_mut(),
                rare.wake.as_ref().map(|w| &w.waker),
            ),
            None => (None, None),
        };
        let state = self.state.parts();
        Ticker {
            bp: &self.blueprint,
            statuses: state.statuses,
            failed: state.failed,
            aux: state.aux,
            objects: state.objects,
            ctx,
            bb: &mut self.blackboard,
            clock: &*self.clock,
            observer: match observer {
                Some(o) => Some(o),
                // A reason given in an earlier pass of this tick: keep noting failures.
                None if watching => Some(failure::stand_in()),
                None => None,
            },
            watching,
            wake: None,
            waker,
            out: &mut self.out,
            waits: sleep::Waits::new(),
            halter: slow_halt::Halter::TREE,
            current: NodeId::ROOT,
            reject_multiple_running: self.reject_multiple_running,
            rested: None,
            replay: None,
            reset_after_store: None,
        }
    }

    /// One pass of the root: returns its status and who, if anyone, asked for another pass
    /// (a node that yielded, or a future that woke during the pass).
    /// `given`: the answer the action the tree rests in gave in this tick already.
    fn pass(
        &mut self,
        ctx: &mut C,
        given: Option<(NodeId, NodeStatus)>,
    ) -> Result<(NodeStatus, Option<Waker>), TickError> {
        // The pass polls every future still running, so earlier wakes are answered by it.
        if let Some(w) = self.wake() {
            w.signal.take();
        }
        let (status, asked) = self.pass_inner(ctx, given)?;
        let woken = self.wake().is_some_and(|w| w.signal.is_woken());
        let waker = match asked {
            Some(node) => Some(Waker::Node(node)),
            None => woken.then_some(Waker::Future),
        };
        Ok((status, waker))
    }

    fn pass_inner(
        &mut self,
        ctx: &mut C,
        given: Option<(NodeId, NodeStatus)>,
    ) -> Result<(NodeStatus, Option<NodeId>), TickError> {
        // Awake, whatever the last pass of the same call left: it may have fallen asleep,
        // then a future or a `WakeHandle` woke the tree during it and asked for this pass.
        // A store rather than a branch: `asleep` is read only while `sleeping` is set.
        self.sleeping = false;
        let writes = self.start_waits();
        let replay = match given {
            Some(given) => Some(given),
            None => match self.rest(ctx, writes) {
                Rest::Running => return Ok((NodeStatus::Running, None)),
                Rest::Answered(leaf, answer) => Some((leaf, answer)),
                Rest::Failed(error) => return Err(error),
                Rest::No => None,
            },
        };
        self.resting = None;
        let mut t = self.ticker(ctx);
        t.replay = replay;
        if let Some(o) = t.observer.as_deref_mut() {
            o.on_tick_start(t.clock.now());
        }
        let status = match tick_root(&mut t) {
            Ok(status) => status,
            Err(panicked) => {
                t.out.keep(&t.waits);
                return Err(recover(&mut t, panicked));
            }
        };
        if status.is_completed() {
            t.set_status(NodeId::ROOT, NodeStatus::Idle);
        }
        if let Some(o) = t.observer.as_deref_mut() {
            o.on_tick_end(status, t.clock.now());
        }
        t.out.keep(&t.waits);
        if let Some(fault) = t.out.take_fault() {
            t.halt_node(NodeId::ROOT);
            return Err(fault);
        }
        let (wake, rested, waits) = (t.wake, t.rested, t.waits);
        if status == NodeStatus::Running && wake.is_none() {
            self.resting = rested.filter(|leaf| self.blueprint.resting[leaf.index()]);
            self.fall_asleep(writes, &waits);
        } else if wake.is_some() && self.out.reason.is_none() {
            self.out.reason = Some((why_awake::AwakeReason::AnotherPass, NodeId::ROOT));
        }
        Ok((status, wake))
    }

    /// Ticks the root exactly once, ignoring wake-up requests. A future that woke during the
    /// pass leaves the [`wake_signal`](Self::wake_signal) set, for a runner to tick again soon.
    ///
    /// A pending [`HaltHandle`] request is served first: the tree is halted and the call
    /// returns [`TickError::HaltRequested`] without ticking.
    // Inlined, so that a caller ticking many resting trees (a crowd) gets the resting
    // case without a call or a result passed through memory; the rest is out of line.
    #[inline]
    pub fn tick_exactly_once(&mut self, ctx: &mut C) -> Result<Status, TickError> {
        // Resting, with no future to poll (nor a halt request to serve): nothing else in
        // this call could run before the action. A tree falls asleep and comes to rest
        // only in a call that returned a status, so it has no error to forget here, and
        // the error this call may end with is kept out of line (`kept`, and the pass from
        // the root).
        if self.sleeps_on() {
            return Ok(Status::Running);
        }
        let mut given = None;
        if self.wake().is_none() {
            let writes = self.start_waits();
            match self.rest(ctx, writes) {
                Rest::Running => {
                    if self.last_root != NodeStatus::Running {
                        self.last_root = NodeStatus::Running;
                    }
                    return Ok(Status::Running);
                }
                Rest::Answered(leaf, answer) => given = Some((leaf, answer)),
                Rest::Failed(error) => {
                    self.last_root = NodeStatus::Idle;
                    return Err(self.kept(error));
                }
                Rest::No => {}
            }
        }
        self.tick_exactly_once_from_root(ctx, given)
    }

    /// [`tick_exactly_once`](Self::tick_exactly_once) past the resting case: a pass from
    /// the root, given the answer of the action the tree rested in, if it gave one; keeps
    /// the error it ends with, forgetting the last call's.
    #[inline(never)]
    fn tick_exactly_once_from_root(
        &mut self,
        ctx: &mut C,
        given: Option<(NodeId, NodeStatus)>,
    ) -> Result<Status, TickError> {
        if self.out.holds_error() {
            self.out.forget_error();
        }
        match self.tick_exactly_once_passes(ctx, given) {
            Ok(status) => Ok(status),
            Err(error) => Err(self.kept(error)),
        }
    }

    /// [`tick_exactly_once_from_root`](Self::tick_exactly_once_from_root), but for the
    /// error it keeps.
    #[inline(always)]
    fn tick_exactly_once_passes(
        &mut self,
        ctx: &mut C,
        given: Option<(NodeId, NodeStatus)>,
    ) -> Result<Status, TickError> {
        if self.halt_requested() {
            return Err(self.serve_halt_request(ctx));
        }
        // The reasons noted now are the resting action's, given in this call with its
        // answer (`rest` runs only with the record empty): the pass that replays the answer
        // keeps them, as a pass from the root would.
        self.start_tick(given.is_none());
        if self.out.halts.count != 0 {
            if let Some(waiting) = self.tree_waits(ctx) {
                return waiting;
            }
        }
        let (status, _) = self.pass(ctx, given)?;
        self.last_root = status;
        to_result(status)
    }

    /// Forgets the last tick's outcome, and with `forget_notes` its record (empty unless a
    /// reason was given).
    #[inline(always)]
    fn start_tick(&mut self, forget_notes: bool) {
        if forget_notes && !self.out.is_quiet() {
            self.forget_notes();
        }
        // A tree of up to 64 nodes has one word of bits: one store, where `fill` of a
        // length known only at run time is a call to `memset`.
        match self.state.parts().failed {
            [word] => *word = 0,
            words => words.fill(0),
        }
        self.last_root = NodeStatus::Idle;
    }

    #[cold]
    #[inline(never)]
    fn forget_notes(&mut self) {
        self.out.forget();
    }

    /// Ticks the root, and again at once while it is Running and a node asked to be woken or
    /// the future of an async action woke during the pass (a future that wakes itself on
    /// every poll therefore keeps this call ticking until it completes).
    ///
    /// The passes are bounded ([`set_max_passes`](Self::set_max_passes), by default
    /// [`DEFAULT_MAX_PASSES`]): a `Repeat` of `-1` over a child that succeeds at once would
    /// otherwise never return. Past the bound the tree is halted and the error
    /// [`TickError::TooManyPasses`] names the node that kept asking.
    ///
    /// A panic in user code (a leaf, a custom node, a hook, an observer): with the `std`
    /// feature it is caught, every Running node is halted (each Running stateful action gets
    /// its one `on_halted`; a panic inside one skips only that node), the observer hears the
    /// tick end, and the call returns [`TickError::Panicked`] naming the node; the next tick
    /// starts afresh. Without `std` nothing can catch it: the panic leaves the tree as it
    /// found it (nodes Running, counts half-way), so call [`halt`](Self::halt) before
    /// ticking it again. [`tick_exactly_once`](Self::tick_exactly_once) does the same.
    ///
    /// A pending [`HaltHandle`] request is served at the start of the call and between two
    /// passes (never during one): the tree is halted and the call returns
    /// [`TickError::HaltRequested`]. A request made during a pass that leaves the root
    /// Running is therefore served in the same call; one made during a pass that completes
    /// the root waits for the next call. See [`halt`].
    pub fn tick_once(&mut self, ctx: &mut C) -> Result<Status, TickError> {
        if self.out.holds_error() {
            self.out.forget_error();
        }
        match self.tick_once_call(ctx) {
            Ok(status) => Ok(status),
            Err(error) => Err(self.kept(error)),
        }
    }

    /// [`tick_once`](Self::tick_once), but for the error it keeps.
    fn tick_once_call(&mut self, ctx: &mut C) -> Result<Status, TickError> {
        self.last_passes = 0;
        if self.sleeps_on() {
            return Ok(Status::Running);
        }
        self.start_tick(true);
        loop {
            if self.halt_requested() {
                return Err(self.serve_halt_request(ctx));
            }
            // Before every pass: a halt made during the last one may wait for the tree.
            if self.out.halts.count != 0 {
                if let Some(waiting) = self.tree_waits(ctx) {
                    return waiting;
                }
            }
            let (status, waker) = self.pass(ctx, None)?;
            self.last_passes += 1;
            match waker {
                Some(waker) if status == NodeStatus::Running => {
                    // A request that came during the pass is served at the top of the loop,
                    // even at the bound: the halt is what its maker asked for.
                    if self.last_passes >= self.max_passes() && !self.halt_requested() {
                        return Err(self.too_many_passes(ctx, waker));
                    }
                }
                _ => {
                    self.last_root = status;
                    return to_result(status);
                }
            }
        }
    }

    /// With `true`, a ReactiveSequence or ReactiveFallback whose child returns Running while
    /// another child returned Running earlier in the same run ends the tick with a
    /// [`TickError::Node`] naming the control ("only a single child can return Running"),
    /// as BehaviorTree.CPP does after `ReactiveSequence::EnableException(true)` and
    /// `ReactiveFallback::EnableException(true)` (one switch here for both, per tree).
    ///
    /// Off by default, as in BehaviorTree.CPP 4.10: the later child runs and the earlier one
    /// is halted. The "earlier child" is the first one that returned Running since the node
    /// last started from Idle or was halted; the same child returning Running again is fine.
    pub fn reject_multiple_running(&mut self, reject: bool) {
        self.reject_multiple_running = reject;
    }

    /// How many passes of the root the last [`tick_once`](Self::tick_once) made: 1 unless
    /// a node yielded or a future woke. A runner that budgets ticks counts these.
    pub fn last_passes(&self) -> u32 {
        self.last_passes
    }

    /// Halts the tree and names who kept asking for passes.
    #[cold]
    fn too_many_passes(&mut self, ctx: &mut C, waker: Waker) -> TickError {
        let _ = self.halt(ctx);
        let (node, path) = match waker {
            Waker::Node(id) => (Some(id), self.blueprint.path(id)),
            Waker::Future => (
                None,
                alloc::string::String::from("the future of an async action"),
            ),
        };
        TickError::TooManyPasses {
            node,
            path,
            passes: self.last_passes,
        }
    }

    /// Ticks with [`tick_once`](Self::tick_once) until the root completes, letting `period`
    /// pass on the tree's clock between ticks with [`Clock::wait`]: a [`SystemClock`]
    /// sleeps the thread, a [`ManualClock`] advances by `period` at once, so a run on a
    /// manual clock is as fast as the ticks and its time-based nodes still complete.
    ///
    /// The next tick starts when the wait is over, so the time a tick takes adds to the
    /// period; for a steady rate, use `neurotree::runtime::FixedRate`. With a zero
    /// period a manual clock never moves, and a tree waiting on time never completes.
    ///
    /// A [`HaltHandle`] request ends the run: the tick call serves it and this returns
    /// [`TickError::HaltRequested`]. Once the tree has a handle, the wait is made of
    /// [`Clock::wait`]s of at most [`HALT_POLL_PERIOD`], with a look for a request before
    /// each, so a request ends it within that much of the clock's time. (Slices rather than
    /// a wait woken by the request: `Clock::wait` is the clock's own way to let time pass,
    /// a sleep on wall time, a step of a manual or simulated clock, and slicing works on
    /// every clock alike; it costs a wake-up every 10 ms of a long wait, and nothing for a
    /// tree without a handle, which waits with one `Clock::wait` as before.)
    ///
    /// ```
    /// use core::time::Duration;
    /// use neurotree_core::{Blueprint, Clock, ManualClock, Status, Tree};
    ///
    /// let blueprint = Blueprint::<()>::builder()
    ///     .sleep("nap", Duration::from_millis(300))
    ///     .build_shared()
    ///     .unwrap();
    /// let clock = ManualClock::new();
    /// let mut tree = Tree::with_clock(blueprint, clock.clone());
    /// // Ticks at 0, 100, 200 and 300 ms, returning at once.
    /// let status = tree.tick_while_running(&mut (), Duration::from_millis(100));
    /// assert_eq!(status, Ok(Status::Success));
    /// assert_eq!(clock.now(), Duration::from_millis(300));
    /// ```
    ///
    /// [`SystemClock`]: crate::SystemClock
    /// [`ManualClock`]: crate::ManualClock
    #[cfg(feature = "std")]
    pub fn tick_while_running(
        &mut self,
        ctx: &mut C,
        period: Duration,
    ) -> Result<Status, TickError> {
        loop {
            let status = self.tick_once(ctx)?;
            if status != Status::Running {
                return Ok(status);
            }
            if self.has_halt_handle() {
                self.wait_unless_halt_requested(period);
            } else {
                self.clock.wait(period);
            }
        }
    }

    /// Lets `period` pass on the clock in slices of at most [`HALT_POLL_PERIOD`], returning
    /// early once a halt is requested.
    #[cfg(feature = "std")]
    fn wait_unless_halt_requested(&self, period: Duration) {
        let until = self.clock.now().saturating_add(period);
        loop {
            let now = self.clock.now();
            if now >= until || self.halt_requested() {
                return;
            }
            self.clock.wait((until - now).min(HALT_POLL_PERIOD));
        }
    }

    /// Time since the tree's clock origin.
    pub fn now(&self) -> Duration {
        self.clock.now()
    }
}

impl<C> core::fmt::Debug for Tree<C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Tree")
            .field("nodes", &self.blueprint.len())
            .field("root", &self.state.statuses()[0])
            .finish_non_exhaustive()
    }
}

#[cfg(test)]
mod tests {
    use super::DEFAULT_MAX_PASSES;
    use crate::blueprint::Blueprint;
    use crate::observer::{Observer, StatusChange};
    use crate::testing::*;
    use crate::Clock;
    use crate::NodeStatus::{Idle, Running as Run, Success as Ok_};
    use std::sync::{Arc as StdArc, Mutex};

    /// Records every event as text.
    #[derive(Clone, Default)]
    struct Recorder(StdArc<Mutex<Vec<String>>>);

    impl Recorder {
        fn take(&self) -> Vec<String> {
            core::mem::take(&mut *self.0.lock().unwrap())
        }
    }

    impl Observer for Recorder {
        fn on_tick_start(&mut self, _now: Duration) {
            self.0.lock().unwrap().push("tick".into());
        }
        fn on_status_change(&mut self, c: StatusChange) {
            self.0
                .lock()
                .unwrap()
                .push(format!("{} {}->{}", c.node.0, c.from, c.to));
        }
        fn on_node_skipped(&mut self, node: NodeId) {
            self.0.lock().unwrap().push(format!("skip {}", node.0));
        }
        fn on_tick_end(&mut self, status: NodeStatus, _now: Duration) {
            self.0.lock().unwrap().push(format!("end {status}"));
        }
    }

    #[test]
    fn observer_sees_every_change_in_order() {
        let mut lab = Lab::new(&[&[S], &[R, S]]);
        let mut tree = lab.tree(|b| b.sequence("seq", |s| s.scripted(0).scripted(1)));
        let rec = Recorder::default();
        tree.set_observer(rec.clone());
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(
            rec.take(),
            [
                "tick",
                "0 IDLE->RUNNING",
                "1 IDLE->SUCCESS",
                "2 IDLE->RUNNING",
                "end RUNNING"
            ]
        );
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(
            rec.take(),
            [
                "tick",
                "2 RUNNING->SUCCESS",
                "1 SUCCESS->IDLE",
                "2 SUCCESS->IDLE",
                "0 RUNNING->SUCCESS",
                "0 SUCCESS->IDLE",
                "end SUCCESS"
            ]
        );
    }

    #[test]
    fn observer_hears_of_skips_after_the_stored_status() {
        let (mut tree, _) = build(|b| {
            b.sequence("seq", |s| {
                s.run_once("once", true, |o| o.always_success("a"))
                    .always_success("b")
            })
        });
        let rec = Recorder::default();
        assert_eq!(tick(&mut tree), Ok(Status::Success));
        tree.set_observer(rec.clone());
        // The spent RunOnce stays Idle, so only the skip event tells of it.
        assert_eq!(tick(&mut tree), Ok(Status::Success));
        assert_eq!(
            rec.take(),
            [
                "tick",
                "0 IDLE->RUNNING",
                "skip 1",
                "3 IDLE->SUCCESS",
                "3 SUCCESS->IDLE",
                "0 RUNNING->SUCCESS",
                "0 SUCCESS->IDLE",
                "end SUCCESS"
            ]
        );

        // A control whose only child is skipped marked itself Running first: its return
        // to Idle comes before its own skip.
        let (mut tree, _) = build(|b| {
            b.sequence("seq", |s| {
                s.run_once("once", true, |o| o.always_success("a"))
            })
        });
        assert_eq!(tick(&mut tree), Ok(Status::Success));
        tree.set_observer(rec.clone());
        assert_eq!(tick(&mut tree), Err(TickError::RootSkipped));
        assert_eq!(
            rec.take(),
            [
                "tick",
                "0 IDLE->RUNNING",
                "skip 1",
                "0 RUNNING->IDLE",
                "skip 0",
                "end SKIPPED"
            ]
        );
    }

    #[test]
    fn observer_counts_each_nodes_own_ticks() {
        #[derive(Clone, Default)]
        struct Ticks(StdArc<Mutex<Vec<u32>>>);
        impl Observer for Ticks {
            fn on_node_tick(&mut self, node: NodeId) {
                self.0.lock().unwrap().push(node.0);
            }
        }
        let mut lab = Lab::new(&[&[S], &[R, S]]);
        let mut tree = lab.tree(|b| {
            b.sequence("seq", |s| {
                s.scripted(0).scripted(1).condition("c", |_: &Lab| true)
            })
        });
        let ticks = Ticks::default();
        tree.set_observer(ticks.clone());
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(*ticks.0.lock().unwrap(), [0, 1, 2, 0, 2, 3]);
    }

    #[test]
    fn passes_of_one_tick_are_bounded_and_name_the_node_that_kept_asking() {
        let bp = Blueprint::<()>::builder()
            .repeat("forever", -1, |r| r.always_success("quick"))
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        tree.set_max_passes(50);
        let err = tree.tick_once(&mut ()).unwrap_err();
        assert_eq!(
            err,
            TickError::TooManyPasses {
                node: Some(NodeId::ROOT),
                path: "forever".into(),
                passes: 50
            }
        );
        assert_eq!(tree.last_passes(), 50);
        // Halted: the next tick starts afresh and is bounded the same way.
        assert!(tree.statuses().iter().all(|s| *s == Idle));
        assert!(matches!(
            tree.tick_once(&mut ()),
            Err(TickError::TooManyPasses { passes: 50, .. })
        ));
        // The default bound ends it too.
        tree.set_max_passes(DEFAULT_MAX_PASSES);
        assert!(matches!(
            tree.tick_once(&mut ()),
            Err(TickError::TooManyPasses {
                passes: DEFAULT_MAX_PASSES,
                ..
            })
        ));
    }

    #[test]
    fn a_finite_repeat_counts_its_passes() {
        let bp = Blueprint::<()>::builder()
            .repeat("five", 5, |r| r.always_success("quick"))
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
        assert_eq!(tree.last_passes(), 5);
        assert_eq!(tree.tick_exactly_once(&mut ()), Ok(Status::Running));
        tree.set_max_passes(4);
        assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
        assert_eq!(tree.last_passes(), 4);
    }

    #[test]
    fn halt_goes_children_first() {
        let mut lab = Lab::new(&[&[R], &[R]]);
        let mut tree = lab.tree(|b| {
            b.parallel("p", -1, 1, |p| {
                p.sequence("a", |s| s.scripted(0))
                    .inverter("b", |i| i.scripted(1))
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        let rec = Recorder::default();
        tree.set_observer(rec.clone());
        lab.halt(&mut tree);
        assert_eq!(
            rec.take(),
            [
                "2 RUNNING->IDLE",
                "1 RUNNING->IDLE",
                "4 RUNNING->IDLE",
                "3 RUNNING->IDLE",
                "0 RUNNING->IDLE"
            ]
        );
        assert_eq!(lab.halts, [1, 1]);
        assert!(tree.statuses().iter().all(|s| *s == Idle));
    }

    #[test]
    fn stored_statuses_while_running() {
        let mut lab = Lab::new(&[&[S], &[R]]);
        let mut tree = lab.tree(|b| b.sequence("seq", |s| s.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(tree.statuses(), [Run, Ok_, Run]);
        assert_eq!(tree.status(NodeId(1)), Ok_);
    }

    #[test]
    fn sync_action_returning_running_is_an_error_and_halts_the_tree() {
        let mut lab = Lab::new(&[&[R]]);
        let mut tree = lab.tree(|b| {
            b.parallel("p", -1, 1, |p| {
                p.scripted(0).action("bad", |_: &mut Lab| Status::Running)
            })
        });
        let err = lab.tick(&mut tree).unwrap_err();
        assert_eq!(
            err,
            TickError::LeafRunning {
                node: NodeId(2),
                path: "p/bad".into(),
                kind: "Action"
            }
        );
        assert!(err.to_string().contains("p/bad"));
        // `?` in `main` prints with Debug: the sentence that says what to do comes first.
        assert_eq!(
            format!("{err:?}"),
            format!("{err} (LeafRunning {{ node: NodeId(2), path: \"p/bad\", kind: \"Action\" }})")
        );
        assert!(format!("{err:?}").contains("use a StatefulAction"));
        // The running sibling was halted, so the tree starts clean.
        assert_eq!(lab.halts, [1]);
        assert!(tree.statuses().iter().all(|s| *s == Idle));
    }

    #[test]
    fn tick_once_rewakes_but_exactly_once_does_not() {
        let mut lab = Lab::new(&[&[S], &[S], &[S]]);
        let mut tree =
            lab.tree(|b| b.async_sequence("a", |s| s.scripted(0).scripted(1).scripted(2)));
        let rec = Recorder::default();
        tree.set_observer(rec.clone());
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        let passes = rec.take().iter().filter(|e| *e == "tick").count();
        assert_eq!(passes, 3);
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        let passes = rec.take().iter().filter(|e| *e == "tick").count();
        assert_eq!(passes, 1);
    }

    #[test]
    fn state_is_small_and_shared_structure_is_not_copied() {
        let bp = Builder::<()>::new()
            .sequence("root", |mut s| {
                for _ in 0..100 {
                    s = s.condition("c", |_: &()| true);
                }
                s
            })
            .build_shared()
            .unwrap();
        let a = Tree::with_clock(Arc::clone(&bp), ManualClock::new());
        let b = Tree::with_clock(Arc::clone(&bp), ManualClock::new());
        // One word saying where the parts end, a bit per node for the tick's failures (two
        // words), one slot for the sequence's cursor, and one status byte per node (in 13
        // words).
        assert_eq!(a.state_bytes(), 8 + 16 + 8 + 13 * 8);
        assert!(Arc::ptr_eq(a.blueprint(), b.blueprint()));
        assert_eq!(Arc::strong_count(&bp), 3);
        // The tree itself, which a crowd keeps one of per member (its blackboard 32 bytes
        // of it).
        #[cfg(target_pointer_width = "64")]
        assert_eq!(core::mem::size_of::<Tree<()>>(), 136);
    }

    #[cfg(feature = "std")]
    #[test]
    fn tick_while_running_loops_until_done() {
        let mut lab = Lab::new(&[&[R, R, S]]);
        let mut tree = lab.tree(|b| b.scripted(0));
        assert_eq!(
            tree.tick_while_running(&mut lab, Duration::ZERO),
            Ok(Status::Success)
        );
        assert_eq!(lab.ticks, [3]);
    }

    /// Runs `work` on its own thread and returns its result, failing the test if it takes
    /// longer than five seconds (a hang would otherwise stall the whole test run).
    #[cfg(feature = "std")]
    fn within_five_seconds<T: Send + 'static>(work: impl FnOnce() -> T + Send + 'static) -> T {
        let (done, result) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            // The receiver is gone only if the watchdog already failed the test.
            let _ = done.send(work());
        });
        result
            .recv_timeout(std::time::Duration::from_secs(5))
            .expect("the work did not finish within 5 s")
    }

    #[cfg(feature = "std")]
    #[test]
    fn tick_while_running_lets_the_period_pass_on_a_manual_clock() {
        /// The clock's time at the start of every pass of the root.
        #[derive(Clone, Default)]
        struct TickTimes(StdArc<Mutex<Vec<Duration>>>);
        impl Observer for TickTimes {
            fn on_tick_start(&mut self, now: Duration) {
                self.0.lock().unwrap().push(now);
            }
        }

        let (mut tree, clock) = build(|b| b.sleep("nap", ms(300)));
        let times = TickTimes::default();
        tree.set_observer(times.clone());
        let status = within_five_seconds(move || tree.tick_while_running(&mut (), ms(100)));

        assert_eq!(status, Ok(Status::Success));
        // Sleep starts at 0 and is still Running at 100 and 200 ms; at 300 ms it is done.
        assert_eq!(*times.0.lock().unwrap(), [ms(0), ms(100), ms(200), ms(300)]);
        // No wait after the last tick: the clock stops where the root completed.
        assert_eq!(clock.now(), ms(300));
    }

    #[test]
    fn trees_move_between_threads_and_blueprints_are_shared() {
        fn send<T: Send>() {}
        fn send_sync<T: Send + Sync>() {}
        // A context that is neither Send nor Sync does not stop the tree from moving.
        send::<Tree<std::rc::Rc<u8>>>();
        send_sync::<crate::Blueprint<std::rc::Rc<u8>>>();
        send_sync::<Arc<crate::Blueprint<Lab>>>();
    }

    #[test]
    fn root_skipped_is_reported() {
        let (mut tree, _) = build(|b| b.run_once("once", true, |o| o.always_success("a")));
        assert_eq!(tick(&mut tree), Ok(Status::Success));
        assert_eq!(tick(&mut tree), Err(TickError::RootSkipped));
    }
}
