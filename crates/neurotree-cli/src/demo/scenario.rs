//! The demo's world: a warehouse with a charging dock and a route graph, a goal, and an
//! obstacle that steps onto the robot's path.

use std::time::Duration;

use neurotree::robotics::{Pose2D, RouteNode};
use neurotree::sim::nav2::{Dock, Nav2Params, RouteGraph};
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

/// Where an application tree places what it picked (the docking example's
/// `placing_location`): in the loading hall.
pub const PLACING_LOCATION: Pose2D = Pose2D::new(5.5, 7.5, 0.0);

/// The warehouse's dock: on the charger, in the robot's starting cell, entered facing west
/// from its staging pose a metre east of it. Its id and type are what the demo writes to
/// the `dock_id` and `dock_type` entries.
pub fn dock() -> Dock {
    Dock::new(
        "warehouse_dock",
        "charging_dock",
        Pose2D::new(1.5, 13.5, std::f64::consts::PI),
    )
}

/// The warehouse's route graph: from the hall's top (node 1) along its north side, through
/// the upper door and along the store to its east side (nodes 2 to 6), with a second way
/// through the lower door (nodes 7 and 8). Every edge runs along free cells.
pub fn route_graph() -> RouteGraph {
    RouteGraph::new(vec![
        RouteNode::new(1, 3.5, 12.5),
        RouteNode::new(2, 9.5, 12.5),
        RouteNode::new(3, 9.5, 9.5),
        RouteNode::new(4, 24.5, 9.5),
        RouteNode::new(5, 36.5, 9.5),
        RouteNode::new(6, 36.5, 4.5),
        RouteNode::new(7, 9.5, 3.5),
        RouteNode::new(8, 24.5, 3.5),
    ])
    .with_way(1, 2)
    .with_way(2, 3)
    .with_way(3, 4)
    .with_way(4, 5)
    .with_way(5, 6)
    .with_way(3, 7)
    .with_way(7, 8)
    .with_way(8, 4)
}

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

    /// The world of the scenario: the warehouse, with the charger under the dock, its
    /// obstacle and the sensors' noise drawn from the seed.
    pub fn world(&self) -> Result<GridWorld, MapError> {
        let world = GridWorld::parse(WAREHOUSE, 1.0)?.with_seed(self.seed);
        let charger = world
            .map()
            .cell_at(&dock().pose)
            .unwrap_or(Cell::new(1, 13));
        let world = world.with_charger(charger)?;
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
    fn the_route_graph_runs_on_free_cells_and_the_dock_on_the_charger() {
        let world = Scenario::new(0, DEFAULT_GOAL, &Nav2Params::default())
            .unwrap()
            .world()
            .unwrap();
        let graph = route_graph();
        for edge in graph.edges() {
            let (a, b) = (
                graph.node(edge.start).unwrap(),
                graph.node(edge.end).unwrap(),
            );
            for i in 0..=40 {
                let t = f64::from(i) / 40.0;
                let p = Pose2D::new(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), 0.0);
                let cell = world.map().cell_at(&p).unwrap();
                assert!(!world.map().is_wall(cell), "edge {} at {p:?}", edge.id);
            }
        }
        assert_eq!(world.charger(), Some(Cell::new(1, 13)));
        assert_eq!(world.robot_cell(), Cell::new(1, 13));
        let staging = world.map().cell_at(&dock().staging_pose()).unwrap();
        assert_eq!(staging, Cell::new(2, 13));
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
