//! The checks on the current path that decide whether the navigator plans again:
//! IsGoalNearby, TruncatePathLocal and ValidatePath.
//!
//! - **IsGoalNearby**: a condition. Ports: `path`, `proximity_threshold` (default 1.0),
//!   `max_robot_pose_search_dist` (default -1).
//!   - Success when the path length from the pose nearest the robot to the end is below the
//!     threshold.
//!   - The search for the nearest pose starts where the last one was found on the same path
//!     and spans `max_robot_pose_search_dist` metres of it (the whole path when negative).
//!   - Empty path: Failure.
//! - **TruncatePathLocal**: a sync action. Ports: `input_path`, `distance_forward` (default
//!   8), `distance_backward` (default 4), `pose` (optional), `angular_distance_weight`
//!   (default 0), `max_robot_pose_search_dist` (default inf); output `output_path`.
//!   - Writes the part of the path from `distance_backward` metres before the pose nearest
//!     the robot (or `pose`) to `distance_forward` metres after it (to the end when
//!     negative). Success.
//! - **ValidatePath**: a sync action. Ports: `path`, `max_lookahead_distance` (default -1),
//!   `stop_at_first_collision` (default true); output `collision_poses`.
//!   - Success if no pose of the path (within the lookahead from the pose nearest the robot,
//!     when positive) lies on a cell the global costmap holds blocked; else Failure, listing
//!     the poses in collision.
//!   - Empty path: Failure.
//!
//! Nav2's navigator keeps a path while the goal is near and the rest of the path is still
//! free: these three say so. The nearest-pose search of IsGoalNearby and TruncatePathLocal
//! remembers where it found the robot on a path, so that a path that doubles back is not
//! matched on its way back; the nodes keep that per tree instance.

use neurotree_core::{Category, Handle, StatefulAction, Status};

use super::{ports, Nav2Context};
use crate::CostmapLayer;
use neurotree_nav2::robotics::{Path, Pose2D};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_stateful_as(
        "IsGoalNearby",
        Category::Condition,
        goal_nearby_ports(),
        IsGoalNearby::default,
    )?;
    r.describe(
        "IsGoalNearby",
        "Succeeds when the rest of the path is shorter than `proximity_threshold`.",
    );
    r.register_stateful_as(
        "TruncatePathLocal",
        Category::Action,
        truncate_ports(),
        TruncatePathLocal::default,
    )?;
    r.describe(
        "TruncatePathLocal",
        "Writes the part of the path around the robot to `output_path`.",
    );
    r.register_action("ValidatePath", validate_ports(), validate_path::<C>)?;
    r.describe(
        "ValidatePath",
        "Succeeds when no pose of the path lies on a blocked cell of the global costmap.",
    );
    Ok(())
}

fn goal_nearby_ports() -> Vec<PortSpec> {
    vec![
        PortSpec::input::<Path>("path").describe("The planned path."),
        PortSpec::input::<f64>("proximity_threshold")
            .default_value("1.0")
            .describe("Remaining path length, in metres, that counts as nearby."),
        PortSpec::input::<f64>("max_robot_pose_search_dist")
            .default_value("-1.0")
            .describe("Metres of path searched for the robot, from where it was last found; negative: all."),
        PortSpec::input::<String>("global_frame").describe("Global frame (unused)."),
        PortSpec::input::<String>("robot_base_frame").describe("Robot frame (unused)."),
    ]
}

fn truncate_ports() -> Vec<PortSpec> {
    vec![
        PortSpec::input::<Path>("input_path").describe("The path to truncate."),
        PortSpec::input::<f64>("distance_forward")
            .default_value("8.0")
            .describe("Metres kept ahead of the robot; -1 keeps the rest of the path."),
        PortSpec::input::<f64>("distance_backward")
            .default_value("4.0")
            .describe("Metres kept behind the robot."),
        PortSpec::input::<String>("robot_base_frame").describe("Robot frame (unused)."),
        PortSpec::input::<f64>("transform_tolerance")
            .default_value("0.2")
            .describe("Pose lookup tolerance (unused)."),
        PortSpec::input::<Pose2D>("pose").describe("A pose to use instead of the robot's."),
        PortSpec::input::<f64>("angular_distance_weight")
            .default_value("0.0")
            .describe("Weight of the heading difference when finding the nearest pose."),
        PortSpec::input::<f64>("max_robot_pose_search_dist")
            .default_value("inf")
            .describe("Metres of path searched for the robot, from where it was last found."),
        PortSpec::output::<Path>("output_path").describe("The truncated path."),
    ]
}

