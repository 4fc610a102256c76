//! Halts that take several ticks, and who waits for them.
//!
//! BehaviorTree.CPP halts a node within the call that halts it (its 5.0 plans otherwise).
//! A robot arm that must decelerate, or an action server that must acknowledge a cancel,
//! cannot. Here two kinds of action may take ticks to halt:
//!
//! - a [`StatefulAction`](crate::StatefulAction) answers
//!   [`on_halt_requested`](crate::StatefulAction::on_halt_requested) with
//!   [`HaltProgress::Halting`] and finishes the halt on later ticks in
//!   [`on_halting`](crate::StatefulAction::on_halting);
//! - an [`AsyncAction`](crate::AsyncAction) returns a [`HaltFuture`](crate::HaltFuture) from
//!   [`on_halt_requested`](crate::AsyncAction::on_halt_requested), polled at once and then
//!   where a stateful action gets `on_halting`, until it is ready.
//!
//! Both follow the same rules below ("action" means either, "`on_halting`" a poll of the
//! halt future). Actions that keep the default halt at once, as in BehaviorTree.CPP.
//! Custom nodes halt at once: [`CustomNode::halt`](crate::CustomNode::halt) is one call,
//! after which the engine halts the node's Running children; a child's halt that takes
//! ticks waits for whoever halted the custom node, so a custom node whose stop takes time
//! puts that work in such a child.
//!
//! A halting action is stored Idle (its run is over for its parent and for observers), and
//! it is never ticked until its halt is done. Every halting action **waits for** one node,
//! or for the tree: the node whose own tick halted it, if that node is one of those below;
//! else the tree. When the node it waits for is itself halted, it waits for whoever halts
//! that node (the tree, for [`Tree::halt`](crate::Tree::halt)).
//!
//! | node | when it halts a Running child | while the halt is in progress | when it is done |
//! |---|---|---|---|
//! | ReactiveSequence, ReactiveFallback | a child ran, or one ended the node | Running; ticks no child | ticks as usual from child 0, in the same tick |
//! | WhileDoElse | the condition chose the other branch, or failed with 2 children | Running; ticks no child | ticks as usual (condition first), in the same tick |
//! | Parallel | it completed with children Running | Running; ticks no child | the outcome it had decided, in the same tick |
//! | Timeout | the time is up | Running; does not tick the child | Failure (timed out), in the same tick |
//! | TryCatch with `catch_on_halt` | halted while it tries: it halts its try block, and its catch conflicts with it | stored Idle; its catch waits, like a halting action, for whoever halted the TryCatch | the catch is ticked once (halted if Running), at that waiter's tick, before the waiter goes on |
//! | the tree | [`Tree::halt`](crate::Tree::halt), a tick's error, and every halt no node above waits for | [`Tree::tick_once`](crate::Tree::tick_once) and `tick_exactly_once` return Running without ticking the root (checked before every pass); [`Tree::tick_halt`](crate::Tree::tick_halt) continues it | the call ticks the root as usual |
//!
//! While it waits, the node calls `on_halting` once on each action that waits for it, at
//! each of its ticks, in node order, then runs the catch of each TryCatch that waits for it
//! and has nothing halting below any more (below).
//!
//! The other nodes never halt a Running child during their own tick: Sequence, Fallback
//! and their Async and WithMemory forms, IfThenElse, TryCatch, ParallelAll and the
//! decorators but Timeout complete only once their children have, and halt children only
//! when halted themselves (their halting descendants then wait for whoever halted them).
//! Two halts are made on no control's behalf, and so wait for the tree: a precondition
//! that skips a Running node, and a custom control's halt of its children. There the parent
//! goes on in the tick of the halt (it sees the skip, or decides for itself), and the tree
//! ticks the root again only once the halt is done; a halting action that a custom control
//! ticks anyway fails, so that it is not taken for Running.
//!
//! A TryCatch with `catch_on_halt`, halted while it tries, runs its catch once the try
//! block has stopped: when halting the try block leaves a halt in progress below it, its
//! catch waits like a halting action, for whoever halted the TryCatch, and runs at that
//! waiter's first tick after the halts below are done, before the waiter goes on (see
//! [TryCatch](crate::nodes::control::try_catch)). A catch that runs then is halted, and
//! its own halt may take ticks; it waits for the same waiter. The catch's subtree is then
//! left all Idle. A TryCatch whose catch waits counts as a halt in progress
//! ([`Tree::is_halting`](crate::Tree::is_halting)); one whose try block halted at once runs
//! its catch within the halt, as before.
//!
//! "Ticks no child" includes the halting action: until its halt is done, the node that
//! waits returns Running and asks nothing else of its subtree, so no sibling branch starts
//! while the action still stops. A ReactiveFallback whose earlier child started running and
//! so halted a later one has ticked that earlier child once already, in that tick, as
//! BehaviorTree.CPP does; it then waits like the others.
//!
//! Cost when no halt takes ticks: one compare per pass of the root, and one per tick of a
//! ReactiveSequence, ReactiveFallback, WhileDoElse, Parallel or Timeout; tree1111 (Sequences,
//! Fallbacks and conditions) takes 4 instructions more per tick than without the feature
//! (47,243 against 47,239 built, 70,153 against 70,149 from XML, under callgrind, when the
//! feature was added). No
//! allocation for a stateful action: its box moves between two variants of its slot, which
//! is no larger for it (the node it waits for is kept in 4 bytes). An async action's halt
//! allocates only if the action returns a halt future (its box); the default allocates
//! nothing. A Parallel keeps one state slot (4 bytes) for the outcome it holds while it
//! waits, a TryCatch its waiting catch in the state slots it has. While halts are in
//! progress, every node that waits, and the tree, look over the nodes once per tick.

