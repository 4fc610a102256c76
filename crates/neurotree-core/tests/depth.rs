//! Deep trees: the depth limit is enforced when building, and within it building, ticking,
//! halting and dropping never overflow a small (2 MiB) stack.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use neurotree_core::nodes::kinds;
use neurotree_core::{
    BuildErrorKind, Builder, Handle, ManualClock, NodeKind, NodeStatus, Observer, StatefulAction,
    Status, StatusChange, Tree, DEFAULT_MAX_DEPTH,
};

/// Counts status changes.
struct CountChanges(Arc<AtomicUsize>);

impl Observer for CountChanges {
    fn on_status_change(&mut self, _c: StatusChange) {
        self.0.fetch_add(1, Ordering::Relaxed);
    }
}

/// Runs until halted; counts halts in the context.
struct Forever;

impl StatefulAction<u32> for Forever {
    fn on_start(&mut self, _h: &mut Handle<'_, u32>) -> Status {
        Status::Running
    }
    fn on_running(&mut self, _h: &mut Handle<'_, u32>) -> Status {
        Status::Running
    }
    fn on_halted(&mut self, h: &mut Handle<'_, u32>) {
        *h.ctx_mut() += 1;
    }
}

/// A chain of `depth` nodes (decorators and one-child sequences) ending in a running leaf.
fn chain(depth: u32) -> Builder<u32> {
    chain_on(Builder::new(), depth)
}

fn chain_on(mut b: Builder<u32>, depth: u32) -> Builder<u32> {
    for level in 0..depth - 1 {
        let kind = match level % 3 {
            0 => NodeKind::Inverter(kinds::Inverter),
            1 => NodeKind::ForceSuccess(kinds::ForceSuccess),
            _ => NodeKind::Sequence(kinds::Sequence),
        };
        b = b.open(kind, "");
    }
    b = b.stateful("bottom", || Forever);
    for _ in 0..depth - 1 {
        b = b.close();
    }
    b
}

fn on_small_stack(f: impl FnOnce() + Send + 'static) {
    std::thread::Builder::new()
        .stack_size(2 * 1024 * 1024)
        .spawn(f)
        .unwrap()
        .join()
        .unwrap();
}

#[test]
fn a_chain_at_the_limit_builds_ticks_halts_and_drops() {
    on_small_stack(|| {
        let bp = chain(DEFAULT_MAX_DEPTH).build_shared().unwrap();
        assert_eq!(bp.len(), DEFAULT_MAX_DEPTH as usize);
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut halts = 0;
        for _ in 0..3 {
            assert_eq!(tree.tick_once(&mut halts), Ok(Status::Running));
            assert_eq!(tree.tick_exactly_once(&mut halts), Ok(Status::Running));
        }
        // Every level is Running down to the leaf; the halt walks the whole chain.
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Running));
        tree.halt(&mut halts);
        assert_eq!(halts, 1);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
        assert_eq!(tree.tick_once(&mut halts), Ok(Status::Running));
        drop(tree);
    });
}

#[test]
fn a_chain_at_the_limit_ticks_and_halts_observed() {
    // The observed code paths (a status write reports to the observer) use their own frames.
    on_small_stack(|| {
        let bp = chain(DEFAULT_MAX_DEPTH).build_shared().unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let changes = Arc::new(AtomicUsize::new(0));
        tree.set_observer(CountChanges(Arc::clone(&changes)));
        let mut halts = 0;
        assert_eq!(tree.tick_once(&mut halts), Ok(Status::Running));
        // Each node went Idle -> Running once.
        assert_eq!(changes.load(Ordering::Relaxed), DEFAULT_MAX_DEPTH as usize);
        tree.halt(&mut halts);
        assert_eq!(halts, 1);
        assert_eq!(
            changes.load(Ordering::Relaxed),
            2 * DEFAULT_MAX_DEPTH as usize
        );
    });
}

#[test]
fn one_level_more_is_rejected() {
    on_small_stack(|| {
        let e = chain(DEFAULT_MAX_DEPTH + 1).build().unwrap_err();
        assert_eq!(
            e.kind,
            BuildErrorKind::TooDeep {
                limit: DEFAULT_MAX_DEPTH
            }
        );
    });
}

#[test]
fn a_chain_of_100000_is_rejected_at_build_time() {
    on_small_stack(|| {
        let e = chain(100_000).build().unwrap_err();
        assert_eq!(
            e.kind,
            BuildErrorKind::TooDeep {
                limit: DEFAULT_MAX_DEPTH
            }
        );
        let message = e.to_string();
        assert!(message.contains('…'), "{message}");
        assert!(
            message.contains("deeper than the limit of 256"),
            "{message}"
        );
    });
}

#[test]
fn a_wide_tree_builds_and_ticks() {
    on_small_stack(|| {
        let mut b = Builder::<u32>::new().open(NodeKind::Sequence(kinds::Sequence), "wide");
        for _ in 0..100_000 {
            b = b.action("inc", |n: &mut u32| {
                *n += 1;
                Status::Success
            });
        }
        let bp = b.close().build_shared().unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut n = 0;
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Success));
        assert_eq!(n, 100_000);
        assert_eq!(tree.tick_exactly_once(&mut n), Ok(Status::Success));
        assert_eq!(n, 200_000);
        drop(tree);
    });
}

#[test]
fn a_wide_tree_halts_its_running_children() {
    on_small_stack(|| {
        let bp = Builder::<u32>::new()
            .parallel_all("wide", 1, |mut p| {
                for _ in 0..100_000 {
                    p = p.stateful("run", || Forever);
                }
                p
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut halts = 0;
        assert_eq!(tree.tick_once(&mut halts), Ok(Status::Running));
        tree.halt(&mut halts);
        assert_eq!(halts, 100_000);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    });
}

#[test]
fn a_raised_limit_accepts_deeper_trees() {
    on_small_stack(|| {
        let bp = chain_on(Builder::new().max_depth(400), 400)
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut halts = 0;
        assert_eq!(tree.tick_once(&mut halts), Ok(Status::Running));
        tree.halt(&mut halts);
        assert_eq!(halts, 1);
    });
}
