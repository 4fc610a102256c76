//! Nav2's `test/plugins/decorator/test_distance_controller.cpp`, without ROS: the robot's
//! pose, which the gtest sends through TF, is the `robot_pose` entry.

use crate::support;
use support::*;

use neurotree::nav2::{DistanceController, ROBOT_POSE};
use neurotree::robotics::Pose2D;

fn controller() -> (Tree<Bench>, Bench) {
    let clock = ManualClock::new();
    let tree = tree(&clock, |b| {
        b.custom("distance_controller", DistanceController::spec(), |c| {
            c.dummy(0)
        })
    });
    (tree, Bench::new(1))
}

/// Ports `TEST_F(DistanceControllerTestFixture, test_behavior)`.
#[test]
fn test_behavior() {
    let (mut tree, mut bench) = controller();
    tree.blackboard_mut()
        .set(ROBOT_POSE, Pose2D::default())
        .unwrap();
    assert_eq!(tree.status(NodeId(1)), I);
    bench.set(0, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(children(&tree, 1), [I]);
    for i in 1..=20 {
        let pose = Pose2D::new(f64::from(i) * 0.51, 0.0, 0.0);
        tree.blackboard_mut().set(ROBOT_POSE, pose).unwrap();
        bench.set(0, S);
        if i % 2 == 1 {
            assert_eq!(bench.ok(&mut tree), R, "{i}");
        } else {
            assert_eq!(bench.ok(&mut tree), S, "{i}");
            assert_eq!(children(&tree, 1), [I]);
        }
    }
    assert_eq!(bench.ticks, [11]);
}

/// Not a gtest: without a pose (Nav2: no transform), the node fails and never ticks the
/// child.
#[test]
fn without_a_pose_it_fails() {
    let (mut tree, mut bench) = controller();
    bench.set(0, S);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(bench.ticks, [0]);
}