fn validate_ports() -> Vec<PortSpec> {
    vec![
        PortSpec::input::<Path>("path").describe("The path to check."),
        PortSpec::input::<u32>("max_cost")
            .default_value("254")
            .describe("Highest cost allowed; every blocked cell is above it."),
        PortSpec::input::<bool>("consider_unknown_as_obstacle")
            .default_value("false")
            .describe("The grid world has no unknown cells (unused)."),
        PortSpec::input::<String>("layer_name")
            .default_value("")
            .describe("Costmap layer to check (unused: the whole global costmap)."),
        PortSpec::input::<String>("footprint")
            .default_value("")
            .describe("Robot footprint (unused: the robot is a point)."),
        PortSpec::input::<bool>("stop_at_first_collision")
            .default_value("true")
            .describe("List only the first pose in collision."),
        PortSpec::input::<f64>("max_lookahead_distance")
            .default_value("-1.0")
            .describe("Metres of path checked from the robot on; -1 checks all of it."),
        PortSpec::input::<String>("service_name").describe("Service name (unused)."),
        PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
        PortSpec::output::<Vec<Pose2D>>("collision_poses")
            .describe("The poses on blocked cells; empty if the path is valid."),
    ]
}

/// The first index after `from` at which the distance integrated along `path` from `from`
/// exceeds `limit`, or the end: Nav2's `first_after_integrated_distance`.
fn first_after(path: &Path, from: usize, limit: f64) -> usize {
    let mut travelled = 0.0;
    for i in from..path.len().saturating_sub(1) {
        travelled += path.poses[i].distance(&path.poses[i + 1]);
        if travelled > limit {
            return i + 1;
        }
    }
    path.len()
}

/// The index in `from..to` of the pose nearest `robot` (the last of equals, as Nav2's
/// `min_by` picks), weighing heading differences by `angular_weight`.
fn nearest(path: &Path, from: usize, to: usize, robot: &Pose2D, angular_weight: f64) -> usize {
    let cost = |p: &Pose2D| {
        let turn = angular_weight * angle_between(p.theta, robot.theta);
        (p.distance(robot).powi(2) + turn * turn).sqrt()
    };
    let mut best = from;
    for i in from..to.min(path.len()) {
        if cost(&path.poses[i]) <= cost(&path.poses[best]) {
            best = i;
        }
    }
    best
}

/// The smallest angle between two headings, in [0, π].
fn angle_between(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

/// Where the robot was last found on a path, for the bounded search.
#[derive(Default)]
struct Memory {
    path: Path,
    from: usize,
}

impl Memory {
    /// The index of the pose nearest `robot` on `path`, searching `limit` metres from
    /// where it was last found when `limit` is finite and not negative (and the path is
    /// the same), else the whole path.
    fn find(&mut self, path: Path, robot: &Pose2D, limit: f64, angular_weight: f64) -> usize {
        let bounded = limit.is_finite() && limit >= 0.0;
        if !bounded || path != self.path {
            self.path = path;
            self.from = 0;
        }
        let to = if bounded {
            first_after(&self.path, self.from, limit)
        } else {
            self.path.len()
        };
        let found = nearest(&self.path, self.from, to, robot, angular_weight);
        if bounded {
            self.from = found;
        }
        found
    }
}

/// IsGoalNearby: see the [module documentation](self).
#[derive(Default)]
struct IsGoalNearby {
    memory: Memory,
}

impl<C: Nav2Context> StatefulAction<C> for IsGoalNearby {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(
            &self.memory.path,
            self.memory.from,
        )))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode::<(Path, usize)>(state)
            .map(|saved| (self.memory.path, self.memory.from) = saved)
            .is_some()
    }

    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        let read = ports::or(h, "path", Path::default()).and_then(|path| {
            let threshold: f64 = ports::or(h, "proximity_threshold", 1.0)?;
            let limit: f64 = ports::or(h, "max_robot_pose_search_dist", -1.0)?;
            Ok((path, threshold, limit))
        });
        let Ok((path, threshold, limit)) = read else {
            return Status::Failure;
        };
        if path.is_empty() {
            return Status::Failure;
        }
        let robot = h.ctx().nav2().world.robot();
        let at = self.memory.find(path, &robot, limit, 0.0);
        if self.memory.path.from_index(at).length() < threshold {
            Status::Success
        } else {
            Status::Failure
        }
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.on_start(h)
    }
}

/// TruncatePathLocal: see the [module documentation](self).
#[derive(Default)]
struct TruncatePathLocal {
    memory: Memory,
}

