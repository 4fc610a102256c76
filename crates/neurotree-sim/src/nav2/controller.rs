//! FollowPath: the controller server, as the world's follow motion; CancelControl, which
//! cancels it.
//!
//! Stateful action on the world's follow motion. Ports: `path`, `controller_id`, …; outputs
//! `tracking_feedback`, `error_code_id`, `error_msg`.
//!
//! - Every tick it reads the *current* `path`: a new path is followed from where the robot is
//!   (Nav2's controller takes new paths while it runs).
//! - Success (motion stopped, error 0) once the robot is within the goal tolerance of the
//!   path's end.
//! - Failure: INVALID_PATH 103 (no or empty path), NO_VALID_CONTROL 106 (blocked by an
//!   obstacle), FAILED_TO_MAKE_PROGRESS 105 (battery empty).
//! - Else Running.
//! - Halt stops the motion.
//!
//! In Nav2's navigator the controller keeps running while a RateController replans beside
//! it in a PipelineSequence; each new plan reaches the controller as a new goal, which it
//! takes over without stopping. So the node compares the path it is given with the one the
//! world follows on every tick, and hands the world the new one. A path whose next cell
//! turns out to be occupied ends the motion in front of it ([`MotionStatus::Blocked`]);
//! the node reports it with the code Nav2's controllers use when no safe command exists,
//! which WouldAControllerRecoveryHelp recognises.
//!
//! **CancelControl** (ports `server_name`, `server_timeout`, unused) is a sync action that
//! cancels the controller's goal, as Nav2's `controller_cancel_node.cpp` cancels the
//! FollowPath action: if the world's motion is a follow, it is stopped (the robot stays
//! where it is). Success, whether or not there was one to cancel.

use neurotree_core::{Handle, StatefulAction, Status};

use super::codes::follow_path as code;
use super::{ports, Nav2Context};
use crate::MotionStatus;
pub use neurotree_nav2::robotics::TrackingFeedback;
use neurotree_nav2::robotics::{Path, Pose2D};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

/// The ports of `nav2_tree_nodes.xml`, in its order.
fn ports() -> Vec<PortSpec> {
    let id = |name: &str, what: &str| {
        PortSpec::input::<String>(name).describe(&format!("{what} plugin to use (unused)."))
    };
    vec![
        PortSpec::input::<Path>("path").describe("The path to follow, read on every tick."),
        id("controller_id", "Controller"),
        id("goal_checker_id", "Goal checker"),
        id("progress_checker_id", "Progress checker"),
        id("path_handler_id", "Path handler"),
        PortSpec::input::<String>("server_name").describe("Action server name (unused)."),
        PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
        PortSpec::output::<TrackingFeedback>("tracking_feedback")
            .describe("Where the robot is along the path, every tick."),
        PortSpec::output::<u16>("error_code_id").describe("0, or the controller's error code."),
        PortSpec::output::<String>("error_msg").describe("Why following failed; empty on success."),
    ]
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_stateful("FollowPath", ports(), FollowPath::default)?;
    r.describe(
        "FollowPath",
        "Follows the current `path` until the robot is at its end; halting it stops the robot.",
    );
    r.register_action(
        "CancelControl",
        vec![
            PortSpec::input::<String>("server_name").describe("Action server name (unused)."),
            PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
        ],
        cancel_control::<C>,
    )?;
    r.describe("CancelControl", "Stops the controller's path following.");
    Ok(())
}

/// CancelControl: see the [module documentation](self).
fn cancel_control<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let world = &mut h.ctx_mut().nav2_mut().world;
    if world.followed_path().is_some() && world.motion_status() == MotionStatus::Active {
        world.stop();
        let name = h.name().to_string();
        h.ctx_mut()
            .nav2_mut()
            .note(|| format!("{name}: cancelled the controller"));
    }
    Status::Success
}

/// The node: see the [module documentation](self).
#[derive(Default)]
struct FollowPath {
    /// The path last handed to the world, as the port gave it.
    following: Option<Path>,
}

