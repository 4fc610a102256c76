//! Nav2's `test/plugins/control/test_recovery_node.cpp`, without ROS. The gtest's
//! `returnSuccessOn(1)` / `returnFailureOn(1)` (a different status on the next tick) are
//! queued outcomes.

use crate::support;
use support::*;

use neurotree::nav2::RecoveryNode;

fn recovery() -> (Tree<Bench>, Bench) {
    let clock = ManualClock::new();
    let tree = tree(&clock, |b| {
        b.custom("recovery", RecoveryNode::spec(), |c| {
            c.ports([Port::literal("number_of_retries", "1")])
                .dummy(0)
                .dummy(1)
        })
    });
    (tree, Bench::new(2))
}

/// Ports `TEST_F(RecoveryNodeTestFixture, test_only_two_children)`: refused when built.
#[test]
fn test_only_two_children() {
    let built = Builder::<Bench>::new()
        .custom("recovery", RecoveryNode::spec(), |c| {
            c.dummy(0).dummy(1).dummy(2)
        })
        .build_shared();
    assert!(built.is_err());
}

/// Ports `TEST_F(RecoveryNodeTestFixture, test_running)`.
#[test]
fn test_running() {
    let (mut tree, mut bench) = recovery();
    bench.set(0, R);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(0, F);
    bench.set(1, R);
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(bench.ticks, [2, 1]);
}

/// Ports `TEST_F(RecoveryNodeTestFixture, test_failure_on_idle_child)`.
#[test]
fn test_failure_on_idle_child() {
    let (mut tree, mut bench) = recovery();
    assert!(matches!(bench.tick(&mut tree), Err(TickError::Node { .. })));
    let (mut tree, mut bench) = recovery();
    bench.set(0, F);
    assert!(matches!(bench.tick(&mut tree), Err(TickError::Node { .. })));
}

/// Ports `TEST_F(RecoveryNodeTestFixture, test_success_one_retry)`.
#[test]
fn test_success_one_retry() {
    let (mut tree, mut bench) = recovery();
    bench.set(0, S);
    assert_eq!(bench.ok(&mut tree), S);
    bench.queued[0].push_back(F);
    bench.set(1, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(children(&tree, 2), [I, I]);
    assert_eq!(bench.ticks, [3, 1]);
}

/// Ports `TEST_F(RecoveryNodeTestFixture, test_failure_one_retry)`.
#[test]
fn test_failure_one_retry() {
    let (mut tree, mut bench) = recovery();
    bench.set(0, F);
    bench.set(1, F);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(children(&tree, 2), [I, I]);
    bench.set(1, S);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(children(&tree, 2), [I, I]);
    // One retry: the action fails twice around one recovery.
    assert_eq!(bench.ticks, [3, 2]);
}

/// Ports `TEST_F(RecoveryNodeTestFixture, test_skipping)`.
#[test]
fn test_skipping() {
    let (mut tree, mut bench) = recovery();
    bench.set(0, K);
    bench.set(1, S);
    assert_eq!(bench.ok(&mut tree), K);
    assert_eq!(children(&tree, 2), [I, I]);
    bench.set(0, F);
    bench.set(1, K);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(children(&tree, 2), [I, I]);
}
