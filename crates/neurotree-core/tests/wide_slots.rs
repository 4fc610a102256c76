//! A node's state slots are 32 bits; the kinds that keep a 64-bit value (the moment a wait
//! began, TryCatch's state) keep it in two. Their values keep every bit: a run that starts
//! when the clock reads past 2^32 ns (4.3 s) or far past it, and one saved and restored on
//! the way, run as a run started at 0 does, and as their semantics say.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

use neurotree_core::{Blueprint, Builder, Handle, ManualClock, StatefulAction, Status, Tree};

const MS: Duration = Duration::from_millis(1);

/// Clock readings a run starts at: 0, just past 2^32 ns, and far past it (2^40 ns, 18 min;
/// 2^50 ns, 13 days).
const STARTS: [Duration; 4] = [
    Duration::ZERO,
    Duration::from_nanos((1 << 32) + 1),
    Duration::from_nanos(1 << 40),
    Duration::from_nanos(1 << 50),
];

/// A tree of each kind that keeps a 64-bit value, with its expected results: after each
/// step of `ms` milliseconds, one tick and its result.
type Case = (&'static str, Arc<Blueprint<()>>, Vec<(u32, Status)>);

/// The cases, and the count of the Service's runs, which a whole run of it makes 3.
fn cases() -> (Vec<Case>, Arc<AtomicUsize>) {
    let build = |b: Builder<()>| b.build_shared().unwrap();
    let runs = Arc::new(AtomicUsize::new(0));
    let counted = Arc::clone(&runs);
    let running = Status::Running;
    let cases = vec![
        (
            "Sleep",
            build(Blueprint::builder().sleep("nap", 1500 * MS)),
            vec![(0, running), (1499, running), (1, Status::Success)],
        ),
        (
            "Delay",
            build(Blueprint::builder().delay("d", 1500 * MS, |d| d.always_success("a"))),
            vec![(0, running), (1499, running), (1, Status::Success)],
        ),
        (
            "Timeout",
            build(Blueprint::builder().timeout("t", 1500 * MS, |t| t.sleep("long", 9000 * MS))),
            vec![(0, running), (1499, running), (1, Status::Failure)],
        ),
        (
            "Cooldown",
            build(Blueprint::builder().cooldown("c", 1500 * MS, |c| c.always_success("a"))),
            vec![
                (0, Status::Success),
                (1499, Status::Failure),
                (1, Status::Success),
            ],
        ),
        (
            // The service runs at the start, and then on the first tick at least 1000 ms
            // after its last run: at 0, 1000 and 2499 ms.
            "Service",
            build(Blueprint::builder().service("s", 1000 * MS, |s| {
                s.action("sense", move |_| {
                    counted.fetch_add(1, Ordering::Relaxed);
                    Status::Success
                })
                .sleep("branch", 2500 * MS)
            })),
            vec![
                (0, running),
                (999, running),
                (1, running),
                (1499, running),
                (1, Status::Success),
            ],
        ),
        (
            // The try block fails; the catch, a sleep, runs: the 64-bit state says "in
            // the catch", and the node resumes there rather than in the try block.
            "TryCatch",
            build(Blueprint::builder().try_catch("tc", false, |t| {
                t.always_failure("try").sleep("catch", 1500 * MS)
            })),
            vec![(0, running), (1499, running), (1, Status::Failure)],
        ),
    ];
    (cases, runs)
}

#[test]
fn sixty_four_bit_values_keep_every_bit_from_any_clock_reading() {
    let (cases, runs) = cases();
    for (kind, bp, steps) in cases {
        for start in STARTS {
            runs.store(0, Ordering::Relaxed);
            let clock = ManualClock::new();
            clock.set(start);
            let mut tree = Tree::with_clock(bp.clone(), clock.clone());
            for (i, &(ms, expected)) in steps.iter().enumerate() {
                clock.advance(MS * ms);
                assert_eq!(
                    tree.tick_once(&mut ()),
                    Ok(expected),
                    "{kind}, started at {start:?}, step {i}"
                );
            }
            if kind == "Service" {
                assert_eq!(runs.load(Ordering::Relaxed), 3, "started at {start:?}");
            }
        }
    }
}

#[test]
fn sixty_four_bit_values_survive_a_save_and_restore_onto_another_reading() {
    let (cases, runs) = cases();
    for (kind, bp, steps) in cases {
        for (from, to) in STARTS.iter().zip(STARTS.iter().rev()) {
            runs.store(0, Ordering::Relaxed);
            let clock = ManualClock::new();
            clock.set(*from);
            let mut tree = Tree::with_clock(bp.clone(), clock.clone());
            // The first two steps here, the rest in a tree restored on a clock that reads
            // another time: it waits what was left.
            for &(ms, expected) in &steps[..2] {
                clock.advance(MS * ms);
                assert_eq!(tree.tick_once(&mut ()), Ok(expected), "{kind}");
            }
            let saved = tree.save_state().unwrap();
            let there = ManualClock::new();
            there.set(*to);
            let mut resumed = Tree::with_clock(bp.clone(), there.clone());
            resumed.restore_state(&saved).unwrap();
            assert_eq!(resumed.statuses(), tree.statuses(), "{kind}");
            for (i, &(ms, expected)) in steps[2..].iter().enumerate() {
                there.advance(MS * ms);
                assert_eq!(
                    resumed.tick_once(&mut ()),
                    Ok(expected),
                    "{kind}, saved at {from:?}, restored at {to:?}, step {}",
                    i + 2
                );
            }
            if kind == "Service" {
                assert_eq!(runs.load(Ordering::Relaxed), 3, "{from:?} to {to:?}");
            }
        }
    }
}

#[test]
fn a_fresh_trees_state_bytes_are_its_blueprints_instance_state_bytes() {
    let mut cases: Vec<Arc<Blueprint<()>>> = cases().0.into_iter().map(|c| c.1).collect();
    cases.push(
        Blueprint::builder()
            .sequence("s", |s| {
                s.stateful("a", || Still)
                    .always_success("b")
                    .stateful("c", || Still)
            })
            .build_shared()
            .unwrap(),
    );
    for bp in cases {
        let tree = Tree::with_clock(bp.clone(), ManualClock::new());
        assert_eq!(tree.state_bytes(), bp.instance_state_bytes());
        // At least its shape, a status byte and a failure bit per node.
        assert!(tree.state_bytes() >= 12 + bp.len() + 8);
    }
}

/// A stateful action that runs until halted.
struct Still;

impl StatefulAction<()> for Still {
    fn on_start(&mut self, _: &mut Handle<'_, ()>) -> Status {
        Status::Running
    }
    fn on_running(&mut self, _: &mut Handle<'_, ()>) -> Status {
        Status::Running
    }
}
