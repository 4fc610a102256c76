//! Async actions: a Rust future per run of the node.
//!
//! On the tick that finds an async action Idle, its start function reads what it needs from the
//! [`Handle`] (ports, blackboard, context) and returns a future, which is polled at once and
//! then once per tick while the node is Running:
//!
//! - Pending → Running.
//! - Ready(status) → that status, and the future is dropped.
//! - Halted while Running: the future is dropped, exactly once, and never polled again;
//!   or, for a halt that takes ticks, handed to
//!   [`on_halt_requested`](AsyncAction::on_halt_requested), whose halt future is polled
//!   until it is ready (see [`slow_halt`](crate::tree::slow_halt)).
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

/// The future of an async action's halt that takes ticks (see
/// [`AsyncAction::on_halt_requested`]): the halt is done when it is ready.
pub type HaltFuture = Pin<Box<dyn Future<Output = ()> + Send + 'static>>;

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

    /// Called when the engine halts the node while its run is pending, with the run's
    /// future. The default drops it and answers `None`: the halt is over at once.
    ///
    /// An action whose halt takes time (a server that must acknowledge a cancel, a run
    /// that must reach a safe point) returns the future of its halt, which may own the
    /// run's future and go on polling it: it is polled at once, and while it is Pending
    /// the node is stored Idle, its parent does not start a conflicting branch, and it is
    /// polled once per tick of whoever waits for the halt, as a
    /// [`StatefulAction`](super::StatefulAction)'s `on_halting` is called, until it is
    /// ready (see [`slow_halt`](crate::tree::slow_halt)). Its wakes wake the tree as the
    /// run's do. Boxing it is the one allocation, and only actions that halt so pay it.
    ///
    /// ```
    /// use std::sync::atomic::{AtomicBool, Ordering};
    /// use std::sync::Arc;
    /// use neurotree_core::{ActionFuture, AsyncAction, Blueprint, HaltFuture, Handle, ManualClock, Status, Tree};
    ///
    /// /// Runs until told to stop, then needs one more poll to stop.
    /// struct Drive { stop: Arc<AtomicBool> }
    /// impl AsyncAction<()> for Drive {
    ///     fn start(&self, _h: &mut Handle<'_, ()>) -> ActionFuture {
    ///         let stop = Arc::clone(&self.stop);
    ///         let mut stopping = false;
    ///         Box::pin(core::future::poll_fn(move |_| {
    ///             if stopping { return core::task::Poll::Ready(Status::Failure); }
    ///             stopping = stop.load(Ordering::Relaxed);
    ///             core::task::Poll::Pending
    ///         }))
    ///     }
    ///     fn on_halt_requested(&self, mut run: ActionFuture, _h: &mut Handle<'_, ()>) -> Option<HaltFuture> {
    ///         self.stop.store(true, Ordering::Relaxed);
    ///         // The halt is done when the run has stopped.
    ///         Some(Box::pin(async move { let _ = run.as_mut().await; }))
    ///     }
    /// }
    /// let stop = Arc::new(AtomicBool::new(false));
    /// let bp = Blueprint::<()>::builder()
    ///     .async_action_node("drive", Drive { stop: Arc::clone(&stop) })
    ///     .build_shared()
    ///     .unwrap();
    /// let mut tree = Tree::with_clock(bp, ManualClock::new());
    /// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    /// assert!(!tree.halt(&mut ()), "the run sees the stop on the halt's first poll");
    /// assert!(tree.tick_halt(&mut ()), "and stops on the next");
    /// ```
    fn on_halt_requested(&self, run: ActionFuture, _h: &mut Handle<'_, C>) -> Option<HaltFuture> {
        drop(run);
        None
    }
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

/// Halts an async action that is Running: hands its future to `on_halt_requested`, and
/// keeps the future of a halt that is not ready at its first poll (see
/// [`slow_halt`](crate::tree::slow_halt)).
pub(crate) fn halt<C>(t: &mut Ticker<'_, C>, id: NodeId, action: &dyn AsyncAction<C>) {
    if t.status(id) != NodeStatus::Running {
        return;
    }
    let halter = t.halter.halter();
    let waker = t.waker;
    let (Some(object), mut h) = t.split(id) else {
        return;
    };
    let Object::Async(run) = object else {
        return;
    };
    let Some(run) = run.take() else {
        return;
    };
    let (Some(mut halt), Some(waker)) = (action.on_halt_requested(run, &mut h), waker) else {
        return;
    };
    if halt
        .as_mut()
        .poll(&mut Context::from_waker(waker))
        .is_ready()
    {
        return;
    }
    *object = Object::AsyncHalting {
        halt,
        owner: crate::tree::slow_halt::Owner::of(halter),
    };
    t.started_halting();
}

/// Polls the future of an async action's halt in progress once: `true` when it is done.
pub(crate) fn continue_halt<C>(t: &mut Ticker<'_, C>, id: NodeId) -> bool {
    let waker = t.waker;
    match (t.split(id), waker) {
        ((Some(Object::AsyncHalting { halt, .. }), _), Some(waker)) => halt
            .as_mut()
            .poll(&mut Context::from_waker(waker))
            .is_ready(),
        _ => true,
    }
}

#[cfg(test)]
mod tests {
    use super::{ActionFuture, AsyncAction, Handle};
    use crate::observer::Observer;
    use crate::testing::*;
    use crate::{NodeStatus, Port, TickError};
    use alloc::boxed::Box;
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

    /// Polls of halt futures, and the halts requested.
    #[derive(Default)]
    struct Halts {
        requested: AtomicU32,
        polls: AtomicU32,
    }

