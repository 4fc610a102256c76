//! Nav2's `test/plugins/decorator/test_goal_updated_controller.cpp`, without ROS. The
//! gtest's goals differ by time stamp only; a `Pose2D` has none, so here they differ by
//! position.

use crate::support;
use support::*;

use neurotree::nav2::GoalUpdatedController;
use neurotree::robotics::Pose2D;

/// Ports `TEST_F(GoalUpdatedControllerTestFixture, test_behavior)`.
#[test]
fn test_behavior() {
    let clock = ManualClock::new();
    let mut tree = tree(&clock, |b| {
        b.custom(
            "goal_updated_controller",
            GoalUpdatedController::spec(),
            |c| c.dummy(0),
        )
    });
    let mut bench = Bench::new(1);
    let goal1 = Pose2D::default();
    let goal2 = Pose2D::new(1.0, 0.0, 0.0);
    tree.blackboard_mut().set("goal", goal1).unwrap();
    tree.blackboard_mut().set("goals", vec![goal1]).unwrap();
    assert_eq!(tree.status(NodeId(1)), I);
    bench.set(0, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(children(&tree, 1), [I]);
    tree.blackboard_mut().set("goal", goal2).unwrap();
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(children(&tree, 1), [I]);
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(children(&tree, 1), [I]);
    tree.blackboard_mut().set("goals", vec![goal2]).unwrap();
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(children(&tree, 1), [I]);
    assert_eq!(bench.ticks, [3]);
}
