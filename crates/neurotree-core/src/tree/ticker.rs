//! The hot path: one recursive pass over the tree, dispatching on the node kind.
//!
//! Nothing here allocates, formats or hashes in the normal course; errors are the exception
//! (they build a path string once, and end the tick). Observers are reached through one
//! `Option` branch per status write, and not even that in the Sequence and Fallback loops,
//! which are compiled twice: for observed and for unobserved trees.

use core::mem;

use crate::blackboard::Blackboard;
use crate::blueprint::call::{Args, Payload};
use crate::blueprint::{Blueprint, Child, NodeDef, NodeKind};
use crate::clock::duration_to_nanos;
use crate::nodes::built_in::Tick;
use crate::nodes::leaf::Handle;
use crate::nodes::{control, decorator, leaf};
use crate::observer::{Observer, StatusChange};
use crate::{Clock, NodeId, NodeStatus, Status, TickError};

use super::sleep::Waits;

pub(crate) use super::contain::contain;
#[cfg(feature = "std")]
pub(crate) use super::contain::panic_message;
use super::failure::{Note, Outcome};
pub(crate) use super::objects::Object;

/// Everything one pass needs, borrowed from the [`Tree`](crate::Tree) for its duration.
pub(crate) struct Ticker<'t, C> {
    pub(crate) bp: &'t Blueprint<C>,
    pub(crate) statuses: &'t mut [NodeStatus],
    /// One bit per node, set when its status is written Failure in this tick: what
    /// [`Tree::last_failure`](crate::Tree::last_failure) explains the root's failure from.
    pub(crate) failed: &'t mut [u64],
    /// The nodes' 32-bit state slots (see [`state`](super::state)); a 64-bit value takes two,
    /// read through [`aux64`](Self::aux64).
    pub(crate) aux: &'t mut [u32],
    pub(crate) objects: &'t mut [Object<C>],
    pub(crate) ctx: &'t mut C,
    pub(crate) bb: &'t mut Blackboard,
    pub(crate) clock: &'t dyn Clock,
    pub(crate) observer: Option<&'t mut dyn Observer>,
    /// The node that yielded and asked to be ticked again at once (the last, if several).
    pub(crate) wake: Option<NodeId>,
    /// The waker async actions poll with; the tree has one when its blueprint has them.
    pub(crate) waker: Option<&'t core::task::Waker>,
    /// The pass's error and the tick's record of reasons, kept in the tree.
    pub(crate) out: &'t mut Outcome,
    /// What the nodes ticked in this pass wait on (see [`sleep`](super::sleep)): the
    /// pass's alone, so that a tree does not carry it between passes.
    pub(crate) waits: Waits,
    /// On whose behalf the engine halts now (see [`slow_halt`](super::slow_halt)).
    pub(crate) halter: super::slow_halt::Halter,
    /// The observer is the engine's stand-in, attached when a reason was given so that the
    /// rest of the tick notes every Failure (see [`failure`](super::failure)).
    pub(crate) watching: bool,
    /// The node ticked or halted last: if user code panics, the one it panicked in.
    pub(crate) current: NodeId,
    /// A reactive control's second Running child is an error (BT.CPP's `EnableException`).
    pub(crate) reject_multiple_running: bool,
    /// The last stateful action that returned Running in this pass: if the pass rests in
    /// it, the next starts at it.
    pub(crate) rested: Option<NodeId>,
    /// The answer a stateful action the last pass rested in already gave in this tick
    /// (see `Tree::resting_answer`), handed to the pass from the root when it reaches the
    /// action, instead of a second call.
    pub(crate) replay: Option<(NodeId, NodeStatus)>,
    /// The custom node whose completed children are reset once its own status is stored
    /// (see [`NodeCtx::reset_completed_children_after_tick`](crate::NodeCtx::reset_completed_children_after_tick)); set only while observed,
    /// between the node's `tick` returning and that store.
    pub(crate) reset_after_store: Option<NodeId>,
}

impl<'t, C> Ticker<'t, C> {
    /// The stored status of a node.
    #[inline(always)]
    pub(crate) fn status(&self, id: NodeId) -> NodeStatus {
        debug_assert!(id.index() < self.statuses.len());
        // SAFETY: every `NodeId` the engine handles comes from this blueprint (the root or a
        // child list the builder filled with indices below `nodes.len()`), and `statuses`
        // was allocated with `nodes.len()` entries for this blueprint (`Tree::new`).
        unsafe { *self.statuses.get_unchecked(id.index()) }
    }

