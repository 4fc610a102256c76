//! Halting a tree from another thread: the [`HaltHandle`].
//!
//! The thread that ticks a tree owns it (`&mut`), so another thread cannot halt it directly.
//! It asks instead: [`HaltHandle::request`] raises a flag the tree reads at its next **tick
//! boundary**, never in the middle of a node:
//!
//! - at the start of every [`Tree::tick_once`](crate::Tree::tick_once) and
//!   [`Tree::tick_exactly_once`](crate::Tree::tick_exactly_once) call;
//! - between two passes of one `tick_once` (a pass that was in progress when the request
//!   came completes normally first).
//!
//! At a boundary with a request pending, the tree does what [`Tree::halt`](crate::Tree::halt)
//! does (every Running node halted, children first, each Running stateful action getting
//! exactly one `on_halted`, every async action's future dropped), clears the request, and
//! the call returns [`TickError::HaltRequested`](crate::TickError::HaltRequested) without
//! ticking anything more. The next call starts afresh. A request made while nothing runs is
//! served the same way: the halt changes nothing, and the call still returns the error, so
//! a loop that ticks ends either way. A halt that takes ticks
//! ([`slow_halt`](super::slow_halt)) goes on in the next calls, which return Running
//! without ticking the root until it is done, or with [`Tree::tick_halt`](crate::Tree::tick_halt).
//!
//! A request made during a pass of `tick_once` that leaves the root Running is served right
//! after that pass: the request wakes the tree, which asks for another pass, and the
//! boundary before it serves the request. One made during a pass that completes the root,
//! or during `tick_exactly_once`'s only pass, waits for the next call, which serves it
//! before ticking. Requests do not queue: any number made before a boundary are served by
//! one halt.
//!
//! Loops that wait between ticks end their wait early:
//! [`Tree::tick_while_running`](crate::Tree::tick_while_running) and the toolkit's runners.
//! A request also sets the tree's [`WakeSignal`], so a runner awaiting
//! it ticks at once.
//!
//! The handle costs nothing until it is made: the flag lives in the tree's wake signal,
//! which trees without async actions make only on demand, and a tree without one checks
//! for a request with a single branch per call.

use core::fmt;

use super::WakeSignal;

/// Asks a [`Tree`](crate::Tree) to halt at its next tick boundary, from any thread; clones
/// ask the same tree. Made by [`Tree::halt_handle`](crate::Tree::halt_handle).
///
/// ```
/// use std::sync::Arc;
/// use neurotree_core::{Blueprint, ManualClock, Status, TickError, Tree};
///
/// let blueprint = Blueprint::<()>::builder()
///     .sleep("nap", core::time::Duration::from_secs(60))
///     .build_shared()
///     .unwrap();
/// let mut tree = Tree::with_clock(blueprint, ManualClock::new());
/// let handle = tree.halt_handle();
/// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
///
/// std::thread::spawn(move || handle.request()).join().unwrap();
/// assert_eq!(tree.tick_once(&mut ()), Err(TickError::HaltRequested));
/// // Served: the tree was halted and the next tick starts afresh.
/// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
/// ```
#[derive(Clone)]
pub struct HaltHandle {
    signal: WakeSignal,
}

impl HaltHandle {
    pub(crate) fn new(signal: WakeSignal) -> Self {
        Self { signal }
    }

    /// Asks the tree to halt at its next tick boundary, and wakes a runner waiting on the
    /// tree's wake signal. Returns at once; the tick thread serves the request.
    pub fn request(&self) {
        self.signal.request_halt();
    }

    /// `true` while a request waits to be served.
    pub fn is_pending(&self) -> bool {
        self.signal.halt_requested()
    }
}

impl fmt::Debug for HaltHandle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("HaltHandle")
            .field("pending", &self.is_pending())
            .finish()
    }
}
