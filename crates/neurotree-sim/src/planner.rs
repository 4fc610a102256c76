//! The grid world as a [`MotionPlanner`], so the navigation node drives the simulated robot.
//!
//! Plans are A* on the global costmap (plus the obstacles the node passes); execution is a
//! follow command at the world's speed, carried out by [`GridWorld::step`]; a path is clear
//! while the global costmap holds none of its cells ahead of the robot blocked.

use super::motion::MotionStatus;
use super::world::GridWorld;
use neurotree_nav2::robotics::{MotionPlanner, NavigationError, Obstacle, Path, Pose2D, Progress};

impl MotionPlanner for GridWorld {
    fn plan_path(
        &mut self,
        start: Pose2D,
        goal: Pose2D,
        obstacles: &[Obstacle],
    ) -> Result<Path, NavigationError> {
        for pose in [start, goal] {
            if self.map().cell_at(&pose).is_none() {
                return Err(NavigationError::OutsideMap(pose));
            }
        }
        self.plan_around(start, goal, obstacles)
            .ok_or(NavigationError::NoPath {
                from: start,
                to: goal,
            })
    }

    fn execute_path(&mut self, path: &Path) -> Result<Progress, NavigationError> {
        if self.followed_path() != Some(path) {
            if self.battery().is_empty() {
                return Err(NavigationError::CannotMove("the battery is empty".into()));
            }
            self.follow(path.clone(), self.speed);
            return Ok(Progress::Moving);
        }
        match self.motion_status() {
            MotionStatus::Active => Ok(Progress::Moving),
            MotionStatus::Succeeded => Ok(Progress::Finished),
            MotionStatus::Blocked(_) => Err(NavigationError::Blocked { at: self.robot() }),
            MotionStatus::BatteryEmpty => {
                Err(NavigationError::CannotMove("the battery is empty".into()))
            }
            // A follow command is never Idle: `stop` drops the command with its status.
            MotionStatus::Idle => Ok(Progress::Moving),
        }
    }

    fn is_path_clear(&self, path: &Path) -> bool {
        let here = self.robot_cell();
        let from = path.closest_index(&self.robot()).unwrap_or(0);
        let costmap = self.costmap(super::CostmapLayer::Global);
        path.poses[from..]
            .iter()
            .filter(|p| self.map().cell_at(p) != Some(here))
            .all(|p| {
                self.map()
                    .cell_at(p)
                    .is_some_and(|c| !costmap.is_blocked(c))
            })
    }

    fn current_pose(&self) -> Pose2D {
        self.robot()
    }

    fn stop_execution(&mut self) {
        self.stop();
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;
    use crate::{Cell, TimedObstacle};
    use neurotree_nav2::robotics::{register_navigation, register_sensor, RoboticsBuilder};
    use neurotree_toolkit::{Blueprint, Status, Tree, XmlLoader};

    const HALF: Duration = Duration::from_millis(500);

    /// Two rows of six cells; the robot bottom left.
    fn corridor() -> GridWorld {
        GridWorld::parse(
            "
            ......
            R.....",
            1.0,
        )
        .unwrap()
    }

    fn navigation(world: &GridWorld, goal: Pose2D) -> Tree<GridWorld> {
        let bp = Blueprint::<GridWorld>::builder()
            .navigate("go", "goal", 0.1, |w: &mut GridWorld| w)
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, world.clock());
        tree.blackboard_mut().set("goal", goal).unwrap();
        tree
    }

    /// Ticks, stepping the world after every Running tick; returns the final status and
    /// the number of ticks.
    fn run(tree: &mut Tree<GridWorld>, world: &mut GridWorld, limit: u32) -> (Status, u32) {
        for tick in 1..=limit {
            match tree.tick_once(world).unwrap() {
                Status::Running => world.step(HALF),
                done => return (done, tick),
            };
        }
        (Status::Running, limit)
    }

    #[test]
    fn navigation_reaches_the_goal_on_a_free_corridor() {
        let mut w = corridor();
        let goal = Pose2D::new(5.5, 0.5, 0.0);
        let mut tree = navigation(&w, goal);
        // 5 m at 1 m/s in half-second steps, and the tick that sees the arrival.
        assert_eq!(run(&mut tree, &mut w, 100), (Status::Success, 11));
        assert_eq!(w.robot(), goal);
        assert_eq!((w.plan_count(), w.stop_count()), (1, 0));
        assert_eq!(w.distance_travelled(), 5.0);
    }

    #[test]
    fn navigation_replans_when_a_timed_obstacle_blocks_the_path() {
        // At 2 s the robot is at x = 2.5; the obstacle lands two cells ahead, within
        // sensing range, so the next tick finds the path blocked and plans round it.
        let mut w = corridor()
            .with_timed_obstacle(TimedObstacle::new(Cell::new(4, 0), Duration::from_secs(2)));
        let goal = Pose2D::new(5.5, 0.5, 0.0);
        let mut tree = navigation(&w, goal);
        let (status, ticks) = run(&mut tree, &mut w, 100);
        assert_eq!(status, Status::Success);
        assert_eq!(w.robot(), goal);
        assert_eq!(w.plan_count(), 2);
        assert_eq!(w.stop_count(), 0);
        // 2 m straight; then diagonally up, 2 m along the top row, and straight down (a
        // diagonal down would cut the obstacle's corner): 5 m + √2.
        let travelled = w.distance_travelled();
        assert!(
            (travelled - (5.0 + std::f64::consts::SQRT_2)).abs() < 1e-9,
            "{travelled}"
        );
        // Four ticks to x = 2.5, the tick that replans, nine half-metre steps for the
        // 4.41 m detour, and the tick that sees the arrival.
        assert_eq!(ticks, 14);
        assert!(!w
            .costmap(crate::CostmapLayer::Global)
            .is_blocked(Cell::new(3, 0)));
        assert!(w
            .costmap(crate::CostmapLayer::Global)
            .is_marked(Cell::new(4, 0)));
    }

