//! Running trees on tokio (feature `tokio`).
//!
//! - [`TokioClock`]: the tree's clock on tokio's time, so that under
//!   `tokio::time::pause()` (or `#[tokio::test(start_paused = true)]`) timeouts, delays and
//!   actions' timers all move together, deterministically.
//! - [`tick_until_done`]: ticks every period, and at once when an async action's future
//!   wakes (its timer fired, its task finished), until the root completes.
//! - [`halt`]: halts a tree and ticks a halt that takes ticks to its end, on tokio's time.
//! - [`spawn_abort_on_drop`]: runs work as a tokio task owned by an async action's future,
//!   so that halting the node aborts the task.
//!
//! ```
//! use std::time::Duration;
//! use neurotree::runtime::tokio::{spawn_abort_on_drop, tick_until_done, TokioClock};
//! use neurotree::{Blueprint, Status, Tree};
//!
//! struct Drone { battery_pct: f32 }
//!
//! # #[tokio::main(flavor = "current_thread", start_paused = true)]
//! # async fn main() {
//! let blueprint = Blueprint::<Drone>::builder()
//!     .sequence("photo", |s| {
//!         s.condition("battery_ok", |d: &Drone| d.battery_pct > 20.0)
//!             .async_action("capture", |_h| async {
//!                 // The exposure runs as a task; halting `capture` aborts it.
//!                 let exposure = spawn_abort_on_drop(async {
//!                     tokio::time::sleep(Duration::from_millis(300)).await;
//!                     42_u32
//!                 });
//!                 match exposure.await {
//!                     Ok(_pixels) => Status::Success,
//!                     Err(_) => Status::Failure,
//!                 }
//!             })
//!     })
//!     .build_shared()
//!     .unwrap();
//! let mut tree = Tree::with_clock(blueprint, TokioClock::new());
//! let mut drone = Drone { battery_pct: 80.0 };
//! let run = tick_until_done(&mut tree, &mut drone, Duration::from_secs(1)).await.unwrap();
//! assert_eq!(run.status, Status::Success);
//! // A tick at 0, and one at 300 ms, early, because the task finished and woke the tree.
//! assert_eq!((run.ticks, run.early_ticks), (2, 1));
//! assert_eq!(tree.now(), Duration::from_millis(300));
//! # }
//! ```

use std::future::Future;
use std::time::Duration;

use ::tokio::time::Instant;
use neurotree_core::{Clock, Status, TickError, Tree, WakeSignal};

pub use tokio_util::task::AbortOnDropHandle;

/// Time as tokio sees it, from the clock's creation: paused and advanced with tokio's.
///
/// Make it inside the runtime whose time it should follow.
#[derive(Clone, Copy, Debug)]
pub struct TokioClock {
    origin: Instant,
}

impl TokioClock {
    /// A clock whose origin is tokio's now.
    pub fn new() -> Self {
        Self {
            origin: Instant::now(),
        }
    }
}

impl Default for TokioClock {
    fn default() -> Self {
        Self::new()
    }
}

impl Clock for TokioClock {
    fn now(&self) -> Duration {
        self.origin.elapsed()
    }

    /// Sleeps the thread for `period`, which is right while tokio's time follows real time.
    ///
    /// Blocking code cannot move paused time (`tokio::time::advance` is async), so under
    /// `tokio::time::pause()` this clock reads the same after the wait. Tick a tree on
    /// tokio's time with [`tick_until_done`], which awaits the period instead;
    /// [`Tree::tick_while_running`] would also block the runtime's thread.
    fn wait(&self, period: Duration) {
        std::thread::sleep(period);
    }
}

/// How a [`tick_until_done`] run went.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunSummary {
    /// What the root completed with.
    pub status: Status,
    /// Calls of [`Tree::tick_once`].
    pub ticks: u64,
    /// Of those, the ticks made before their period was over because a future woke.
    pub early_ticks: u64,
}

