//! Nav2's `test/plugins/control/test_round_robin_node.cpp`, without ROS.

use crate::support;
use support::*;

use neurotree::nav2::RoundRobin;

/// RoundRobin(dummy0, dummy1, dummy2), `wrap_around` as given (the fixture's is "true").
fn round_robin(wrap: &str) -> (Tree<Bench>, Bench) {
    let clock = ManualClock::new();
    let tree = tree(&clock, |b| {
        b.custom("round_robin", RoundRobin::spec(), |c| {
            c.ports([Port::literal("wrap_around", wrap)])
                .dummy(0)
                .dummy(1)
                .dummy(2)
        })
    });
    (tree, Bench::new(3))
}

/// Ports `TEST_F(RoundRobinNodeTestFixture, test_failure_on_idle_child)`.
#[test]
fn test_failure_on_idle_child() {
    let (mut tree, mut bench) = round_robin("true");
    bench.set(0, I);
    assert!(matches!(bench.tick(&mut tree), Err(TickError::Node { .. })));
}

/// Ports `TEST_F(RoundRobinNodeTestFixture, test_failure)`.
#[test]
fn test_failure() {
    let (mut tree, mut bench) = round_robin("true");
    bench.set(0, F);
    bench.set(1, R);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(1, F);
    bench.set(2, R);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(2, F);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(children(&tree, 3), [I, I, I]);
    assert_eq!(bench.ticks, [1, 2, 2]);
}

/// Ports `TEST_F(RoundRobinNodeTestFixture, test_behavior)`.
#[test]
fn test_behavior() {
    let (mut tree, mut bench) = round_robin("true");
    bench.set(0, R);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(0, F);
    bench.set(1, R);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(1, S);
    assert_eq!(bench.ok(&mut tree), S);
    bench.set(2, R);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(0, R);
    bench.set(2, F);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(0, F);
    bench.set(1, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(children(&tree, 3), [I, I, I]);
    assert_eq!(bench.ticks, [4, 3, 2]);
    assert_eq!(bench.halts, [0, 0, 0]);
}

/// Ports `TEST_F(RoundRobinNodeTestFixture, test_skikpped)`.
#[test]
fn test_skipped() {
    let (mut tree, mut bench) = round_robin("true");
    bench.set(0, K);
    bench.set(1, S);
    bench.set(2, F);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(children(&tree, 3), [I, I, I]);
    bench.set(1, K);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(children(&tree, 3), [I, I, I]);
    bench.set(2, K);
    assert_eq!(bench.ok(&mut tree), K);
    assert_eq!(children(&tree, 3), [I, I, I]);
}

/// Ports `TEST_F(RoundRobinNodeTestFixture, test_wrap_around_disabled)`, and adds the case
/// the gtest leaves out: the last child's Success.
#[test]
fn test_wrap_around_disabled() {
    let (mut tree, mut bench) = round_robin("false");
    for i in 0..3 {
        bench.set(i, F);
    }
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(bench.ticks, [1, 1, 1]);
    for i in 0..3 {
        bench.set(i, K);
    }
    assert_eq!(bench.ok(&mut tree), K);
    assert_eq!(children(&tree, 3), [I, I, I]);

    let (mut tree, mut bench) = round_robin("false");
    bench.set(0, S);
    bench.set(1, S);
    bench.set(2, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(bench.ok(&mut tree), S);
    // The last child succeeds: the node halts itself and fails.
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(children(&tree, 3), [I, I, I]);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(bench.ticks, [2, 1, 1]);
}
