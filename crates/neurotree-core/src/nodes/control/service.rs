//! Service(interval_msec), a NeuroTree node (BehaviorTree.CPP has none; Unreal's behavior
//! trees call it a service): keeps something up to date, at an interval, while a branch runs.
//!
//! Two children: the service (sensing, scoring: it copies the world into the blackboard)
//! and the branch.
//!
//! - On the tick that starts it (the node Idle), it ticks the service, then the branch.
//! - On later ticks, it ticks the service again when `interval_msec` has passed since the
//!   service was last started, then the branch. A service still Running is ticked on every
//!   tick until it completes; its result is otherwise ignored.
//! - It returns the branch's status. When the branch completes (or is Skipped), it halts
//!   the service if it is Running and resets both: the next tick starts afresh, service
//!   first.
//! - Halted, it halts both children and forgets when the service last ran.
//!
//! A tree whose branch sleeps sleeps under a Service too: the Service declares the next
//! interval as a deadline, so the tree wakes to run the service, as a tree ticked every
//! frame would (see [`sleep`](crate::tree::sleep)).
//!
//! The interval is measured on the tree's clock from the tick that started the service,
//! not from when it was due: a tree ticked every 16 ms with a 100 ms interval runs its
//! service at 0, 112, 224 ms, ...

use core::time::Duration;

use crate::blueprint::NodeDef;
use crate::clock::{duration_to_nanos, moment};
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::blueprint::{Builder, NodeKind, Param, PortBinding, PortBindingError};
use crate::nodes::built_in::{self, BuiltIn, Tick};
use crate::nodes::decl::{NodeDecl, PortDecl};
use crate::nodes::semantics::{Order, Semantics, Statuses};
use crate::{Arity, Category};
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

/// Service's declaration: its name, family, children and ports.
pub const SERVICE: NodeDecl = NodeDecl {
    name: "Service",
    category: Category::Control,
    arity: Arity::Range { min: 2, max: 2 },
    ports: &[PortDecl::input(
        "interval_msec",
        "u64",
        "Milliseconds between two starts of the service (the first child) while the branch runs.",
    )],
    summary: "Ticks its first child (the service) at the start and every `interval_msec`, then its second (the branch), whose status it returns (a NeuroTree node).",
    // The service on some ticks, then the branch on every tick whatever the service said;
    // the branch's status, or a Failure when the interval read from the blackboard is bad.
    semantics: Semantics::new(Order::again(Statuses::ANY, Statuses::ANY), |l, c| {
        c[1].or(Statuses::FAILURE.when(l.int("interval_msec").is_none()))
    }),
};

#[inline(never)]
pub(crate) fn tick<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
    interval: Duration,
) -> NodeStatus {
    let slot = t.bp.slot(id);
    let now = t.now_nanos();
    let interval = duration_to_nanos(interval);
    t.set_status(id, NodeStatus::Running);
    let service = t.child(def, 0);
    let due = match moment::elapsed(t.aux64(slot), now) {
        None => true,
        Some(since) => since >= interval,
    };
    if due {
        t.set_aux64(slot, moment::at(now));
        if t.status(service) != NodeStatus::Running {
            t.set_status(service, NodeStatus::Idle);
        }
    }
    if due || t.status(service) == NodeStatus::Running {
        let status = t.tick(service);
        if status != NodeStatus::Running {
            // Its result is not the node's: back to Idle, to start afresh when next due.
            t.halt_child(service);
        }
    }
    let branch = t.child(def, 1);
    let status = t.tick(branch);
    if status == NodeStatus::Running {
        let since = moment::elapsed(t.aux64(slot), now).unwrap_or(0);
        // A sleeping tree wakes for the next service.
        t.wake_at(now.saturating_add(interval.saturating_sub(since)));
        return NodeStatus::Running;
    }
    t.reset_children(id);
    t.set_aux64(slot, 0);
    status
}

/// The Service node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Service {
    /// The interval, whose port holds milliseconds.
    pub interval: Param<Duration>,
}

impl BuiltIn for Service {
    fn port_values(&self, _: usize) -> Vec<Option<String>> {
        vec![built_in::millis_text(&self.interval)]
    }
}

impl Tick for Service {
    const DECL: &'static NodeDecl = &SERVICE;
    /// A moment: 64 bits.
    const AUX_SLOTS: u32 = 2;

    fn shift_aux(aux: u64, saved: u64, now: u64) -> u64 {
        crate::clock::moment::shift(aux, saved, now)
    }

