//! Time, as the tree sees it.
//!
//! Every time-based node (Delay, Timeout, Cooldown, Sleep) reads the tree's [`Clock`] and
//! nothing else: no timer threads, no sleeping. A [`ManualClock`] therefore makes a run fully
//! deterministic (tests, simulation, replay), while [`SystemClock`] (feature `std`) follows
//! the wall of monotonic time.
//!
//! A loop that ticks every period lets the period pass with [`Clock::wait`], so the wait
//! happens on the same time the nodes read: a manual clock moves forward at once, a system
//! clock sleeps the thread.

use alloc::sync::Arc;
use core::sync::atomic::{AtomicU64, Ordering};
use core::time::Duration;

/// A monotonic source of time for one tree.
///
/// `now` is measured from an arbitrary origin fixed for the clock's lifetime; only
/// differences between two readings are meaningful.
pub trait Clock: Send + Sync {
    /// The current time since the clock's origin.
    fn now(&self) -> Duration;

    /// Lets `period` pass on this clock: returns once `now` reads at least `period` later
    /// than when called. [`Tree::tick_while_running`](crate::Tree::tick_while_running) waits
    /// with it between ticks.
    ///
    /// The default suits a clock that moves by itself (wall time, a simulator's time kept by
    /// another thread): it reads `now` until the period is over, sleeping the thread for the
    /// time still left between readings with feature `std`, spinning without it. A clock
    /// that moves only when told, as [`ManualClock`] does, must override it, or the wait
    /// never ends.
    fn wait(&self, period: Duration) {
        let until = self.now().saturating_add(period);
        loop {
            let now = self.now();
            if now >= until {
                return;
            }
            // Sleeping for the time left on this clock is exact for wall time and wakes
            // again, without harm, for a clock that runs slower.
            #[cfg(feature = "std")]
            std::thread::sleep(until - now);
            #[cfg(not(feature = "std"))]
            core::hint::spin_loop();
        }
    }
}

/// A clock that moves only when told to; clones share the same time.
///
/// ```
/// use core::time::Duration;
/// use neurotree_core::{Clock, ManualClock};
///
/// let clock = ManualClock::new();
/// let seen_by_tree = clock.clone();
/// clock.advance(Duration::from_millis(250));
/// assert_eq!(seen_by_tree.now(), Duration::from_millis(250));
/// ```
#[derive(Clone, Debug, Default)]
pub struct ManualClock {
    nanos: Arc<AtomicU64>,
}

impl ManualClock {
    /// A clock at time zero.
    pub fn new() -> Self {
        Self::default()
    }

    /// Moves the time forward by `by`. Time saturates at the largest moment a clock holds
    /// (about 584 years) rather than wrapping round to zero, which would run time backwards
    /// and keep a Timeout from ever firing.
    pub fn advance(&self, by: Duration) {
        let by = duration_to_nanos(by);
        // `fetch_update` with a closure that always returns `Some` cannot fail.
        let _ = self
            .nanos
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |now| {
                Some(now.saturating_add(by))
            });
    }

    /// Sets the time; it may move backwards, which time-based nodes treat as "no time passed".
    pub fn set(&self, to: Duration) {
        self.nanos.store(duration_to_nanos(to), Ordering::Relaxed);
    }
}

impl Clock for ManualClock {
    fn now(&self) -> Duration {
        Duration::from_nanos(self.nanos.load(Ordering::Relaxed))
    }

    /// Advances the clock by `period` and returns at once: nobody else would move it, and
    /// a simulated period should cost no real time.
    fn wait(&self, period: Duration) {
        self.advance(period);
    }
}

/// Monotonic time from `std::time::Instant`, with its origin at the clock's creation.
#[cfg(feature = "std")]
#[derive(Clone, Copy, Debug)]
pub struct SystemClock {
    origin: std::time::Instant,
}

#[cfg(feature = "std")]
impl SystemClock {
    /// A clock whose origin is now.
    pub fn new() -> Self {
        Self {
            origin: std::time::Instant::now(),
        }
    }
}

#[cfg(feature = "std")]
impl Default for SystemClock {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(feature = "std")]
impl Clock for SystemClock {
    fn now(&self) -> Duration {
        self.origin.elapsed()
    }

    /// Sleeps the thread for `period`.
    fn wait(&self, period: Duration) {
        std::thread::sleep(period);
    }
}

