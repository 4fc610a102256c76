//! TryCatch: a Sequence with a clean-up child that runs when it fails.
//!
//! `TryCatch(catch_on_halt)`: children 0..N-2 as a Sequence; on Failure tick the last child
//! (the catch) and return Failure whatever it returns.
//!
//! On a failure in the try block, every child is halted and reset, then the catch child is
//! ticked in the same tick; while it runs, the node is Running. With `catch_on_halt`, halting
//! the node while it is trying also runs the catch child once (halting it if it runs).
//!
//! The catch and the try block conflict (the catch cleans up after the try block), so the
//! catch never runs while the try block still stops. When halting the try block leaves a
//! halt in progress below the node (an action whose halt takes ticks, see
//! [`slow_halt`](crate::tree::slow_halt)), the catch does not run within the halt: the node
//! is stored Idle, and its catch waits, as a halting action does, for whoever halted the
//! node (a ReactiveSequence, ReactiveFallback, WhileDoElse, Parallel or Timeout, else the
//! tree). The waiter returns Running and ticks no child (the tree ticks no root) until the
//! halts below the node are done; at its first tick after that (for the tree: its next tick
//! call, or [`Tree::tick_halt`](crate::Tree::tick_halt)) the catch is ticked once and halted
//! if it runs, that halt waiting for the same waiter if it takes ticks, its subtree left all
//! Idle, and the waiter goes on as usual in the same tick. A TryCatch whose catch waits is halting:
//! [`Tree::is_halting`](crate::Tree::is_halting) is `true` and [`Tree::halt`](crate::Tree::halt)
//! returns `false`; halting it again changes nothing, and a custom control that ticks it
//! meanwhile gets Failure.

use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::blueprint::{Builder, NodeKind, Param, PortBinding, PortBindingError};
use crate::nodes::built_in::{self, BuiltIn, Tick};
use crate::nodes::decl::{NodeDecl, PortDecl};
use crate::nodes::semantics::{chain, Order, Semantics, Statuses};
use crate::{Arity, Category};
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

/// TryCatch's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const TRY_CATCH: NodeDecl = NodeDecl {
    name: "TryCatch",
    category: Category::Control,
    arity: Arity::AtLeast(2),
    ports: &[PortDecl::input(
        "catch_on_halt",
        "bool",
        "Also run the catch child when the node is halted while its try block runs.",
    )
    .or("false")],
    summary:
        "Children but the last as a Sequence; on failure ticks the last (the catch) and fails.",
    semantics: Semantics::new(Order::in_turn(Statuses::ANY), |_, c| {
        let (tries, catch) = c.split_at(c.len().saturating_sub(1));
        let tried = chain(tries, Statuses::SUCCESS);
        let caught = catch.first().is_some_and(|c| c.can_run());
        tried.or(Statuses::RUNNING.when(caught && tried.can_fail()))
    }),
};

const IN_CATCH: u64 = 1 << 63;
/// The node was halted while trying, with `catch_on_halt`, and its catch waits for the
/// halts below it; the low bits say whom the catch waits for.
const CATCH_PENDING: u64 = 1 << 62;
/// With [`CATCH_PENDING`]: the catch waits for the node whose id is in the low 32 bits
/// (else for the tree).
const FOR_NODE: u64 = 1 << 32;

/// The state slot of a TryCatch whose catch waits, for `owner`.
pub(crate) fn pending(owner: Option<NodeId>) -> u64 {
    CATCH_PENDING
        | match owner {
            Some(id) => FOR_NODE | u64::from(id.0),
            None => 0,
        }
}

/// Whom a TryCatch's catch waits for, if it waits (`Some(None)`: the tree).
pub(crate) fn pending_owner(slot: u64) -> Option<Option<NodeId>> {
    (slot & CATCH_PENDING != 0).then(|| (slot & FOR_NODE != 0).then_some(NodeId(slot as u32)))
}

/// The cursor (the low 32 bits), the count of skipped children (the next 30) and whether
/// the catch runs, from the node's 64-bit state.
fn unpack(slot: u64) -> (u32, u32, bool) {
    let skipped = (slot & !IN_CATCH) >> 32;
    (slot as u32, skipped as u32, slot & IN_CATCH != 0)
}

fn pack(cursor: u32, skipped: u32, in_catch: bool) -> u64 {
    u64::from(cursor) | (u64::from(skipped) << 32) | if in_catch { IN_CATCH } else { 0 }
}

