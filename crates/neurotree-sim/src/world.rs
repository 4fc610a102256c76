//! The grid world: the ground truth, the robot in it, and the one call that moves time on.

use std::time::Duration;

use neurotree_core::{Clock, ManualClock};

use super::battery::Battery;
use super::costmap::Costmap;
use super::grid::{parse, Cell, GridMap, MapError};
use super::motion::Motion;
use super::obstacle::TimedObstacle;
use super::sensors::{BatterySensor, Camera, Lidar};
use neurotree_nav2::robotics::{Obstacle, Path, Pose2D};

/// Which of the robot's two costmaps: the planner's or the controller's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CostmapLayer {
    /// What routes are planned on.
    Global,
    /// What the motion is checked against; cleared separately, as Nav2 does.
    Local,
}

/// What is really there at one moment: the walls and the timed obstacles present.
pub(crate) struct Truth<'w> {
    pub(crate) map: &'w GridMap,
    pub(crate) timed: &'w [TimedObstacle],
    pub(crate) now: Duration,
}

impl Truth<'_> {
    /// `true` if a timed obstacle fills `cell` now.
    pub(crate) fn is_obstacle(&self, cell: Cell) -> bool {
        self.timed
            .iter()
            .any(|o| o.cell == cell && o.is_present(self.now))
    }

    /// `true` if `cell` is a wall, holds an obstacle, or is off the map.
    pub(crate) fn is_occupied(&self, cell: Cell) -> bool {
        self.map.is_wall(cell) || self.is_obstacle(cell)
    }
}

/// A small deterministic world for one robot: see the [module documentation](super).
#[derive(Clone, Debug)]
pub struct GridWorld {
    pub(super) map: GridMap,
    pub(super) timed: Vec<TimedObstacle>,
    pub(super) clock: ManualClock,
    pub(super) robot: Pose2D,
    pub(super) battery: Battery,
    pub(super) charger: Option<Cell>,
    pub(super) charging: bool,
    pub(super) global: Costmap,
    pub(super) local: Costmap,
    pub(super) sensing_radius: f64,
    pub(super) speed: f64,
    pub(super) motion: Motion,
    pub(super) travelled: f64,
    pub(super) stops: u32,
    pub(super) plans: u32,
    pub(super) lidar: Lidar,
    pub(super) camera: Camera,
    pub(super) battery_sensor: BatterySensor,
}

impl GridWorld {
    /// A world on `map` with the robot at `robot` (on a free cell), a full default battery,
    /// no charger, a sensing radius of two cells and a speed of one cell per second.
    pub fn new(map: GridMap, robot: Pose2D) -> Result<Self, MapError> {
        match map.cell_at(&robot) {
            None => {
                return Err(MapError::OutsideMap {
                    what: "robot",
                    pose: robot,
                })
            }
            Some(cell) if map.is_wall(cell) => {
                return Err(MapError::Blocked {
                    what: "robot",
                    cell,
                })
            }
            Some(_) => {}
        }
        let resolution = map.resolution();
        let mut world = Self {
            global: Costmap::new(&map),
            local: Costmap::new(&map),
            map,
            timed: Vec::new(),
            clock: ManualClock::new(),
            robot,
            battery: Battery::default(),
            charger: None,
            charging: false,
            sensing_radius: 2.0 * resolution,
            speed: resolution,
            motion: Motion::default(),
            travelled: 0.0,
            stops: 0,
            plans: 0,
            lidar: Lidar::new(0),
            camera: Camera::new(1),
            battery_sensor: BatterySensor::default(),
        };
        world.refresh();
        Ok(world)
    }

    /// A world drawn as text, top row first: `#` wall, `.` free, `R` the robot (facing +x
    /// at its cell's centre), `C` the charger; cells of `resolution` metres. Everything
    /// beyond the edge counts as wall.
    ///
    /// ```
    /// use neurotree::sim::{Cell, GridWorld};
    ///
    /// // One row of four half-metre cells; beyond the edge is wall.
    /// let world = GridWorld::parse("R..C", 0.5).unwrap();
    /// assert_eq!(world.robot_cell(), Cell::new(0, 0));
    /// assert_eq!(world.charger(), Some(Cell::new(3, 0)));
    /// assert_eq!(world.robot().x, 0.25);
    /// ```
    pub fn parse(text: &str, resolution: f64) -> Result<Self, MapError> {
        let parsed = parse(text, resolution)?;
        let robot = parsed.map.centre(parsed.robot);
        let mut world = Self::new(parsed.map, robot)?;
        world.charger = parsed.charger;
        Ok(world)
    }