    /// The stored status of a node, writable.
    #[inline(always)]
    pub(crate) fn status_mut(&mut self, id: NodeId) -> &mut NodeStatus {
        debug_assert!(id.index() < self.statuses.len());
        // SAFETY: as in `status`.
        unsafe { self.statuses.get_unchecked_mut(id.index()) }
    }

    /// Marks node `id` as failed in this tick (see [`failure`](super::failure)): a bit
    /// set, so that every Failure is known after the tick at the cost of one store.
    #[inline(always)]
    pub(crate) fn mark_failed(&mut self, id: NodeId) {
        let i = id.index();
        debug_assert!(i / 64 < self.failed.len());
        // SAFETY: `failed` holds a bit for each of this blueprint's nodes
        // (`NodeState::new`), and `id` is one of them (as in `status`).
        unsafe { *self.failed.get_unchecked_mut(i / 64) |= 1 << (i % 64) };
    }

    /// Stores a node's status and tells the observer about a change.
    #[inline(always)]
    pub(crate) fn set_status(&mut self, id: NodeId, to: NodeStatus) {
        if to == NodeStatus::Failure {
            self.mark_failed(id);
        }
        if self.observer.is_some() {
            self.set_status_observed(id, to);
        } else {
            *self.status_mut(id) = to;
        }
    }

    #[inline(never)]
    fn set_status_observed(&mut self, id: NodeId, to: NodeStatus) {
        if to == NodeStatus::Failure && !self.out.is_quiet() {
            self.note_failed(id);
        }
        let from = mem::replace(self.status_mut(id), to);
        // When watching, the observer is the engine's stand-in, which hears nothing:
        // neither the clock nor the call is worth its cost on every change of a tick.
        if from != to && !self.watching {
            let at = self.clock.now();
            if let Some(observer) = self.observer.as_deref_mut() {
                observer.on_status_change(StatusChange {
                    node: id,
                    from,
                    to,
                    at,
                });
            }
        }
    }

    /// The clock in nanoseconds, the unit of time-based nodes' state slots.
    #[inline]
    pub(crate) fn now_nanos(&self) -> u64 {
        duration_to_nanos(self.clock.now())
    }

    /// The `i`-th child of a node.
    #[inline(always)]
    pub(crate) fn child(&self, def: &NodeDef<C>, i: u32) -> NodeId {
        self.bp.children[(def.first_child + i) as usize]
    }

    /// Ticks a node and stores what it returned (a Skipped node keeps its stored status).
    ///
    /// Inlined into every control's loop with a fast path for closure conditions, the most
    /// common leaves, so that ticking them costs no call into the dispatcher.
    #[inline(always)]
    pub(crate) fn tick(&mut self, id: NodeId) -> NodeStatus {
        let def = self.bp.def(id);
        if let (NodeKind::ConditionFn(f), None) = (&def.kind, self.bp.hooks(id)) {
            self.current = id;
            self.note_tick(id);
            self.waits.opaque(id);
            let status = if f(self.ctx) {
                NodeStatus::Success
            } else {
                NodeStatus::Failure
            };
            self.set_status(id, status);
            return status;
        }
        self.tick_other(id, def)
    }

    /// Ticks a node that is not a closure condition and stores what it returned.
    #[inline(always)]
    fn tick_other(&mut self, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        self.current = id;
        let status = match self.bp.hooks(id) {
            None => {
                self.note_tick(id);
                self.dispatch(id, def)
            }
            Some(hooks) => self.tick_hooked(id, def, hooks),
        };
        self.store_result(id, status);
        status
    }

    /// Stores what a node returned. A skipped node keeps (or returns to) Idle, though a
    /// control marks itself Running before it finds that all its children were skipped.
    #[inline(always)]
    fn store_result(&mut self, id: NodeId, status: NodeStatus) {
        if status == NodeStatus::Failure {
            self.mark_failed(id);
        }
        if self.observer.is_some() {
            self.store_result_observed(id, status);
        } else {
            *self.status_mut(id) = if status == NodeStatus::Skipped {
                NodeStatus::Idle
            } else {
                status
            };
        }
    }

