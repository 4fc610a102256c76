//! The time of each tick, kept one by one, and the percentiles a robot's loop cares about.
//!
//! A control loop at 10 or 100 Hz misses its period on its worst tick, not on its mean: a
//! mean of 1 µs says nothing of the one tick in a thousand that takes a millisecond. A
//! [`TickTimes`] records every tick's duration in a buffer reserved up front (the recording
//! itself allocates nothing and costs one clock read per tick), and [`TickTimes::percentiles`]
//! gives p50, p99, p99.9 and the maximum by the nearest-rank method.

use std::time::{Duration, Instant};

/// Tick durations in nanoseconds, recorded one by one.
#[derive(Clone, Debug, Default)]
pub struct TickTimes {
    nanos: Vec<u64>,
}

/// The nearest-rank percentiles of a run's tick durations, in nanoseconds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TickPercentiles {
    /// Ticks recorded.
    pub ticks: usize,
    /// The median.
    pub p50: u64,
    /// 99 % of ticks took at most this.
    pub p99: u64,
    /// 99.9 % of ticks took at most this.
    pub p999: u64,
    /// The slowest tick.
    pub max: u64,
}

impl TickTimes {
    /// A recorder with room for `ticks` durations, so that recording them allocates nothing.
    pub fn with_capacity(ticks: usize) -> Self {
        Self {
            nanos: Vec::with_capacity(ticks),
        }
    }

    /// Runs `tick` once and records how long it took; returns what it returned.
    #[inline]
    pub fn time<R>(&mut self, tick: impl FnOnce() -> R) -> R {
        let start = Instant::now();
        let result = tick();
        self.record(start.elapsed());
        result
    }

    /// Records one tick's duration.
    #[inline]
    pub fn record(&mut self, tick: Duration) {
        self.nanos
            .push(u64::try_from(tick.as_nanos()).unwrap_or(u64::MAX));
    }

    /// Ticks recorded so far.
    pub fn len(&self) -> usize {
        self.nanos.len()
    }

    /// Whether no tick was recorded.
    pub fn is_empty(&self) -> bool {
        self.nanos.is_empty()
    }

    /// p50, p99, p99.9 and the maximum of the ticks recorded (all zero when none was).
    pub fn percentiles(&self) -> TickPercentiles {
        let mut sorted = self.nanos.clone();
        sorted.sort_unstable();
        // Nearest rank: the smallest value with at least q of the samples at or below it.
        let rank = |q: f64| -> u64 {
            if sorted.is_empty() {
                return 0;
            }
            let index = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len()) - 1;
            sorted[index]
        };
        TickPercentiles {
            ticks: sorted.len(),
            p50: rank(0.50),
            p99: rank(0.99),
            p999: rank(0.999),
            max: sorted.last().copied().unwrap_or(0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn times(nanos: impl IntoIterator<Item = u64>) -> TickTimes {
        let mut t = TickTimes::default();
        for n in nanos {
            t.record(Duration::from_nanos(n));
        }
        t
    }

    #[test]
    fn percentiles_are_nearest_ranks_whatever_the_order() {
        // 1..=1000 ns shuffled by a stride coprime with 1000.
        let t = times((0..1000u64).map(|i| (i * 7919) % 1000 + 1));
        assert_eq!(
            t.percentiles(),
            TickPercentiles {
                ticks: 1000,
                p50: 500,
                p99: 990,
                p999: 999,
                max: 1000
            }
        );
    }

    #[test]
    fn one_slow_tick_shows_in_the_tail_only() {
        let t = times((0..10_000).map(|i| if i == 4321 { 1_000_000 } else { 800 }));
        let p = t.percentiles();
        assert_eq!((p.p50, p.p99, p.p999, p.max), (800, 800, 800, 1_000_000));
    }

    #[test]
    fn no_tick_gives_zeros() {
        assert_eq!(
            TickTimes::default().percentiles(),
            TickPercentiles {
                ticks: 0,
                p50: 0,
                p99: 0,
                p999: 0,
                max: 0
            }
        );
    }
}
