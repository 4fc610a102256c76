//! Repeat(num_cycles): run a succeeding child again, `num_cycles` times.
//!
//! - Child Success: count, yield Running until num_cycles reached (exactly −1: forever) →
//!   Success.
//! - Child Failure → Failure, count reset.
//! - 0 cycles, or any negative count other than −1 → Success with no tick (BehaviorTree.CPP's
//!   loop condition is `count < num_cycles || num_cycles == -1`).
//!
//! The yield follows BehaviorTree.CPP: after a child that succeeded from Idle within this
//! tick, the node returns Running and asks to be woken, so
//! [`Tree::tick_once`](crate::Tree::tick_once) runs all cycles of an instant child in one
//! call while [`Tree::tick_exactly_once`](crate::Tree::tick_exactly_once) runs one cycle per
//! tick. A child that ran over several ticks goes straight on to its next cycle. A skipped
//! child makes the node Skipped without resetting the count. Halt resets the count.

use crate::blueprint::NodeDef;
use crate::tree::failure::{Note, Reason};
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::blueprint::{Builder, NodeKind, Param, PortBinding, PortBindingError};
use crate::nodes::built_in::{self, BuiltIn, Tick};
use crate::nodes::decl::{NodeDecl, PortDecl};
use crate::nodes::semantics::{first, Literals, Order, Semantics, Statuses};
use crate::{Arity, Category};
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

/// Repeat's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const REPEAT: NodeDecl = NodeDecl {
    name: "Repeat",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[PortDecl::input(
        "num_cycles",
        "i32",
        "How many times a succeeding child runs before the node succeeds; -1 repeats forever.",
    )],
    summary: "Runs a succeeding child `num_cycles` times (-1: forever); a failure fails.",
    semantics: Semantics::new(Order::again(Statuses::ANY, Statuses::SUCCESS), outcomes),
};

/// What a Repeat can return: its child's statuses, with SUCCESS only once the cycles are
/// done (never with -1) and RUNNING between cycles; SUCCESS at once, without a tick, for 0
/// cycles (or a negative count other than -1).
fn outcomes(l: &Literals<'_>, c: &[Statuses]) -> Statuses {
    loop_outcomes(l.int("num_cycles"), first(c), Statuses::SUCCESS)
}

/// What a loop that goes again after `again` (Repeat: SUCCESS; RetryUntilSuccessful:
/// FAILURE) can return over a `child`, with a literal `limit` (`None`: read when it runs).
pub(crate) fn loop_outcomes(limit: Option<i64>, child: Statuses, again: Statuses) -> Statuses {
    match limit {
        None => Statuses::ANY,
        Some(-1) => child
            .without(again)
            .or(Statuses::RUNNING.when(child.meets(again))),
        Some(n) if n <= 0 => again,
        Some(n) => child.or(Statuses::RUNNING.when(child.meets(again) && n >= 2)),
    }
}

/// Repeat (`REPEAT`) or RetryUntilSuccessful (`!REPEAT`): the two mirror each other, one
/// counting successes and stopping at a failure, the other counting failures and stopping at
/// a success. `limit` is `num_cycles` or `num_attempts` (exactly -1: forever; another
/// negative value: no cycle).
#[inline(never)]
pub(crate) fn tick<C, const REPEAT: bool>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
    limit: i32,
) -> NodeStatus {
    let (again, stop) = if REPEAT {
        (NodeStatus::Success, NodeStatus::Failure)
    } else {
        (NodeStatus::Failure, NodeStatus::Success)
    };
    let slot = t.bp.slot(id);
    let child = t.child(def, 0);
    // BehaviorTree.CPP's `count < n || n == -1`: only -1 is "forever"; any other negative
    // limit, like 0, allows no cycle at all.
    // A count stays below `limit` (an `i32`, as BehaviorTree.CPP's `int`) but forever, where it
    // saturates at `u32::MAX`: read again only if a limit bound to the blackboard changes, when
    // the saturated count is past any limit.
    let more = |count: u32| limit == -1 || (limit >= 0 && count < limit as u32);
    t.set_status(id, NodeStatus::Running);
    while more(t.aux[slot]) {
        let prev = t.status(child);
        let status = t.tick(child);
        if status == NodeStatus::Running {
            return NodeStatus::Running;
        }
        t.halt_child(child);
        // Completed, it would yield between its cycles if ticked again.
        t.answers_otherwise_next(id);
        if status == NodeStatus::Skipped {
            // Skipped with its count kept, as BehaviorTree.CPP does.
            return NodeStatus::Skipped;
        }
        if status != again {
            t.aux[slot] = 0;
            return stop;
        }
        t.aux[slot] = t.aux[slot].saturating_add(1);
        if prev == NodeStatus::Idle && more(t.aux[slot]) {
            t.wake = Some(id);
            return NodeStatus::Running;
        }
    }
    if !REPEAT {
        // Ran out of attempts: the Retry's own reason for its Failure.
        t.note(id, Note::Gave(Reason::gave_up(u64::from(t.aux[slot]))));
    }
    t.aux[slot] = 0;
    again
}

