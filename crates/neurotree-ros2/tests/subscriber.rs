//! The subscriber condition: Failure before any message, then Success with the newest
//! message on its `message` port.

use crate::common;

use std::time::{Duration, Instant};

use common::{free_domain, node};
use neurotree_ros2::msg::geometry_msgs::{Point, Pose, PoseStamped};
use neurotree_ros2::{LatestMessage, RosTopicSubNode};
use neurotree_toolkit::{Blueprint, Port, Status, Tree};

pub(crate) fn the_condition_fails_until_a_message_arrives_then_outputs_the_newest() {
    let domain = free_domain();
    let robot = node("robot", domain.id);
    let ros = node("tree", domain.id);
    let sub = ros.clone();
    let blueprint = Blueprint::<()>::builder()
        .stateful("goal_received", move || {
            RosTopicSubNode::new(
                sub.clone(),
                "goal_pose",
                LatestMessage::<PoseStamped>::default(),
            )
        })
        .ports([Port::entry("message", "goal")])
        .build_shared()
        .unwrap();
    let mut tree = Tree::new(blueprint);
    let publisher = robot.publisher::<PoseStamped>("goal_pose").unwrap();

    assert_eq!(
        tree.tick_once(&mut ()).unwrap(),
        Status::Failure,
        "no message yet"
    );

    let pose = |x: f64| PoseStamped {
        pose: Pose {
            position: Point { x, y: 2.0, z: 0.0 },
            ..Pose::default()
        },
        ..PoseStamped::default()
    };
    let until = Instant::now() + common::HANG;
    let mut status = Status::Failure;
    while status == Status::Failure && Instant::now() < until {
        publisher.publish(pose(1.0)).unwrap();
        std::thread::sleep(Duration::from_millis(20));
        status = tree.tick_once(&mut ()).unwrap();
    }
    assert_eq!(status, Status::Success);
    assert_eq!(
        tree.blackboard().get::<PoseStamped>("goal").unwrap(),
        pose(1.0)
    );

    // Two more messages between ticks: the newest is kept.
    publisher.publish(pose(3.0)).unwrap();
    publisher.publish(pose(4.0)).unwrap();
    let until = Instant::now() + common::HANG;
    while tree.blackboard().get::<PoseStamped>("goal").unwrap() != pose(4.0)
        && Instant::now() < until
    {
        std::thread::sleep(Duration::from_millis(20));
        assert_eq!(tree.tick_once(&mut ()).unwrap(), Status::Success);
    }
    assert_eq!(
        tree.blackboard().get::<PoseStamped>("goal").unwrap(),
        pose(4.0)
    );
}