    /// As [`store_result`](Self::store_result), telling the observer of the change and of
    /// a skip, which changes no stored status.
    #[inline(never)]
    fn store_result_observed(&mut self, id: NodeId, status: NodeStatus) {
        if status == NodeStatus::Skipped {
            self.set_status_observed(id, NodeStatus::Idle);
            if let Some(observer) = self.observer.as_deref_mut() {
                observer.on_node_skipped(id);
            }
        } else {
            self.set_status_observed(id, status);
        }
        if self.reset_after_store == Some(id) {
            self.reset_after_store = None;
            self.reset_completed_children(id);
        }
    }

    /// Ticks a node with pre- and post-conditions (see [`crate::nodes::hooks`]).
    #[inline(never)]
    fn tick_hooked(
        &mut self,
        id: NodeId,
        def: &NodeDef<C>,
        hooks: &dyn crate::nodes::hooks::NodeHooks<C>,
    ) -> NodeStatus {
        let stored = self.status(id);
        let before = hooks.before(&mut self.handle(id), stored);
        let status = match before {
            Some(NodeStatus::Skipped) if stored == NodeStatus::Running => {
                self.halt_node(id);
                NodeStatus::Skipped
            }
            // A result decided for a Running node (a fault forced by hand) ends its run
            // first, as a halt does.
            Some(decided @ (NodeStatus::Success | NodeStatus::Failure))
                if stored == NodeStatus::Running =>
            {
                self.halt_node(id);
                if decided == NodeStatus::Failure {
                    self.note(id, Note::Gave(super::failure::Reason::PRECONDITION));
                }
                decided
            }
            Some(NodeStatus::Failure) => {
                self.note(id, Note::Gave(super::failure::Reason::PRECONDITION));
                NodeStatus::Failure
            }
            Some(decided) => decided,
            None => {
                self.note_tick(id);
                self.dispatch(id, def)
            }
        };
        if status.is_completed() {
            hooks.after(&mut self.handle(id), status);
        }
        if !hooks.reads_only_blackboard() {
            // Checked again next tick (by a reactive parent, or `_while` while Running), it
            // could answer otherwise with no write to wake the tree.
            self.waits.opaque(id);
            if status == NodeStatus::Running {
                self.stay_awake(crate::AwakeReason::ReactiveCondition, id);
            }
        }
        status
    }

    /// Ticks a child from its parent's loop: closure conditions are called straight from
    /// the child list, everything else goes through [`tick`](Self::tick).
    ///
    /// `OBSERVED` is the loop-invariant answer to "is an observer attached?", so that a
    /// control's loop compiles twice and the unobserved one stores statuses directly.
    #[inline(always)]
    pub(crate) fn tick_child<const OBSERVED: bool>(&mut self, child: &Child) -> NodeStatus {
        if child.condition() == Some(true) {
            if OBSERVED {
                self.note_tick(child.id);
            }
            let holds = self.check(child, true, false);
            return self.store_condition::<OBSERVED>(child.id, holds);
        }
        self.tick_child_slow::<OBSERVED>(child)
    }

    /// Calls condition `child` (a closure with the context, else an object with a handle)
    /// and tells whether it holds; a panic in it goes on, blamed on it. `tracked`: the
    /// object's call noted whether it may read more than the blackboard (see
    /// `call::entry_of`), asked here.
    #[inline(always)]
    pub(crate) fn check(&mut self, child: &Child, closure: bool, tracked: bool) -> bool {
        let (answer, panic) = if closure {
            // A closure of the context: it may read anything.
            self.waits.opaque(child.id);
            let mut args = Args::new(&raw const *self.ctx);
            // SAFETY: a closure condition of this blueprint's `C`, with the context; the
            // answer asked about once.
            unsafe {
                let answer = child.call(&mut args);
                (answer, args.panicked(answer))
            }
        } else {
            let mut args = Args::new(self.handle(child.id));
            // SAFETY: as above, for a `Condition` object, with a handle.
            let answered = unsafe {
                let answer = child.call(&mut args);
                (answer, args.panicked(answer))
            };
            if tracked && self.out.reads.take_opaque() {
                self.waits.opaque(child.id);
            }
            answered
        };
        if let Some(payload) = panic {
            self.resume_panic(child.id, payload);
        }
        answer == 1
    }

