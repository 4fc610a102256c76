//! Halting from another thread through a `HaltHandle`: a request is served at the next
//! tick boundary (the start of a tick call, or between two passes of `tick_once`), the
//! tree is halted as `Tree::halt` halts it, and the call returns `TickError::HaltRequested`.
//!
//! Every stateful action here keeps its own books: starts, completions, halts, and any
//! halt or start that broke the rule "a run ends exactly once, by a completion or one halt".

use crate::counting_alloc;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::time::Duration;

use neurotree_core::{
    Blueprint, Builder, Clock, HaltHandle, Handle, ManualClock, NodeStatus, StatefulAction, Status,
    TickError, Tree, HALT_POLL_PERIOD,
};

/// Per action: what happened to its runs.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
struct Books {
    starts: u32,
    completions: u32,
    halts: u32,
    /// `on_halted` while not running, or `on_start` while a run was still open.
    broken: u32,
    /// `on_running` calls.
    ticks: u32,
}

/// The context: one set of books per action.
#[derive(Default)]
struct Lab {
    books: Vec<Books>,
}

impl Lab {
    fn new(actions: usize) -> Self {
        Self {
            books: vec![Books::default(); actions],
        }
    }

    fn halts(&self) -> Vec<u32> {
        self.books.iter().map(|b| b.halts).collect()
    }

    fn starts(&self) -> Vec<u32> {
        self.books.iter().map(|b| b.starts).collect()
    }
}

/// Action `id`: Running for `length(run)` ticks after its start, then Success; a length of
/// `u32::MAX` runs forever.
struct Worker {
    id: usize,
    length: fn(u32) -> u32,
    left: u32,
    running: bool,
}

impl Worker {
    fn new(id: usize, length: fn(u32) -> u32) -> Self {
        Self {
            id,
            length,
            left: 0,
            running: false,
        }
    }

    fn step(&mut self, b: &mut Books) -> Status {
        if self.left == 0 {
            self.running = false;
            b.completions += 1;
            Status::Success
        } else {
            self.left -= 1;
            Status::Running
        }
    }
}

impl StatefulAction<Lab> for Worker {
    fn on_start(&mut self, h: &mut Handle<'_, Lab>) -> Status {
        let b = &mut h.ctx_mut().books[self.id];
        if self.running {
            b.broken += 1;
        }
        b.starts += 1;
        self.running = true;
        self.left = (self.length)(b.starts);
        self.step(b)
    }

    fn on_running(&mut self, h: &mut Handle<'_, Lab>) -> Status {
        let b = &mut h.ctx_mut().books[self.id];
        b.ticks += 1;
        self.step(b)
    }

    fn on_halted(&mut self, h: &mut Handle<'_, Lab>) {
        let b = &mut h.ctx_mut().books[self.id];
        if !self.running {
            b.broken += 1;
        }
        b.halts += 1;
        self.running = false;
    }
}

fn forever(_: u32) -> u32 {
    u32::MAX
}

fn at_once(_: u32) -> u32 {
    0
}

/// Two actions that run forever, side by side.
fn two_forever(b: Builder<Lab>) -> Builder<Lab> {
    b.parallel("p", -1, 1, |p| {
        p.stateful("a", || Worker::new(0, forever))
            .stateful("b", || Worker::new(1, forever))
    })
}

fn tree(clock: ManualClock, shape: fn(Builder<Lab>) -> Builder<Lab>) -> Tree<Lab> {
    Tree::with_clock(shape(Blueprint::builder()).build_shared().unwrap(), clock)
}

fn all_idle(tree: &Tree<Lab>) -> bool {
    tree.statuses().iter().all(|s| *s == NodeStatus::Idle)
}

