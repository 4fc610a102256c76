//! Running trees on tokio (feature `tokio`).
//!
//! - [`TokioClock`]: the tree's clock on tokio's time, so that under
//!   `tokio::time::pause()` (or `#[tokio::test(start_paused = true)]`) timeouts, delays and
//!   actions' timers all move together, deterministically.
//! - [`tick_until_done`]: ticks every period, and at once when an async action's future
//!   wakes (its timer fired, its task finished), until the root completes.
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
use neurotree_core::{Clock, Status, TickError, Tree};

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
/// [`WakeSignal`](crate::WakeSignal)). The next period is counted from each tick.
///
/// A tick error ends the run with that error (the tree has halted itself). A request from
/// the tree's [`HaltHandle`](neurotree_core::HaltHandle) wakes the run at once (it sets the
/// wake signal), and the tick it makes serves the request: the run returns
/// `Err(TickError::HaltRequested)` without waiting for its period. Dropping the
/// returned future before it completes (a `select!`, a timeout) halts the tree, so its
/// running actions are halted and their futures dropped.
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
    use neurotree_core::Blueprint;

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
