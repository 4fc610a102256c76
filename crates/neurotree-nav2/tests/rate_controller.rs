//! Nav2's `test/plugins/decorator/test_rate_controller.cpp`, without ROS: its sleeps are a
//! manual clock.

use std::time::Duration;

use crate::support;
use support::*;

use neurotree::nav2::RateController;

/// Ports `TEST_F(RateControllerTestFixture, test_behavior)`. The fixture assigns the double
/// 10.0 to the port's text, which makes it the character 10: `hz` does not parse and
/// Nav2's node keeps its 1 Hz; so `hz` is 1 here.
#[test]
fn test_behavior() {
    let clock = ManualClock::new();
    let mut tree = tree(&clock, |b| {
        b.custom("rate_controller", RateController::spec(), |c| {
            c.ports([Port::literal("hz", "1.0")]).dummy(0)
        })
    });
    let mut bench = Bench::new(1);
    assert_eq!(tree.status(NodeId(1)), I);
    bench.set(0, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(children(&tree, 1), [I]);
    for i in 0..10 {
        bench.set(0, S);
        clock.advance(Duration::from_millis(500));
        if i % 2 == 1 {
            assert_eq!(bench.ok(&mut tree), S, "{i}");
            assert_eq!(children(&tree, 1), [I]);
        } else {
            assert_eq!(bench.ok(&mut tree), R, "{i}");
        }
    }
    assert_eq!(bench.ticks, [6]);
}