use core::mem;

use crate::blueprint::NodeKind;
use crate::nodes::control::try_catch;
use crate::nodes::leaf::{async_action, HaltProgress};
use crate::{NodeId, NodeStatus};

use super::ticker::{contain, Object, Ticker};

/// The tree's count of halting actions, kept between ticks.
#[derive(Default)]
pub(crate) struct Halts {
    /// How many halts are in progress: halting actions, and TryCatch nodes whose catch
    /// waits.
    pub(crate) count: u32,
}

/// On whose behalf the engine halts now: the ticker's alone, since it is the tree's at
/// the start of every pass and of every halt, so that a tree does not carry it.
pub(crate) struct Halter {
    /// The node on whose behalf the engine halts now (the tree, but within
    /// [`Ticker::halting_for`]).
    halter: Owner,
    /// A halt since `halter` was set left an action halting.
    pub(crate) left: bool,
}

impl Halter {
    /// Halts on behalf of the tree.
    pub(crate) const TREE: Self = Self {
        halter: Owner(Owner::TREE),
        left: false,
    };

    /// The node on whose behalf the engine halts now (`None`: the tree).
    #[inline]
    pub(crate) fn halter(&self) -> Option<NodeId> {
        self.halter.get()
    }

    /// Halts from now on behalf of `halter` (`None`: the tree); returns the one before.
    #[inline]
    pub(crate) fn set_halter(&mut self, halter: Option<NodeId>) -> Option<NodeId> {
        mem::replace(&mut self.halter, Owner::of(halter)).get()
    }
}

/// Whom a halt in progress waits for, in four bytes (a node's id, or the tree), so that
/// a halting object fits in the slot of the object it was.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) struct Owner(u32);

impl Owner {
    /// The tree: no node has `u32::MAX` as its id.
    const TREE: u32 = u32::MAX;

    /// Node `owner`, or the tree for `None`.
    #[inline]
    pub(crate) fn of(owner: Option<NodeId>) -> Self {
        Self(owner.map_or(Self::TREE, |id| id.0))
    }

    /// The node, or `None` for the tree.
    #[inline]
    pub(crate) fn get(self) -> Option<NodeId> {
        (self.0 != Self::TREE).then_some(NodeId(self.0))
    }
}

