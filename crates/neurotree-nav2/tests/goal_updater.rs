//! Nav2's `test/plugins/decorator/test_goal_updater_node.cpp`, without ROS: the messages the
//! gtest publishes on `goal_update` and `goals_update` are entries of those names, stamped
//! with the time they were written.

use std::time::Duration;

use crate::support;
use support::*;

use neurotree::nav2::{GoalUpdater, GOALS_UPDATE, GOAL_UPDATE};
use neurotree::robotics::Pose2D;

fn updater(clock: &ManualClock) -> (Tree<Bench>, Bench) {
    let tree = tree(clock, |b| {
        b.custom("goal_updater", GoalUpdater::spec(), |c| {
            c.ports([
                Port::entry("input_goal", "goal"),
                Port::entry("input_goals", "goals"),
                Port::entry("output_goal", "updated_goal"),
                Port::entry("output_goals", "updated_goals"),
            ])
            .dummy(0)
        })
    });
    let mut bench = Bench::new(1);
    bench.set(0, S);
    (tree, bench)
}

fn set<T: Send + Sync + 'static>(tree: &mut Tree<Bench>, clock: &ManualClock, key: &str, v: T) {
    let now = neurotree::Clock::now(clock);
    tree.blackboard_mut()
        .set_in(neurotree::ScopeId::ROOT, key, v, now)
        .unwrap();
}

fn outputs(tree: &Tree<Bench>) -> (Pose2D, Vec<Pose2D>) {
    (
        tree.blackboard().get("updated_goal").unwrap(),
        tree.blackboard().get("updated_goals").unwrap(),
    )
}

/// Ports `TEST_F(GoalUpdaterTestFixture, test_tick)`.
#[test]
fn test_tick() {
    let clock = ManualClock::new();
    let (mut tree, mut bench) = updater(&clock);
    let goal = Pose2D::new(1.0, 0.0, 0.0);
    set(&mut tree, &clock, "goal", goal);
    set(&mut tree, &clock, "goals", vec![goal]);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(outputs(&tree), (goal, vec![goal]));
}

/// Ports `TEST_F(GoalUpdaterTestFixture, test_older_goal_update)`.
#[test]
fn test_older_goal_update() {
    let clock = ManualClock::new();
    let (mut tree, mut bench) = updater(&clock);
    let older = Pose2D::new(2.0, 0.0, 0.0);
    set(&mut tree, &clock, GOAL_UPDATE, older);
    set(&mut tree, &clock, GOALS_UPDATE, vec![older]);
    clock.advance(Duration::from_secs(1));
    let goal = Pose2D::new(1.0, 0.0, 0.0);
    set(&mut tree, &clock, "goal", goal);
    set(&mut tree, &clock, "goals", vec![goal]);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(outputs(&tree), (goal, vec![goal]));
}

/// Ports `TEST_F(GoalUpdaterTestFixture, test_get_latest_goal_update)`.
#[test]
fn test_get_latest_goal_update() {
    let clock = ManualClock::new();
    let (mut tree, mut bench) = updater(&clock);
    let goal = Pose2D::new(1.0, 0.0, 0.0);
    set(&mut tree, &clock, "goal", goal);
    set(&mut tree, &clock, "goals", vec![goal]);
    clock.advance(Duration::from_millis(10));
    // Two messages each: the entry keeps the last.
    for x in [2.0, 3.0] {
        let update = Pose2D::new(x, 0.0, 0.0);
        set(&mut tree, &clock, GOAL_UPDATE, update);
        set(&mut tree, &clock, GOALS_UPDATE, vec![update]);
    }
    assert_eq!(bench.ok(&mut tree), S);
    let latest = Pose2D::new(3.0, 0.0, 0.0);
    assert_eq!(outputs(&tree), (latest, vec![latest]));
    assert_eq!(bench.ticks, [1]);
}
