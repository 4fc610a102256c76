//! Async actions: a Rust future per run of the node.
//!
//! On the tick that finds an async action Idle, its start function reads what it needs from the
//! [`Handle`] (ports, blackboard, context) and returns a future, which is polled at once and
//! then once per tick while the node is Running:
//!
//! - Pending → Running.
//! - Ready(status) → that status, and the future is dropped.
//! - Halted while Running: the future is dropped, exactly once, and never polled again.
//!
//! In short: the future is made on the tick from Idle, polled once per tick (Pending →
//! Running), dropped on completion or halt.
//!
//! This is the classic start/update/stop action written as Rust writes long work: starting is the
//! start function, each update is a poll, stopping is the future's drop. Work that waits (a timer,
//! a reply, a task on another thread) is an `async` block; cancelling it is dropping it, so cleanup
//! lives in `Drop` (a guard, an abort-on-drop task handle). When stopping needs the context, use a
//! [`StatefulAction`](super::StatefulAction) instead.
//!
//! The future outlives the tick, so it cannot borrow the context or the blackboard: it is
//! `Send + 'static` and owns what it needs (copied values, `Arc`s, channel ends) taken
//! synchronously at start. Its result comes back as its status; a value it produces goes
//! to a shared place it owns a handle to.
//!
//! Each start allocates once, the boxed future; polling allocates nothing. No runtime is
//! needed: the tree polls with its own [`Waker`](core::task::Waker) (see
//! [`WakeSignal`](crate::WakeSignal)), and a wake makes `tick_once` tick again at once, or
//! tells a runner to tick before its next period. A future that waits on a runtime's timer
//! or I/O must be polled inside that runtime (the `neurotree` crate's tokio runner does so).
//!
//! ```
//! use std::sync::Arc;
//! use neurotree_core::{Blueprint, ManualClock, Port, Status, Tree};
//!
//! let blueprint = Blueprint::<()>::builder()
//!     .async_action("count_down", |h| {
//!         // Read synchronously at start; the future owns the value.
//!         let mut left: u32 = h.input("from").unwrap_or(0);
//!         core::future::poll_fn(move |_| {
//!             if left == 0 {
//!                 return core::task::Poll::Ready(Status::Success);
//!             }
//!             left -= 1;
//!             core::task::Poll::Pending
//!         })
//!     })
//!     .ports([Port::literal("from", "2")])
//!     .build_shared()
//!     .unwrap();
//! let mut tree = Tree::with_clock(blueprint, ManualClock::new());
//! assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
//! assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
//! assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
//! ```

use alloc::boxed::Box;
use core::future::Future;
use core::pin::Pin;
use core::task::{Context, Poll};

use super::Handle;
use crate::tree::ticker::{Object, Ticker};
use crate::{NodeId, NodeStatus, Status};

/// The future of one run of an async action.
pub type ActionFuture = Pin<Box<dyn Future<Output = Status> + Send + 'static>>;