impl<C: Nav2Context> StatefulAction<C> for TruncatePathLocal {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(
            &self.memory.path,
            self.memory.from,
        )))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode::<(Path, usize)>(state)
            .map(|saved| (self.memory.path, self.memory.from) = saved)
            .is_some()
    }

    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        let read = ports::or(h, "input_path", Path::default()).and_then(|path| {
            let forward: f64 = ports::or(h, "distance_forward", 8.0)?;
            let backward: f64 = ports::or(h, "distance_backward", 4.0)?;
            let weight: f64 = ports::or(h, "angular_distance_weight", 0.0)?;
            let limit: f64 = ports::or(h, "max_robot_pose_search_dist", f64::INFINITY)?;
            let pose = ports::optional::<Pose2D, C>(h, "pose")?;
            Ok((path, forward, backward, weight, limit, pose))
        });
        let Ok((path, forward, backward, weight, limit, pose)) = read else {
            return Status::Failure;
        };
        if path.is_empty() {
            ports::emit(h, "output_path", path);
            return Status::Success;
        }
        let robot = pose.unwrap_or_else(|| h.ctx().nav2().world.robot());
        let at = self.memory.find(path, &robot, limit, weight);
        let path = &self.memory.path;
        let end = if forward < 0.0 {
            path.len()
        } else {
            first_after(path, at, forward)
        };
        let start = at - backward_steps(path, at, backward);
        ports::emit(h, "output_path", Path::new(path.poses[start..end].to_vec()));
        Status::Success
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.on_start(h)
    }
}

/// How many poses before `at` lie within `limit` metres of it along `path`, plus the one
/// that crosses the limit, as Nav2 counts backwards.
fn backward_steps(path: &Path, at: usize, limit: f64) -> usize {
    let mut travelled = 0.0;
    for i in (1..=at).rev() {
        travelled += path.poses[i].distance(&path.poses[i - 1]);
        if travelled > limit {
            return at - i;
        }
    }
    at
}

