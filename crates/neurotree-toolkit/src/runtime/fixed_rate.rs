//! A fixed-rate tick loop: tick at the start of every period, sleep until the next one.
//!
//! Period `k` starts at `start + k × period`, so the loop keeps its phase however long each
//! tick takes. A tick that ends after its period is over has **overrun**: it is counted, the
//! worst overrun is kept, and the period starts it ran past get no tick of their own (the
//! next tick is at the next period start, with no burst of late ticks to catch up, which a
//! controller would take as a jump in time).
//!
//! Time and sleep come from a [`Pacer`]: [`SystemPacer`] reads the monotonic clock and
//! sleeps the thread; [`ManualPacer`] moves a [`ManualClock`] instead of sleeping, so a test
//! or a simulation runs the loop at once and deterministically. The loop ticks with
//! [`Tree::tick_once`] and stops when the root completes or its [`StopFlag`] is raised; a
//! stopped loop halts the tree first, so every running action gets its halt. A halt that
//! takes ticks ([`slow_halt`](neurotree_core::tree::slow_halt)) is ticked to its end, a
//! period apart, before the run returns, whatever ended it (the stop flag, a halt request,
//! an error).
//!
//! A request from the tree's [`HaltHandle`](neurotree_core::HaltHandle) ends the loop too:
//! the next tick serves it (the tree halts itself) and the run returns
//! `Err(TickError::HaltRequested)`. Once the tree has a handle, the sleep between ticks is
//! made of sleeps of at most [`HALT_POLL_PERIOD`] with a look for a request before each, so
//! a request ends it within that time instead of at the next period.
//!
//! ```
//! use std::time::Duration;
//! use neurotree::runtime::{FixedRate, Finish, ManualPacer};
//! use neurotree::{Blueprint, Clock, ManualClock, Status, Tree};
//!
//! // Three ticks of work, 4 ms each, at 100 Hz.
//! let clock = ManualClock::new();
//! let work = clock.clone();
//! let blueprint = Blueprint::<u32>::builder()
//!     .async_action("work", move |_| {
//!         let work = work.clone();
//!         let mut ticks = 0;
//!         core::future::poll_fn(move |_| {
//!             work.advance(Duration::from_millis(4));
//!             ticks += 1;
//!             if ticks == 3 { core::task::Poll::Ready(Status::Success) } else { core::task::Poll::Pending }
//!         })
//!     })
//!     .build_shared()
//!     .unwrap();
//! let mut tree = Tree::with_clock(blueprint, clock.clone());
//! let mut pacer = ManualPacer::new(clock.clone());
//! let report = FixedRate::new(Duration::from_millis(10))
//!     .run_with(&mut tree, &mut 0, &mut pacer, |_| {})
//!     .unwrap();
//! assert_eq!(report.finish, Finish::Completed(Status::Success));
//! assert_eq!((report.ticks, report.overruns), (3, 0));
//! assert_eq!(clock.now(), Duration::from_millis(24));
//! ```

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use neurotree_core::{Clock, ManualClock, Status, SystemClock, TickError, Tree, HALT_POLL_PERIOD};

/// What paces a loop: the time, and a way to wait until a moment.
pub trait Pacer {
    /// The current time, from the pacer's own origin.
    fn now(&self) -> Duration;
    /// Returns once `now()` has reached `deadline` (at once if it has already).
    fn sleep_until(&mut self, deadline: Duration);
}

/// Real time: the monotonic clock, and sleeping the thread.
#[derive(Clone, Copy, Debug, Default)]
pub struct SystemPacer {
    clock: SystemClock,
}

impl SystemPacer {
    /// A pacer whose time starts now.
    pub fn new() -> Self {
        Self::default()
    }
}

impl Pacer for SystemPacer {
    fn now(&self) -> Duration {
        self.clock.now()
    }

    fn sleep_until(&mut self, deadline: Duration) {
        let now = self.clock.now();
        if deadline > now {
            std::thread::sleep(deadline - now);
        }
    }
}

/// Simulated time: sleeping moves a [`ManualClock`] to the deadline at once. Share the
/// clock with the tree so that its time-based nodes see the same time.
#[derive(Clone, Debug, Default)]
pub struct ManualPacer {
    clock: ManualClock,
}

impl ManualPacer {
    /// A pacer that moves `clock`.
    pub fn new(clock: ManualClock) -> Self {
        Self { clock }
    }