/// Which halting actions to continue.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Waiter {
    /// Those that wait for this node (`Some`) or for the tree (`None`).
    Owner(Option<NodeId>),
    /// Every one.
    Any,
}

impl<'t, C> Ticker<'t, C> {
    /// Asks the Running stateful action `id` to halt; one that answers Halting now waits
    /// for the node on whose behalf the engine halts (see [`halting_for`](Self::halting_for)).
    pub(crate) fn request_halt(&mut self, id: NodeId) {
        let halter = self.halter.halter();
        let (Some(object), mut h) = self.split(id) else {
            return;
        };
        let Object::Stateful(action) = object else {
            return;
        };
        if action.on_halt_requested(&mut h) == HaltProgress::Done {
            return;
        }
        if let Object::Stateful(action) = mem::replace(object, Object::Vacant) {
            *object = Object::Halting {
                action,
                owner: Owner::of(halter),
            };
        }
        self.started_halting();
    }

    /// Counts a halt that now takes ticks.
    #[inline]
    pub(crate) fn started_halting(&mut self) {
        self.out.halts.count += 1;
        self.halter.left = true;
    }

    /// Runs `halt` on behalf of node `owner`: the actions it leaves halting wait for
    /// `owner`. Returns `true` if any did.
    #[inline]
    pub(crate) fn halting_for(&mut self, owner: NodeId, halt: impl FnOnce(&mut Self)) -> bool {
        let outer_halter = self.halter.set_halter(Some(owner));
        let outer_left = mem::replace(&mut self.halter.left, false);
        halt(self);
        let left = self.halter.left;
        self.halter.set_halter(outer_halter);
        self.halter.left = outer_left;
        left
    }

    /// Node `id` is halted: the halts that waited for it wait for whoever halts it.
    #[cold]
    #[inline(never)]
    pub(crate) fn pass_on_halts_of(&mut self, id: NodeId) {
        let halter = self.halter.halter();
        let mut passed = false;
        for object in self.objects.iter_mut() {
            if let Some(owner) = object.halt_owner() {
                if owner.get() == Some(id) {
                    *owner = Owner::of(halter);
                    passed = true;
                }
            }
        }
        let bp = self.bp;
        for tc in bp.ids() {
            if bp.def(tc).kind.waits_on_halts() {
                let slot = bp.slot(tc);
                if try_catch::pending_owner(self.aux64(slot)) == Some(Some(id)) {
                    self.set_aux64(slot, try_catch::pending(halter));
                    passed = true;
                }
            }
        }
        self.halter.left |= passed;
    }

    /// If halts wait for node `id`, continues them: `true` while any is left, and the node
    /// then returns Running without ticking a child.
    #[inline(always)]
    pub(crate) fn waits_for_halts(&mut self, id: NodeId) -> bool {
        self.out.halts.count != 0 && self.continue_halts(Waiter::Owner(Some(id)))
    }

    /// `true` if node `id` is halting: an action whose halt is in progress, or a TryCatch
    /// whose catch waits for the halts below it.
    pub(crate) fn is_halting_node(&self, id: NodeId) -> bool {
        let bp = self.bp;
        match &bp.def(id).kind {
            NodeKind::Stateful(_) | NodeKind::Async(_) | NodeKind::Custom(_) => {
                matches!(
                    self.objects.get(bp.slot(id)),
                    Some(object) if object.is_halting()
                )
            }
            kind if kind.waits_on_halts() => {
                try_catch::pending_owner(self.aux64(bp.slot(id))).is_some()
            }
            _ => false,
        }
    }

    /// `true` if a node below `id` is halting.
    #[cold]
    #[inline(never)]
    pub(crate) fn halting_below(&self, id: NodeId) -> bool {
        self.bp
            .ids()
            .any(|other| self.is_halting_node(other) && self.is_below(other, id))
    }

    /// `true` if `node` is a descendant of `ancestor`.
    fn is_below(&self, node: NodeId, ancestor: NodeId) -> bool {
        let mut up = self.bp.parent(node);
        while let Some(p) = up {
            if p == ancestor {
                return true;
            }
            up = self.bp.parent(p);
        }
        false
    }

