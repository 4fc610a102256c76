//! Nav2's `test/plugins/control/test_nonblocking_sequence.cpp`, without ROS.

use crate::support;
use support::*;

use neurotree::nav2::NonblockingSequence;

fn sequence() -> (Tree<Bench>, Bench) {
    let clock = ManualClock::new();
    let tree = tree(&clock, |b| {
        b.custom("nonblocking_sequence", NonblockingSequence::spec(), |c| {
            c.dummy(0).dummy(1).dummy(2)
        })
    });
    (tree, Bench::new(3))
}

/// Ports `TEST_F(NonblockingSequenceTestFixture, test_failure_on_idle_child)`.
#[test]
fn test_failure_on_idle_child() {
    let (mut tree, mut bench) = sequence();
    assert!(matches!(bench.tick(&mut tree), Err(TickError::Node { .. })));
}

/// Ports `TEST_F(NonblockingSequenceTestFixture, test_failure)`.
#[test]
fn test_failure() {
    let (mut tree, mut bench) = sequence();
    bench.set(0, F);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(children(&tree, 3), [I, I, I]);
    assert_eq!(bench.ticks, [1, 0, 0]);
    bench.set(0, S);
    bench.set(1, F);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(children(&tree, 3), [I, I, I]);
    bench.set(1, S);
    bench.set(2, F);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(children(&tree, 3), [I, I, I]);
    bench.set(2, R);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(0, F);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(children(&tree, 3), [I, I, I]);
    // The Running third child is halted once by the failure of the first.
    assert_eq!(bench.halts, [0, 0, 1]);
    assert_eq!(bench.ticks, [5, 3, 2]);
}

/// Ports `TEST_F(NonblockingSequenceTestFixture, test_behavior)`.
#[test]
fn test_behavior() {
    let (mut tree, mut bench) = sequence();
    bench.set(0, R);
    bench.set(1, S);
    bench.set(2, R);
    assert_eq!(bench.ok(&mut tree), R);
    // Every child is ticked although the first runs.
    assert_eq!(bench.ticks, [1, 1, 1]);
    bench.set(0, S);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(0, R);
    bench.set(2, S);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(0, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(children(&tree, 3), [I, I, I]);
    bench.set(0, R);
    bench.set(1, R);
    bench.set(2, F);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(children(&tree, 3), [I, I, I]);
    assert_eq!(bench.halts, [1, 1, 0]);
    assert_eq!(bench.ticks, [5, 5, 5]);
}