    /// An action whose runs wait forever and whose halt is ready on its `halt_polls`-th
    /// poll (0: the default halt, at once). The halt owns the run until it is done.
    struct Braking {
        probe: Arc<Probe>,
        halts: Arc<Halts>,
        halt_polls: u32,
    }

    impl<C> AsyncAction<C> for Braking {
        fn start(&self, _h: &mut Handle<'_, C>) -> ActionFuture {
            self.probe.starts.fetch_add(1, SeqCst);
            Box::pin(Run {
                probe: Arc::clone(&self.probe),
                steps: vec![Wait],
                at: 0,
            })
        }
        fn on_halt_requested(
            &self,
            run: ActionFuture,
            _h: &mut Handle<'_, C>,
        ) -> Option<super::HaltFuture> {
            self.halts.requested.fetch_add(1, SeqCst);
            if self.halt_polls == 0 {
                return None;
            }
            let halts = Arc::clone(&self.halts);
            let last = self.halt_polls;
            let mut polls = 0;
            Some(Box::pin(core::future::poll_fn(move |_| {
                let _owned = &run;
                halts.polls.fetch_add(1, SeqCst);
                polls += 1;
                if polls == last {
                    Poll::Ready(())
                } else {
                    Poll::Pending
                }
            })))
        }
    }

    fn braking<C: 'static>(
        b: Builder<C>,
        probe: &Arc<Probe>,
        halts: &Arc<Halts>,
        halt_polls: u32,
    ) -> Builder<C> {
        b.async_action_node(
            "braking",
            Braking {
                probe: Arc::clone(probe),
                halts: Arc::clone(halts),
                halt_polls,
            },
        )
    }

    #[test]
    fn a_halt_future_keeps_a_reactive_parent_waiting_until_it_is_ready() {
        let probe: Arc<Probe> = Arc::default();
        let halts: Arc<Halts> = Arc::default();
        let alts = Arc::new(AtomicU32::new(0));
        let seen = Arc::clone(&alts);
        let bp = Builder::<bool>::new()
            .fallback("root", |f| {
                f.reactive_sequence("guarded", |s| {
                    braking(s.condition("go", |g: &bool| *g), &probe, &halts, 3)
                })
                .action("alt", move |_| {
                    seen.fetch_add(1, SeqCst);
                    Status::Success
                })
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut go = true;
        let counts = || {
            (
                halts.requested.load(SeqCst),
                halts.polls.load(SeqCst),
                probe.drops.load(SeqCst),
                alts.load(SeqCst),
            )
        };
        assert_eq!(tree.tick_once(&mut go), Ok(Status::Running));
        go = false;
        // Requested and polled once: Pending, so the sequence waits, Running.
        assert_eq!(tree.tick_once(&mut go), Ok(Status::Running));
        assert_eq!(counts(), (1, 1, 0, 0));
        assert!(tree.is_halting());
        assert_eq!(tree.status(NodeId(3)), NodeStatus::Idle);
        assert_eq!(tree.tick_once(&mut go), Ok(Status::Running));
        assert_eq!(counts(), (1, 2, 0, 0));
        // Ready on the third poll: the run is dropped with it, and in the same tick the
        // sequence fails and the alternative runs.
        assert_eq!(tree.tick_once(&mut go), Ok(Status::Success));
        assert_eq!(counts(), (1, 3, 1, 1));
        assert!(!tree.is_halting());
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
        // The run was polled once, on the first tick, and never after the halt.
        assert_eq!(probe.counts(), (1, 1, 1));
    }

    #[test]
    fn tree_halt_waits_for_a_halt_future_and_tick_halt_polls_it_to_its_end() {
        let probe: Arc<Probe> = Arc::default();
        let halts: Arc<Halts> = Arc::default();
        let (mut tree, _) = build(|b| braking(b, &probe, &halts, 3));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        assert!(!tree.halt(&mut ()));
        assert!(!tree.tick_halt(&mut ()));
        assert_eq!(halts.polls.load(SeqCst), 2);
        assert!(tree.tick_halt(&mut ()));
        assert_eq!(halts.polls.load(SeqCst), 3);
        assert!(tree.tick_halt(&mut ()), "done stays done");
        assert_eq!(halts.polls.load(SeqCst), 3);
        assert_eq!(probe.counts(), (1, 1, 1));
        // The next tick starts a new run.
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        assert_eq!(probe.counts(), (2, 2, 1));
        assert_eq!(halts.requested.load(SeqCst), 1);
    }

    #[test]
    fn a_halt_ready_at_its_first_poll_and_the_default_halt_are_done_at_once() {
        for halt_polls in [0, 1] {
            let probe: Arc<Probe> = Arc::default();
            let halts: Arc<Halts> = Arc::default();
            let (mut tree, _) = build(|b| braking(b, &probe, &halts, halt_polls));
            assert_eq!(tick(&mut tree), Ok(Status::Running));
            assert!(tree.halt(&mut ()));
            assert!(!tree.is_halting());
            assert_eq!(halts.polls.load(SeqCst), halt_polls);
            assert_eq!(probe.counts(), (1, 1, 1));
        }
    }

    #[test]
    fn dropping_the_tree_drops_a_halt_in_progress_once() {
        let probe: Arc<Probe> = Arc::default();
        let halts: Arc<Halts> = Arc::default();
        let (mut tree, _) = build(|b| braking(b, &probe, &halts, 3));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        assert!(!tree.halt(&mut ()));
        assert_eq!(probe.counts(), (1, 1, 0));
        drop(tree);
        assert_eq!(probe.counts(), (1, 1, 1));
        assert_eq!(halts.polls.load(SeqCst), 1);
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
