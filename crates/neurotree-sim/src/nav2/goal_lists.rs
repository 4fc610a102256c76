//! Lists of goals: AppendGoalPoseToGoals and GetNextFewGoals.
//!
//! Goals are a `Vec<Pose2D>` (Nav2's `nav_msgs/Goals`).
//!
//! - **AppendGoalPoseToGoals**: a sync action. Ports `goal_pose`, `input_goals`; output
//!   `output_goals`: the goals with `goal_pose` added at the end. Success. As Nav2's node,
//!   an absent input counts as empty (an absent pose as the origin).
//! - **GetNextFewGoals**: a sync action. Ports `num_goals`, `input_goals`; output
//!   `output_goals`: the first `num_goals` goals (all of them when there are fewer).
//!   Failure without goals, as Nav2's `get_next_few_goals_action.cpp`.

use neurotree_core::{Handle, Status};

use super::{ports, Nav2Context};
use neurotree_nav2::robotics::Pose2D;
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_action(
        "AppendGoalPoseToGoals",
        vec![
            PortSpec::input::<Pose2D>("goal_pose").describe("The pose to add."),
            PortSpec::input::<Vec<Pose2D>>("input_goals").describe("The goals."),
            PortSpec::output::<Vec<Pose2D>>("output_goals")
                .describe("The goals with `goal_pose` last."),
        ],
        append_goal_pose::<C>,
    )?;
    r.describe(
        "AppendGoalPoseToGoals",
        "Adds a pose at the end of a list of goals.",
    );
    r.register_action(
        "GetNextFewGoals",
        vec![
            PortSpec::input::<u32>("num_goals").describe("How many goals to take."),
            PortSpec::input::<Vec<Pose2D>>("input_goals").describe("The goals."),
            PortSpec::output::<Vec<Pose2D>>("output_goals").describe("The first `num_goals`."),
        ],
        get_next_few_goals::<C>,
    )?;
    r.describe(
        "GetNextFewGoals",
        "Takes the first `num_goals` goals of a list.",
    );
    Ok(())
}

/// AppendGoalPoseToGoals: see the [module documentation](self).
fn append_goal_pose<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let read = ports::or(h, "goal_pose", Pose2D::default())
        .and_then(|pose| Ok((pose, ports::or(h, "input_goals", Vec::<Pose2D>::new())?)));
    let Ok((pose, mut goals)) = read else {
        return Status::Failure;
    };
    goals.push(pose);
    ports::emit(h, "output_goals", goals);
    Status::Success
}

/// GetNextFewGoals: see the [module documentation](self).
fn get_next_few_goals<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let read = ports::or(h, "input_goals", Vec::<Pose2D>::new())
        .and_then(|goals| Ok((goals, ports::or(h, "num_goals", 0_u32)?)));
    let Ok((mut goals, count)) = read else {
        return Status::Failure;
    };
    if goals.is_empty() {
        return Status::Failure;
    }
    goals.truncate(usize::try_from(count).unwrap_or(usize::MAX));
    ports::emit(h, "output_goals", goals);
    Status::Success
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;
    use Status::{Failure as F, Success as S};

    fn at(x: f64) -> Pose2D {
        Pose2D::new(x, 0.0, 0.0)
    }

    #[test]
    fn the_goal_pose_goes_last() {
        let mut b = Bench::new(
            "R",
            r#"<AppendGoalPoseToGoals goal_pose="{g}" input_goals="{l}" output_goals="{l}"/>"#,
        );
        b.set("g", at(3.0));
        assert_eq!(b.tick(), S);
        assert_eq!(b.get::<Vec<Pose2D>>("l"), [at(3.0)]);
        b.set("g", at(4.0));
        assert_eq!(b.tick(), S);
        assert_eq!(b.get::<Vec<Pose2D>>("l"), [at(3.0), at(4.0)]);
    }

    #[test]
    fn the_next_few_goals_are_the_first_ones_and_none_fails() {
        let mut b = Bench::new(
            "R",
            r#"<GetNextFewGoals num_goals="2" input_goals="{l}" output_goals="{out}"/>"#,
        );
        b.set("l", vec![at(1.0), at(2.0), at(3.0)]);
        assert_eq!(b.tick(), S);
        assert_eq!(b.get::<Vec<Pose2D>>("out"), [at(1.0), at(2.0)]);
        b.set("l", vec![at(5.0)]);
        assert_eq!(b.tick(), S);
        assert_eq!(b.get::<Vec<Pose2D>>("out"), [at(5.0)]);
        b.set("l", Vec::<Pose2D>::new());
        assert_eq!(b.tick(), F);
        assert_eq!(b.get::<Vec<Pose2D>>("out"), [at(5.0)]);
    }
}