    /// One `on_halting` for each halting action `waiter` selects, in node order, then the
    /// catch of each TryCatch `waiter` selects whose halts below are done, from the last
    /// one up; `true` while any of them is still halting. A panic in one ends its halt
    /// (with `std`, it is the pass's error).
    #[cold]
    #[inline(never)]
    pub(crate) fn continue_halts(&mut self, waiter: Waiter) -> bool {
        let bp = self.bp;
        let mut left = false;
        let mut catches = false;
        for id in bp.ids() {
            let kind = &bp.def(id).kind;
            match kind {
                NodeKind::Stateful(_) | NodeKind::Async(_) => {}
                kind if kind.waits_on_halts() => {
                    catches |= try_catch::pending_owner(self.aux64(bp.slot(id))).is_some();
                    continue;
                }
                _ => continue,
            }
            let slot = bp.slot(id);
            let Some(owner) = self.objects[slot].waits_for() else {
                continue;
            };
            if waiter != Waiter::Any && waiter != Waiter::Owner(owner) {
                continue;
            }
            self.current = id;
            // A panic leaves `done` true: it ends the halt.
            let mut done = true;
            contain(self, id, |t| {
                done = match kind {
                    NodeKind::Async(_) => async_action::continue_halt(t, id),
                    _ => match t.split(id) {
                        (Some(Object::Halting { action, .. }), mut h) => {
                            action.on_halting(&mut h) == HaltProgress::Done
                        }
                        _ => true,
                    },
                };
            });
            if done {
                let object = mem::replace(&mut self.objects[slot], Object::Vacant);
                self.objects[slot] = object.halted();
                self.out.halts.count -= 1;
                debug_assert_eq!(self.status(id), NodeStatus::Idle);
            } else {
                left = true;
            }
        }
        if catches {
            left |= self.continue_catches(waiter);
        }
        left
    }

    /// Runs the catch of each TryCatch `waiter` selects once nothing below it is halting,
    /// the innermost first; `true` while any catch still waits, or the halt of one that
    /// ran takes ticks.
    fn continue_catches(&mut self, waiter: Waiter) -> bool {
        let bp = self.bp;
        let mut left = false;
        for tc in (0..bp.len() as u32).rev().map(NodeId) {
            let def = bp.def(tc);
            if !def.kind.waits_on_halts() {
                continue;
            }
            let slot = bp.slot(tc);
            let Some(owner) = try_catch::pending_owner(self.aux64(slot)) else {
                continue;
            };
            if waiter != Waiter::Any && waiter != Waiter::Owner(owner) {
                continue;
            }
            if self.halting_below(tc) {
                left = true;
                continue;
            }
            self.set_aux64(slot, 0);
            self.out.halts.count -= 1;
            let outer_halter = self.halter.set_halter(owner);
            let outer_left = mem::replace(&mut self.halter.left, false);
            let catch = self.child(def, def.child_count - 1);
            contain(self, tc, |t| {
                t.tick(catch);
            });
            // Once, as when the halt was done at once: a catch that runs is halted, and
            // its halt waits for whoever the catch waited for. Its subtree is then left all
            // Idle, as `Tree::halt` leaves a tree (a two-child IfThenElse keeps its failed
            // condition otherwise), since no control above resets it any more.
            self.halt_child(catch);
            for id in bp.ids() {
                if self.is_below(id, catch) {
                    self.halt_node(id);
                }
            }
            left |= self.halter.left;
            self.halter.set_halter(outer_halter);
            self.halter.left = outer_left;
        }
        left
    }
}

#[cfg(test)]
mod tests {
    /// The halting variants fit in the slot an object had before (a box and a tag): trees
    /// that never halt slowly keep their size.
    #[test]
    fn a_halting_action_takes_no_more_room_than_an_object_did() {
        assert_eq!(core::mem::size_of::<super::Object<()>>(), 24);
    }
}
