//! Nav2's `test/plugins/decorator/test_single_trigger_node.cpp`, without ROS.

use crate::support;
use support::*;

use neurotree::nav2::SingleTrigger;

/// Ports `TEST_F(SingleTriggerTestFixture, test_behavior)`.
#[test]
fn test_behavior() {
    let clock = ManualClock::new();
    let mut tree = tree(&clock, |b| {
        b.custom("single_trigger", SingleTrigger::spec(), |c| c.dummy(0))
    });
    let mut bench = Bench::new(1);
    assert_eq!(tree.status(NodeId(1)), I);
    bench.set(0, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(children(&tree, 1), [I]);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(bench.ticks, [1]);
    // The gtest halts the node and resets it to Idle: a new run.
    tree.halt(&mut bench);
    bench.set(0, R);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(0, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(bench.ticks, [3]);
}
