//! Delay(delay_msec): wait on the clock, then tick the child.
//!
//! Running until the delay has passed on the tree's clock, then tick the child.
//!
//! The wait starts on the tick that finds the node not started; once it has passed, the
//! child is ticked on every tick until it completes, which ends the Delay (the next run waits
//! again). A halt forgets the wait. A delay of 0 ticks the child on the first tick.

use core::time::Duration;

use crate::blueprint::NodeDef;
use crate::clock::{duration_to_nanos, moment};
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

/// Delay's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const DELAY: NodeDecl = NodeDecl {
    name: "Delay",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[PortDecl::input(
        "delay_msec",
        "u64",
        "Milliseconds to wait, on the tree's clock, before the child is first ticked.",
    )],
    summary: "Running until `delay_msec` has passed on the tree's clock, then ticks the child.",
    semantics: Semantics::new(Order::in_turn(Statuses::ANY), |_, c| {
        first(c).or(Statuses::RUNNING).or(Statuses::FAILURE)
    }),
};

#[inline(never)]
pub(crate) fn tick<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
    wait: Duration,
) -> NodeStatus {
    let slot = t.bp.slot(id);
    let now = t.now_nanos();
    let waited = match moment::elapsed(t.aux64(slot), now) {
        Some(waited) => waited,
        None => {
            t.set_aux64(slot, moment::at(now));
            t.set_status(id, NodeStatus::Running);
            0
        }
    };
    let wait = duration_to_nanos(wait);
    if waited < wait {
        // A sleeping tree wakes when the wait is over.
        t.wake_at(now.saturating_add(wait - waited));
        return NodeStatus::Running;
    }
    let child = t.child(def, 0);
    let status = t.tick(child);
    if status.is_completed() {
        t.set_aux64(slot, 0);
        t.halt_child(child);
        if wait != 0 {
            t.answers_otherwise_next(id);
        }
    }
    status
}

/// The Delay node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Delay {
    /// The time, whose port holds milliseconds.
    pub delay: Param<Duration>,
}

impl BuiltIn for Delay {
    fn port_values(&self, _: usize) -> Vec<Option<String>> {
        vec![built_in::millis_text(&self.delay)]
    }
}

impl Tick for Delay {
    const DECL: &'static NodeDecl = &DELAY;
    /// A moment: 64 bits.
    const AUX_SLOTS: u32 = 2;

    fn shift_aux(aux: u64, saved: u64, now: u64) -> u64 {
        crate::clock::moment::shift(aux, saved, now)
    }

    fn from_ports(port: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(Delay {
            delay: built_in::millis(port, "delay_msec")?,
        })
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        match t.millis(id, self.delay, "delay_msec") {
            Some(delay) => tick(t, id, def, delay),
            None => NodeStatus::Failure,
        }
    }

    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, _: &NodeDef<C>) {
        t.halt_afresh(id);
    }
}

impl<C> Builder<C> {
    /// A [Delay](self): wait on the clock, then tick the child.
    pub fn delay(self, name: &str, delay: Duration, child: impl FnOnce(Self) -> Self) -> Self {
        let node = Delay {
            delay: delay.into(),
        };
        self.node(NodeKind::Delay(node), name, child)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn waits_then_ticks_the_child() {
        let mut lab = Lab::new(&[&[R, S]]);
        let mut tree = lab.tree(|b| b.delay("d", ms(100), |d| d.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.clock.advance(ms(99));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [0]);
        lab.clock.advance(ms(1));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [2]);
        // A new run waits again.
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [2]);
    }

    #[test]
    fn zero_delay_ticks_at_once() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| b.delay("d", ms(0), |d| d.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1]);
    }

    #[test]
    fn halt_forgets_the_wait() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| b.delay("d", ms(100), |d| d.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.clock.advance(ms(90));
        lab.halt(&mut tree);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.clock.advance(ms(90));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.clock.advance(ms(10));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
    }
}