    /// The clock it moves.
    pub fn clock(&self) -> &ManualClock {
        &self.clock
    }
}

impl Pacer for ManualPacer {
    fn now(&self) -> Duration {
        self.clock.now()
    }

    fn sleep_until(&mut self, deadline: Duration) {
        let now = self.clock.now();
        if deadline > now {
            self.clock.advance(deadline - now);
        }
    }
}

/// Asks a loop to stop; clones share the flag, so another thread (or a signal handler) can
/// raise it. The loop sees it before its next tick.
#[derive(Clone, Debug, Default)]
pub struct StopFlag(Arc<AtomicBool>);

impl StopFlag {
    /// A flag that is down.
    pub fn new() -> Self {
        Self::default()
    }

    /// Raises the flag.
    pub fn stop(&self) {
        self.0.store(true, Ordering::Release);
    }

    /// `true` once the flag is raised.
    pub fn is_stopped(&self) -> bool {
        self.0.load(Ordering::Acquire)
    }
}

/// What one tick of a [`FixedRate`] loop did and when.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TickStats {
    /// The tick's number, from 0.
    pub index: u64,
    /// The period start the tick was meant for.
    pub scheduled: Duration,
    /// When the tick started (later than `scheduled` when the sleep overshot).
    pub started: Duration,
    /// How long the tick took.
    pub took: Duration,
    /// How far past the end of its period the tick ended; zero when it ended in time.
    pub overrun: Duration,
    /// What the root returned.
    pub status: Status,
}

impl TickStats {
    /// `true` when the tick ended after its period was over.
    pub fn overran(&self) -> bool {
        !self.overrun.is_zero()
    }
}

/// Why a [`FixedRate`] loop ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Finish {
    /// The root completed with this status.
    Completed(Status),
    /// The stop flag was raised; the tree was halted.
    Stopped,
}

/// What a [`FixedRate`] loop did, once it has ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunReport {
    /// Why it ended.
    pub finish: Finish,
    /// Ticks made.
    pub ticks: u64,
    /// Ticks that ended after their period was over.
    pub overruns: u64,
    /// The longest overrun, zero if none.
    pub worst_overrun: Duration,
    /// Period starts that got no tick because a tick overran them.
    pub skipped_periods: u64,
}

/// Ticks a tree at a fixed rate until its root completes or it is told to stop.
#[derive(Clone, Debug)]
pub struct FixedRate {
    period: Duration,
    stop: StopFlag,
}

impl FixedRate {
    /// A loop that ticks every `period`; a zero period ticks back to back.
    pub fn new(period: Duration) -> Self {
        Self {
            period,
            stop: StopFlag::new(),
        }
    }

    /// Uses `flag` (shared with whoever will raise it) as the loop's stop flag.
    pub fn with_stop_flag(mut self, flag: StopFlag) -> Self {
        self.stop = flag;
        self
    }

    /// The loop's stop flag; clone it to stop the loop from elsewhere.
    pub fn stop_flag(&self) -> &StopFlag {
        &self.stop
    }

    /// The period between tick starts.
    pub fn period(&self) -> Duration {
        self.period
    }

    /// Runs in real time (sleeping this thread between ticks).
    pub fn run<C>(&self, tree: &mut Tree<C>, ctx: &mut C) -> Result<RunReport, TickError> {
        self.run_with(tree, ctx, &mut SystemPacer::new(), |_| {})
    }

