//! The `cores` line of `neurotree bench`: how long a cache line written by one thread takes
//! to reach another and come back.
//!
//! A crowd's two-thread figures follow it. On a virtual machine the host may place its two
//! cores beside each other (a round trip of about 60 ns on the machine of BENCHMARKS.md) or
//! apart (about 340 ns), and moves them within seconds; a frame of a crowd that mostly
//! sleeps took as long on two threads as on one while the round trip was long, where a
//! crowd all awake, and two one-thread runs side by side, did not slow. The line, printed
//! before and after the crowd lines, says which a run met.
//!
//! It also times a loop of arithmetic on one thread, then on two at once, each thread its
//! own: whether both threads had a core at full speed (1.95–2.01 times as fast as one on
//! that machine, the cores beside each other or apart). The loop is one chain of dependent
//! steps, so two threads sharing one core's hardware threads would score about as well: it
//! says the threads ran at once, not that they had a core each.

use std::hint::black_box;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Barrier;
use std::time::{Duration, Instant};

/// Round trips timed at most.
const MOST_TRIPS: u32 = 100_000;

/// Time spent on round trips at most, beyond the warm-up.
const MOST_TIME: Duration = Duration::from_millis(50);

/// Round trips before the timing, which start the second thread and bring the line in.
const WARM_UP: u32 = 1_000;

/// Result of the `cores` benchmark.
#[derive(Clone, Debug, PartialEq)]
pub struct CoresResult {
    /// When in the run it was measured: `"start"` (before the crowd lines) or `"end"`.
    pub at: &'static str,
    /// Round trips timed.
    pub round_trips: u32,
    /// Mean nanoseconds per round trip.
    pub round_trip_ns: f64,
    /// How many times as fast two threads ran a loop of arithmetic, each its own, as one
    /// thread ran it alone (2.0: no loss), the best of a few tries of each.
    pub arithmetic_speedup: f64,
}

/// Steps of the arithmetic loop per thread: about 40 ms on the machine of BENCHMARKS.md (a
/// tenth with `--quick`).
pub const ARITHMETIC_STEPS: u64 = 25_000_000;

/// Tries of the arithmetic on one thread and on two.
const ARITHMETIC_TRIES: usize = 3;

/// A chain of shifts, exclusive ors and multiplications, each step waiting for the last
/// and none that the compiler can fold into fewer: the core's own speed, with no memory
/// to share.
fn arithmetic(steps: u64) -> u64 {
    let mut x = black_box(0x9e37_79b9_7f4a_7c15_u64);
    for _ in 0..steps {
        x ^= x >> 29;
        x = x.wrapping_mul(0xbf58_476d_1ce4_e5b9);
    }
    black_box(x)
}

/// [`CoresResult::arithmetic_speedup`], for `steps` steps a thread. The two threads' steps
/// are timed from the first of them to leave a barrier both reached to the last to finish:
/// a thread's start is not counted, and a thread that waits for a core is.
pub fn arithmetic_speedup(steps: u64) -> f64 {
    let mut one = Duration::MAX;
    let mut two = Duration::MAX;
    for _ in 0..ARITHMETIC_TRIES {
        let start = Instant::now();
        arithmetic(steps);
        one = one.min(start.elapsed());
        let barrier = Barrier::new(2);
        let run = || {
            barrier.wait();
            let start = Instant::now();
            arithmetic(steps);
            (start, Instant::now())
        };
        let both = std::thread::scope(|s| {
            let other = s.spawn(run);
            let (start, end) = run();
            match other.join() {
                Ok((start2, end2)) => end.max(end2).duration_since(start.min(start2)),
                Err(_) => Duration::MAX,
            }
        });
        two = two.min(both);
    }
    2.0 * one.as_secs_f64() / two.as_secs_f64().max(f64::MIN_POSITIVE)
}

/// One atomic alone in its cache lines, so that the round trip moves no other data.
#[repr(align(128))]
struct Line(AtomicU64);