    /// With a charger on `cell` (a free cell).
    pub fn with_charger(mut self, cell: Cell) -> Result<Self, MapError> {
        if self.map.is_wall(cell) {
            return Err(MapError::Blocked {
                what: "charger",
                cell,
            });
        }
        self.charger = Some(cell);
        Ok(self)
    }

    /// With an obstacle that appears (and perhaps vanishes) on the world's clock.
    pub fn with_timed_obstacle(mut self, obstacle: TimedObstacle) -> Self {
        self.timed.push(obstacle);
        self.refresh();
        self
    }

    /// With the robot sensing obstacles within `metres` of its position.
    pub fn with_sensing_radius(mut self, metres: f64) -> Self {
        self.sensing_radius = metres;
        self.refresh();
        self
    }

    /// With `battery` instead of a full default one.
    pub fn with_battery(mut self, battery: Battery) -> Self {
        self.battery = battery;
        self.refresh();
        self
    }

    /// With the speed, in metres per second, at which the robot follows the paths it is
    /// given through [`MotionPlanner`](neurotree_nav2::robotics::MotionPlanner).
    pub fn with_speed(mut self, metres_per_second: f64) -> Self {
        self.speed = metres_per_second;
        self
    }

    /// With the simulated sensors' noise drawn from `seed`: the same seed, the same run.
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.lidar.reseed(seed.wrapping_mul(2));
        self.camera.reseed(seed.wrapping_mul(2).wrapping_add(1));
        self.refresh();
        self
    }

    /// The static map.
    pub fn map(&self) -> &GridMap {
        &self.map
    }

    /// The timed obstacles, present or not.
    pub fn timed_obstacles(&self) -> &[TimedObstacle] {
        &self.timed
    }

    /// World time.
    pub fn now(&self) -> Duration {
        self.clock.now()
    }

    /// A clock that reads world time, for the tree: `Tree::with_clock(bp, world.clock())`.
    pub fn clock(&self) -> ManualClock {
        self.clock.clone()
    }

    /// Where the robot is.
    pub fn robot(&self) -> Pose2D {
        self.robot
    }

    /// Puts the robot at `pose`, as reported by a robot elsewhere: for a world that mirrors
    /// one it does not drive (a ROS 2 navigator's view of the robot the simulator moves).
    /// The current motion is dropped and the sensors look around the new pose.
    pub fn set_robot(&mut self, pose: Pose2D) -> Result<(), MapError> {
        match self.map.cell_at(&pose) {
            None => Err(MapError::OutsideMap {
                what: "robot",
                pose,
            }),
            Some(cell) if self.map.is_wall(cell) => Err(MapError::Blocked {
                what: "robot",
                cell,
            }),
            Some(_) => {
                self.robot = pose;
                self.motion = Motion::default();
                self.refresh();
                Ok(())
            }
        }
    }

    /// The cell the robot is in.
    pub fn robot_cell(&self) -> Cell {
        // The robot starts on the map and every motion checks its next cell is on it.
        self.map
            .cell_at(&self.robot)
            .unwrap_or(Cell::new(i32::MIN, i32::MIN))
    }

    /// The battery.
    pub fn battery(&self) -> &Battery {
        &self.battery
    }

    /// Sets the battery's charge to `level` percent (clamped to 0..=100), its rates kept: a
    /// battery that fails at a given moment.
    pub fn set_battery_level(&mut self, level: f64) {
        let mut battery = Battery::at(level);
        battery.drain_per_metre = self.battery.drain_per_metre;
        battery.drain_per_radian = self.battery.drain_per_radian;
        battery.charge_per_second = self.battery.charge_per_second;
        self.battery = battery;
        self.refresh();
    }

    /// The charger's cell, if the world has one.
    pub fn charger(&self) -> Option<Cell> {
        self.charger
    }

    /// `true` if the battery gained charge in the last step.
    pub fn is_charging(&self) -> bool {
        self.charging
    }

    /// Metres driven so far (backwards counts too).
    pub fn distance_travelled(&self) -> f64 {
        self.travelled
    }

    /// How many times the motion was stopped with [`stop`](Self::stop).
    pub fn stop_count(&self) -> u32 {
        self.stops
    }

    /// How many paths were planned with [`plan`](Self::plan) or the motion planner.
    pub fn plan_count(&self) -> u32 {
        self.plans
    }

    /// `true` if `cell` is really occupied now (a wall, an obstacle, or off the map),
    /// whatever the robot believes.
    pub fn is_occupied(&self, cell: Cell) -> bool {
        self.truth().is_occupied(cell)
    }

    /// One of the robot's costmaps.
    pub fn costmap(&self, layer: CostmapLayer) -> &Costmap {
        match layer {
            CostmapLayer::Global => &self.global,
            CostmapLayer::Local => &self.local,
        }
    }

    /// Forgets the obstacles a costmap learned; those still within sensing range are
    /// learned again at the next step.
    pub fn clear_costmap(&mut self, layer: CostmapLayer) {
        match layer {
            CostmapLayer::Global => self.global.clear(),
            CostmapLayer::Local => self.local.clear(),
        }
    }

    /// Forgets the obstacles a costmap learned in the cells for which `forget` is `true`;
    /// returns how many.
    pub fn clear_costmap_where(
        &mut self,
        layer: CostmapLayer,
        forget: impl Fn(Cell) -> bool,
    ) -> usize {
        match layer {
            CostmapLayer::Global => self.global.clear_where(forget),
            CostmapLayer::Local => self.local.clear_where(forget),
        }
    }

    /// `true` while the robot stands on the charger's cell with no motion under way: the
    /// battery reports itself charging (or full).
    pub fn is_on_charger(&self) -> bool {
        self.charger == Some(self.robot_cell())
            && self.motion_status() != super::MotionStatus::Active
    }

    /// A path from `from` to `to` on the global costmap, or `None` if there is none.
    pub fn plan(&mut self, from: Pose2D, to: Pose2D) -> Option<Path> {
        self.plan_around(from, to, &[])
    }

    /// As [`plan`](Self::plan), also keeping clear of `obstacles`.
    pub fn plan_around(
        &mut self,
        from: Pose2D,
        to: Pose2D,
        obstacles: &[Obstacle],
    ) -> Option<Path> {
        self.plans += 1;
        self.global.plan(from, to, obstacles)
    }

    /// `true` if no pose of `path` lies on a cell the global costmap holds blocked.
    pub fn is_path_free(&self, path: &Path) -> bool {
        self.global.is_path_free(path)
    }

    /// The simulated lidar, sampled at the end of every step.
    pub fn lidar(&mut self) -> &mut Lidar {
        &mut self.lidar
    }

    /// The simulated camera, sampled at the end of every step.
    pub fn camera(&mut self) -> &mut Camera {
        &mut self.camera
    }

    /// The battery gauge, sampled at the end of every step.
    pub fn battery_sensor(&mut self) -> &mut BatterySensor {
        &mut self.battery_sensor
    }

    /// Moves time on by `dt`: obstacles come and go, the commanded motion runs for `dt`,
    /// the battery drains or charges, the costmaps learn what is within sensing range, and
    /// the sensors take a sample. Returns the motion's status after the step.
    pub fn step(&mut self, dt: Duration) -> super::MotionStatus {
        self.clock.advance(dt);
        let moved = self.advance_motion(dt);
        self.charging =
            !moved && self.charger == Some(self.robot_cell()) && self.battery.level() < 100.0;
        if self.charging {
            self.battery.charge(dt.as_secs_f64());
        }
        self.refresh();
        self.motion_status()
    }

    pub(super) fn truth(&self) -> Truth<'_> {
        Truth {
            map: &self.map,
            timed: &self.timed,
            now: self.clock.now(),
        }
    }

    /// Learns the obstacles within sensing range and samples the sensors.
    fn refresh(&mut self) {
        let truth = Truth {
            map: &self.map,
            timed: &self.timed,
            now: self.clock.now(),
        };
        // No farther than the map is wide: a huge radius must not mean a huge loop.
        let cells = (self.sensing_radius / self.map.resolution()).ceil();
        let reach = cells.clamp(0.0, f64::from(self.map.width().max(self.map.height()))) as i32;
        let here = self.map.cell_at(&self.robot).unwrap_or(Cell::new(0, 0));
        for dy in -reach..=reach {
            for dx in -reach..=reach {
                let cell = Cell::new(here.x + dx, here.y + dy);
                let centre = self.map.centre(cell);
                if centre.distance(&self.robot) <= self.sensing_radius && truth.is_obstacle(cell) {
                    self.global.mark(cell);
                    self.local.mark(cell);
                }
            }
        }
        self.lidar.sample(&truth, self.robot);
        self.camera.sample(&truth, self.robot);
        self.battery_sensor
            .sample(truth.now, &self.battery, self.charging);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SECOND: Duration = Duration::from_secs(1);

    /// A 7 × 3 room, the robot in the middle row on the left.
    fn room() -> GridWorld {
        GridWorld::parse(
            "
            .......
            R......
            .......",
            1.0,
        )
        .unwrap()
    }

    #[test]
    fn timed_obstacles_appear_and_vanish_on_the_world_clock() {
        let cell = Cell::new(5, 1);
        let mut w =
            room().with_timed_obstacle(TimedObstacle::new(cell, 2 * SECOND).until(4 * SECOND));
        let mut seen = Vec::new();
        for _ in 0..6 {
            seen.push(w.is_occupied(cell));
            w.step(SECOND);
        }
        assert_eq!(seen, [false, false, true, true, false, false]);
        assert_eq!(w.now(), 6 * SECOND);
        assert!(w.is_occupied(Cell::new(-1, 0)));
    }

    #[test]
    fn costmaps_learn_obstacles_within_the_sensing_radius_and_forget_when_cleared() {
        let near = Cell::new(2, 1);
        let far = Cell::new(5, 1);
        let mut w = room()
            .with_timed_obstacle(TimedObstacle::new(near, SECOND).until(3 * SECOND))
            .with_timed_obstacle(TimedObstacle::new(far, SECOND));
        let marked = |w: &GridWorld, layer| w.costmap(layer).marked().collect::<Vec<_>>();
        assert!(marked(&w, CostmapLayer::Global).is_empty());
        w.step(SECOND);
        // Two cells away is within the default radius of two cells; five is not.
        assert_eq!(marked(&w, CostmapLayer::Global), [near]);
        assert_eq!(marked(&w, CostmapLayer::Local), [near]);
        w.step(2 * SECOND);
        assert!(!w.is_occupied(near));
        // Gone, but remembered until cleared.
        assert_eq!(marked(&w, CostmapLayer::Global), [near]);
        w.clear_costmap(CostmapLayer::Local);
        assert!(marked(&w, CostmapLayer::Local).is_empty());
        assert_eq!(marked(&w, CostmapLayer::Global), [near]);
        w.clear_costmap(CostmapLayer::Global);
        w.step(SECOND);
        assert!(marked(&w, CostmapLayer::Global).is_empty());
    }

    #[test]
    fn an_obstacle_still_in_range_is_learned_again_after_clearing() {
        let cell = Cell::new(1, 1);
        let mut w = room().with_timed_obstacle(TimedObstacle::new(cell, Duration::ZERO));
        assert!(w.costmap(CostmapLayer::Global).is_marked(cell));
        w.clear_costmap(CostmapLayer::Global);
        assert!(!w.costmap(CostmapLayer::Global).is_marked(cell));
        w.step(Duration::ZERO);
        assert!(w.costmap(CostmapLayer::Global).is_marked(cell));
    }

    #[test]
    fn plans_avoid_what_the_robot_knows_and_count() {
        let mut w = room().with_timed_obstacle(TimedObstacle::new(Cell::new(2, 1), Duration::ZERO));
        let goal = Pose2D::new(4.5, 1.5, 0.0);
        let path = w.plan(w.robot(), goal).unwrap();
        let cells: Vec<Cell> = path
            .poses
            .iter()
            .filter_map(|p| w.map().cell_at(p))
            .collect();
        assert!(!cells.contains(&Cell::new(2, 1)));
        assert_eq!(cells.len(), 5);
        assert!(w.is_path_free(&path));
        let straight = Path::new(vec![w.robot(), goal]);
        assert!(
            w.is_path_free(&straight),
            "only poses are checked, not the line between"
        );
        let through = Path::new(vec![w.robot(), Pose2D::new(2.5, 1.5, 0.0), goal]);
        assert!(!w.is_path_free(&through));
        let disc = Obstacle::new(3.5, 1.5, 0.5);
        let avoided = w.plan_around(w.robot(), goal, &[disc]).unwrap();
        assert!(avoided.poses.iter().all(|p| !disc.covers(p.x, p.y)));
        // A goal under an obstacle cannot be reached.
        let on_goal = Obstacle::new(4.5, 1.5, 0.1);
        assert_eq!(w.plan_around(w.robot(), goal, &[on_goal]), None);
        assert_eq!(w.plan(w.robot(), Pose2D::new(-1.0, 0.0, 0.0)), None);
        assert_eq!(w.plan_count(), 4);
    }

    #[test]
    fn worlds_refuse_robots_and_chargers_on_walls_or_off_the_map() {
        let map = GridMap::new(3, 1, 1.0).unwrap();
        assert!(matches!(
            GridWorld::new(map.clone(), Pose2D::new(5.0, 0.5, 0.0)),
            Err(MapError::OutsideMap { what: "robot", .. })
        ));
        let mut walled = map.clone();
        walled.set_wall(Cell::new(2, 0), true);
        assert_eq!(
            GridWorld::new(walled.clone(), Pose2D::new(2.5, 0.5, 0.0)).unwrap_err(),
            MapError::Blocked {
                what: "robot",
                cell: Cell::new(2, 0)
            }
        );
        let w = GridWorld::new(walled, Pose2D::new(0.5, 0.5, 0.0)).unwrap();
        assert!(w.with_charger(Cell::new(2, 0)).is_err());
    }
}
