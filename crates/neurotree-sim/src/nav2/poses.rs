//! Poses and paths on the blackboard: GetCurrentPose, GetPoseFromPath, ConcatenatePaths,
//! ArePosesNear and GoalReached.
//!
//! - **GetCurrentPose**: a sync action. Output `current_pose`: the robot's pose (Nav2 reads
//!   it from TF; the simulated robot always has one). Success. `global_frame` and
//!   `robot_base_frame` are declared and unused.
//! - **GetPoseFromPath**: a sync action. Ports `path`, `index` (default 0); output `pose`.
//!   As Nav2's `get_pose_from_path_action.cpp`: a negative index counts from the end (-1 is
//!   the last pose); an empty path or an index out of range: Failure; else writes the pose,
//!   Success.
//! - **ConcatenatePaths**: a sync action. Ports `input_path1`, `input_path2`; output
//!   `output_path`: the poses of the first, then those of the second. Both empty (or absent):
//!   Failure, as Nav2's node refuses to join two empty paths.
//! - **ArePosesNear**: a condition. Ports `ref_pose`, `target_pose`, `tolerance` (default
//!   0.5), `global_frame` (unused). Success when the two positions are within `tolerance`
//!   (`<=`, heading ignored), as Nav2's `are_poses_near_condition.cpp`; an absent pose is
//!   the origin, as Nav2's default-made pose is.
//! - **GoalReached**: a condition. Port `goal`, `robot_base_frame` (unused). Success when
//!   the robot is within the goal tolerance (Nav2's `goal_reached_tol`, here
//!   [`Nav2Params::goal_tolerance`](super::Nav2Params::goal_tolerance), 0.25 m by default)
//!   of `goal` (`<=`).

use neurotree_core::{Handle, Status};

use super::{ports, Nav2Context};
use neurotree_nav2::robotics::{Path, Pose2D};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

fn frame(name: &str) -> PortSpec {
    PortSpec::input::<String>(name).describe("Frame name (unused: the world has one frame).")
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_action(
        "GetCurrentPose",
        vec![
            frame("robot_base_frame"),
            frame("global_frame"),
            PortSpec::output::<Pose2D>("current_pose").describe("The robot's pose."),
        ],
        get_current_pose::<C>,
    )?;
    r.describe("GetCurrentPose", "Writes the robot's pose.");
    r.register_action(
        "GetPoseFromPath",
        vec![
            PortSpec::input::<Path>("path").describe("The path to take a pose from."),
            PortSpec::input::<i32>("index")
                .default_value("0")
                .describe("Which pose; negative counts from the end (-1 is the last)."),
            PortSpec::output::<Pose2D>("pose").describe("The pose at `index`."),
        ],
        get_pose_from_path::<C>,
    )?;
    r.describe("GetPoseFromPath", "Writes the pose at `index` of a path.");
    r.register_action(
        "ConcatenatePaths",
        vec![
            PortSpec::input::<Path>("input_path1").describe("The first path."),
            PortSpec::input::<Path>("input_path2").describe("The path joined after it."),
            PortSpec::output::<Path>("output_path").describe("The two, one after the other."),
        ],
        concatenate_paths::<C>,
    )?;
    r.describe("ConcatenatePaths", "Joins two paths into one.");
    r.register_condition(
        "ArePosesNear",
        vec![
            PortSpec::input::<Pose2D>("ref_pose").describe("One pose."),
            PortSpec::input::<Pose2D>("target_pose").describe("The other pose."),
            frame("global_frame"),
            PortSpec::input::<f64>("tolerance")
                .default_value("0.5")
                .describe("Metres within which the poses are near."),
        ],
        are_poses_near::<C>,
    )?;
    r.describe(
        "ArePosesNear",
        "Succeeds when two poses are within `tolerance`.",
    );
    r.register_condition(
        "GoalReached",
        vec![
            PortSpec::input::<Pose2D>("goal").describe("The goal."),
            frame("robot_base_frame"),
        ],
        goal_reached::<C>,
    )?;
    r.describe(
        "GoalReached",
        "Succeeds when the robot is within the goal tolerance of `goal`.",
    );
    Ok(())
}

/// GetCurrentPose: see the [module documentation](self).
fn get_current_pose<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let pose = h.ctx().nav2().world.robot();
    ports::emit(h, "current_pose", pose);
    Status::Success
}

/// GetPoseFromPath: see the [module documentation](self).
fn get_pose_from_path<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let read = ports::or(h, "path", Path::default())
        .and_then(|path| Ok((path, ports::or(h, "index", 0_i32)?)));
    let Ok((path, index)) = read else {
        return Status::Failure;
    };
    let len = path.poses.len() as i64;
    let index = match i64::from(index) {
        i if i < 0 => len + i,
        i => i,
    };
    let pose = usize::try_from(index)
        .ok()
        .and_then(|i| path.poses.get(i).copied());
    match pose {
        Some(pose) => {
            ports::emit(h, "pose", pose);
            Status::Success
        }
        None => Status::Failure,
    }
}