impl FollowPath {
    fn control<C: Nav2Context>(&mut self, h: &mut Handle<'_, C>, starting: bool) -> Status {
        let path = match ports::optional::<Path, C>(h, "path") {
            Ok(Some(path)) if !path.is_empty() => path,
            Ok(_) => {
                let message = "no path to follow".into();
                return self.abort(h, code::INVALID_PATH, "no path", message);
            }
            Err(e) => return self.abort(h, code::INVALID_PATH, "bad path", e.to_string()),
        };
        let sim = h.ctx_mut().nav2_mut();
        let (tolerance, speed) = (sim.params.goal_tolerance, sim.params.speed);
        let world = &mut sim.world;
        let robot = world.robot();
        let feedback = TrackingFeedback::new(&path, &robot);
        // `path` is not empty.
        let end = path.goal().unwrap_or(robot);
        let status = if robot.distance(&end) <= tolerance {
            if world.motion_status() == MotionStatus::Active {
                world.stop();
            }
            self.following = None;
            Ok(Status::Success)
        } else if starting
            || world.motion_status() == MotionStatus::Idle
            || self.following.as_ref() != Some(&path)
        {
            world.follow(ahead_of(&path, robot), speed);
            self.following = Some(path);
            Ok(Status::Running)
        } else {
            match world.motion_status() {
                MotionStatus::Active | MotionStatus::Idle => Ok(Status::Running),
                MotionStatus::Blocked(cell) => Err((
                    code::NO_VALID_CONTROL,
                    "blocked",
                    format!("blocked by an obstacle in cell {cell}"),
                )),
                MotionStatus::BatteryEmpty => Err((
                    code::FAILED_TO_MAKE_PROGRESS,
                    "battery empty",
                    "the battery is empty".to_string(),
                )),
                MotionStatus::Succeeded => Err((
                    code::FAILED_TO_MAKE_PROGRESS,
                    "stopped short of the goal",
                    format!(
                        "the path ended {:.2} m from its goal",
                        world.robot().distance(&end)
                    ),
                )),
            }
        };
        ports::emit(h, "tracking_feedback", feedback);
        match status {
            Ok(Status::Success) => ports::succeed(h),
            Ok(status) => status,
            Err((code, why, message)) => {
                self.following = None;
                ports::fail(h, code, why, message)
            }
        }
    }

    /// Fails, stopping the robot if it is still driving (a path taken away mid-run).
    fn abort<C: Nav2Context>(
        &mut self,
        h: &mut Handle<'_, C>,
        code: u16,
        why: &'static str,
        message: String,
    ) -> Status {
        if self.following.take().is_some() {
            let world = &mut h.ctx_mut().nav2_mut().world;
            if world.motion_status() == MotionStatus::Active {
                world.stop();
            }
        }
        ports::fail(h, code, why, message)
    }
}

/// The part of `path` still ahead of a robot at `robot`, starting where the robot is: what
/// Nav2's path handler gives the controller, so that a path handed over again (after a
/// recovery) is not driven from its start.
fn ahead_of(path: &Path, robot: Pose2D) -> Path {
    let mut from = path.closest_index(&robot).unwrap_or(0);
    // Past the nearest pose already (nearer the next one than it is): head for the next.
    if let (Some(near), Some(next)) = (path.poses.get(from), path.poses.get(from + 1)) {
        if robot.distance(next) < near.distance(next) {
            from += 1;
        }
    }
    let mut poses = Vec::with_capacity(path.len() - from + 1);
    if path
        .poses
        .get(from)
        .is_none_or(|p| p.x != robot.x || p.y != robot.y)
    {
        poses.push(robot);
    }
    poses.extend_from_slice(&path.poses[from..]);
    Path::new(poses)
}

