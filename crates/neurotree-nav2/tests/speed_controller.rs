//! Nav2's `test/plugins/decorator/test_speed_controller.cpp`, without ROS: the odometry the
//! gtest publishes is the `robot_speed` entry, and its sleeps are a manual clock.

use std::time::Duration;

use crate::support;
use support::*;

use neurotree::nav2::{SpeedController, ROBOT_SPEED};

/// Ports `TEST_F(SpeedControllerTestFixture, test_behavior)`.
#[test]
fn test_behavior() {
    let clock = ManualClock::new();
    let mut tree = tree(&clock, |b| {
        b.custom("speed_controller", SpeedController::spec(), |c| {
            c.ports([
                Port::literal("min_rate", "0.1"),
                Port::literal("max_rate", "1.0"),
                Port::literal("min_speed", "0.0"),
                Port::literal("max_speed", "0.5"),
            ])
            .dummy(0)
        })
    });
    let mut bench = Bench::new(1);
    let second = || clock.advance(Duration::from_secs(1));
    tree.blackboard_mut().set(ROBOT_SPEED, 0.223_f64).unwrap();
    assert_eq!(tree.status(NodeId(1)), I);
    bench.set(0, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(children(&tree, 1), [I]);
    // The first period is 1/max_rate: too early.
    assert_eq!(bench.ok(&mut tree), R);
    second();
    assert_eq!(bench.ok(&mut tree), S);
    // At 0.223 m/s the rate is 0.5014 Hz: a period of about 2 s.
    tree.blackboard_mut().set(ROBOT_SPEED, 0.0_f64).unwrap();
    second();
    assert_eq!(bench.ok(&mut tree), R);
    second();
    assert_eq!(bench.ok(&mut tree), S);
    // Stopped: 0.1 Hz, ten seconds.
    for _ in 0..9 {
        second();
        assert_eq!(bench.ok(&mut tree), R);
    }
    second();
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(bench.ticks, [4]);
}
