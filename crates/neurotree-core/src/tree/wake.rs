//! The tree's wake signal: how the future of an async leaf tells whoever ticks the tree that
//! it can make progress.
//!
//! Every future an [async action](crate::nodes::leaf::async_action) runs is polled with the
//! tree's one [`Waker`], which sets the tree's [`WakeSignal`]. What a wake does depends on
//! when it comes:
//!
//! - during a pass of [`Tree::tick_once`](crate::Tree::tick_once) (a future that yields, or
//!   one woken from another thread while the tree is being ticked): the tree is ticked again
//!   at once, as for a node's wake-up request;
//! - between ticks (a timer fired, a task finished): the signal stays set until the next
//!   pass starts, so a runner that waits for its next period can tick early instead. It
//!   awaits [`WakeSignal::woken`], polls [`WakeSignal::is_woken`], or registers its own
//!   waker with [`WakeSignal::register`].
//!
//! [`Tree::tick_exactly_once`](crate::Tree::tick_exactly_once) never ticks twice, so a wake
//! during its pass is left set for the runner to see.
//!
//! The signal also carries the tree's halt request, raised by a
//! [`HaltHandle`](crate::HaltHandle): a request wakes the signal too, so that a runner
//! waiting on it ticks at once, and the tick serves the request (see [`super::halt`]).

use alloc::sync::Arc;
use alloc::task::Wake;
use core::fmt;
use core::future::Future;
use core::pin::Pin;
use core::sync::atomic::{AtomicBool, Ordering};
use core::task::{Context, Poll, Waker};

use atomic_waker::AtomicWaker;

/// Set when a future of the tree's async leaves wakes; clones share one signal.
///
/// ```
/// use neurotree_core::WakeSignal;
///
/// let signal = WakeSignal::new();
/// let seen_by_runner = signal.clone();
/// signal.waker().wake_by_ref();
/// assert!(seen_by_runner.is_woken());
/// assert!(seen_by_runner.take());
/// assert!(!signal.is_woken());
/// ```
#[derive(Clone, Default)]
pub struct WakeSignal {
    inner: Arc<Inner>,
}

#[derive(Default)]
struct Inner {
    woken: AtomicBool,
    /// A [`HaltHandle`](crate::HaltHandle) asked for a halt that no tick has served yet.
    halt: AtomicBool,
    /// The runner waiting for the signal, if one registered.
    runner: AtomicWaker,
}

impl Wake for Inner {
    fn wake(self: Arc<Self>) {
        self.wake_by_ref();
    }

    fn wake_by_ref(self: &Arc<Self>) {
        // Release pairs with the Acquire of `is_woken`/`take`: whoever sees the flag also
        // sees what the waking side wrote before waking.
        self.woken.store(true, Ordering::Release);
        self.runner.wake();
    }
}

impl WakeSignal {
    /// A signal that is not set.
    pub fn new() -> Self {
        Self::default()
    }

    /// `true` if a future woke since the tree's last pass started (or since [`take`](Self::take)).
    pub fn is_woken(&self) -> bool {
        self.inner.woken.load(Ordering::Acquire)
    }

    /// Clears the signal and says whether it was set. Each pass of the tree clears it as it
    /// starts, since the pass polls every future that is still running.
    pub fn take(&self) -> bool {
        self.inner.woken.swap(false, Ordering::AcqRel)
    }

    /// Sets the signal, as a waking future does: for code outside the tree that changed
    /// something the tree should see before its next period.
    pub fn wake(&self) {
        self.inner.wake_by_ref();
    }

    /// Registers `waker` to be woken the next time the signal is set. One runner waits at a
    /// time: registering replaces the waker registered before.
    pub fn register(&self, waker: &Waker) {
        self.inner.runner.register(waker);
    }

    /// A future that completes once the signal is set (at once if it is already). It does
    /// not clear the signal: the tree's next pass does.
    pub fn woken(&self) -> Woken {
        Woken {
            signal: self.clone(),
        }
    }