    /// Resumes the panic of condition `node` (caught by its entry), blamed on it.
    #[cold]
    #[inline(never)]
    pub(crate) fn resume_panic(&mut self, node: NodeId, payload: Payload) -> ! {
        self.current = node;
        #[cfg(feature = "std")]
        std::panic::resume_unwind(payload);
        #[cfg(not(feature = "std"))]
        match payload {}
    }

    /// [`tick_child`](Self::tick_child) for a child that is no closure condition: a
    /// `Condition` object is still called straight from the child list (with a handle that
    /// costs a few register moves); anything else goes through the dispatcher. Out of line,
    /// so that the closure case keeps the parent's loop small: inlined, it costs the
    /// builder's tree1111 three instructions per leaf and saves the XML one eight.
    #[inline(never)]
    fn tick_child_slow<const OBSERVED: bool>(&mut self, child: &Child) -> NodeStatus {
        if child.condition() == Some(false) {
            if OBSERVED {
                self.note_tick(child.id);
            }
            let holds = self.check(child, false, child.tracked());
            return self.store_condition::<OBSERVED>(child.id, holds);
        }
        let def = self.bp.def(child.id);
        self.tick_other(child.id, def)
    }

    /// Ticks node `id` (without hooks) with `tick`, the function the dispatcher would pick
    /// for its kind, and stores what it returned: a parent's loop that knows the kind
    /// saves the dispatch.
    #[inline(always)]
    pub(crate) fn tick_direct(
        &mut self,
        id: NodeId,
        tick: fn(&mut Ticker<'t, C>, NodeId, &NodeDef<C>) -> NodeStatus,
    ) -> NodeStatus {
        self.current = id;
        self.note_tick(id);
        let status = tick(self, id, self.bp.def(id));
        self.store_result(id, status);
        status
    }

    /// Ticks a child that is no condition called from its parent's list, for a loop that
    /// handles those itself (`ordered::run_quiet`).
    #[inline(never)]
    pub(crate) fn tick_child_stored(&mut self, child: &Child) -> NodeStatus {
        use crate::blueprint::{FastControl, Guards};
        use control::ordered::{tick, tick_guard, PLAIN};
        let Some(FastControl { sequence, guards }) = child.fast_control() else {
            return self.tick_other(child.id, self.bp.def(child.id));
        };
        let id = child.id;
        match (sequence, guards) {
            (true, Guards::Mixed) => self.tick_direct(id, tick::<C, true, PLAIN>),
            (false, Guards::Mixed) => self.tick_direct(id, tick::<C, false, PLAIN>),
            (true, Guards::Closures) => self.tick_direct(id, tick_guard::<C, true, true>),
            (false, Guards::Closures) => self.tick_direct(id, tick_guard::<C, false, true>),
            (true, Guards::Objects) => self.tick_direct(id, tick_guard::<C, true, false>),
            (false, Guards::Objects) => self.tick_direct(id, tick_guard::<C, false, false>),
        }
    }

    /// Stores what a condition answered, and returns it as a status.
    #[inline(always)]
    fn store_condition<const OBSERVED: bool>(&mut self, id: NodeId, holds: bool) -> NodeStatus {
        let status = if holds {
            NodeStatus::Success
        } else {
            self.mark_failed(id);
            NodeStatus::Failure
        };
        if OBSERVED {
            self.set_status(id, status);
        } else {
            *self.status_mut(id) = status;
        }
        status
    }

    /// Tells the observer that a node's own tick runs.
    #[inline(always)]
    fn note_tick(&mut self, id: NodeId) {
        if let Some(observer) = self.observer.as_deref_mut() {
            observer.on_node_tick(id);
        }
    }

    /// `true` when an observer is attached.
    #[inline(always)]
    pub(crate) fn observed(&self) -> bool {
        self.observer.is_some()
    }

    /// A sync leaf's result; Running breaks its contract and ends the tick with an error.
    #[inline]
    pub(crate) fn sync_result(&mut self, id: NodeId, s: Status, kind: &'static str) -> NodeStatus {
        if s == Status::Running {
            let bp = self.bp;
            self.out.fault(|| TickError::LeafRunning {
                node: id,
                path: bp.path(id),
                kind,
            });
            return NodeStatus::Failure;
        }
        s.into()
    }

    /// Records a node's own error; the first error of a pass wins.
    pub(crate) fn fault_node(&mut self, id: NodeId, message: alloc::string::String) {
        let bp = self.bp;
        self.out.fault(|| TickError::Node {
            node: id,
            path: bp.path(id),
            message,
        });
    }

    /// A handle for node `id`, to the pass's context, blackboard and clock.
    #[inline(always)]
    pub(crate) fn handle(&mut self, id: NodeId) -> Handle<'_, C> {
        Handle {
            ctx: &mut *self.ctx,
            blackboard: &mut *self.bb,
            clock: self.clock,
            node: id,
            bp: self.bp,
            out: &mut *self.out,
            waits: &mut self.waits,
        }
    }

