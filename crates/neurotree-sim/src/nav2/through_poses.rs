//! Navigating through poses: ComputePathThroughPoses and RemovePassedGoals.
//!
//! - **ComputePathThroughPoses**: a sync action. Ports: `goals`, `start` (optional),
//!   `planner_id`; outputs `path`, `last_reached_index`, `error_code_id`, `error_msg`.
//!   - A* on the global costmap from `start` (the robot when absent) through each of
//!     `goals` in order, as [ComputePathToPose](super::planner) plans through its
//!     viapoints. Success: writes `path`, `last_reached_index` -1 (all goals reached) and
//!     error code 0.
//!   - Failure: an empty `path` and the code of ComputePathToPose's failure plus 100, as
//!     Nav2's action numbers them (NO_VALID_PATH 308, GOAL_OCCUPIED 306, ...);
//!     NO_VIAPOINTS_GIVEN 309 without goals.
//! - **RemovePassedGoals**: a sync action. Ports: `input_goals`, `radius` (default 0.5),
//!   `input_waypoint_statuses`; outputs `output_goals`, `output_waypoint_statuses`. As
//!   Nav2's `remove_passed_goals_action.cpp`:
//!   - Drops goals from the front of the list while the robot is within `radius` of the
//!     first one, keeping the last goal; writes the rest. Success.
//!   - The waypoint statuses are declared and not kept: the simulator has no
//!     waypoint-status type, and a navigator that reads them runs on Nav2's side.

use neurotree_core::{Handle, Status};

use super::codes::compute_path_through_poses as code;
use super::{planner, ports, Nav2Context};
use neurotree_nav2::robotics::{Path, Pose2D};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_action(
        "ComputePathThroughPoses",
        vec![
            PortSpec::input::<Pose2D>("start").describe("Start pose, instead of the robot's."),
            PortSpec::input::<Vec<Pose2D>>("goals").describe("The poses to pass, in order."),
            PortSpec::input::<String>("planner_id")
                .default_value("")
                .describe("Planner plugin to use; the simulation has one and accepts any id."),
            PortSpec::input::<String>("server_name").describe("Action server name (unused)."),
            PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
            PortSpec::output::<Path>("path").describe("The path planned; empty after a failure."),
            PortSpec::output::<i32>("last_reached_index")
                .describe("-1: the path reaches every goal."),
            PortSpec::output::<u16>("error_code_id").describe("0, or the planner's error code."),
            PortSpec::output::<String>("error_msg")
                .describe("Why planning failed; empty on success."),
        ],
        compute_path_through_poses::<C>,
    )?;
    r.describe(
        "ComputePathThroughPoses",
        "Plans a path on the global costmap from the robot through each of `goals`.",
    );
    register_remove_passed_goals(r)
}

/// RemovePassedGoals alone: it reads only the robot's pose, so a navigator whose planner is
/// served elsewhere has it too.
pub(super) fn register_remove_passed_goals<C: Nav2Context>(
    r: &mut Registry<C>,
) -> Result<(), RegistryError> {
    r.register_action(
        "RemovePassedGoals",
        vec![
            PortSpec::input::<f64>("radius")
                .default_value("0.5")
                .describe("Metres from a goal at which it counts as passed."),
            PortSpec::input::<String>("robot_base_frame").describe("Robot frame (unused)."),
            PortSpec::input::<Vec<Pose2D>>("input_goals").describe("The goals still to pass."),
            PortSpec::input::<String>("input_waypoint_statuses")
                .describe("Waypoint statuses (not kept)."),
            PortSpec::output::<Vec<Pose2D>>("output_goals")
                .describe("The goals, less those passed."),
            PortSpec::output::<String>("output_waypoint_statuses")
                .describe("Waypoint statuses (not written)."),
        ],
        remove_passed_goals::<C>,
    )?;
    r.describe(
        "RemovePassedGoals",
        "Drops the goals the robot has come within `radius` of, but the last.",
    );
    Ok(())
}