    /// Runs on `pacer`'s time, calling `on_tick` after every tick. A tick error ends the
    /// run with that error (the tree has halted itself), [`TickError::HaltRequested`]
    /// included.
    pub fn run_with<C, P: Pacer + ?Sized>(
        &self,
        tree: &mut Tree<C>,
        ctx: &mut C,
        pacer: &mut P,
        mut on_tick: impl FnMut(&TickStats),
    ) -> Result<RunReport, TickError> {
        let mut report = RunReport {
            finish: Finish::Stopped,
            ticks: 0,
            overruns: 0,
            worst_overrun: Duration::ZERO,
            skipped_periods: 0,
        };
        let mut scheduled = pacer.now();
        loop {
            if self.stop.is_stopped() {
                tree.halt(ctx);
                self.finish_halt(tree, ctx, pacer);
                return Ok(report);
            }
            let started = pacer.now();
            let status = match tree.tick_once(ctx) {
                Ok(status) => status,
                Err(e) => {
                    // The tree halted itself; its halt may take ticks.
                    self.finish_halt(tree, ctx, pacer);
                    return Err(e);
                }
            };
            let ended = pacer.now();
            // Back-to-back ticks have no period to overrun.
            let overrun = if self.period.is_zero() {
                Duration::ZERO
            } else {
                ended.saturating_sub(scheduled.saturating_add(self.period))
            };
            let stats = TickStats {
                index: report.ticks,
                scheduled,
                started,
                took: ended.saturating_sub(started),
                overrun,
                status,
            };
            report.ticks += 1;
            if stats.overran() {
                report.overruns += 1;
                report.worst_overrun = report.worst_overrun.max(stats.overrun);
            }
            on_tick(&stats);
            if status != Status::Running {
                report.finish = Finish::Completed(status);
                return Ok(report);
            }
            let (next, skipped) = next_period_start(scheduled, self.period, ended);
            report.skipped_periods += skipped;
            scheduled = next;
            if !self.stop.is_stopped() {
                sleep_until(pacer, scheduled, tree);
            }
        }
    }
}

impl FixedRate {
    /// Ticks a halt in progress to its end with [`Tree::tick_halt`], a period apart.
    fn finish_halt<C, P: Pacer + ?Sized>(&self, tree: &mut Tree<C>, ctx: &mut C, pacer: &mut P) {
        while tree.is_halting() {
            pacer.sleep_until(pacer.now().saturating_add(self.period));
            tree.tick_halt(ctx);
        }
    }
}

/// Sleeps until `deadline`, or, once `tree` has a halt handle, until a halt is requested,
/// looking for one every [`HALT_POLL_PERIOD`] of the pacer's time.
fn sleep_until<C, P: Pacer + ?Sized>(pacer: &mut P, deadline: Duration, tree: &Tree<C>) {
    if !tree.has_halt_handle() {
        pacer.sleep_until(deadline);
        return;
    }
    loop {
        let now = pacer.now();
        if now >= deadline || tree.halt_requested() {
            return;
        }
        pacer.sleep_until(deadline.min(now.saturating_add(HALT_POLL_PERIOD)));
    }
}