    fn from_ports(port: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(Service {
            interval: built_in::millis(port, "interval_msec")?,
        })
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        match t.millis(id, self.interval, "interval_msec") {
            Some(interval) => tick(t, id, def, interval),
            None => NodeStatus::Failure,
        }
    }

    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, _: &NodeDef<C>) {
        t.halt_afresh(id);
    }
}

impl<C> Builder<C> {
    /// A [Service](self): its first child, the service, at the start and every `interval`
    /// while its second child, the branch, runs.
    pub fn service(
        self,
        name: &str,
        interval: Duration,
        children: impl FnOnce(Self) -> Self,
    ) -> Self {
        let node = Service {
            interval: interval.into(),
        };
        self.node(NodeKind::Service(node), name, children)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;
    use crate::{Handle, StatefulAction};

    #[test]
    fn ticks_the_service_at_the_start_and_every_interval() {
        // Service: always Success; branch: Running four ticks, then Success.
        let mut lab = Lab::new(&[&[S], &[R, R, R, R, S]]);
        let mut tree = lab.tree(|b| b.service("sense", ms(100), |s| s.scripted(0).scripted(1)));
        // 0 ms: both.
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [1, 1]);
        // 60 ms: the branch only.
        lab.clock.advance(ms(60));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [1, 2]);
        // 100 ms: the interval has passed: both, the service first.
        lab.clock.advance(ms(40));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [2, 3]);
        assert_eq!(lab.log_of(0), ["start", "start"]);
        // 199 ms: not yet.
        lab.clock.advance(ms(99));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [2, 4]);
        // 250 ms: the service, then the branch, which succeeds: the node's Success.
        lab.clock.advance(ms(51));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [3, 5]);
        assert_eq!(lab.halts, [0, 0]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
        // The next run starts with the service, whatever the time.
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [4, 6]);
    }

    #[test]
    fn returns_the_branch_status_whatever_the_service_says() {
        let mut lab = Lab::new(&[&[F], &[F]]);
        let mut tree = lab.tree(|b| b.service("s", ms(100), |s| s.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1, 1]);
    }

    #[test]
    fn a_running_service_is_ticked_until_it_completes_and_halted_with_the_branch() {
        // Service: Running twice, then Success; the branch runs on, then succeeds.
        let mut lab = Lab::new(&[&[R, R, S, R], &[R, R, R, R, S]]);
        let mut tree = lab.tree(|b| b.service("s", ms(100), |s| s.scripted(0).scripted(1)));
        for expected in [[1, 1], [2, 2], [3, 3], [3, 4]] {
            assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
            assert_eq!(lab.ticks, expected);
        }
        // 100 ms: the service starts again (Running), the branch succeeds: the Running
        // service is halted.
        lab.clock.advance(ms(100));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [4, 5]);
        assert_eq!(lab.halts, [1, 0]);
        assert_eq!(
            lab.log_of(0),
            ["start", "running", "running", "start", "halted"]
        );
    }

    #[test]
    fn halted_it_halts_both_and_starts_afresh() {
        let mut lab = Lab::new(&[&[R], &[R]]);
        let mut tree = lab.tree(|b| b.service("s", ms(100), |s| s.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [1, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
        // Afresh: the service starts at once, not 100 ms later.
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [2, 2]);
        assert_eq!(lab.log_of(0), ["start", "halted", "start"]);
    }

    /// Counts its calls, and waits for the entry `done`, saying so.
    struct Waits;

    impl StatefulAction<u32> for Waits {
        fn on_start(&mut self, h: &mut Handle<'_, u32>) -> Status {
            self.on_running(h)
        }
        fn on_running(&mut self, h: &mut Handle<'_, u32>) -> Status {
            *h.ctx_mut() += 1;
            if h.blackboard().get::<bool>("done").unwrap_or(false) {
                return Status::Success;
            }
            h.wake_on("done");
            Status::Running
        }
    }

    #[test]
    fn between_intervals_the_tree_sleeps_until_the_next() {
        let clock = ManualClock::new();
        let bp = Builder::<u32>::new()
            .service("s", ms(100), |s| {
                s.action("sense", |n: &mut u32| {
                    *n += 1000;
                    Status::Success
                })
                .stateful("wait", || Waits)
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, clock.clone());
        let mut n = 0;
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        assert!(tree.is_asleep());
        assert_eq!(tree.wakes_at(), Some(ms(100)));
        assert_eq!(n, 1001);
        for _ in 0..6 {
            clock.advance(ms(16));
            assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        }
        // 96 ms: asleep all along.
        assert_eq!(n, 1001);
        clock.advance(ms(16));
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        // 112 ms: the service, and the branch.
        assert_eq!(n, 2002);
        assert_eq!(tree.wakes_at(), Some(ms(212)));
    }
}