impl<C: Nav2Context> StatefulAction<C> for FollowPath {
    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.control(h, true)
    }

    /// The path it follows: the world's motion, saved with the world, follows it too.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&self.following))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|following| self.following = following)
            .is_some()
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.control(h, false)
    }

    fn on_halted(&mut self, h: &mut Handle<'_, C>) {
        self.following = None;
        h.ctx_mut().nav2_mut().world.stop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;
    use crate::{Cell, CostmapLayer, TimedObstacle};
    use std::time::Duration;

    use Status::{Failure as F, Running as R, Success as S};

    const CORRIDOR: &str = "
        #######
        #R....#
        #.....#
        #######";

    const LEAF: &str = r#"<FollowPath path="{path}" tracking_feedback="{fb}" error_code_id="{code}" error_msg="{msg}"/>"#;

    fn straight(xs: &[f64]) -> Path {
        Path::new(xs.iter().map(|x| Pose2D::new(*x, 2.5, 0.0)).collect())
    }

    #[test]
    fn follows_to_the_end_and_succeeds_within_tolerance() {
        let mut b = Bench::new(CORRIDOR, LEAF);
        b.set("path", straight(&[1.5, 2.5, 3.5, 4.5]));
        // 3 m at 1 m/s in 0.1 s steps: within 0.25 m after 28 steps (2.8 m).
        let run = b.run(100);
        assert_eq!(run.len(), 29);
        assert_eq!(run.last(), Some(&S));
        assert!(run[..28].iter().all(|s| *s == R));
        let robot = b.sim.world.robot();
        assert!((robot.x - 4.3).abs() < 1e-9, "{robot:?}");
        // Stopped short of the end: one stop, by the success itself.
        assert_eq!(b.sim.world.stop_count(), 1);
        assert_eq!(b.get::<u16>("code"), 0);
        let fb: TrackingFeedback = b.get("fb");
        assert_eq!(fb.current_path_index, 3);
        assert!((fb.tracking_error - 0.2).abs() < 1e-9);
    }

    #[test]
    fn a_new_path_is_taken_over_while_running() {
        let mut b = Bench::new(CORRIDOR, LEAF);
        b.set("path", straight(&[1.5, 2.5, 3.5, 4.5]));
        assert_eq!(b.run(6), [R; 6]);
        assert!((b.sim.world.robot().x - 2.1).abs() < 1e-9);
        // A replan from where the robot is, down to the lower row.
        let here = b.sim.world.robot();
        b.set(
            "path",
            Path::new(vec![
                here,
                Pose2D::new(2.5, 1.5, 0.0),
                Pose2D::new(3.5, 1.5, 0.0),
            ]),
        );
        assert_eq!(b.tick(), R);
        assert_eq!(b.sim.world.followed_path().map(Path::len), Some(3));
        let rest = b.run(100);
        assert_eq!(rest.last(), Some(&S));
        assert_eq!(
            b.sim.world.map().cell_at(&b.sim.world.robot()),
            Some(Cell::new(3, 1))
        );
        assert_eq!(b.sim.world.stop_count(), 1);
    }

    #[test]
    fn cancel_control_stops_a_follow_and_nothing_else() {
        let mut b = Bench::new(
            "R....",
            r#"<Sequence><CancelControl/><AlwaysFailure/></Sequence>"#,
        );
        let path = b
            .sim
            .world
            .plan(b.sim.world.robot(), Pose2D::new(4.5, 0.5, 0.0));
        b.sim.world.follow(path.unwrap(), 1.0);
        b.sim.step();
        assert_eq!(b.sim.world.motion_status(), MotionStatus::Active);
        b.tick();
        assert_eq!(b.sim.world.motion_status(), MotionStatus::Idle);
        assert_eq!(b.sim.world.stop_count(), 1);
        // A spin is not the controller's: it goes on.
        b.sim.world.spin(1.0, 1.0);
        b.tick();
        assert_eq!(b.sim.world.motion_status(), MotionStatus::Active);
        assert_eq!(b.sim.world.stop_count(), 1);
    }

    #[test]
    fn blocked_fails_with_no_valid_control_without_stopping() {
        let world = crate::GridWorld::parse(CORRIDOR, 1.0)
            .unwrap()
            .with_sensing_radius(0.0)
            .with_timed_obstacle(TimedObstacle::new(Cell::new(3, 2), Duration::ZERO));
        let mut b = Bench::with_world(world, LEAF);
        b.set("path", straight(&[1.5, 2.5, 3.5, 4.5]));
        // A metre to the centre of the cell before the obstacle: blocked in the tenth step,
        // seen at the eleventh tick.
        let run = b.run(100);
        assert_eq!(run.len(), 11);
        assert_eq!(run.last(), Some(&F));
        assert_eq!(b.get::<u16>("code"), code::NO_VALID_CONTROL);
        assert_eq!(b.reason().as_deref(), Some("blocked (error 106)"));
        assert_eq!(
            b.get::<String>("msg"),
            "blocked by an obstacle in cell (3, 2)"
        );
        assert_eq!(b.sim.world.stop_count(), 0);
        assert!(b
            .sim
            .world
            .costmap(CostmapLayer::Local)
            .is_marked(Cell::new(3, 2)));
        // Started again on the same path, it tries again (and is blocked again).
        assert_eq!(b.run(3), [R, F]);
    }

    #[test]
    fn halting_stops_the_motion_exactly_once() {
        let mut b = Bench::new(CORRIDOR, LEAF);
        b.set("path", straight(&[1.5, 4.5]));
        assert_eq!(b.run(3), [R, R, R]);
        b.tree.halt(&mut b.sim);
        assert_eq!(b.sim.world.stop_count(), 1);
        assert_eq!(b.sim.world.motion_status(), MotionStatus::Idle);
        b.tree.halt(&mut b.sim);
        assert_eq!(b.sim.world.stop_count(), 1);
    }

    #[test]
    fn no_path_or_an_empty_one_is_an_invalid_path() {
        let mut b = Bench::new(CORRIDOR, LEAF);
        assert_eq!(b.tick(), F);
        assert_eq!(b.get::<u16>("code"), code::INVALID_PATH);
        b.set("path", Path::default());
        assert_eq!(b.tick(), F);
        assert_eq!(b.get::<String>("msg"), "no path to follow");
        assert_eq!(b.reason().as_deref(), Some("no path (error 103)"));
        // Taken away while driving: the robot stops.
        b.set("path", straight(&[1.5, 4.5]));
        assert_eq!(b.run(2), [R, R]);
        b.set("path", Path::default());
        assert_eq!(b.tick(), F);
        assert_eq!(b.sim.world.stop_count(), 1);
    }
}
