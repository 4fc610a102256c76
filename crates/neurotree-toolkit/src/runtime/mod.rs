//! Running a tree in time: the loops that decide when to tick.
//!
//! A [`Tree`](crate::Tree) ticks when told to; a robot or a game needs a loop that tells it.
//!
//! | loop | ticks | for |
//! |---|---|---|
//! | [`FixedRate`] | every period, on a thread | real-time control loops |
//! | `tokio::tick_until_done` (feature `tokio`) | each period or on a wake | actions on tokio |
//!
//! - [`FixedRate`] ticks at the start of every period, on a thread, and reports overruns; it is
//!   for real-time control loops that tick, then sleep until the next interval.
//! - `tokio::tick_until_done` ticks every period, or at once when an async action's future
//!   wakes; it is for trees whose actions await timers, tasks and I/O on tokio.
//!
//! Both stop when the root completes. Stopping them early halts the tree, so every running
//! action ends with its halt; a halt that takes ticks
//! ([`slow_halt`](neurotree_core::tree::slow_halt)) is ticked to its end, a period apart,
//! before they return. The one exception is a tokio run that is dropped: a drop cannot
//! wait, so the halt goes on in the tree's next tick calls, or in `tokio::halt`.
//!
//! A server that runs requests on threads of its own halts the trees a request runs, at a
//! time limit or when it is cancelled, through a [`HaltScope`].

mod fixed_rate;
mod halt_scope;
#[cfg(feature = "tokio")]
pub mod tokio;

pub use fixed_rate::{
    Finish, FixedRate, ManualPacer, Pacer, RunReport, StopFlag, SystemPacer, TickStats,
};
pub use halt_scope::{attach, Entered, HaltScope};
