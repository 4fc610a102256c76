//! Nav2's `test/plugins/decorator/test_path_longer_on_approach.cpp`, without ROS.

use crate::support;
use support::*;

use neurotree::nav2::PathLongerOnApproach;
use neurotree::robotics::{Path, Pose2D};

fn along_x(n: usize, step: f64, from: usize) -> Path {
    Path::new(
        (from..from + n)
            .map(|i| Pose2D::new(step * i as f64, 0.0, 0.0))
            .collect(),
    )
}

fn approach(prox_len: &str, length_factor: &str) -> (Tree<Bench>, Bench) {
    let clock = ManualClock::new();
    let tree = tree(&clock, |b| {
        b.custom("path_longer", PathLongerOnApproach::spec(), |c| {
            c.ports([
                Port::entry("path", "path"),
                Port::literal("prox_len", prox_len),
                Port::literal("length_factor", length_factor),
            ])
            .dummy(0)
        })
    });
    (tree, Bench::new(1))
}

/// Ports `TEST_F(PathLongerOnApproachTestFixture, test_tick)`.
#[test]
fn test_tick() {
    // A first path: nothing to compare with, Success without ticking the child.
    let (mut tree, mut bench) = approach("5.0", "2.0");
    bench.set(0, S);
    tree.blackboard_mut()
        .set("path", along_x(10, 1.5, 0))
        .unwrap();
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(bench.ticks, [0]);

    // Near the goal (12 m of old path, under 20), a new path to the same goal that is
    // longer (15 m, more than 1.0 times): the child (AlwaysFailure in the gtest) is ticked.
    let (mut tree, mut bench) = approach("20.0", "1.0");
    bench.set(0, F);
    tree.blackboard_mut()
        .set("path", along_x(5, 3.0, 1))
        .unwrap();
    assert_eq!(bench.ok(&mut tree), S);
    tree.blackboard_mut()
        .set("path", along_x(11, 1.5, 0))
        .unwrap();
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(bench.ticks, [1]);
}
