//! Nav2's `test/plugins/control/test_pipeline_sequence.cpp`, without ROS.

use crate::support;
use support::*;

use neurotree::nav2::PipelineSequence;

fn pipeline() -> (Tree<Bench>, Bench) {
    let clock = ManualClock::new();
    let tree = tree(&clock, |b| {
        b.custom("pipeline", PipelineSequence::spec(), |c| {
            c.dummy(0).dummy(1).dummy(2)
        })
    });
    (tree, Bench::new(3))
}

/// Ports `TEST_F(PipelineSequenceTestFixture, test_failure_on_idle_child)`.
#[test]
fn test_failure_on_idle_child() {
    let (mut tree, mut bench) = pipeline();
    assert!(matches!(bench.tick(&mut tree), Err(TickError::Node { .. })));
}

/// Ports `TEST_F(PipelineSequenceTestFixture, test_failure)`.
#[test]
fn test_failure() {
    let (mut tree, mut bench) = pipeline();
    bench.set(0, F);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(children(&tree, 3), [I, I, I]);
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
    assert_eq!(bench.halts, [0, 0, 1]);
}

/// Ports `TEST_F(PipelineSequenceTestFixture, test_behavior)`.
#[test]
fn test_behavior() {
    let (mut tree, mut bench) = pipeline();
    bench.set(0, R);
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(bench.ticks, [1, 0, 0]);
    bench.set(0, S);
    bench.set(1, R);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(0, R);
    bench.set(1, S);
    bench.set(2, R);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(2, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(children(&tree, 3), [I, I, I]);
    // The first child, Running when the pipeline completed, is halted once.
    assert_eq!(bench.halts, [1, 0, 0]);
    assert_eq!(bench.ticks, [4, 3, 2]);
}

/// Ports `TEST_F(PipelineSequenceTestFixture, test_skipped)`.
#[test]
fn test_skipped() {
    let (mut tree, mut bench) = pipeline();
    bench.set(0, K);
    bench.set(1, S);
    bench.set(2, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(children(&tree, 3), [I, I, I]);
    bench.set(2, F);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(children(&tree, 3), [I, I, I]);
    bench.set(1, K);
    bench.set(2, K);
    assert_eq!(bench.ok(&mut tree), K);
    assert_eq!(children(&tree, 3), [I, I, I]);
}