    /// A waker that sets this signal; wakers are reference counted, so this allocates nothing.
    pub fn waker(&self) -> Waker {
        Waker::from(Arc::clone(&self.inner))
    }

    /// Raises the halt request, then wakes the signal.
    pub(crate) fn request_halt(&self) {
        // Release pairs with the Acquire of `take_halt`, as for `woken`.
        self.inner.halt.store(true, Ordering::Release);
        self.wake();
    }

    /// `true` while a halt request waits to be served.
    #[inline]
    pub(crate) fn halt_requested(&self) -> bool {
        self.inner.halt.load(Ordering::Relaxed)
    }

    /// Clears the halt request and the wake (a halt drops every future, so no wake is left
    /// to answer); says whether a request was pending.
    pub(crate) fn take_halt(&self) -> bool {
        let requested = self.inner.halt.swap(false, Ordering::AcqRel);
        if requested {
            self.inner.woken.store(false, Ordering::Release);
        }
        requested
    }
}

impl fmt::Debug for WakeSignal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("WakeSignal")
            .field("woken", &self.is_woken())
            .finish()
    }
}

/// Completes once its [`WakeSignal`] is set; see [`WakeSignal::woken`].
#[derive(Debug)]
#[must_use = "futures do nothing unless polled"]
pub struct Woken {
    signal: WakeSignal,
}

impl Future for Woken {
    type Output = ();

    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<()> {
        if self.signal.is_woken() {
            return Poll::Ready(());
        }
        self.signal.register(cx.waker());
        // Checked again after registering: a wake between the first check and the
        // registration would otherwise be lost.
        if self.signal.is_woken() {
            Poll::Ready(())
        } else {
            Poll::Pending
        }
    }
}

/// The signal and the waker made from it, kept by a tree that has async leaves, a runner
/// that asked for the signal, or a [`HaltHandle`](crate::HaltHandle).
pub(crate) struct TreeWake {
    pub(crate) signal: WakeSignal,
    pub(crate) waker: Waker,
    /// A halt handle was made, so waits between ticks watch for its requests.
    pub(crate) halt_handle: bool,
}

impl TreeWake {
    pub(crate) fn new() -> Self {
        let signal = WakeSignal::new();
        let waker = signal.waker();
        Self {
            signal,
            waker,
            halt_handle: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    /// A waker that counts its wakes.
    #[derive(Default)]
    struct Count(AtomicUsize);
    impl Wake for Count {
        fn wake(self: Arc<Self>) {
            self.0.fetch_add(1, Ordering::SeqCst);
        }
    }

    #[test]
    fn a_wake_sets_the_signal_and_wakes_the_registered_runner() {
        let signal = WakeSignal::new();
        let runner = Arc::new(Count::default());
        let runner_waker = Waker::from(Arc::clone(&runner));
        let mut woken = signal.woken();
        let mut cx = Context::from_waker(&runner_waker);
        assert_eq!(Pin::new(&mut woken).poll(&mut cx), Poll::Pending);
        assert_eq!(runner.0.load(Ordering::SeqCst), 0);

        signal.waker().wake();
        assert_eq!(runner.0.load(Ordering::SeqCst), 1);
        assert_eq!(Pin::new(&mut woken).poll(&mut cx), Poll::Ready(()));
        // Awaiting does not clear it; taking does, once.
        assert!(signal.is_woken());
        assert!(signal.take());
        assert!(!signal.take());
    }

    #[test]
    fn a_set_signal_completes_a_new_wait_at_once() {
        let signal = WakeSignal::new();
        signal.wake();
        let runner = Arc::new(Count::default());
        let runner_waker = Waker::from(Arc::clone(&runner));
        let mut cx = Context::from_waker(&runner_waker);
        assert_eq!(Pin::new(&mut signal.woken()).poll(&mut cx), Poll::Ready(()));
        assert_eq!(runner.0.load(Ordering::SeqCst), 0);
    }
}