/// The first period start at or after `ended`, for periods that start at `scheduled`, and
/// how many period starts lie strictly between `scheduled` and it.
fn next_period_start(scheduled: Duration, period: Duration, ended: Duration) -> (Duration, u64) {
    if period.is_zero() {
        return (ended.max(scheduled), 0);
    }
    let elapsed = ended.saturating_sub(scheduled).as_nanos();
    let p = period.as_nanos();
    // At least one period on: the tick's own period is used up even if it ended early.
    let periods = elapsed.div_ceil(p).max(1);
    let offset = u64::try_from(periods * p).unwrap_or(u64::MAX);
    let skipped = u64::try_from(periods - 1).unwrap_or(u64::MAX);
    (
        scheduled.saturating_add(Duration::from_nanos(offset)),
        skipped,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_core::{Blueprint, HaltProgress, Handle, StatefulAction};

    /// The controlled plant: a clock that work moves forward, and what the action saw.
    struct Plant {
        clock: ManualClock,
        /// How long each tick of the action takes; the action succeeds on the last one.
        work: Vec<u64>,
        ticks: usize,
        halts: u32,
        /// Keep running after the last entry instead of succeeding.
        forever: bool,
    }

    impl Plant {
        fn new(clock: &ManualClock, work: &[u64]) -> Self {
            Self {
                clock: clock.clone(),
                work: work.to_vec(),
                ticks: 0,
                halts: 0,
                forever: false,
            }
        }
    }

    /// Takes `work[i]` milliseconds on its i-th tick.
    struct Work;
    impl StatefulAction<Plant> for Work {
        fn on_start(&mut self, h: &mut Handle<'_, Plant>) -> Status {
            self.on_running(h)
        }
        fn on_running(&mut self, h: &mut Handle<'_, Plant>) -> Status {
            let p = h.ctx_mut();
            let ms = p.work[p.ticks.min(p.work.len() - 1)];
            p.clock.advance(Duration::from_millis(ms));
            p.ticks += 1;
            if p.ticks == p.work.len() && !p.forever {
                Status::Success
            } else {
                Status::Running
            }
        }
        fn on_halted(&mut self, h: &mut Handle<'_, Plant>) {
            h.ctx_mut().halts += 1;
        }
    }

    fn tree(clock: &ManualClock) -> Tree<Plant> {
        let bp = Blueprint::builder()
            .stateful("work", || Work)
            .build_shared()
            .unwrap();
        Tree::with_clock(bp, clock.clone())
    }

    fn ms(n: u64) -> Duration {
        Duration::from_millis(n)
    }

    /// Runs at 100 Hz on a manual clock and returns the report and every tick's stats.
    fn run(plant: &mut Plant, rate: &FixedRate) -> (RunReport, Vec<TickStats>) {
        let clock = plant.clock.clone();
        let mut tree = tree(&clock);
        let mut pacer = ManualPacer::new(clock);
        let mut seen = Vec::new();
        let report = rate
            .run_with(&mut tree, plant, &mut pacer, |s| seen.push(*s))
            .unwrap();
        (report, seen)
    }

    #[test]
    fn ticks_that_end_in_time_start_on_every_period() {
        let clock = ManualClock::new();
        let mut plant = Plant::new(&clock, &[2, 3, 1]);
        let (report, seen) = run(&mut plant, &FixedRate::new(ms(10)));
        assert_eq!(report.finish, Finish::Completed(Status::Success));
        assert_eq!(
            (report.ticks, report.overruns, report.skipped_periods),
            (3, 0, 0)
        );
        assert_eq!(report.worst_overrun, Duration::ZERO);
        let starts: Vec<_> = seen.iter().map(|s| s.started).collect();
        assert_eq!(starts, [ms(0), ms(10), ms(20)]);
        let took: Vec<_> = seen.iter().map(|s| s.took).collect();
        assert_eq!(took, [ms(2), ms(3), ms(1)]);
        assert_eq!(clock.now(), ms(21));
    }

    #[test]
    fn overruns_are_counted_and_the_periods_they_ran_into_are_skipped() {
        let clock = ManualClock::new();
        // Period 10 ms: the second tick ends 2 ms late, the third 15 ms late.
        let mut plant = Plant::new(&clock, &[3, 12, 25, 4]);
        let (report, seen) = run(&mut plant, &FixedRate::new(ms(10)));
        assert_eq!(report.finish, Finish::Completed(Status::Success));
        assert_eq!(report.ticks, 4);
        assert_eq!(report.overruns, 2);
        assert_eq!(report.worst_overrun, ms(15));
        // [20, 30) after the second tick; [40, 50) and [50, 60) after the third.
        assert_eq!(report.skipped_periods, 3);
        let scheduled: Vec<_> = seen.iter().map(|s| s.scheduled).collect();
        assert_eq!(scheduled, [ms(0), ms(10), ms(30), ms(60)]);
        let overruns: Vec<_> = seen.iter().map(|s| s.overrun).collect();
        assert_eq!(overruns, [ms(0), ms(2), ms(15), ms(0)]);
        assert_eq!(seen.iter().filter(|s| s.overran()).count(), 2);
        assert_eq!(clock.now(), ms(64));
    }

    #[test]
    fn a_tick_ending_exactly_at_the_period_end_is_in_time() {
        let clock = ManualClock::new();
        let mut plant = Plant::new(&clock, &[10, 20, 1]);
        let (report, seen) = run(&mut plant, &FixedRate::new(ms(10)));
        // The first tick ends as its period does: in time. The second (10..30) ends 10 ms
        // late, on a period start, which is where the third starts: one period skipped.
        let overruns: Vec<_> = seen.iter().map(|s| s.overrun).collect();
        assert_eq!(overruns, [ms(0), ms(10), ms(0)]);
        assert_eq!((report.overruns, report.skipped_periods), (1, 1));
        let scheduled: Vec<_> = seen.iter().map(|s| s.scheduled).collect();
        assert_eq!(scheduled, [ms(0), ms(10), ms(30)]);
    }

    #[test]
    fn raising_the_stop_flag_halts_the_tree_and_ends_the_loop_without_sleeping() {
        let clock = ManualClock::new();
        let mut plant = Plant::new(&clock, &[1]);
        plant.forever = true;
        let rate = FixedRate::new(ms(10));
        let stop = rate.stop_flag().clone();
        let mut tree = tree(&clock);
        let mut pacer = ManualPacer::new(clock.clone());
        let report = rate
            .run_with(&mut tree, &mut plant, &mut pacer, |s| {
                if s.index == 2 {
                    stop.stop();
                }
            })
            .unwrap();
        assert_eq!(report.finish, Finish::Stopped);
        assert_eq!(report.ticks, 3);
        assert_eq!((plant.ticks, plant.halts), (3, 1));
        // Ticks at 0, 10 and 20, each taking 1 ms; no sleep after the last.
        assert_eq!(clock.now(), ms(21));
    }

    /// Runs until halted, then brakes for `brake_ticks` ticks (the request and
    /// `brake_ticks - 1` calls of `on_halting`), noting the time of each.
    struct Brake {
        left: u32,
        at: std::sync::Arc<std::sync::Mutex<Vec<Duration>>>,
    }
    impl StatefulAction<Plant> for Brake {
        fn on_start(&mut self, _: &mut Handle<'_, Plant>) -> Status {
            Status::Running
        }
        fn on_running(&mut self, _: &mut Handle<'_, Plant>) -> Status {
            Status::Running
        }
        fn on_halt_requested(&mut self, h: &mut Handle<'_, Plant>) -> HaltProgress {
            self.at.lock().unwrap().push(h.now());
            self.left = 2;
            HaltProgress::Halting
        }
        fn on_halting(&mut self, h: &mut Handle<'_, Plant>) -> HaltProgress {
            self.at.lock().unwrap().push(h.now());
            self.left -= 1;
            if self.left == 0 {
                h.ctx_mut().halts += 1;
                HaltProgress::Done
            } else {
                HaltProgress::Halting
            }
        }
    }

    #[test]
    fn a_stopped_loop_ticks_a_slow_halt_to_its_end_a_period_apart() {
        let clock = ManualClock::new();
        let at = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let seen = std::sync::Arc::clone(&at);
        let bp = Blueprint::builder()
            .stateful("brake", move || Brake {
                left: 0,
                at: std::sync::Arc::clone(&seen),
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, clock.clone());
        let mut plant = Plant::new(&clock, &[1]);
        let rate = FixedRate::new(ms(10));
        let stop = rate.stop_flag().clone();
        let mut pacer = ManualPacer::new(clock.clone());
        let report = rate
            .run_with(&mut tree, &mut plant, &mut pacer, |_| stop.stop())
            .unwrap();
        assert_eq!((report.finish, report.ticks), (Finish::Stopped, 1));
        // Requested as the loop stopped, then continued 10 and 20 ms later.
        assert_eq!(*at.lock().unwrap(), [ms(0), ms(10), ms(20)]);
        assert_eq!(plant.halts, 1);
        assert!(!tree.is_halting());
    }

    #[test]
    fn a_loop_stopped_before_it_starts_ticks_nothing() {
        let clock = ManualClock::new();
        let mut plant = Plant::new(&clock, &[1]);
        let flag = StopFlag::new();
        flag.stop();
        let rate = FixedRate::new(ms(10)).with_stop_flag(flag.clone());
        assert!(rate.stop_flag().is_stopped());
        let (report, seen) = run(&mut plant, &rate);
        assert_eq!((report.finish, report.ticks), (Finish::Stopped, 0));
        assert!(seen.is_empty());
        assert_eq!((plant.ticks, plant.halts), (0, 0));
    }

    #[test]
    fn a_zero_period_ticks_back_to_back() {
        let clock = ManualClock::new();
        let mut plant = Plant::new(&clock, &[2, 2, 2]);
        let (report, seen) = run(&mut plant, &FixedRate::new(Duration::ZERO));
        assert_eq!((report.ticks, report.overruns), (3, 0));
        let starts: Vec<_> = seen.iter().map(|s| s.started).collect();
        assert_eq!(starts, [ms(0), ms(2), ms(4)]);
    }

    #[test]
    fn a_tick_error_ends_the_run() {
        let bp = Blueprint::<()>::builder()
            .action("bad", |_| Status::Running)
            .build_shared()
            .unwrap();
        let clock = ManualClock::new();
        let mut tree = Tree::with_clock(bp, clock.clone());
        let mut pacer = ManualPacer::new(clock);
        let result = FixedRate::new(ms(10)).run_with(&mut tree, &mut (), &mut pacer, |_| {});
        assert!(matches!(result, Err(TickError::LeafRunning { .. })));
    }

    #[test]
    fn the_system_pacer_runs_a_tree_that_completes_at_once() {
        let bp = Blueprint::<u32>::builder()
            .action("inc", |n| {
                *n += 1;
                Status::Success
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::new(bp);
        let mut n = 0;
        let report = FixedRate::new(ms(10)).run(&mut tree, &mut n).unwrap();
        assert_eq!(report.finish, Finish::Completed(Status::Success));
        assert_eq!((report.ticks, n), (1, 1));
    }

    #[test]
    fn a_halt_request_ends_the_run_with_its_error_after_one_halt() {
        let clock = ManualClock::new();
        let mut plant = Plant::new(&clock, &[1]);
        plant.forever = true;
        let mut tree = tree(&clock);
        let handle = tree.halt_handle();
        let mut pacer = ManualPacer::new(clock.clone());
        let result = FixedRate::new(ms(10)).run_with(&mut tree, &mut plant, &mut pacer, |s| {
            if s.index == 2 {
                handle.request();
            }
        });
        assert_eq!(result, Err(TickError::HaltRequested));
        assert_eq!((plant.ticks, plant.halts), (3, 1));
        // The sleep after the third tick ended at once: its first look saw the request.
        assert_eq!(clock.now(), ms(21));
    }

    #[test]
    fn with_a_handle_but_no_request_the_loop_keeps_its_periods() {
        let clock = ManualClock::new();
        let mut plant = Plant::new(&clock, &[2, 3, 1]);
        let mut tree = tree(&clock);
        let _handle = tree.halt_handle();
        let mut pacer = ManualPacer::new(clock.clone());
        let mut starts = Vec::new();
        let report = FixedRate::new(ms(25))
            .run_with(&mut tree, &mut plant, &mut pacer, |s| {
                starts.push(s.started)
            })
            .unwrap();
        assert_eq!(report.finish, Finish::Completed(Status::Success));
        assert_eq!(starts, [ms(0), ms(25), ms(50)]);
    }

    /// A manual pacer whose first sleep lets another thread act before it ends: the test
    /// knows the loop sleeps when the other thread acts, with no wall time involved.
    struct Gate {
        time: ManualPacer,
        asleep: Option<std::sync::mpsc::Sender<()>>,
        go: std::sync::mpsc::Receiver<()>,
    }

    impl Pacer for Gate {
        fn now(&self) -> Duration {
            self.time.now()
        }
        fn sleep_until(&mut self, deadline: Duration) {
            if let Some(asleep) = self.asleep.take() {
                asleep.send(()).unwrap();
                self.go.recv().unwrap();
            }
            self.time.sleep_until(deadline);
        }
    }

    #[test]
    fn a_request_from_another_thread_wakes_a_long_sleep() {
        let clock = ManualClock::new();
        let mut plant = Plant::new(&clock, &[0]);
        plant.forever = true;
        let mut tree = tree(&clock);
        let handle = tree.halt_handle();
        let (asleep, sleeping) = std::sync::mpsc::channel();
        let (go, gate) = std::sync::mpsc::channel();
        let mut pacer = Gate {
            time: ManualPacer::new(clock.clone()),
            asleep: Some(asleep),
            go: gate,
        };
        let requester = std::thread::spawn(move || {
            sleeping.recv().unwrap();
            handle.request();
            go.send(()).unwrap();
        });
        let result = FixedRate::new(Duration::from_secs(10)).run_with(
            &mut tree,
            &mut plant,
            &mut pacer,
            |_| {},
        );
        requester.join().unwrap();
        assert_eq!(result, Err(TickError::HaltRequested));
        // The sleep of 10 s ended after the slice in which the request came.
        assert_eq!(clock.now(), HALT_POLL_PERIOD);
        assert_eq!((plant.ticks, plant.halts), (1, 1));
    }

    #[test]
    fn next_period_start_keeps_the_phase() {
        assert_eq!(next_period_start(ms(0), ms(10), ms(3)), (ms(10), 0));
        assert_eq!(next_period_start(ms(0), ms(10), ms(10)), (ms(10), 0));
        assert_eq!(next_period_start(ms(0), ms(10), ms(11)), (ms(20), 1));
        assert_eq!(next_period_start(ms(5), ms(10), ms(40)), (ms(45), 3));
        assert_eq!(next_period_start(ms(5), Duration::ZERO, ms(7)), (ms(7), 0));
    }
}
