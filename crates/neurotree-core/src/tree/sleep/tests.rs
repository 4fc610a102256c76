use crate::testing::*;
use crate::{Handle, StatefulAction};

/// What a [`Nap`] leaf did, in the context.
#[derive(Default)]
struct Naps {
    /// Calls of `on_start` / `on_running`.
    calls: u32,
    halts: u32,
}

/// A stateful action that runs until `done_at`, saying so (`declare`), or that wakes on
/// the blackboard entry `go` being true.
struct Nap {
    done_at: Duration,
    declare: bool,
    on_go: bool,
}

impl Nap {
    fn step(&mut self, h: &mut Handle<'_, Naps>) -> Status {
        h.ctx_mut().calls += 1;
        if self.on_go {
            if h.blackboard().get::<bool>("go").unwrap_or(false) {
                return Status::Success;
            }
            h.wake_on("go");
            return Status::Running;
        }
        if h.now() >= self.done_at {
            return Status::Success;
        }
        if self.declare {
            h.sleep_until(self.done_at);
        }
        Status::Running
    }
}

impl StatefulAction<Naps> for Nap {
    fn on_start(&mut self, h: &mut Handle<'_, Naps>) -> Status {
        self.done_at = h.now() + ms(1000);
        self.step(h)
    }
    fn on_running(&mut self, h: &mut Handle<'_, Naps>) -> Status {
        self.step(h)
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Naps>) {
        h.ctx_mut().halts += 1;
    }
}

fn nap(declare: bool, on_go: bool) -> impl Fn() -> Nap + Send + Sync + 'static {
    move || Nap {
        done_at: Duration::ZERO,
        declare,
        on_go,
    }
}

fn naps(f: impl FnOnce(Builder<Naps>) -> Builder<Naps>) -> (Tree<Naps>, ManualClock) {
    let clock = ManualClock::new();
    let bp = f(Builder::new())
        .build_shared()
        .expect("test tree is valid");
    (Tree::with_clock(bp, clock.clone()), clock)
}

/// Ticks every 100 ms until the root completes or 40 ticks; the statuses returned.
fn run(tree: &mut Tree<Naps>, clock: &ManualClock, naps: &mut Naps) -> Vec<Status> {
    let mut seen = Vec::new();
    for _ in 0..40 {
        let status = tree.tick_once(naps).unwrap();
        seen.push(status);
        if status != Status::Running {
            break;
        }
        clock.advance(ms(100));
    }
    seen
}

#[test]
fn an_action_that_sleeps_until_its_deadline_is_called_at_the_start_and_at_the_deadline() {
    let (mut tree, clock) = naps(|b| b.stateful("nap", nap(true, false)));
    let mut n = Naps::default();
    assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
    assert!(tree.is_asleep());
    assert_eq!(tree.wakes_at(), Some(ms(1000)));
    let seen = run(&mut tree, &clock, &mut n);
    // 11 ticks: 0 ms (again, asleep) up to 1000 ms, where it completes.
    assert_eq!(seen.len(), 11);
    assert_eq!(seen.last(), Some(&Status::Success));
    assert_eq!((n.calls, n.halts), (2, 0));
    assert!(!tree.is_asleep());
}

#[test]
fn an_action_that_declares_nothing_is_called_every_tick() {
    let (mut tree, clock) = naps(|b| b.stateful("nap", nap(false, false)));
    let mut n = Naps::default();
    let seen = run(&mut tree, &clock, &mut n);
    assert_eq!(seen.len(), 11);
    assert_eq!(n.calls, 11);
    assert!(!tree.is_asleep());
}

#[test]
fn a_timeout_fires_on_the_tick_its_time_is_up_while_the_tree_sleeps() {
    let (mut tree, clock) =
        naps(|b| b.timeout("t", ms(450), |t| t.stateful("nap", nap(true, false))));
    let mut n = Naps::default();
    let seen = run(&mut tree, &clock, &mut n);
    // Ticks at 0, 100, ..., 500 ms: the first at or past 450 ms fails.
    assert_eq!(seen.len(), 6);
    assert_eq!(seen.last(), Some(&Status::Failure));
    assert_eq!((n.calls, n.halts), (1, 1));
}

