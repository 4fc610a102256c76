//! Timeout(msec): fail and halt the child when it runs too long.
//!
//! Start timing on the first tick from Idle; at a tick where the time is up, halt the child and
//! return Failure. Deterministic: reads the clock, no timer thread.
//!
//! The time is checked before the child is ticked, and only a Running child is timed out
//! (as BehaviorTree.CPP's timer only halts a Running child). A child that completes in time
//! ends the run; the next run times afresh. `msec = 0` never times out.
//!
//! A Timeout that fires gives its own [reason](crate::Reason) for its Failure: "timed out
//! after 100 ms" (whole seconds as "2 s"), code 0.
//!
//! A halt that takes ticks ([`slow_halt`](crate::tree::slow_halt)): when the child it times
//! out answers Halting, the node returns Running, continues the halt on later ticks (the
//! child is not ticked), and returns the timeout's Failure on the tick the halt is done.

use core::time::Duration;

use crate::blueprint::NodeDef;
use crate::clock::{duration_to_nanos, moment};
use crate::tree::failure::{Note, Reason};
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::blueprint::{Builder, NodeKind, Param, PortBinding, PortBindingError};
use crate::nodes::built_in::{self, BuiltIn, Tick};
use crate::nodes::decl::{NodeDecl, PortDecl};
use crate::nodes::semantics::{first, Order, Semantics, Statuses};
use crate::{Arity, Category};
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

/// Timeout's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const TIMEOUT: NodeDecl = NodeDecl {
    name: "Timeout",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[PortDecl::input(
        "msec",
        "u64",
        "Milliseconds the child may run; past them it is halted and the node fails (0: no limit).",
    )],
    summary: "Times from the first tick; when `msec` is up, halts the Running child and fails.",
    semantics: Semantics::new(Order::in_turn(Statuses::ANY), |_, c| {
        first(c).or(Statuses::RUNNING).or(Statuses::FAILURE)
    }),
};

#[inline(never)]
pub(crate) fn tick<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
    limit: Duration,
) -> NodeStatus {
    let slot = t.bp.slot(id);
    if t.aux64(slot) == TIMED_OUT {
        return finish_halt(t, id, limit);
    }
    let now = t.now_nanos();
    let child = t.child(def, 0);
    let ran = match moment::elapsed(t.aux64(slot), now) {
        None => {
            t.set_aux64(slot, moment::at(now));
            t.set_status(id, NodeStatus::Running);
            0
        }
        Some(ran) => {
            if !limit.is_zero()
                && ran >= duration_to_nanos(limit)
                && t.status(child) == NodeStatus::Running
            {
                if t.halting_for(id, |t| t.halt_child(child)) {
                    t.set_aux64(slot, TIMED_OUT);
                    return NodeStatus::Running;
                }
                t.set_aux64(slot, moment::NONE);
                t.note(id, Note::Gave(Reason::timed_out(limit)));
                t.answers_otherwise_next(id);
                return NodeStatus::Failure;
            }
            ran
        }
    };
    let status = t.tick(child);
    if status.is_completed() {
        t.set_aux64(slot, moment::NONE);
        t.halt_child(child);
    } else if status == NodeStatus::Running && !limit.is_zero() {
        // A sleeping tree wakes when the time is up.
        let limit = duration_to_nanos(limit);
        t.wake_at(now.saturating_add(limit.saturating_sub(ran)));
    }
    status
}

/// The state slot of a Timeout that timed out and waits for its child's halt (never a
/// moment: those stay below it).
const TIMED_OUT: u64 = u64::MAX;

/// A tick of a Timeout that waits for its child's halt: Running until it is done, then the
/// timeout's Failure.
#[cold]
#[inline(never)]
fn finish_halt<C>(t: &mut Ticker<'_, C>, id: NodeId, limit: Duration) -> NodeStatus {
    if t.waits_for_halts(id) {
        return NodeStatus::Running;
    }
    t.set_aux64(t.bp.slot(id), moment::NONE);
    t.note(id, Note::Gave(Reason::timed_out(limit)));
    t.answers_otherwise_next(id);
    NodeStatus::Failure
}

/// The Timeout node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timeout {
    /// The time, whose port holds milliseconds.
    pub limit: Param<Duration>,
}

impl BuiltIn for Timeout {
    fn port_values(&self, _: usize) -> Vec<Option<String>> {
        vec![built_in::millis_text(&self.limit)]
    }
}

impl Tick for Timeout {
    const DECL: &'static NodeDecl = &TIMEOUT;
    /// A moment: 64 bits.
    const AUX_SLOTS: u32 = 2;

    fn shift_aux(aux: u64, saved: u64, now: u64) -> u64 {
        if aux == TIMED_OUT {
            return aux;
        }
        crate::clock::moment::shift(aux, saved, now)
    }

    fn from_ports(port: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(Timeout {
            limit: built_in::millis(port, "msec")?,
        })
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        match t.millis(id, self.limit, "msec") {
            Some(limit) => tick(t, id, def, limit),
            None => NodeStatus::Failure,
        }
    }

    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, _: &NodeDef<C>) {
        t.halt_afresh(id);
    }
}

impl<C> Builder<C> {
    /// A [Timeout](self): fail and halt the child when it runs too long.
    pub fn timeout(self, name: &str, limit: Duration, child: impl FnOnce(Self) -> Self) -> Self {
        let node = Timeout {
            limit: limit.into(),
        };
        self.node(NodeKind::Timeout(node), name, child)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn times_out_a_running_child() {
        let mut lab = Lab::new(&[&[R]]);
        let mut tree = lab.tree(|b| b.timeout("t", ms(100), |t| t.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.clock.advance(ms(99));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.clock.advance(ms(1));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [2]);
        assert_eq!(lab.halts, [1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn a_child_that_completes_in_time_passes() {
        let mut lab = Lab::new(&[&[R, S]]);
        let mut tree = lab.tree(|b| b.timeout("t", ms(100), |t| t.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.clock.advance(ms(50));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        // A new run is timed from its own start.
        lab.clock.advance(ms(80));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.halts, [0]);
    }

    #[test]
    fn zero_never_times_out() {
        let mut lab = Lab::new(&[&[R]]);
        let mut tree = lab.tree(|b| b.timeout("t", ms(0), |t| t.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.clock.advance(ms(10_000));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
    }
}
