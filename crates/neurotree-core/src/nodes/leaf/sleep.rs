//! Sleep(msec): a stateful leaf on the tree's clock, its start time kept in a state slot.
//!
//! - On the tick from Idle: Success at once if `msec` is 0, else note the time and return
//!   Running.
//! - Later ticks: Success once `msec` has passed, else Running.
//! - Ticked again after completing, before its parent reset it (Nav2's PipelineSequence
//!   re-ticks its finished children): the status it has, with no new sleep, as
//!   BehaviorTree.CPP's `StatefulActionNode::tick` does.
//! - Halt forgets the start.
//!
//! It reads only the clock, so it is deterministic under a [`ManualClock`](crate::ManualClock).

use core::time::Duration;

use crate::clock::{duration_to_nanos, moment};
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::blueprint::NodeDef;
use crate::blueprint::{Builder, NodeKind, Param, PortBinding, PortBindingError};
use crate::nodes::built_in::{self, BuiltIn, Tick};
use crate::nodes::decl::{NodeDecl, PortDecl};
use crate::nodes::semantics::{Order, Semantics, Statuses};
use crate::{Arity, Category};
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

/// Sleep's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const SLEEP: NodeDecl = NodeDecl {
    name: "Sleep",
    category: Category::Action,
    arity: Arity::Leaf,
    ports: &[PortDecl::input(
        "msec",
        "u64",
        "Milliseconds to stay Running, on the tree's clock.",
    )],
    summary: "Running until `msec` has passed on the tree's clock, then Success.",
    semantics: Semantics::new(Order::AllAtOnce, |l, _| {
        // A duration read from an entry that cannot be read fails the tick.
        let read = Statuses::FAILURE.when(l.text("msec").is_none());
        Statuses::SUCCESS.or(Statuses::RUNNING).or(read)
    }),
};

pub(crate) fn tick<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    slot: usize,
    wait: Duration,
) -> NodeStatus {
    let now = t.now_nanos();
    match t.status(id) {
        NodeStatus::Running => {}
        NodeStatus::Idle | NodeStatus::Skipped => {
            if wait.is_zero() {
                return NodeStatus::Success;
            }
            t.set_aux64(slot, moment::at(now));
            t.wake_at(now.saturating_add(duration_to_nanos(wait)));
            return NodeStatus::Running;
        }
        // Completed and not yet reset by its parent: BehaviorTree.CPP's StatefulActionNode
        // returns the status it has.
        done => return done,
    }
    let wait = duration_to_nanos(wait);
    let slept = moment::elapsed(t.aux64(slot), now).unwrap_or(u64::MAX);
    if slept >= wait {
        t.answers_otherwise_next(id);
        NodeStatus::Success
    } else {
        t.wake_at(now.saturating_add(wait - slept));
        NodeStatus::Running
    }
}

/// The Sleep node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sleep {
    /// The time, whose port holds milliseconds.
    pub duration: Param<Duration>,
}

impl BuiltIn for Sleep {
    fn port_values(&self, _: usize) -> Vec<Option<String>> {
        vec![built_in::millis_text(&self.duration)]
    }
}

impl Tick for Sleep {
    const DECL: &'static NodeDecl = &SLEEP;
    /// A moment: 64 bits.
    const AUX_SLOTS: u32 = 2;

    fn shift_aux(aux: u64, saved: u64, now: u64) -> u64 {
        moment::shift(aux, saved, now)
    }

    fn from_ports(port: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(Sleep {
            duration: built_in::millis(port, "msec")?,
        })
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        match t.millis(id, self.duration, "msec") {
            Some(duration) => {
                let _ = def;
                tick(t, id, t.bp.slot(id), duration)
            }
            None => NodeStatus::Failure,
        }
    }
}

impl<C> Builder<C> {
    /// A [Sleep](self) leaf: Running until the duration has passed, then Success.
    pub fn sleep(self, name: &str, duration: Duration) -> Self {
        let node = Sleep {
            duration: duration.into(),
        };
        self.leaf(NodeKind::Sleep(node), name)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;
    use crate::{Arity, CustomNode, CustomSpec, NodeCtx};
    use alloc::boxed::Box;
    use std::sync::Mutex;

    #[test]
    fn sleeps_on_the_clock() {
        let (mut tree, clock) = build(|b| b.sleep("nap", ms(100)));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        clock.advance(ms(99));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        clock.advance(ms(1));
        assert_eq!(tick(&mut tree), Ok(Status::Success));
        // The root was reset, so the next tick sleeps again from now.
        assert_eq!(tick(&mut tree), Ok(Status::Running));
    }

    #[test]
    fn zero_succeeds_at_once() {
        let (mut tree, _) = build(|b| b.sleep("nap", ms(0)));
        assert_eq!(tick(&mut tree), Ok(Status::Success));
    }

    #[test]
    fn halt_restarts_the_wait() {
        let (mut tree, clock) = build(|b| b.sleep("nap", ms(100)));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        clock.advance(ms(80));
        tree.halt(&mut ());
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        clock.advance(ms(80));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        clock.advance(ms(20));
        assert_eq!(tick(&mut tree), Ok(Status::Success));
    }

    /// Ticks its child every tick and never resets it (as Nav2's PipelineSequence leaves
    /// its finished children); records what the child returned.
    struct Hold(Arc<Mutex<Vec<NodeStatus>>>);

    impl CustomNode<()> for Hold {
        fn tick(&mut self, node: &mut NodeCtx<'_, '_, ()>) -> NodeStatus {
            let status = node.tick_child(0);
            self.0.lock().unwrap().push(status);
            NodeStatus::Running
        }
    }

    #[test]
    fn re_ticked_after_completing_it_returns_its_status_until_reset() {
        // As BehaviorTree.CPP's StatefulActionNode: a completed status is returned as it is,
        // with no new sleep, until the parent resets it.
        let seen = Arc::new(Mutex::new(Vec::new()));
        let log = Arc::clone(&seen);
        let hold = CustomSpec::new(
            "Hold",
            Arity::One,
            Box::new(move || Box::new(Hold(Arc::clone(&log)))),
        );
        let (mut tree, clock) = build(|b| b.custom("hold", hold, |h| h.sleep("nap", ms(10))));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        clock.advance(ms(10));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        use NodeStatus::{Running as Run, Success as Succ};
        assert_eq!(*seen.lock().unwrap(), [Run, Succ, Succ]);
        // Halted (and so reset), it sleeps afresh.
        tree.halt(&mut ());
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        assert_eq!(seen.lock().unwrap().last(), Some(&Run));
    }
}