/// Bounces a value between this thread and another through one atomic, each thread
/// waiting for the other's write before writing its own, then times
/// [`arithmetic_speedup`] (for a tenth of [`ARITHMETIC_STEPS`] with `quick`). `None` on a
/// machine with one core, where the two threads would take turns on it rather than run at
/// once.
pub fn cores_bench(at: &'static str, quick: bool) -> Option<CoresResult> {
    if std::thread::available_parallelism().map_or(1, |n| n.get()) < 2 {
        return None;
    }
    // Odd values are this thread's, even ones the other's; `STOP` ends the other.
    const STOP: u64 = u64::MAX;
    let line = Line(AtomicU64::new(0));
    let line = &line.0;
    let (trips, took) = std::thread::scope(|s| {
        s.spawn(|| loop {
            // An odd value is this thread's write, not yet answered: the answer is even, so
            // the thread does not answer it twice.
            match line.load(Ordering::Acquire) {
                STOP => return,
                value if value % 2 == 1 => line.store(value + 1, Ordering::Release),
                _ => std::hint::spin_loop(),
            }
        });
        let mut value = 0;
        let trip = |value: &mut u64| {
            *value += 1;
            line.store(*value, Ordering::Release);
            *value += 1;
            while line.load(Ordering::Acquire) != *value {
                std::hint::spin_loop();
            }
        };
        for _ in 0..WARM_UP {
            trip(&mut value);
        }
        let start = Instant::now();
        let mut trips = 0;
        while trips < MOST_TRIPS && (trips % 1024 != 0 || start.elapsed() < MOST_TIME) {
            trip(&mut value);
            trips += 1;
        }
        let took = start.elapsed();
        line.store(STOP, Ordering::Release);
        (trips, took)
    });
    Some(CoresResult {
        at,
        round_trips: trips,
        round_trip_ns: took.as_secs_f64() * 1e9 / f64::from(trips.max(1)),
        arithmetic_speedup: arithmetic_speedup(if quick {
            ARITHMETIC_STEPS / 10
        } else {
            ARITHMETIC_STEPS
        }),
    })
}

/// A `cores` line.
pub(super) fn cores_json(c: &CoresResult) -> String {
    format!(
        r#"{{"name":"cores","at":"{}","round_trips":{},"round_trip_ns":{:.1},"arithmetic_speedup":{:.3}}}"#,
        c.at, c.round_trips, c.round_trip_ns, c.arithmetic_speedup
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_round_trip_is_timed_between_two_running_threads() {
        let Some(c) = cores_bench("start", true) else {
            assert_eq!(std::thread::available_parallelism().unwrap().get(), 1);
            return;
        };
        assert_eq!(c.at, "start");
        // Timed in batches of 1,024 until 50 ms have passed, or 100,000.
        assert!((1024..=MOST_TRIPS).contains(&c.round_trips), "{c:?}");
        assert_eq!(
            c.round_trips % 1024 == 0,
            c.round_trips < MOST_TRIPS,
            "{c:?}"
        );
        // Two stores and two loads that cross between the threads: more than a nanosecond.
        // No bound above: with other tests on the cores, a trip may wait for one.
        assert!(
            c.round_trip_ns > 1.0 && c.round_trip_ns.is_finite(),
            "{c:?}"
        );
        assert!(c.arithmetic_speedup > 0.0, "{c:?}");
        assert_eq!(
            cores_json(&CoresResult {
                at: "end",
                round_trips: 100_000,
                round_trip_ns: 61.27,
                arithmetic_speedup: 1.9312,
            }),
            r#"{"name":"cores","at":"end","round_trips":100000,"round_trip_ns":61.3,"arithmetic_speedup":1.931}"#
        );
    }

    #[test]
    fn two_threads_do_at_most_twice_the_arithmetic_of_one() {
        // Each thread does the steps one thread did alone, timed to the last to finish: two
        // threads take at least as long as one (2.0 at best, a little over with noise), and
        // not ten times as long, however busy the cores are with other tests.
        let speedup = arithmetic_speedup(200_000);
        assert!(speedup > 0.2 && speedup < 2.5, "{speedup}");
    }
}
