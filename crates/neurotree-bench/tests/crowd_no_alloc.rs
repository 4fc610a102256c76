//! A crowd's frames allocate nothing in steady state, on any thread of the pool, beyond
//! rayon's own queue: a global allocator counts every thread's allocations while frames run.
//!
//! One test in this binary, so that no other test allocates while it counts.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

use neurotree::crowd::Crowd;
use neurotree::{Clock, ManualClock, Tree};
use neurotree_bench::{agent_tree, sleepy_agent_crowd, Agent};

struct Counting;

static WATCHING: AtomicBool = AtomicBool::new(false);
static COUNT: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is forwarded unchanged to the system allocator; counting touches only
// two atomics.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note();
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note();
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note();
        System.realloc(ptr, layout, new_size)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}

fn note() {
    if WATCHING.load(Ordering::Relaxed) {
        COUNT.fetch_add(1, Ordering::Relaxed);
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations made by any thread while `f` runs.
fn allocations(f: impl FnOnce()) -> usize {
    COUNT.store(0, Ordering::SeqCst);
    WATCHING.store(true, Ordering::SeqCst);
    f();
    WATCHING.store(false, Ordering::SeqCst);
    COUNT.load(Ordering::SeqCst)
}

#[test]
fn crowd_frames_allocate_nothing_in_steady_state() {
    // Guards the guard: without this, a broken counter would make the test pass.
    assert!(allocations(|| drop(std::hint::black_box(vec![1u8; 64]))) >= 1);

    let clock = ManualClock::new();
    let shared: Arc<dyn Clock> = Arc::new(clock.clone());
    let bp = agent_tree();
    for threads in [1, 2, 4] {
        let mut crowd = Crowd::with_shared_clock(Arc::clone(&shared))
            .with_threads(threads)
            .unwrap();
        for i in 0..2000u32 {
            // The record of failure reasons made up front, as for any tree that must not
            // allocate while ticking (an agent's Retry gives a reason when it gives up).
            let mut tree = Tree::with_shared_clock(Arc::clone(&bp), Arc::clone(&shared));
            tree.reserve_failure_record();
            crowd.add_tree(tree, Agent::new(i));
        }
        crowd.set_level_of_detail(|a: &Agent| if a.threat > 50 { 4 } else { 1 });
        for budget in [None, Some(40_000)] {
            crowd.set_budget(budget);
            let mut run = |frames: usize| {
                for _ in 0..frames {
                    clock.advance(Duration::from_millis(16));
                    let report = crowd.frame();
                    assert_eq!(report.errors, 0);
                }
            };
            // Warm-up: the pool's threads start, the queue of deferred members grows to
            // its size.
            run(20);
            // Rayon's own: handing a frame to the pool queues one job in its injector,
            // whose blocks hold 63 jobs; a bare `ThreadPool::install(|| ())` allocates as
            // often. The crowd adds nothing to it.
            const FRAMES: usize = 126;
            let n = allocations(|| run(FRAMES));
            assert!(
                n <= FRAMES / 63 + 1,
                "{n} allocations in {FRAMES} frames, {threads} threads, budget {budget:?}"
            );
            if budget.is_some() {
                assert!(crowd.behind().overdue > 0);
            }
        }
    }

    // Sleeping members: woken by writes, by the crowd and from a waker, and by their
    // deadlines (the agent tree's Delay and Sleep), falling asleep again.
    for threads in [1, 2] {
        let mut crowd = sleepy_agent_crowd(2000, threads, clock.clone());
        for mut member in crowd.iter_mut() {
            member.tree_mut().reserve_failure_record();
        }
        let ids: Vec<_> = crowd.iter().map(|m| m.id()).collect();
        let waker = crowd.waker();
        let mut next = 0;
        let mut alerted = Vec::new();
        // The frames' allocations and those of the alerts written on the crowd's threads
        // (the writes themselves find their entry, declared when the crowd was made): 20
        // agents, each named again and again, enough names to be shared among threads.
        let mut run = |frames: usize| {
            let mut n = 0;
            for f in 0..frames {
                alerted.clear();
                for _ in 0..20 {
                    alerted.push(ids[next % ids.len()]);
                    next += 7;
                }
                while alerted.len() < neurotree::crowd::SHARED_VISITS {
                    alerted.extend_from_within(..20);
                }
                let calls = AtomicUsize::new(0);
                let alert = |mut member: neurotree::crowd::MemberMut<'_, _>| {
                    calls.fetch_add(1, Ordering::Relaxed);
                    member
                        .tree_mut()
                        .blackboard_mut()
                        .set("alert", true)
                        .unwrap();
                };
                waker.wake(ids[next % ids.len()]);
                crowd.wake(ids[(next + 3) % ids.len()]);
                clock.advance(Duration::from_millis(16));
                let mut report = None;
                // Every other frame delivers its alerts in the frame's own trip to the pool.
                if f % 2 == 0 {
                    n += allocations(|| crowd.for_each_mut(&alerted, alert));
                    n += allocations(|| report = Some(crowd.frame()));
                } else {
                    n += allocations(|| report = Some(crowd.frame_with(&alerted, alert)));
                }
                assert_eq!(calls.into_inner(), alerted.len());
                let report = report.unwrap();
                assert_eq!(report.errors, 0);
                assert!(report.frame == 0 || report.asleep > 1000, "{report:?}");
                assert!(report.ticked >= 20, "the 20 alerted tick: {report:?}");
            }
            n
        };
        // Warm-up: the heaps of deadlines, the lists of sleepers to watch and the room of
        // the alerts' sort grow to their size.
        run(300);
        const FRAMES: usize = 126;
        let n = run(FRAMES);
        // At most two jobs handed to the pool per frame (the alerts, the frame), and nothing else:
        // each agent clears its alert in its tick by writing the entry in place.
        assert!(
            n <= 2 * FRAMES / 63 + 2,
            "{n} allocations in {FRAMES} frames of sleeping members, {threads} threads"
        );
    }
}
