//! The demo's world: a warehouse, a goal, and an obstacle that steps onto the robot's path.

use std::time::Duration;

use neurotree::robotics::Pose2D;
use neurotree::sim::nav2::Nav2Params;
use neurotree::sim::{Cell, GridWorld, MapError, TimedObstacle};

/// The warehouse of `neurotree demo`, 1 m cells: the loading hall on the left, joined to
/// the store by two doors; shelves in both; the robot at the top left.
pub const WAREHOUSE: &str = "
    ########################################
    #R.........#...........................#
    #..........#.....................##....#
    #..........#.....######..........##....#
    #....###...#...........................#
    #....###...............................#
    #..........#......######...............#
    #..........#...........................#
    #..........#.................######....#
    #....###...#...........................#
    #....###...#.....######................#
    #..........................#...........#
    #..........#...............#...........#
    #..........#...............#...........#
    ########################################";

/// Where the robot is sent unless told otherwise: the far corner of the store.
pub const DEFAULT_GOAL: Pose2D = Pose2D::new(36.5, 1.5, 0.0);

/// How long after the start of a second the obstacle appears: just after the 1 Hz
/// navigator has planned, so that its next plan comes too late to avoid it.
const AFTER_PLAN: Duration = Duration::from_millis(50);

/// What happens in a demo run: where the robot goes, and the obstacle in its way.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// The seed it was made from.
    pub seed: u64,
    /// Where the robot is sent.
    pub goal: Pose2D,
    /// The obstacle that steps onto the first path, if the goal can be reached at all.
    pub obstacle: Option<TimedObstacle>,
}

impl Scenario {
    /// The scenario of `seed` for a robot sent to `goal` in the [`WAREHOUSE`] with the
    /// servers' `params`.
    ///
    /// The seed picks a cell of the first path (neither of the first two nor the last
    /// one) and whether the obstacle that appears there stays or leaves again after a few
    /// seconds. It appears in the second the robot would reach the cell before it, just
    /// after the navigator planned, so that the robot meets it before the next plan: it is
    /// blocked, and recovers. The same seed gives the same scenario.
    pub fn new(seed: u64, goal: Pose2D, params: &Nav2Params) -> Result<Self, MapError> {
        let mut world = GridWorld::parse(WAREHOUSE, 1.0)?;
        let obstacle = world
            .plan(world.robot(), goal)
            .and_then(|path| Self::obstacle_on(seed, &world, &path.poses, params.speed));
        Ok(Self {
            seed,
            goal,
            obstacle,
        })
    }

    fn obstacle_on(
        seed: u64,
        world: &GridWorld,
        path: &[Pose2D],
        speed: f64,
    ) -> Option<TimedObstacle> {
        // Poses 1.. are cell centres; the last one is the goal's cell.
        if path.len() < 5 || speed.is_nan() || speed <= 0.0 {
            return None;
        }
        let mut rng = fastrand::Rng::with_seed(seed);
        let at = rng.usize(2..path.len() - 1);
        let cell: Cell = world.map().cell_at(&path[at])?;
        // The robot stops in front of the cell on reaching the pose before it.
        let reach: f64 = path[..at].windows(2).map(|w| w[0].distance(&w[1])).sum();
        let second = (reach / speed).floor();
        let appears = Duration::try_from_secs_f64(second).ok()? + AFTER_PLAN;
        let obstacle = TimedObstacle::new(cell, appears);
        Some(match rng.u8(0..3) {
            0 => obstacle.until(appears + Duration::from_secs(rng.u64(3..8))),
            _ => obstacle,
        })
    }

    /// The world of the scenario: the warehouse, with its obstacle and the sensors' noise
    /// drawn from the seed.
    pub fn world(&self) -> Result<GridWorld, MapError> {
        let world = GridWorld::parse(WAREHOUSE, 1.0)?.with_seed(self.seed);
        Ok(match self.obstacle {
            Some(obstacle) => world.with_timed_obstacle(obstacle),
            None => world,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_seed_decides_the_obstacle_and_nothing_else_does() {
        let params = Nav2Params::default();
        let a = Scenario::new(0, DEFAULT_GOAL, &params).unwrap();
        assert_eq!(a, Scenario::new(0, DEFAULT_GOAL, &params).unwrap());
        let others: Vec<Option<TimedObstacle>> = (1..6)
            .map(|seed| Scenario::new(seed, DEFAULT_GOAL, &params).unwrap().obstacle)
            .collect();
        assert!(others.iter().any(|o| *o != a.obstacle));
        assert!(a.obstacle.is_some());
    }

    #[test]
    fn an_unreachable_goal_has_no_obstacle() {
        let params = Nav2Params::default();
        let walled = Scenario::new(3, Pose2D::new(0.5, 0.5, 0.0), &params).unwrap();
        assert_eq!(walled.obstacle, None);
        let off_map = Scenario::new(3, Pose2D::new(99.0, 1.0, 0.0), &params).unwrap();
        assert_eq!(off_map.obstacle, None);
        assert_eq!(walled.world().unwrap().timed_obstacles(), []);
    }
}