/// The Repeat node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Repeat {
    /// How many times; -1 forever, another negative value none.
    pub num_cycles: Param<i32>,
}

impl BuiltIn for Repeat {
    fn port_values(&self, _: usize) -> Vec<Option<String>> {
        vec![built_in::text(&self.num_cycles)]
    }
}

impl Tick for Repeat {
    /// With a fixed count, the count that let the Running child start still lets it run
    /// (it changes only when the child completes); a count read from a port may have
    /// changed.
    fn passes_through(&self) -> bool {
        matches!(self.num_cycles, Param::Value(_))
    }

    const DECL: &'static NodeDecl = &REPEAT;
    const AUX_SLOTS: u32 = 1;

    /// The cycles done: a count saved when slots were 64 bits, past 2^32 (only a Repeat of
    /// `-1`, which never reads it), saturates as the count does now.
    fn restored_aux(saved: u64, children: u32) -> Option<u64> {
        let _ = children;
        Some(saved.min(u64::from(u32::MAX)))
    }

    fn from_ports(port: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(Repeat {
            num_cycles: built_in::param(port, "num_cycles")?,
        })
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        match t.param(id, self.num_cycles, "num_cycles") {
            Some(n) => tick::<C, true>(t, id, def, n),
            None => NodeStatus::Failure,
        }
    }

    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, _: &NodeDef<C>) {
        t.halt_afresh(id);
    }
}

impl<C> Builder<C> {
    /// A [Repeat](self); exactly `-1` repeats forever, another negative count runs no cycle.
    pub fn repeat(self, name: &str, num_cycles: i32, child: impl FnOnce(Self) -> Self) -> Self {
        let node = Repeat {
            num_cycles: num_cycles.into(),
        };
        self.node(NodeKind::Repeat(node), name, child)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn tick_once_runs_every_cycle_of_an_instant_child() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| b.repeat("r", 3, |r| r.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [3]);
    }

    #[test]
    fn tick_exactly_once_runs_one_cycle_per_tick() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| b.repeat("r", 3, |r| r.scripted(0)));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [3]);
    }

    #[test]
    fn failure_ends_and_resets_the_count() {
        let mut lab = Lab::new(&[&[S, F, S]]);
        let mut tree = lab.tree(|b| b.repeat("r", 2, |r| r.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [2]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [4]);
    }

    #[test]
    fn zero_cycles_succeed_without_a_tick() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| b.repeat("r", 0, |r| r.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [0]);
    }

    #[test]
    fn only_minus_one_loops_forever_another_negative_count_succeeds_without_a_tick() {
        // BehaviorTree.CPP: `repeat_count_ < num_cycles_ || num_cycles_ == -1`.
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| b.repeat("r", -2, |r| r.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [0]);
        assert_eq!(lab.halts, [0]);
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| b.repeat("r", -1, |r| r.scripted(0)));
        for _ in 0..5 {
            assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        }
        assert_eq!(lab.ticks, [5]);
    }

    #[test]
    fn a_running_child_continues_without_yield() {
        let mut lab = Lab::new(&[&[R, S, R, S]]);
        let mut tree = lab.tree(|b| b.repeat("r", 2, |r| r.scripted(0)));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        // Success after Running: no yield, the next cycle starts in the same tick.
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [3]);
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [4]);
    }

    #[test]
    fn halt_resets_the_count() {
        let mut lab = Lab::new(&[&[S, R, S, S]]);
        let mut tree = lab.tree(|b| b.repeat("r", 2, |r| r.scripted(0)));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [1]);
        // Two full cycles are needed again: without the reset, the next success would end it.
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [4]);
    }
}