/// Nanoseconds as stored in a node's state slot; saturates after ~584 years.
#[inline]
pub(crate) fn duration_to_nanos(d: Duration) -> u64 {
    u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)
}

/// A moment kept in two of a node's 32-bit state slots, as one `u64`, where 0 must mean
/// "none".
///
/// A moment is stored as its nanoseconds plus [`EPOCH`](moment::EPOCH): a state restored on a
/// clock that began later than the wait (a new process's system clock, a manual clock at 0)
/// must hold a moment before that clock's origin, which a plain reading cannot.
pub(crate) mod moment {
    /// No moment stored.
    pub(crate) const NONE: u64 = 0;

    /// What a moment at the clock's origin is stored as: 2^62 ns (146 years) before it can
    /// be stored too, and the largest moment stays below `u64::MAX`, which nodes may use as a
    /// mark of their own.
    pub(crate) const EPOCH: u64 = 1 << 62;

    /// The slot value for the moment `now` (nanoseconds).
    #[inline]
    pub(crate) fn at(now: u64) -> u64 {
        now.saturating_add(EPOCH).min(u64::MAX - 1)
    }

    /// A stored moment read on a clock at `saved`, moved to a clock at `now` so that the
    /// time elapsed since it stays the same (a saved state restored on another clock).
    pub(crate) fn shift(slot: u64, saved: u64, now: u64) -> u64 {
        match elapsed(slot, saved) {
            Some(elapsed) => at(now).saturating_sub(elapsed).max(1),
            None => NONE,
        }
    }

    /// Nanoseconds from the stored moment to `now`, or `None` if no moment is stored.
    #[inline]
    pub(crate) fn elapsed(slot: u64, now: u64) -> Option<u64> {
        (slot != NONE).then(|| at(now).saturating_sub(slot))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_manual_clock_saturates_instead_of_wrapping() {
        let clock = ManualClock::new();
        clock.advance(Duration::from_secs(1));
        clock.advance(Duration::MAX);
        let end = Duration::from_nanos(u64::MAX);
        assert_eq!(clock.now(), end);
        clock.advance(Duration::from_millis(1));
        assert_eq!(clock.now(), end, "time never runs backwards");
    }

    #[test]
    fn manual_clock_is_shared_by_clones() {
        let a = ManualClock::new();
        let b = a.clone();
        a.advance(Duration::from_millis(5));
        b.advance(Duration::from_millis(7));
        assert_eq!(a.now(), Duration::from_millis(12));
        a.set(Duration::from_secs(1));
        assert_eq!(b.now(), Duration::from_secs(1));
    }

    #[test]
    fn waiting_on_a_manual_clock_advances_it_by_the_period() {
        let clock = ManualClock::new();
        let seen_by_tree = clock.clone();
        clock.wait(Duration::from_millis(100));
        clock.wait(Duration::from_millis(100));
        assert_eq!(seen_by_tree.now(), Duration::from_millis(200));
    }

    /// A clock that moves by itself: every reading is one millisecond after the last.
    #[derive(Default)]
    struct Stepping(AtomicU64);

    impl Clock for Stepping {
        fn now(&self) -> Duration {
            Duration::from_millis(self.0.fetch_add(1, Ordering::Relaxed))
        }
    }

    #[test]
    fn default_wait_returns_once_the_clock_has_moved_by_the_period() {
        let clock = Stepping::default();
        // Reads 0 to fix the end at 5 ms, then 1, 2, 3, 4 (waiting) and 5 (done).
        clock.wait(Duration::from_millis(5));
        assert_eq!(clock.now(), Duration::from_millis(6));
        // A zero period reads the clock twice and does not wait.
        clock.wait(Duration::ZERO);
        assert_eq!(clock.now(), Duration::from_millis(9));
    }

    #[test]
    fn moments_distinguish_time_zero_from_none() {
        assert_eq!(moment::elapsed(moment::NONE, 5), None);
        assert_eq!(moment::elapsed(moment::at(0), 5), Some(5));
        // A clock set backwards reads as no time passed.
        assert_eq!(moment::elapsed(moment::at(9), 5), Some(0));
    }

    #[cfg(feature = "std")]
    #[test]
    fn system_clock_is_monotonic() {
        let c = SystemClock::new();
        let t0 = c.now();
        let t1 = c.now();
        assert!(t1 >= t0);
    }
}