    /// Clears node `id`'s state slots and halts its children: the halt of a node that starts
    /// afresh after it.
    pub(crate) fn halt_afresh(&mut self, id: NodeId) {
        let slot = self.bp.slot(id);
        let slots = self.bp.aux_slots_of(id);
        self.aux[slot..slot + slots].fill(0);
        self.reset_children(id);
    }

    /// BehaviorTree.CPP's `haltChild`: halt if Running, then reset to Idle.
    #[inline]
    pub(crate) fn halt_child(&mut self, child: NodeId) {
        if self.status(child) == NodeStatus::Running {
            self.halt_node(child);
        } else {
            self.set_status(child, NodeStatus::Idle);
        }
    }

    /// Halts every Running child and resets all children to Idle, in order.
    pub(crate) fn reset_children(&mut self, id: NodeId) {
        let bp = self.bp;
        for &child in bp.children_of(bp.def(id)) {
            self.halt_child(child);
        }
    }

    /// BehaviorTree.CPP's `DecoratorNode::executeTick` after the tick: a child that is
    /// Success or Failure goes back to Idle, with no halt (it is not Running).
    pub(crate) fn reset_completed_children(&mut self, id: NodeId) {
        let bp = self.bp;
        for &child in bp.children_of(bp.def(id)) {
            if self.status(child).is_completed() {
                self.set_status(child, NodeStatus::Idle);
            }
        }
    }

    /// Resets to Idle the children a Sequence or Fallback has ticked since its last reset.
    ///
    /// None of them is Running: each returned Success, Failure or Skipped (stored as Idle) to
    /// this very control, and only the control ticks its children. So, unlike
    /// [`reset_children`](Self::reset_children), no halt is needed and, with no observer,
    /// the reset is a run of plain stores.
    #[inline]
    pub(crate) fn reset_completed(&mut self, children: &[NodeId]) {
        if self.observer.is_none() {
            let statuses = &mut *self.statuses;
            for &child in children {
                debug_assert!(child.index() < statuses.len());
                // SAFETY: as in `status`.
                let status = unsafe { statuses.get_unchecked_mut(child.index()) };
                debug_assert_ne!(*status, NodeStatus::Running);
                *status = NodeStatus::Idle;
            }
        } else {
            for &child in children {
                self.halt_child(child);
            }
        }
    }

    /// Halts children `from..` of a node, in order.
    pub(crate) fn halt_children_from(&mut self, def: &NodeDef<C>, from: u32) {
        for i in from..def.child_count {
            let child = self.child(def, i);
            self.halt_child(child);
        }
    }
}

