//! Cooldown(duration), a NeuroTree node (BehaviorTree.CPP has none): after the child
//! completes, rest for a while.
//!
//! After the child completes, return Failure without ticking it until the duration has passed.
//! Halt does not clear the cooldown.
//!
//! The rest starts at the clock reading of the tick on which the child completed, whatever
//! its outcome; a Running child is not limited.

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

/// Cooldown's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const COOLDOWN: NodeDecl = NodeDecl {
    name: "Cooldown",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[
        PortDecl::input("cooldown_msec", "u64", "Milliseconds after the child completed during which the node fails without ticking it."),
    ],
    summary: "After the child completes, fails without ticking it until `cooldown_msec` has passed (a NeuroTree node).",
    semantics: Semantics::new(Order::in_turn(Statuses::ANY), |_, c| {
        first(c).or(Statuses::FAILURE)
    }),
};

#[inline(never)]
pub(crate) fn tick<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
    period: Duration,
) -> NodeStatus {
    let slot = t.bp.slot(id);
    let now = t.now_nanos();
    let period = duration_to_nanos(period);
    if let Some(rested) = moment::elapsed(t.aux64(slot), now).filter(|&rested| rested < period) {
        // Its answer changes when the period is over: a reactive node re-checking it may
        // let the tree sleep until then.
        t.wake_at(now.saturating_add(period - rested));
        return NodeStatus::Failure;
    }
    t.set_status(id, NodeStatus::Running);
    let child = t.child(def, 0);
    let status = t.tick(child);
    if status.is_completed() {
        t.set_aux64(slot, moment::at(now));
        t.halt_child(child);
        // Next tick it fails, cooling down, whatever the child answered now.
        t.answers_otherwise_next(id);
    }
    status
}

/// The Cooldown node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cooldown {
    /// The time, whose port holds milliseconds.
    pub period: Param<Duration>,
}

impl BuiltIn for Cooldown {
    fn port_values(&self, _: usize) -> Vec<Option<String>> {
        vec![built_in::millis_text(&self.period)]
    }
}

impl Tick for Cooldown {
    const DECL: &'static NodeDecl = &COOLDOWN;
    /// A moment: 64 bits.
    const AUX_SLOTS: u32 = 2;

    fn shift_aux(aux: u64, saved: u64, now: u64) -> u64 {
        crate::clock::moment::shift(aux, saved, now)
    }

    fn from_ports(port: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(Cooldown {
            period: built_in::millis(port, "cooldown_msec")?,
        })
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        match t.millis(id, self.period, "cooldown_msec") {
            Some(period) => tick(t, id, def, period),
            None => NodeStatus::Failure,
        }
    }
}

impl<C> Builder<C> {
    /// A [Cooldown](self): after the child completes, fail for a while without ticking it.
    pub fn cooldown(self, name: &str, period: Duration, child: impl FnOnce(Self) -> Self) -> Self {
        let node = Cooldown {
            period: period.into(),
        };
        self.node(NodeKind::Cooldown(node), name, child)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn rests_after_completion() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| b.cooldown("c", ms(1000), |c| c.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        lab.clock.advance(ms(999));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1]);
        lab.clock.advance(ms(1));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [2]);
    }

    #[test]
    fn halt_keeps_the_cooldown() {
        let mut lab = Lab::new(&[&[F]]);
        let mut tree = lab
            .tree(|b| b.reactive_sequence("rs", |s| s.cooldown("c", ms(500), |c| c.scripted(0))));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        lab.halt(&mut tree);
        lab.clock.advance(ms(100));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1]);
    }

    #[test]
    fn running_child_is_not_limited() {
        let mut lab = Lab::new(&[&[R, R, S]]);
        let mut tree = lab.tree(|b| b.cooldown("c", ms(100), |c| c.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.clock.advance(ms(500));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [3]);
    }
}