#[test]
fn a_request_halts_the_running_actions_once_at_the_next_tick_and_the_tick_after_starts_afresh() {
    let mut lab = Lab::new(2);
    let mut tree = tree(ManualClock::new(), two_forever);
    let handle = tree.halt_handle();
    assert_eq!(tree.tick_once(&mut lab), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut lab), Ok(Status::Running));

    handle.request();
    assert!(handle.is_pending() && tree.halt_requested());
    assert_eq!(tree.tick_once(&mut lab), Err(TickError::HaltRequested));
    assert!(!handle.is_pending());
    // Halted without being ticked: one halt each, no tick beyond the two before.
    assert_eq!(lab.halts(), [1, 1]);
    assert!(lab.books.iter().all(|b| b.ticks == 1 && b.broken == 0));
    assert_eq!(tree.last_passes(), 0);
    assert!(all_idle(&tree));

    // Served once: the next tick starts every action again.
    assert_eq!(tree.tick_once(&mut lab), Ok(Status::Running));
    assert_eq!(lab.starts(), [2, 2]);
    assert_eq!(lab.halts(), [1, 1]);

    // `tick_exactly_once` serves a request the same way.
    handle.request();
    assert_eq!(
        tree.tick_exactly_once(&mut lab),
        Err(TickError::HaltRequested)
    );
    assert_eq!(lab.halts(), [2, 2]);
    assert!(all_idle(&tree));
    assert!(lab.books.iter().all(|b| b.broken == 0));
}

#[test]
fn requests_do_not_queue() {
    let mut lab = Lab::new(2);
    let mut tree = tree(ManualClock::new(), two_forever);
    let handle = tree.halt_handle();
    let other = handle.clone();
    assert_eq!(tree.tick_once(&mut lab), Ok(Status::Running));
    handle.request();
    other.request();
    handle.request();
    assert_eq!(tree.tick_once(&mut lab), Err(TickError::HaltRequested));
    assert_eq!(tree.tick_once(&mut lab), Ok(Status::Running));
    assert_eq!(lab.halts(), [1, 1]);
}

#[test]
fn a_request_while_nothing_runs_is_served_and_changes_nothing() {
    let mut lab = Lab::new(1);
    let mut tree = tree(ManualClock::new(), |b| {
        b.stateful("quick", || Worker::new(0, at_once))
    });
    let handle = tree.halt_handle();
    // Before the first tick.
    handle.request();
    assert_eq!(tree.tick_once(&mut lab), Err(TickError::HaltRequested));
    assert_eq!(lab.books[0], Books::default());

    // After a tick that completed.
    assert_eq!(tree.tick_once(&mut lab), Ok(Status::Success));
    handle.request();
    assert_eq!(tree.tick_once(&mut lab), Err(TickError::HaltRequested));
    assert!(all_idle(&tree));
    let books = &lab.books[0];
    assert_eq!((books.starts, books.completions, books.halts), (1, 1, 0));
    assert_eq!(books.broken, 0);
    assert_eq!(tree.tick_once(&mut lab), Ok(Status::Success));
}

/// Where the tree's handle is put once the tree is made (its actions are made with it).
type HandleSlot = Arc<Mutex<Option<HaltHandle>>>;

/// Asks for a halt from inside a tick, as another thread could at that moment.
struct RequestThenSucceed(HandleSlot);

impl StatefulAction<Lab> for RequestThenSucceed {
    fn on_start(&mut self, h: &mut Handle<'_, Lab>) -> Status {
        let slot = self.0.lock().unwrap();
        slot.as_ref().expect("set before ticking").request();
        h.ctx_mut().books[0].starts += 1;
        h.ctx_mut().books[0].completions += 1;
        Status::Success
    }
    fn on_running(&mut self, _: &mut Handle<'_, Lab>) -> Status {
        unreachable!("completes in on_start")
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Lab>) {
        h.ctx_mut().books[0].broken += 1;
    }
}