/// ValidatePath: see the [module documentation](self).
fn validate_path<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let read = ports::or(h, "path", Path::default()).and_then(|path| {
        let lookahead: f64 = ports::or(h, "max_lookahead_distance", -1.0)?;
        let first_only: bool = ports::or(h, "stop_at_first_collision", true)?;
        Ok((path, lookahead, first_only))
    });
    let Ok((path, lookahead, first_only)) = read else {
        return Status::Failure;
    };
    if path.is_empty() {
        return Status::Failure;
    }
    let world = &h.ctx().nav2().world;
    let (start, end) = if lookahead > 0.0 {
        let at = path.closest_index(&world.robot()).unwrap_or(0);
        (at, first_after(&path, at, lookahead))
    } else {
        (0, path.len())
    };
    let costmap = world.costmap(CostmapLayer::Global);
    let blocked = |p: &&Pose2D| {
        world
            .map()
            .cell_at(p)
            .is_none_or(|cell| costmap.is_blocked(cell))
    };
    let mut collisions = path.poses[start..end].iter().filter(blocked);
    let collisions: Vec<Pose2D> = if first_only {
        collisions.next().copied().into_iter().collect()
    } else {
        collisions.copied().collect()
    };
    let valid = collisions.is_empty();
    ports::emit(h, "collision_poses", collisions);
    if valid {
        Status::Success
    } else {
        Status::Failure
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;
    use crate::{Cell, TimedObstacle};
    use std::time::Duration;

    /// Along y = 0.5 through x = 0.5, 1.5, … (one pose per cell of "R.......").
    fn line(xs: std::ops::Range<i32>) -> Path {
        Path::new(
            xs.map(|x| Pose2D::new(f64::from(x) + 0.5, 0.5, 0.0))
                .collect(),
        )
    }

    #[test]
    fn goal_nearby_measures_the_rest_of_the_path_from_the_robot() {
        let mut b = Bench::new(
            "R.......",
            r#"<IsGoalNearby path="{path}" proximity_threshold="4.0" max_robot_pose_search_dist="1.5"/>"#,
        );
        assert_eq!(b.tick(), Status::Failure, "no path");
        // Ticked once a second, as the navigator's RateController does, while the robot
        // drives the 7 m path at 1 m/s: 7, 6, 5, 4 and then 3 m are left.
        b.set("path", line(0..8));
        b.sim.world.follow(line(0..8), 1.0);
        let mut seen = Vec::new();
        for _ in 0..5 {
            seen.push(b.tick());
            for _ in 0..10 {
                b.sim.step();
            }
        }
        use Status::{Failure as F, Success as S};
        assert_eq!(seen, [F, F, F, F, S]);
    }

    #[test]
    fn the_bounded_search_does_not_jump_to_a_later_part_of_the_path() {
        // Out and back: the robot, on the way out, is nearest a pose of the way back too.
        let there_and_back = Path::new(
            [0.5, 1.5, 2.5, 3.5, 2.5, 1.5, 0.5]
                .iter()
                .map(|x| Pose2D::new(*x, 0.5, 0.0))
                .collect(),
        );
        let mut memory = Memory::default();
        let robot = Pose2D::new(1.5, 0.5, 0.0);
        assert_eq!(memory.find(there_and_back.clone(), &robot, 1.5, 0.0), 1);
        let mut unbounded = Memory::default();
        // Nav2's min_by keeps the last of equals: the way back.
        assert_eq!(unbounded.find(there_and_back, &robot, -1.0, 0.0), 5);
    }

    #[test]
    fn truncate_keeps_the_part_around_the_robot() {
        let mut b = Bench::new(
            "R.......",
            r#"<TruncatePathLocal input_path="{path}" output_path="{rest}" distance_forward="2.0" distance_backward="1.0" pose="{pose}"/>"#,
        );
        b.set("path", line(0..8));
        b.set("pose", Pose2D::new(3.6, 0.5, 0.0));
        assert_eq!(b.tick(), Status::Success);
        // From 1 m behind x = 3.5 to the first pose past 2 m ahead of it (exclusive).
        assert_eq!(
            b.get::<Path>("rest"),
            Path::new(line(2..8).poses[..4].to_vec())
        );
        // The navigator's use: from the robot to the end.
        let mut b = Bench::new(
            "R.......",
            r#"<TruncatePathLocal input_path="{path}" output_path="{rest}" distance_forward="-1" distance_backward="0.0"/>"#,
        );
        b.set("path", line(0..8));
        b.sim.world.follow(line(0..8), 1.0);
        for _ in 0..26 {
            b.sim.step();
        }
        assert_eq!(b.tick(), Status::Success);
        assert_eq!(b.get::<Path>("rest"), line(3..8));
        b.set("path", Path::default());
        assert_eq!(b.tick(), Status::Success);
        assert_eq!(b.get::<Path>("rest"), Path::default());
    }

    #[test]
    fn validate_path_checks_the_global_costmap() {
        let world = crate::GridWorld::parse("R.......", 1.0)
            .unwrap()
            .with_timed_obstacle(TimedObstacle::new(Cell::new(2, 0), Duration::ZERO))
            .with_timed_obstacle(TimedObstacle::new(Cell::new(6, 0), Duration::ZERO));
        let mut b = Bench::with_world(
            world,
            r#"<ValidatePath path="{path}" collision_poses="{hits}" stop_at_first_collision="{first}"/>"#,
        );
        b.set("first", true);
        b.set("path", line(0..2));
        assert_eq!(b.tick(), Status::Success);
        assert_eq!(b.get::<Vec<Pose2D>>("hits"), []);
        // Cell 2 is known (within the sensing radius); cell 6 is not yet.
        b.set("path", line(0..8));
        assert_eq!(b.tick(), Status::Failure);
        assert_eq!(b.get::<Vec<Pose2D>>("hits"), [Pose2D::new(2.5, 0.5, 0.0)]);
        b.sim.world.clear_costmap(CostmapLayer::Global);
        assert_eq!(b.tick(), Status::Success);
        // Sensed again at the next step.
        b.sim.step();
        assert_eq!(b.tick(), Status::Failure);
        b.set("path", Path::default());
        assert_eq!(b.tick(), Status::Failure);
    }

    #[test]
    fn validate_path_lists_every_collision_within_the_lookahead() {
        let world = crate::GridWorld::parse("R.......", 1.0)
            .unwrap()
            .with_sensing_radius(10.0)
            .with_timed_obstacle(TimedObstacle::new(Cell::new(2, 0), Duration::ZERO))
            .with_timed_obstacle(TimedObstacle::new(Cell::new(6, 0), Duration::ZERO));
        let mut b = Bench::with_world(
            world,
            r#"<ValidatePath path="{path}" collision_poses="{hits}" stop_at_first_collision="false" max_lookahead_distance="{ahead}"/>"#,
        );
        b.set("path", line(0..8));
        b.set("ahead", -1.0);
        assert_eq!(b.tick(), Status::Failure);
        assert_eq!(
            b.get::<Vec<Pose2D>>("hits"),
            [Pose2D::new(2.5, 0.5, 0.0), Pose2D::new(6.5, 0.5, 0.0)]
        );
        // 2.5 m from the robot reaches x = 2.5 but not x = 6.5; 1.5 m stops short of both.
        b.set("ahead", 2.5);
        assert_eq!(b.tick(), Status::Failure);
        assert_eq!(b.get::<Vec<Pose2D>>("hits"), [Pose2D::new(2.5, 0.5, 0.0)]);
        b.set("ahead", 1.5);
        assert_eq!(b.tick(), Status::Success);
    }
}