#[inline(never)]
pub(crate) fn tick<C>(t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
    let slot = t.bp.slot(id);
    if t.aux64(slot) & CATCH_PENDING != 0 {
        // Only a custom control ticks a node whose halt is in progress; it fails, as a
        // halting action does, so that it is not taken for Running.
        return NodeStatus::Failure;
    }
    let (mut cursor, mut skipped, mut in_catch) = unpack(t.aux64(slot));
    if !t.status(id).is_active() {
        skipped = 0;
        in_catch = false;
    }
    t.set_status(id, NodeStatus::Running);
    let tries = def.child_count - 1;
    while !in_catch && cursor < tries {
        let child = t.child(def, cursor);
        match t.tick(child) {
            NodeStatus::Running => {
                t.set_aux64(slot, pack(cursor, skipped, false));
                return NodeStatus::Running;
            }
            NodeStatus::Failure | NodeStatus::Idle => {
                t.reset_children(id);
                cursor = 0;
                in_catch = true;
            }
            NodeStatus::Success => cursor += 1,
            NodeStatus::Skipped => {
                cursor += 1;
                skipped += 1;
            }
        }
    }
    if in_catch {
        let catch = t.child(def, tries);
        if t.tick(catch) == NodeStatus::Running {
            t.set_aux64(slot, pack(cursor, skipped, true));
            return NodeStatus::Running;
        }
        t.reset_children(id);
        t.set_aux64(slot, pack(0, skipped, false));
        return NodeStatus::Failure;
    }
    let all_skipped = skipped == tries;
    t.reset_children(id);
    t.set_aux64(slot, 0);
    if all_skipped {
        NodeStatus::Skipped
    } else {
        NodeStatus::Success
    }
}

pub(crate) fn halt<C>(t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>, catch_on_halt: bool) {
    let slot = t.bp.slot(id);
    if t.aux64(slot) & CATCH_PENDING != 0 {
        // Halted again while its catch waits (by `Tree::halt`'s sweep): the catch still
        // runs once the halts below are done.
        t.reset_children(id);
        return;
    }
    let (_, _, in_catch) = unpack(t.aux64(slot));
    if catch_on_halt && !in_catch && t.status(id).is_active() {
        let catch = t.child(def, def.child_count - 1);
        for i in 0..def.child_count - 1 {
            let child = t.child(def, i);
            t.halt_child(child);
        }
        if t.out.halts.count != 0 && t.halting_below(id) {
            // The catch conflicts with the try block: it runs once the try block has
            // stopped, as the end of this halt (see `slow_halt`).
            t.set_aux64(slot, pending(t.halter.halter()));
            t.started_halting();
            t.reset_children(id);
            return;
        }
        if t.tick(catch) == NodeStatus::Running {
            t.halt_child(catch);
        }
    }
    t.set_aux64(slot, 0);
    t.reset_children(id);
}

/// The TryCatch node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TryCatch {
    /// Run the catch child when halted while trying.
    pub catch_on_halt: Param<bool>,
}

impl BuiltIn for TryCatch {
    fn port_values(&self, _: usize) -> Vec<Option<String>> {
        vec![built_in::text(&self.catch_on_halt)]
    }
}

impl Tick for TryCatch {
    const DECL: &'static NodeDecl = &TRY_CATCH;
    /// Its state (a cursor, a count and flags, or whom its catch waits for) takes 64 bits.
    const AUX_SLOTS: u32 = 2;

    /// Where the tries are and whether the catch runs: a saved tree is never halting, so a
    /// state whose catch waits for a halt, or whose cursor or count is past the children,
    /// is none a TryCatch keeps.
    fn restored_aux(saved: u64, children: u32) -> Option<u64> {
        let (cursor, skipped, _) = unpack(saved);
        (saved & CATCH_PENDING == 0 && cursor <= children && skipped <= children).then_some(saved)
    }
    const WAITS_ON_HALTS: bool = true;

    fn from_ports(port: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(TryCatch {
            catch_on_halt: built_in::param(port, "catch_on_halt")?,
        })
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        tick(t, id, def)
    }

    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) {
        // Read when halted, as BehaviorTree.CPP reads it; unreadable: no catch.
        let catch = t.param(id, self.catch_on_halt, "catch_on_halt");
        halt(t, id, def, catch.unwrap_or(false));
    }
}

impl<C> Builder<C> {
    /// A [TryCatch](self): the children but the last as a Sequence, the last on failure.
    pub fn try_catch(
        self,
        name: &str,
        catch_on_halt: bool,
        children: impl FnOnce(Self) -> Self,
    ) -> Self {
        let node = TryCatch {
            catch_on_halt: catch_on_halt.into(),
        };
        self.node(NodeKind::TryCatch(node), name, children)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn success_skips_the_catch() {
        let mut lab = Lab::new(&[&[S], &[S], &[S]]);
        let mut tree =
            lab.tree(|b| b.try_catch("tc", false, |c| c.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 1, 0]);
    }

    #[test]
    fn failure_runs_the_catch_and_fails() {
        let mut lab = Lab::new(&[&[S], &[F], &[R, S]]);
        let mut tree =
            lab.tree(|b| b.try_catch("tc", false, |c| c.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1, 1, 2]);
        // A catch that succeeds still makes the node fail; the next run starts from the try.
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [2, 2, 3]);
    }

    #[test]
    fn catch_on_halt_runs_the_catch_once() {
        let mut lab = Lab::new(&[&[R], &[S]]);
        let mut tree = lab.tree(|b| b.try_catch("tc", true, |c| c.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [1, 0]);
        assert_eq!(lab.ticks, [1, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn halt_without_catch_on_halt_skips_the_catch() {
        let mut lab = Lab::new(&[&[R], &[S]]);
        let mut tree = lab.tree(|b| b.try_catch("tc", false, |c| c.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.halt(&mut tree);
        assert_eq!(lab.ticks, [1, 0]);
        assert_eq!(lab.halts, [1, 0]);
    }
}