#[test]
fn a_request_during_a_pass_lets_the_pass_finish_and_is_served_before_the_next() {
    // A Repeat of 3 yields after each cycle, so one `tick_once` would make three passes.
    let handle_slot = HandleSlot::default();
    let slot = Arc::clone(&handle_slot);
    let bp = Blueprint::<Lab>::builder()
        .repeat("thrice", 3, move |r| {
            r.stateful("asks", move || RequestThenSucceed(Arc::clone(&slot)))
        })
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(bp, ManualClock::new());
    *handle_slot.lock().unwrap() = Some(tree.halt_handle());
    let mut lab = Lab::new(1);
    assert_eq!(tree.tick_once(&mut lab), Err(TickError::HaltRequested));
    // The first pass ran to its end (the action completed, nothing was halted mid-node);
    // the boundary after it served the request.
    assert_eq!(tree.last_passes(), 1);
    assert_eq!((lab.books[0].completions, lab.books[0].broken), (1, 0));
    assert!(all_idle(&tree));

    // With `tick_exactly_once` the request made during its only pass waits for the next
    // call, which serves it before ticking.
    assert_eq!(tree.tick_exactly_once(&mut lab), Ok(Status::Running));
    assert_eq!(lab.books[0].completions, 2);
    assert_eq!(
        tree.tick_exactly_once(&mut lab),
        Err(TickError::HaltRequested)
    );
    assert_eq!(lab.books[0].completions, 2);
    assert!(all_idle(&tree));
}

/// A small deterministic generator for the stress test (xorshift64*).
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: u64) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) % n
    }
}

/// Runs of 0 to 4 ticks, different for each action and each run.
fn varied(start: u32) -> u32 {
    (start * 7) % 5
}

#[test]
fn halts_requested_from_another_thread_while_ticking_end_every_run_exactly_once() {
    const TICKS: u32 = 2_000;
    const ACTIONS: usize = 5;
    let bp = Blueprint::<Lab>::builder()
        .sequence("root", |s| {
            s.parallel("p", -1, 1, |p| {
                p.stateful("a", || Worker::new(0, varied))
                    .stateful("b", || Worker::new(1, |n| varied(n + 1)))
                    .sequence("s", |s| {
                        s.stateful("c", || Worker::new(2, |n| varied(n + 2)))
                            .stateful("d", || Worker::new(3, |n| varied(n + 3)))
                    })
            })
            .stateful("e", || Worker::new(4, |n| varied(n + 4)))
        })
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(bp, ManualClock::new());
    let handle = tree.halt_handle();
    let done = Arc::new(AtomicBool::new(false));

    let halter = {
        let handle = handle.clone();
        let done = Arc::clone(&done);
        std::thread::spawn(move || {
            let mut rng = Rng(0x5eed_1234_abcd_0001);
            let mut requests = 0_u32;
            while !done.load(Ordering::Acquire) && requests < 20_000 {
                std::thread::sleep(Duration::from_micros(rng.below(300)));
                handle.request();
                requests += 1;
            }
            requests
        })
    };

    let mut lab = Lab::new(ACTIONS);
    let mut served = 0_u32;
    for _ in 0..TICKS {
        match tree.tick_once(&mut lab) {
            Ok(_) => {}
            Err(TickError::HaltRequested) => {
                served += 1;
                assert!(all_idle(&tree), "a served request leaves every node Idle");
            }
            Err(e) => panic!("unexpected tick error: {e}"),
        }
        // Room for the other thread's requests to land between and during ticks.
        std::thread::sleep(Duration::from_micros(20));
    }
    done.store(true, Ordering::Release);
    let requests = halter.join().unwrap();
    // Close the runs still open, the same way.
    handle.request();
    assert_eq!(tree.tick_once(&mut lab), Err(TickError::HaltRequested));

    assert!(served >= 1 && served <= requests, "{served} of {requests}");
    for (id, b) in lab.books.iter().enumerate() {
        assert_eq!(
            b.broken, 0,
            "action {id}: a halt or start out of turn: {b:?}"
        );
        assert_eq!(
            b.starts,
            b.completions + b.halts,
            "action {id}: every run ends once, by a completion or a halt: {b:?}"
        );
    }
    assert!(lab.books.iter().any(|b| b.halts > 0));
}