/// An action whose runs are futures; one object serves every instance.
///
/// A closure does the same through [`Builder::async_action`](crate::Builder::async_action);
/// implement the trait for an action that keeps configuration in `self`.
///
/// ```
/// use neurotree_core::{ActionFuture, AsyncAction, Blueprint, Handle, Status};
///
/// /// Succeeds when the future it starts is polled for the `after`-th time.
/// struct Countdown { after: u32 }
/// impl AsyncAction<()> for Countdown {
///     fn start(&self, _h: &mut Handle<'_, ()>) -> ActionFuture {
///         let mut left = self.after;
///         Box::pin(core::future::poll_fn(move |_| {
///             left -= 1;
///             if left == 0 { core::task::Poll::Ready(Status::Success) } else { core::task::Poll::Pending }
///         }))
///     }
/// }
/// let bp = Blueprint::<()>::builder().async_action_node("wait", Countdown { after: 3 }).build();
/// assert!(bp.is_ok());
/// ```
pub trait AsyncAction<C>: Send + Sync {
    /// Starts a run: read the ports, blackboard and context now, return the future that
    /// does the work. Its output is the node's Success or Failure (Running is reported as
    /// a [`TickError`](crate::TickError)).
    fn start(&self, h: &mut Handle<'_, C>) -> ActionFuture;
}

/// A closure that starts a future, as an [`AsyncAction`].
pub(crate) struct AsyncFn<F>(pub(crate) F);

impl<C, F, Fut> AsyncAction<C> for AsyncFn<F>
where
    F: Fn(&mut Handle<'_, C>) -> Fut + Send + Sync,
    Fut: Future<Output = Status> + Send + 'static,
{
    fn start(&self, h: &mut Handle<'_, C>) -> ActionFuture {
        Box::pin((self.0)(h))
    }
}

/// Ticks an async action: starts a run from Idle, then polls it once.
pub(crate) fn tick<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    action: &dyn AsyncAction<C>,
) -> NodeStatus {
    let prev = t.status(id);
    let Some(waker) = t.waker else {
        // A tree makes its waker when its blueprint holds an async action.
        return NodeStatus::Failure;
    };
    let (Some(Object::Async(run)), mut h) = t.split(id) else {
        // Objects are laid out from the same blueprint that chose this kind.
        return NodeStatus::Failure;
    };
    match prev {
        // A run that completed or was halted left no future behind.
        NodeStatus::Idle | NodeStatus::Skipped => *run = Some(action.start(&mut h)),
        NodeStatus::Running => {}
        // Completed and not yet reset by its parent: BehaviorTree.CPP repeats the result.
        done => return done,
    }
    let Some(future) = run.as_mut() else {
        // Running always has its future: it is stored before Running is returned and
        // taken only by completion or a halt, both of which leave the node not Running.
        return NodeStatus::Failure;
    };
    match future.as_mut().poll(&mut Context::from_waker(waker)) {
        Poll::Pending => NodeStatus::Running,
        Poll::Ready(status) => {
            *run = None;
            t.sync_result(id, status, "AsyncAction")
        }
    }
}

/// Halts an async action that is Running: drops its future.
pub(crate) fn halt<C>(t: &mut Ticker<'_, C>, id: NodeId) {
    if t.status(id) == NodeStatus::Running {
        if let (Some(Object::Async(run)), _) = t.split(id) {
            *run = None;
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::observer::Observer;
    use crate::testing::*;
    use crate::{NodeStatus, Port, TickError};
    use core::future::Future;
    use core::pin::Pin;
    use core::sync::atomic::{AtomicU32, Ordering::SeqCst};
    use core::task::{Context, Poll, Waker};
    use std::sync::Mutex;

    /// What a run's future does on each poll; the last step repeats.
    #[derive(Clone, Copy, Debug)]
    enum Step {
        /// Pending, without waking.
        Wait,
        /// Wakes its own waker, then Pending: a yield.
        Yield,
        /// Completes.
        Done(Status),
    }
    use Step::{Done, Wait, Yield};

    /// Counts what happens to the futures of one async action.
    #[derive(Default)]
    struct Probe {
        starts: AtomicU32,
        polls: AtomicU32,
        drops: AtomicU32,
        /// The waker of the last poll, to wake the future from outside.
        waker: Mutex<Option<Waker>>,
    }

    impl Probe {
        fn counts(&self) -> (u32, u32, u32) {
            (
                self.starts.load(SeqCst),
                self.polls.load(SeqCst),
                self.drops.load(SeqCst),
            )
        }
    }

    /// A run that plays its steps, one per poll.
    struct Run {
        probe: Arc<Probe>,
        steps: Vec<Step>,
        at: usize,
    }

    impl Future for Run {
        type Output = Status;
        fn poll(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Status> {
            self.probe.polls.fetch_add(1, SeqCst);
            *self.probe.waker.lock().unwrap() = Some(cx.waker().clone());
            let step = self.steps[self.at.min(self.steps.len() - 1)];
            self.at += 1;
            match step {
                Wait => Poll::Pending,
                Yield => {
                    cx.waker().wake_by_ref();
                    Poll::Pending
                }
                Done(status) => Poll::Ready(status),
            }
        }
    }

    impl Drop for Run {
        fn drop(&mut self) {
            self.probe.drops.fetch_add(1, SeqCst);
        }
    }

    /// Adds an async action named `name` whose runs play `steps` and report to `probe`.
    fn scripted<C: 'static>(
        b: Builder<C>,
        name: &str,
        probe: &Arc<Probe>,
        steps: &[Step],
    ) -> Builder<C> {
        let probe = Arc::clone(probe);
        let steps = steps.to_vec();
        b.async_action(name, move |_h| {
            probe.starts.fetch_add(1, SeqCst);
            Run {
                probe: Arc::clone(&probe),
                steps: steps.clone(),
                at: 0,
            }
        })
    }

    /// Counts passes of the root.
    #[derive(Clone, Default)]
    struct Passes(Arc<AtomicU32>);
    impl Observer for Passes {
        fn on_tick_start(&mut self, _now: Duration) {
            self.0.fetch_add(1, SeqCst);
        }
    }

    #[test]
    fn polled_once_per_tick_until_ready_then_dropped() {
        let probe = Arc::default();
        let (mut tree, _) = build(|b| scripted(b, "work", &probe, &[Wait, Wait, Done(S)]));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        assert_eq!(probe.counts(), (1, 1, 0));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        assert_eq!(probe.counts(), (1, 2, 0));
        assert_eq!(tick(&mut tree), Ok(Status::Success));
        assert_eq!(probe.counts(), (1, 3, 1));
        // The next tick is a new run.
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        assert_eq!(probe.counts(), (2, 4, 1));
    }

    #[test]
    fn ready_on_first_poll_completes_in_the_same_tick() {
        let probe = Arc::default();
        let (mut tree, _) = build(|b| {
            b.sequence("s", |s| {
                scripted(s, "quick", &probe, &[Done(F)]).always_success("never")
            })
        });
        assert_eq!(tick(&mut tree), Ok(Status::Failure));
        assert_eq!(probe.counts(), (1, 1, 1));
    }

    #[test]
    fn halt_drops_the_future_once_and_it_is_never_polled_again() {
        let probe = Arc::default();
        let (mut tree, _) = build(|b| scripted(b, "work", &probe, &[Wait]));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        tree.halt(&mut ());
        assert_eq!(probe.counts(), (1, 2, 1));
        tree.halt(&mut ());
        assert_eq!(probe.counts(), (1, 2, 1));
        assert_eq!(tree.status(NodeId::ROOT), NodeStatus::Idle);
        // Ticking again starts afresh rather than polling the dropped run.
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        assert_eq!(probe.counts(), (2, 3, 1));
    }

    #[test]
    fn a_reactive_parent_halts_it_when_its_condition_fails() {
        let probe = Arc::default();
        let mut go = true;
        let bp = Builder::<bool>::new()
            .reactive_sequence("guarded", |s| {
                scripted(s.condition("go", |g: &bool| *g), "work", &probe, &[Wait])
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        assert_eq!(tree.tick_once(&mut go), Ok(Status::Running));
        assert_eq!(tree.tick_once(&mut go), Ok(Status::Running));
        go = false;
        assert_eq!(tree.tick_once(&mut go), Ok(Status::Failure));
        assert_eq!(probe.counts(), (1, 2, 1));
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn a_timeout_halts_it_when_time_is_up() {
        let probe = Arc::default();
        let (mut tree, clock) =
            build(|b| b.timeout("limit", ms(100), |t| scripted(t, "work", &probe, &[Wait])));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        clock.advance(ms(60));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        clock.advance(ms(60));
        assert_eq!(tick(&mut tree), Ok(Status::Failure));
        assert_eq!(probe.counts(), (1, 2, 1));
    }

    #[test]
    fn a_wake_reticks_within_tick_once_but_not_tick_exactly_once() {
        let probe = Arc::default();
        let (mut tree, _) = build(|b| scripted(b, "yielding", &probe, &[Yield, Yield, Done(S)]));
        let passes = Passes::default();
        tree.set_observer(passes.clone());
        assert_eq!(tick(&mut tree), Ok(Status::Success));
        assert_eq!(passes.0.load(SeqCst), 3);
        assert_eq!(probe.counts(), (1, 3, 1));

        let signal = tree.wake_signal().clone();
        assert_eq!(tree.tick_exactly_once(&mut ()), Ok(Status::Running));
        assert_eq!(passes.0.load(SeqCst), 4);
        assert_eq!(probe.counts(), (2, 4, 1));
        // The wake stays set, for a runner to tick early.
        assert!(signal.is_woken());
        // The next pass clears it and, the future yielding again, sets it anew.
        assert_eq!(tree.tick_exactly_once(&mut ()), Ok(Status::Running));
        assert!(signal.is_woken());
        assert_eq!(tree.tick_exactly_once(&mut ()), Ok(Status::Success));
        assert!(!signal.is_woken());
        assert_eq!(probe.counts(), (2, 6, 2));
    }

    #[test]
    fn a_wake_between_ticks_is_seen_by_the_runner_and_cleared_by_the_next_pass() {
        let probe: Arc<Probe> = Arc::default();
        let (mut tree, _) = build(|b| scripted(b, "waiting", &probe, &[Wait, Wait, Done(S)]));
        let signal = tree.wake_signal().clone();
        let passes = Passes::default();
        tree.set_observer(passes.clone());
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        assert!(!signal.is_woken());

        // Something outside (a timer, another thread) wakes the run.
        let waker = probe.waker.lock().unwrap().clone().unwrap();
        waker.wake();
        assert!(signal.is_woken());
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        // One pass: the wake came before the tick, not during it.
        assert_eq!(passes.0.load(SeqCst), 2);
        assert!(!signal.is_woken());
        assert_eq!(tick(&mut tree), Ok(Status::Success));
        assert_eq!(probe.counts(), (1, 3, 1));
    }

    #[test]
    fn completing_with_running_is_an_error_and_halts_the_tree() {
        let other = Arc::default();
        let (mut tree, _) = build(|b| {
            b.parallel("p", -1, 1, |p| {
                scripted(p, "waits", &other, &[Wait]).async_action("bad", |_| async { R })
            })
        });
        let err = tick(&mut tree).unwrap_err();
        assert_eq!(
            err,
            TickError::LeafRunning {
                node: NodeId(2),
                path: "p/bad".into(),
                kind: "AsyncAction"
            }
        );
        // The other run was halted with the tree.
        assert_eq!(other.counts(), (1, 1, 1));
    }

    #[test]
    fn start_reads_ports_and_context_synchronously() {
        let bp = Builder::<Vec<u32>>::new()
            .async_action("log", |h| {
                let n: u32 = h.input("n").unwrap();
                h.ctx_mut().push(n);
                async move {
                    if n > 2 {
                        Status::Success
                    } else {
                        Status::Failure
                    }
                }
            })
            .ports([Port::literal("n", "3")])
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut log = Vec::new();
        assert_eq!(tree.tick_once(&mut log), Ok(Status::Success));
        assert_eq!(log, [3]);
    }

    #[test]
    fn dropping_the_tree_drops_a_running_future_once() {
        let probe = Arc::default();
        let (mut tree, _) = build(|b| scripted(b, "work", &probe, &[Wait]));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        drop(tree);
        assert_eq!(probe.counts(), (1, 1, 1));
    }

    #[test]
    fn instances_run_their_own_futures() {
        let probe = Arc::default();
        let (mut a, _) = build(|b| scripted(b, "work", &probe, &[Wait, Done(S)]));
        let mut b = Tree::with_clock(Arc::clone(a.blueprint()), ManualClock::new());
        assert_eq!(tick(&mut a), Ok(Status::Running));
        assert_eq!(tick(&mut b), Ok(Status::Running));
        b.halt(&mut ());
        assert_eq!(probe.counts(), (2, 2, 1));
        assert_eq!(tick(&mut a), Ok(Status::Success));
        assert_eq!(probe.counts(), (2, 3, 2));
    }
}
