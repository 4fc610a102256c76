//! A small deterministic 2D grid world, so that robotics trees run without a robot.
//!
//! A [`GridWorld`] holds:
//! - the ground truth: a static [`GridMap`] of walls and [`TimedObstacle`]s that appear and
//!   vanish on the world's clock;
//! - the robot: a [`Pose2D`](neurotree_nav2::robotics::Pose2D) in metres, a [`Battery`] that drains
//!   as it moves and charges on the charger, the distance it has travelled;
//! - what the robot believes: a global and a local [`Costmap`], which start from the static
//!   map, learn every obstacle within the sensing radius, and forget only when cleared;
//! - its sensors ([`Lidar`], [`Camera`], [`BatterySensor`]), sampled every step.
//!
//! Time moves only when [`GridWorld::step`] is called, by the `dt` it is given: obstacles
//! come and go, the commanded motion (follow a path, spin, back up, wait — see [`motion`])
//! runs, the costmaps learn, the sensors sample. Nothing reads the wall clock and all noise
//! is seeded, so the same calls give the same world, to the last bit; tests assert exact
//! poses and tick counts. [`GridWorld::clock`] gives the tree a clock that reads world time.
//!
//! The world is a [`MotionPlanner`](neurotree_nav2::robotics::MotionPlanner) (A* on the global
//! costmap, via the `pathfinding` crate), and its sensors are
//! [`SensorReader`](neurotree_nav2::robotics::SensorReader)s, so the robotics nodes drive it as
//! they would a robot. [`GridWorld::render`] draws it as plain text, [`GridWorld::scene`] as
//! a [`Scene`](neurotree_toolkit::scene::Scene) for a viewer.
//!
//! ```
//! use std::time::Duration;
//! use neurotree::robotics::{Pose2D, RoboticsBuilder};
//! use neurotree::sim::{Cell, GridWorld, TimedObstacle};
//! use neurotree::{Blueprint, Status, Tree};
//!
//! // Two rows of five 1 m cells (beyond the edge is wall). A crate lands in front of the
//! // robot at t = 1 s; the robot bumps into it and goes round.
//! let mut world = GridWorld::parse(
//!     ".....
//!      R....",
//!     1.0,
//! )
//! .unwrap()
//! .with_timed_obstacle(TimedObstacle::new(Cell::new(2, 0), Duration::from_secs(1)));
//!
//! let blueprint = Blueprint::<GridWorld>::builder()
//!     .navigate("go", "goal", 0.1, |w: &mut GridWorld| w)
//!     .build_shared()
//!     .unwrap();
//! let mut tree = Tree::with_clock(blueprint, world.clock());
//! tree.blackboard_mut().set("goal", Pose2D::new(4.5, 0.5, 0.0)).unwrap();
//! while tree.tick_once(&mut world).unwrap() == Status::Running {
//!     world.step(Duration::from_millis(500));
//! }
//! assert_eq!(world.robot(), Pose2D::new(4.5, 0.5, 0.0));
//! assert_eq!(world.plan_count(), 2);
//! print!("{}", world.render());
//! ```

#![forbid(unsafe_code)]

mod battery;
mod costmap;
mod grid;
pub mod motion;
pub mod nav2;
mod obstacle;
mod planner;
pub mod render;
pub mod scene;
mod sensors;
mod world;

pub use battery::Battery;
pub use costmap::Costmap;
pub use grid::{Cell, GridMap, MapError};
pub use motion::{MotionKind, MotionStatus};
pub use obstacle::TimedObstacle;
pub use render::LEGEND;
pub use sensors::{BatterySensor, Camera, Lidar};
pub use world::{CostmapLayer, GridWorld};