/// Ticks `tree` with [`Tree::tick_once`] until its root completes: every `period`, or
/// sooner when the future of one of its async actions wakes (see
/// [`WakeSignal`]). The next period is counted from each tick.
///
/// A tick error ends the run with that error (the tree has halted itself). A request from
/// the tree's [`HaltHandle`](neurotree_core::HaltHandle) wakes the run at once (it sets the
/// wake signal), and the tick it makes serves the request: the run returns
/// `Err(TickError::HaltRequested)` without waiting for its period.
///
/// A halt that takes ticks ([`slow_halt`](neurotree_core::tree::slow_halt)) is ticked to
/// its end before the run returns its error, with [`Tree::tick_halt`] every `period` or at
/// once on a wake, as [`halt`] does; the run then returns with [`Tree::is_halting`] false.
///
/// Dropping the returned future before it completes (a `select!`, a timeout) halts the
/// tree, so its running actions are halted and their futures dropped. A drop cannot wait:
/// a halt that takes ticks is left in progress there, and the tree's next tick calls
/// continue it before they tick the root (await [`halt`] to finish it at once). To stop a
/// run and have its halt finished by the run itself, request the halt through the tree's
/// `HaltHandle` instead of dropping the run.
pub async fn tick_until_done<C>(
    tree: &mut Tree<C>,
    ctx: &mut C,
    period: Duration,
) -> Result<RunSummary, TickError> {
    let signal = tree.wake_signal().clone();
    let mut run = HaltOnDrop {
        tree,
        ctx,
        done: false,
    };
    let mut summary = RunSummary {
        status: Status::Running,
        ticks: 0,
        early_ticks: 0,
    };
    let mut early = false;
    loop {
        let ticked = run.tree.tick_once(run.ctx);
        summary.ticks += 1;
        summary.early_ticks += u64::from(early);
        let status = match ticked {
            Ok(status) => status,
            Err(e) => {
                // The tree halted itself; its halt may take ticks.
                finish_halt(run.tree, run.ctx, &signal, period).await;
                run.done = true;
                return Err(e);
            }
        };
        if status != Status::Running {
            run.done = true;
            summary.status = status;
            return Ok(summary);
        }
        let deadline = Instant::now() + period;
        early = ::tokio::time::timeout_at(deadline, signal.woken())
            .await
            .is_ok();
    }
}

/// Halts `tree` as [`Tree::halt`] does, then ticks a halt that takes ticks to its end with
/// [`Tree::tick_halt`]: every `period`, or at once when the future of an async action's
/// halt wakes. Returns the number of `tick_halt` calls it made (0 when the tree halted at
/// once).
///
/// For a tree whose run was dropped while an action was halting, or any tree to stop on
/// tokio's time. Dropping this future leaves the rest of the halt to the tree's next tick
/// calls, as a dropped run does.
pub async fn halt<C>(tree: &mut Tree<C>, ctx: &mut C, period: Duration) -> u64 {
    let signal = tree.wake_signal().clone();
    tree.halt(ctx);
    finish_halt(tree, ctx, &signal, period).await
}

/// Ticks a halt in progress to its end, a period apart or on a wake; returns the number of
/// `tick_halt` calls.
async fn finish_halt<C>(
    tree: &mut Tree<C>,
    ctx: &mut C,
    signal: &WakeSignal,
    period: Duration,
) -> u64 {
    let mut calls = 0;
    while tree.is_halting() {
        let deadline = Instant::now() + period;
        // A wake before the deadline only makes the next call early.
        let _ = ::tokio::time::timeout_at(deadline, signal.woken()).await;
        tree.tick_halt(ctx);
        calls += 1;
    }
    calls
}

/// Halts the tree when a run is dropped before it finished.
struct HaltOnDrop<'a, C> {
    tree: &'a mut Tree<C>,
    ctx: &'a mut C,
    done: bool,
}

impl<C> Drop for HaltOnDrop<'_, C> {
    fn drop(&mut self) {
        if !self.done {
            self.tree.halt(self.ctx);
        }
    }
}