#[test]
fn sleep_and_delay_declare_their_deadlines() {
    let (mut tree, clock) = naps(|b| {
        b.sequence("s", |s| {
            s.sleep("z", ms(250))
                .delay("d", ms(300), |d| d.stateful("nap", nap(true, false)))
        })
    });
    let mut n = Naps::default();
    assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
    assert_eq!(tree.wakes_at(), Some(ms(250)));
    let seen = run(&mut tree, &clock, &mut n);
    // Sleep ends at 300 ms (the tick at or past 250), the delay at 600, the nap at 1600.
    assert_eq!(seen.len(), 17);
    assert_eq!(seen.last(), Some(&Status::Success));
    assert_eq!(n.calls, 2);
}

#[test]
fn a_write_to_the_blackboard_wakes_a_tree_waiting_on_an_entry() {
    let (mut tree, _clock) = naps(|b| b.stateful("nap", nap(true, true)));
    let mut n = Naps::default();
    tree.blackboard_mut().set("go", false).unwrap();
    assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
    assert!(tree.is_asleep());
    assert_eq!(tree.wakes_at(), None);
    for _ in 0..5 {
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
    }
    assert_eq!(n.calls, 1);
    // Any write wakes it: the tree does not tell entries apart.
    tree.blackboard_mut().set("other", 1).unwrap();
    assert!(tree.is_due());
    assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
    assert_eq!(n.calls, 2);
    tree.blackboard_mut().set("go", true).unwrap();
    assert_eq!(tree.tick_once(&mut n), Ok(Status::Success));
    assert_eq!(n.calls, 3);
}

#[test]
fn a_wake_handle_a_halt_and_an_observer_wake_a_sleeping_tree() {
    let (mut tree, _clock) = naps(|b| b.stateful("nap", nap(true, true)));
    let mut n = Naps::default();
    let handle = tree.wake_handle();
    assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
    assert!(tree.is_asleep());
    handle.wake();
    assert!(tree.is_due());
    assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
    assert_eq!(n.calls, 2);
    assert!(tree.is_asleep());
    tree.halt(&mut n);
    assert_eq!(n.halts, 1);
    assert!(!tree.is_asleep());
    assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
    assert_eq!(n.calls, 3);
    struct Quiet;
    impl crate::Observer for Quiet {}
    tree.set_observer(Quiet);
    assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
    assert_eq!(n.calls, 5);
}

#[test]
fn a_running_reactive_tree_and_a_tree_not_allowed_to_never_sleep() {
    let (mut tree, _clock) = naps(|b| {
        b.reactive_sequence("r", |r| {
            r.condition("ok", |_: &Naps| true)
                .stateful("nap", nap(true, false))
        })
    });
    let mut n = Naps::default();
    for _ in 0..3 {
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        assert!(!tree.is_asleep());
    }
    assert_eq!(n.calls, 3);
    let (mut tree, _clock) = naps(|b| b.stateful("nap", nap(true, false)));
    tree.set_sleep_allowed(false);
    for _ in 0..3 {
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
    }
    assert_eq!(n.calls, 6);
}

#[test]
fn keep_running_until_failure_over_a_success_keeps_the_tree_awake() {
    let mut lab = Lab::new(&[&[S]]);
    let mut tree = lab.tree(|b| {
        b.parallel_policy("p", ParallelPolicy::RequireAll, |p| {
            p.keep_running_until_failure("k", |k| k.scripted(0))
                .sleep("z", ms(1000))
        })
    });
    for _ in 0..4 {
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert!(!tree.is_asleep());
    }
    assert_eq!(lab.ticks, [4]);
}