    #[test]
    fn halting_the_tree_stops_the_robot_exactly_once() {
        let mut w = corridor();
        let mut tree = navigation(&w, Pose2D::new(5.5, 0.5, 0.0));
        assert_eq!(run(&mut tree, &mut w, 3), (Status::Running, 3));
        assert_eq!(w.robot(), Pose2D::new(2.0, 0.5, 0.0));
        tree.halt(&mut w);
        assert_eq!((w.stop_count(), w.motion_status()), (1, MotionStatus::Idle));
        tree.halt(&mut w);
        assert_eq!(w.stop_count(), 1);
        w.step(HALF);
        w.step(HALF);
        assert_eq!(w.robot(), Pose2D::new(2.0, 0.5, 0.0));
    }

    #[test]
    fn an_unreachable_goal_fails_without_moving() {
        let mut w = GridWorld::parse("R.#.", 1.0).unwrap();
        let mut tree = navigation(&w, Pose2D::new(3.5, 0.5, 0.0));
        assert_eq!(run(&mut tree, &mut w, 10), (Status::Failure, 1));
        assert_eq!(w.distance_travelled(), 0.0);
        let mut off = navigation(&w, Pose2D::new(9.5, 0.5, 0.0));
        assert_eq!(run(&mut off, &mut w, 10), (Status::Failure, 1));
        assert_eq!(
            w.plan_path(w.robot(), Pose2D::new(9.5, 0.5, 0.0), &[]),
            Err(NavigationError::OutsideMap(Pose2D::new(9.5, 0.5, 0.0)))
        );
    }

    #[test]
    fn execute_path_reports_progress_of_the_path_it_follows() {
        let mut w = corridor();
        let path = w.plan(w.robot(), Pose2D::new(1.5, 0.5, 0.0)).unwrap();
        assert_eq!(w.execute_path(&path), Ok(Progress::Moving));
        w.step(HALF);
        assert_eq!(w.execute_path(&path), Ok(Progress::Moving));
        w.step(HALF);
        assert_eq!(w.execute_path(&path), Ok(Progress::Finished));
        // Another path starts afresh.
        let back = w.plan(w.robot(), Pose2D::new(0.5, 0.5, 0.0)).unwrap();
        assert_eq!(w.execute_path(&back), Ok(Progress::Moving));
        assert_eq!(w.followed_path(), Some(&back));
    }

    #[test]
    fn only_the_path_ahead_must_be_clear() {
        let mut w = corridor().with_sensing_radius(10.0);
        let path = w.plan(w.robot(), Pose2D::new(5.5, 0.5, 0.0)).unwrap();
        w.follow(path.clone(), 1.0);
        for _ in 0..6 {
            w.step(HALF);
        }
        assert_eq!(w.robot(), Pose2D::new(3.5, 0.5, 0.0));
        let w = w
            .with_timed_obstacle(TimedObstacle::new(Cell::new(1, 0), Duration::ZERO))
            .with_timed_obstacle(TimedObstacle::new(Cell::new(3, 0), Duration::ZERO));
        // Behind the robot, and the cell it stands in, do not count.
        assert!(w.is_path_clear(&path));
        assert!(!w.is_path_free(&path));
        let w = w.with_timed_obstacle(TimedObstacle::new(Cell::new(5, 0), Duration::ZERO));
        assert!(!w.is_path_clear(&path));
    }

    #[test]
    fn xml_trees_drive_the_world() {
        let mut registry = neurotree_toolkit::Registry::<GridWorld>::new();
        register_navigation(&mut registry, "Navigate", |w: &mut GridWorld| w).unwrap();
        register_sensor(&mut registry, "ReadBattery", |w: &mut GridWorld| {
            w.battery_sensor()
        })
        .unwrap();
        let mut loader = XmlLoader::new(&registry);
        loader
            .load_str(
                r#"<root BTCPP_format="4">
                     <BehaviorTree ID="Main">
                       <Sequence>
                         <ReadBattery output="{battery}" min_quality="0.9"/>
                         <Navigate goal="3.5;1.5;1.57" goal_tolerance="0.2" path="{path}"/>
                         <ReadBattery output="{battery_after}"/>
                       </Sequence>
                     </BehaviorTree>
                   </root>"#,
                "drive.xml",
            )
            .unwrap();
        let mut w = corridor();
        let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), w.clock());
        let (status, _) = run(&mut tree, &mut w, 100);
        assert_eq!(status, Status::Success);
        assert_eq!(w.robot(), Pose2D::new(3.5, 1.5, 1.57));
        let before: neurotree_nav2::robotics::SensorData =
            tree.blackboard().get("battery").unwrap();
        let after: neurotree_nav2::robotics::SensorData =
            tree.blackboard().get("battery_after").unwrap();
        assert_eq!(before.number("level"), Some(100.0));
        let used = 100.0 - after.number("level").unwrap();
        assert!((used - w.distance_travelled()).abs() < 1e-9, "{used}");
        let path: Path = tree.blackboard().get("path").unwrap();
        assert_eq!(path.goal(), Some(Pose2D::new(3.5, 1.5, 1.57)));
    }
}