/// Spawns `future` as a task on the current tokio runtime and returns its handle, which
/// aborts the task when dropped.
///
/// An async action that awaits the handle owns the task: halting the node drops the
/// action's future, which drops the handle, which aborts the task. Awaiting the handle
/// gives the task's output, or a `JoinError` if it panicked or was aborted.
///
/// # Panics
/// Outside a tokio runtime, as `tokio::spawn` does.
pub fn spawn_abort_on_drop<F>(future: F) -> AbortOnDropHandle<F::Output>
where
    F: Future + Send + 'static,
    F::Output: Send + 'static,
{
    AbortOnDropHandle::new(::tokio::spawn(future))
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_core::{Blueprint, HaltProgress, Handle, NodeStatus, StatefulAction};

    /// What an [`Arm`] did, and when on the tree's clock.
    type Log = Vec<(&'static str, Duration)>;

    /// Runs until halted; its halt takes 3 ticks: the request and two `on_halting`.
    struct Arm {
        left: u32,
    }

    impl StatefulAction<Log> for Arm {
        fn on_start(&mut self, h: &mut Handle<'_, Log>) -> Status {
            let now = h.now();
            h.ctx_mut().push(("start", now));
            Status::Running
        }
        fn on_running(&mut self, h: &mut Handle<'_, Log>) -> Status {
            let now = h.now();
            h.ctx_mut().push(("running", now));
            Status::Running
        }
        fn on_halt_requested(&mut self, h: &mut Handle<'_, Log>) -> HaltProgress {
            let now = h.now();
            h.ctx_mut().push(("halt requested", now));
            self.left = 2;
            HaltProgress::Halting
        }
        fn on_halting(&mut self, h: &mut Handle<'_, Log>) -> HaltProgress {
            let now = h.now();
            self.left -= 1;
            if self.left == 0 {
                h.ctx_mut().push(("halted", now));
                HaltProgress::Done
            } else {
                h.ctx_mut().push(("halting", now));
                HaltProgress::Halting
            }
        }
    }

    fn arm_tree() -> Tree<Log> {
        let blueprint = Blueprint::<Log>::builder()
            .stateful("arm", || Arm { left: 0 })
            .build_shared()
            .unwrap();
        Tree::with_clock(blueprint, TokioClock::new())
    }

    fn ms(n: u64) -> Duration {
        Duration::from_millis(n)
    }

    #[tokio::test(start_paused = true)]
    async fn a_halt_request_is_ticked_to_its_end_before_the_run_returns() {
        let mut tree = arm_tree();
        let handle = tree.halt_handle();
        let requester = ::tokio::spawn(async move {
            ::tokio::time::sleep(ms(250)).await;
            handle.request();
        });
        let mut log = Log::new();
        let result = tick_until_done(&mut tree, &mut log, ms(100)).await;
        assert_eq!(result, Err(TickError::HaltRequested));
        // Ticks at 0, 100 and 200 ms; the request is served at 250 ms, and the halt is
        // continued a period apart until it is done.
        assert_eq!(
            log,
            [
                ("start", ms(0)),
                ("running", ms(100)),
                ("running", ms(200)),
                ("halt requested", ms(250)),
                ("halting", ms(350)),
                ("halted", ms(450)),
            ]
        );
        assert_eq!(tree.now(), ms(450));
        assert!(!tree.is_halting());
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
        assert!(tree.halt(&mut log), "nothing is left to halt");
        assert_eq!(log.len(), 6);
        requester.await.unwrap();
    }

    #[tokio::test(start_paused = true)]
    async fn a_dropped_run_leaves_the_halt_in_progress_and_halt_finishes_it() {
        let mut tree = arm_tree();
        let mut log = Log::new();
        let run = tick_until_done(&mut tree, &mut log, ms(100));
        assert!(::tokio::time::timeout(ms(150), run).await.is_err());
        // Dropped at 150 ms: the tree was halted, and the arm's halt is in progress.
        assert!(tree.is_halting());
        assert_eq!(log.last(), Some(&("halt requested", ms(150))));
        assert_eq!(halt(&mut tree, &mut log, ms(100)).await, 2);
        assert_eq!(
            log,
            [
                ("start", ms(0)),
                ("running", ms(100)),
                ("halt requested", ms(150)),
                ("halting", ms(250)),
                ("halted", ms(350)),
            ]
        );
        assert!(!tree.is_halting());
        // Halting a halted tree is done at once, and calls nothing.
        assert_eq!(halt(&mut tree, &mut log, ms(100)).await, 0);
        assert!(tree.halt(&mut log));
        assert_eq!(log.len(), 5);
        assert_eq!(tree.now(), ms(350));
    }

    #[tokio::test(start_paused = true)]
    async fn a_run_after_a_dropped_one_finishes_the_halt_before_the_root_runs_again() {
        let mut tree = arm_tree();
        let mut log = Log::new();
        let run = tick_until_done(&mut tree, &mut log, ms(100));
        assert!(::tokio::time::timeout(ms(50), run).await.is_err());
        let handle = tree.halt_handle();
        // Requested at 300 ms.
        let requester = ::tokio::spawn(async move {
            ::tokio::time::sleep(ms(250)).await;
            handle.request();
        });
        // The next run's first two ticks (50 and 150 ms) continue the halt; the third
        // (250 ms) starts the arm again.
        let result = tick_until_done(&mut tree, &mut log, ms(100)).await;
        assert_eq!(result, Err(TickError::HaltRequested));
        assert_eq!(
            log,
            [
                ("start", ms(0)),
                ("halt requested", ms(50)),
                ("halting", ms(50)),
                ("halted", ms(150)),
                ("start", ms(150)),
                ("running", ms(250)),
                ("halt requested", ms(300)),
                ("halting", ms(400)),
                ("halted", ms(500)),
            ]
        );
        requester.await.unwrap();
    }

    #[tokio::test(start_paused = true)]
    async fn a_halt_request_wakes_the_run_before_its_period_is_over() {
        let blueprint = Blueprint::<u32>::builder()
            .async_action("forever", |_| core::future::pending::<Status>())
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(blueprint, TokioClock::new());
        let handle = tree.halt_handle();
        let requester = ::tokio::spawn(async move {
            ::tokio::time::sleep(Duration::from_secs(1)).await;
            handle.request();
        });
        let result = tick_until_done(&mut tree, &mut 0, Duration::from_secs(10)).await;
        assert_eq!(result, Err(TickError::HaltRequested));
        // Woken at 1 s by the request, not at the 10 s period.
        assert_eq!(tree.now(), Duration::from_secs(1));
        requester.await.unwrap();
    }
}