/// A manual clock whose first wait lets another thread act before it lets time pass: the
/// test knows the tree is waiting when the other thread acts, with no wall time involved.
struct GateClock {
    time: ManualClock,
    /// Told when the first wait starts.
    waiting: Mutex<Option<mpsc::Sender<()>>>,
    /// Says when the first wait may go on.
    go: Mutex<mpsc::Receiver<()>>,
}

impl Clock for GateClock {
    fn now(&self) -> Duration {
        self.time.now()
    }

    fn wait(&self, period: Duration) {
        if let Some(waiting) = self.waiting.lock().unwrap().take() {
            waiting.send(()).unwrap();
            self.go.lock().unwrap().recv().unwrap();
        }
        self.time.wait(period);
    }
}

#[test]
fn a_request_from_another_thread_ends_a_long_wait_of_tick_while_running() {
    let (waiting, asleep) = mpsc::channel();
    let (go, gate) = mpsc::channel();
    let clock = GateClock {
        time: ManualClock::new(),
        waiting: Mutex::new(Some(waiting)),
        go: Mutex::new(gate),
    };
    let bp = two_forever(Blueprint::builder()).build_shared().unwrap();
    let mut tree = Tree::with_clock(bp, clock);
    let handle = tree.halt_handle();
    let requester = std::thread::spawn(move || {
        asleep.recv().unwrap();
        handle.request();
        go.send(()).unwrap();
    });
    let mut lab = Lab::new(2);
    let result = tree.tick_while_running(&mut lab, Duration::from_secs(10));
    requester.join().unwrap();
    assert_eq!(result, Err(TickError::HaltRequested));
    // The wait of 10 s ended after the slice in which the request came.
    assert_eq!(tree.now(), HALT_POLL_PERIOD);
    // One tick before the wait; the request ended the wait and was served.
    assert_eq!(lab.starts(), [1, 1]);
    assert_eq!(lab.halts(), [1, 1]);
}

#[test]
fn on_a_manual_clock_a_wait_in_slices_ends_where_one_wait_would() {
    let mut tree = Tree::with_clock(
        Blueprint::<()>::builder()
            .sleep("nap", Duration::from_millis(300))
            .build_shared()
            .unwrap(),
        ManualClock::new(),
    );
    let _handle = tree.halt_handle();
    assert_eq!(
        tree.tick_while_running(&mut (), Duration::from_millis(125)),
        Ok(Status::Success)
    );
    // Ticks at 0, 125, 250 and 375 ms, as without a handle.
    assert_eq!(tree.now(), Duration::from_millis(375));
}

#[test]
fn ticking_allocates_nothing_with_or_without_a_handle() {
    let mut lab = Lab::new(2);
    let mut plain = tree(ManualClock::new(), two_forever);
    plain.tick_once(&mut lab).unwrap();
    let n = counting_alloc::allocations(|| {
        for _ in 0..100 {
            assert_eq!(plain.tick_once(&mut lab), Ok(Status::Running));
            assert_eq!(plain.tick_exactly_once(&mut lab), Ok(Status::Running));
        }
    });
    assert_eq!(n, 0);
    assert!(!plain.has_halt_handle() && !plain.halt_requested());

    let mut lab = Lab::new(2);
    let mut handled = tree(ManualClock::new(), two_forever);
    let handle = handled.halt_handle();
    assert!(handled.has_halt_handle());
    // The tree's first error makes the box that keeps a tick call's error: once.
    handled.tick_once(&mut lab).unwrap();
    handle.request();
    assert_eq!(handled.tick_once(&mut lab), Err(TickError::HaltRequested));
    let n = counting_alloc::allocations(|| {
        for _ in 0..100 {
            assert_eq!(handled.tick_once(&mut lab), Ok(Status::Running));
            handle.request();
            assert_eq!(handled.tick_once(&mut lab), Err(TickError::HaltRequested));
        }
    });
    assert_eq!(n, 0);
    assert_eq!(lab.halts(), [101, 101]);
}

#[test]
fn the_handle_crosses_threads() {
    fn send_sync<T: Send + Sync + Clone + 'static>() {}
    send_sync::<HaltHandle>();
}