/// ConcatenatePaths: see the [module documentation](self).
fn concatenate_paths<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let read = ports::or(h, "input_path1", Path::default())
        .and_then(|first| Ok((first, ports::or(h, "input_path2", Path::default())?)));
    let Ok((mut first, second)) = read else {
        return Status::Failure;
    };
    if first.is_empty() && second.is_empty() {
        return Status::Failure;
    }
    first.poses.extend(second.poses);
    ports::emit(h, "output_path", first);
    Status::Success
}

/// ArePosesNear: see the [module documentation](self).
fn are_poses_near<C: Nav2Context>(h: &Handle<'_, C>) -> bool {
    let read = (|| {
        let a = ports::or(h, "ref_pose", Pose2D::default())?;
        let b = ports::or(h, "target_pose", Pose2D::default())?;
        let tolerance: f64 = ports::or(h, "tolerance", 0.5)?;
        Ok::<_, neurotree_core::PortError>((a, b, tolerance))
    })();
    read.is_ok_and(|(a, b, tolerance)| within(&a, &b, tolerance))
}

/// `true` when `a` and `b` are within `tolerance` metres, compared squared as Nav2 does.
fn within(a: &Pose2D, b: &Pose2D, tolerance: f64) -> bool {
    let (dx, dy) = (a.x - b.x, a.y - b.y);
    dx * dx + dy * dy <= tolerance * tolerance
}

/// GoalReached: see the [module documentation](self).
fn goal_reached<C: Nav2Context>(h: &Handle<'_, C>) -> bool {
    let Ok(goal) = ports::or(h, "goal", Pose2D::default()) else {
        return false;
    };
    let sim = h.ctx().nav2();
    within(&sim.world.robot(), &goal, sim.params.goal_tolerance)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;
    use Status::{Failure as F, Success as S};

    fn path(xs: &[f64]) -> Path {
        Path::new(xs.iter().map(|&x| Pose2D::new(x, 0.5, 0.0)).collect())
    }

    #[test]
    fn get_current_pose_writes_the_robots_pose() {
        let mut b = Bench::new("..R..", r#"<GetCurrentPose current_pose="{p}"/>"#);
        assert_eq!(b.tick(), S);
        assert_eq!(b.get::<Pose2D>("p"), Pose2D::new(2.5, 0.5, 0.0));
    }

    #[test]
    fn get_pose_from_path_counts_negative_indices_from_the_end() {
        let mut b = Bench::new(
            "R",
            r#"<GetPoseFromPath path="{path}" index="{i}" pose="{p}"/>"#,
        );
        b.set("path", path(&[1.0, 2.0, 3.0]));
        for (i, expected) in [
            (0, Some(1.0)),
            (2, Some(3.0)),
            (-1, Some(3.0)),
            (-3, Some(1.0)),
        ] {
            b.set("i", i);
            assert_eq!(b.tick(), S, "{i}");
            assert_eq!(b.get::<Pose2D>("p").x, expected.unwrap_or_default(), "{i}");
        }
        for i in [3, -4] {
            b.set("i", i);
            assert_eq!(b.tick(), F, "{i}");
        }
        b.set("path", Path::default());
        b.set("i", 0);
        assert_eq!(b.tick(), F);
    }

    #[test]
    fn concatenate_paths_joins_them_and_refuses_two_empty_ones() {
        let mut b = Bench::new(
            "R",
            r#"<ConcatenatePaths input_path1="{a}" input_path2="{b}" output_path="{a}"/>"#,
        );
        b.set("a", path(&[1.0]));
        b.set("b", path(&[2.0, 3.0]));
        assert_eq!(b.tick(), S);
        assert_eq!(b.get::<Path>("a"), path(&[1.0, 2.0, 3.0]));
        b.set("a", Path::default());
        b.set("b", Path::default());
        assert_eq!(b.tick(), F);
        b.set("b", path(&[4.0]));
        assert_eq!(b.tick(), S);
        assert_eq!(b.get::<Path>("a"), path(&[4.0]));
    }

    #[test]
    fn poses_are_near_within_the_tolerance_inclusive() {
        let mut b = Bench::new(
            "R",
            r#"<ArePosesNear ref_pose="{a}" target_pose="{b}" tolerance="0.5"/>"#,
        );
        b.set("a", Pose2D::new(1.0, 1.0, 0.0));
        for (x, expected) in [(1.0, S), (1.5, S), (1.51, F), (0.5, S)] {
            b.set("b", Pose2D::new(x, 1.0, 3.0));
            assert_eq!(b.tick(), expected, "{x}");
        }
    }

    #[test]
    fn goal_reached_within_the_goal_tolerance() {
        let mut b = Bench::new("R....", r#"<GoalReached goal="{goal}"/>"#);
        for (x, expected) in [(0.75, S), (0.76, F), (4.5, F)] {
            b.set("goal", Pose2D::new(x, 0.5, 1.0));
            assert_eq!(b.tick(), expected, "{x}");
        }
    }
}