/// Makes the tick dispatch and the halt of every kind from [the list of
/// built-ins](crate::nodes): a built-in goes to its type's [`Tick`], the doors for user code
/// to the ticker's own functions.
macro_rules! dispatch {
    ($($name:ident in $($module:ident)::+;)*) => {
        impl<'t, C> Ticker<'t, C> {
            #[inline(never)]
            fn dispatch(&mut self, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
                match &def.kind {
                    NodeKind::ConditionFn(f) => {
                        // A closure of the context: it may read anything.
                        self.waits.opaque(id);
                        Status::from(f(self.ctx)).into()
                    }
                    $(NodeKind::$name(node) => node.tick(self, id, def),)*
                    NodeKind::SubTree(_) => decorator::subtree::tick(self, id, def),
                    NodeKind::Condition(c) => {
                        self.out.reads.declare(c.reads_only_blackboard());
                        let h = self.handle(id);
                        let s = Status::from(c.check(&h));
                        self.note_reads(id);
                        s.into()
                    }
                    NodeKind::SharedCondition(s) => {
                        let bp = self.bp;
                        let c = &bp.shared[s.index()];
                        self.out.reads.declare(c.reads_only_blackboard());
                        let h = self.handle(id);
                        let s = Status::from(c.check(&h));
                        self.note_reads(id);
                        s.into()
                    }
                    NodeKind::ActionFn(f) => {
                        self.waits.opaque(id);
                        let s = f(self.ctx);
                        self.sync_result(id, s, "Action")
                    }
                    NodeKind::Action(a) => {
                        self.out.reads.declare(a.reads_only_blackboard());
                        let mut h = self.handle(id);
                        let s = a.tick(&mut h);
                        self.note_reads(id);
                        self.watch_if_noted();
                        self.sync_result(id, s, "Action")
                    }
                    NodeKind::Stateful(_) => {
                        if let Some((node, answer)) = self.replay {
                            if node == id {
                                self.replay = None;
                                return answer;
                            }
                        }
                        self.waits.declared = false;
                        self.out.reads.declare(false);
                        let s = self.tick_stateful(id);
                        if self.out.reads.event() {
                            self.waits.on_event();
                        }
                        self.watch_if_noted();
                        if s == NodeStatus::Running {
                            self.rested = Some(id);
                            if !self.waits.declared {
                                self.stay_awake(crate::AwakeReason::UndeclaredLeaf, id);
                            }
                        } else {
                            // Completed, it answered from its context: re-checked, it
                            // could answer otherwise.
                            self.waits.opaque(id);
                        }
                        s
                    }
                    NodeKind::Async(action) => {
                        let s = leaf::async_action::tick(self, id, &**action);
                        self.watch_if_noted();
                        // A future may rely on being polled every tick: it keeps the tree awake.
                        if s == NodeStatus::Running {
                            self.stay_awake(crate::AwakeReason::AsyncLeaf, id);
                        } else {
                            self.waits.opaque(id);
                        }
                        s
                    }
                    NodeKind::Custom(_) => self.tick_custom(id),
                }
            }

            /// Halts a node (its Running descendants first) and resets it to Idle.
            ///
            /// With `std`, a panic in user code that halts (`on_halted`, a custom node's
            /// `halt`, a future's `Drop`) is caught: that node is skipped, the halt goes on,
            /// and the panic becomes the pass's error.
            pub(crate) fn halt_node(&mut self, id: NodeId) {
                if self.out.halts.count != 0 {
                    self.pass_on_halts_of(id);
                }
                let bp = self.bp;
                let def = bp.def(id);
                match &def.kind {
                    $(NodeKind::$name(node) => node.halt(self, id, def),)*
                    NodeKind::Stateful(_) => {
                        if self.status(id) == NodeStatus::Running {
                            // Halted in a pass, it starts afresh when its branch is ticked
                            // again: a reactive node re-checking that branch would call it.
                            self.waits.opaque(id);
                            self.current = id;
                            contain(self, id, |t| t.request_halt(id));
                        }
                    }
                    NodeKind::Async(action) => {
                        if self.status(id) == NodeStatus::Running {
                            self.waits.opaque(id);
                        }
                        self.current = id;
                        contain(self, id, |t| leaf::async_action::halt(t, id, &**action));
                    }
                    NodeKind::Custom(_) => {
                        if self.status(id) == NodeStatus::Running {
                            self.waits.opaque(id);
                        }
                        self.halt_custom(id)
                    }
                    NodeKind::SubTree(_)
                    | NodeKind::ConditionFn(_)
                    | NodeKind::Condition(_)
                    | NodeKind::SharedCondition(_)
                    | NodeKind::ActionFn(_)
                    | NodeKind::Action(_) => self.reset_children(id),
                }
                let was_running = self.status(id) == NodeStatus::Running;
                self.set_status(id, NodeStatus::Idle);
                if was_running {
                    if let Some(hooks) = self.bp.hooks(id) {
                        hooks.halted(&mut self.handle(id));
                    }
                }
            }
        }
    };
}
crate::nodes::with_built_ins!(dispatch);