/// ComputePathThroughPoses: see the [module documentation](self).
fn compute_path_through_poses<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let inputs = ports::or(h, "goals", Vec::<Pose2D>::new())
        .and_then(|goals| Ok((goals, ports::optional::<Pose2D, C>(h, "start")?)));
    let (goals, start) = match inputs {
        Ok(inputs) => inputs,
        Err(e) => return failed(h, code::UNKNOWN, "bad input", e.to_string()),
    };
    let Some((goal, viapoints)) = goals.split_last() else {
        let message = "no goals: bind `goals` to a list of poses".into();
        return failed(h, code::NO_VIAPOINTS_GIVEN, "no goals", message);
    };
    let planned = {
        let world = &mut h.ctx_mut().nav2_mut().world;
        let start = start.unwrap_or_else(|| world.robot());
        planner::plan_through(world, start, viapoints, *goal)
    };
    let path = match planned {
        Ok(path) => path,
        // ComputePathToPose's codes are 200..=208; this action's are the same, 100 higher.
        Err((code, why, message)) => return failed(h, code + 100, why, message),
    };
    let previous = ports::optional::<Path, C>(h, "path").ok().flatten();
    let replaced = previous.as_ref() != Some(&path);
    let (poses, length) = (path.len(), path.length());
    let sim = h.ctx_mut().nav2_mut();
    sim.count_plan(replaced);
    sim.note(|| format!("ComputePathThroughPoses: a path of {poses} poses, {length:.1} m"));
    ports::emit(h, "path", path);
    ports::emit(h, "last_reached_index", -1i32);
    ports::succeed(h)
}

/// A failed run: an empty path and the error.
fn failed<C>(h: &mut Handle<'_, C>, code: u16, why: &'static str, message: String) -> Status {
    ports::emit(h, "path", Path::default());
    ports::fail(h, code, why, message)
}

/// RemovePassedGoals: see the [module documentation](self).
fn remove_passed_goals<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let read = ports::or(h, "input_goals", Vec::<Pose2D>::new())
        .and_then(|goals| Ok((goals, ports::or(h, "radius", 0.5)?)));
    let Ok((mut goals, radius)) = read else {
        return Status::Failure;
    };
    let robot = h.ctx().nav2().world.robot();
    let passed = goals
        .iter()
        .take(goals.len().saturating_sub(1))
        .take_while(|goal| goal.distance(&robot) <= radius)
        .count();
    goals.drain(..passed);
    ports::emit(h, "output_goals", goals);
    Status::Success
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;

    const ROOM: &str = "
        #######
        #R....#
        #.....#
        #######";

    #[test]
    fn a_path_through_each_goal_in_order() {
        let leaf = r#"<ComputePathThroughPoses goals="{goals}" path="{path}" error_code_id="{code}" last_reached_index="{last}"/>"#;
        let mut b = Bench::new(ROOM, leaf);
        let goals = vec![Pose2D::new(5.5, 1.5, 0.0), Pose2D::new(1.5, 1.5, 0.0)];
        b.set("goals", goals);
        assert_eq!(b.tick(), Status::Success);
        let path: Path = b.get("path");
        assert_eq!(b.get::<u16>("code"), 0);
        assert_eq!(b.get::<i32>("last"), -1);
        // Out to the far end of the room and back.
        assert!(path.poses.iter().any(|p| (p.x - 5.5).abs() < 1e-9));
        assert_eq!(path.poses.last().map(|p| (p.x, p.y)), Some((1.5, 1.5)));
        // A goal in a wall: ComputePathToPose's GOAL_OCCUPIED, 100 higher.
        b.set("goals", vec![Pose2D::new(0.5, 0.5, 0.0)]);
        assert_eq!(b.tick(), Status::Failure);
        assert_eq!(b.get::<u16>("code"), 306);
        assert!(b.get::<Path>("path").is_empty());
        b.set("goals", Vec::<Pose2D>::new());
        assert_eq!(b.tick(), Status::Failure);
        assert_eq!(b.get::<u16>("code"), code::NO_VIAPOINTS_GIVEN);
    }

    #[test]
    fn passed_goals_are_dropped_but_the_last() {
        let leaf =
            r#"<RemovePassedGoals input_goals="{goals}" output_goals="{goals}" radius="0.7"/>"#;
        let mut b = Bench::new(ROOM, leaf);
        // The robot is at (1.5, 2.5).
        let near = Pose2D::new(1.5, 2.0, 0.0);
        let far = Pose2D::new(5.5, 1.5, 0.0);
        b.set("goals", vec![near, near, far]);
        assert_eq!(b.tick(), Status::Success);
        assert_eq!(b.get::<Vec<Pose2D>>("goals"), [far]);
        b.set("goals", vec![near]);
        assert_eq!(b.tick(), Status::Success);
        assert_eq!(b.get::<Vec<Pose2D>>("goals"), [near]);
        b.set("goals", vec![far, near]);
        assert_eq!(b.tick(), Status::Success);
        assert_eq!(b.get::<Vec<Pose2D>>("goals"), [far, near]);
    }
}
