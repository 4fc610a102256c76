//! The goals of the newer Nav2 releases (Kilted's, main's), served as the Jazzy action
//! whose leaf runs them.

use std::time::Duration;

use neurotree_nav2::robotics::TrackingFeedback;
use neurotree_sim::nav2::Nav2Sim;
use neurotree_toolkit::Blackboard;

use super::actions::SimAction;
use super::stats::{ServerCounts, SimStats};
use crate::msg::nav2_msgs::{
    kilted, main, BackUp, BackUpGoal, ComputePathThroughPoses, ComputePathThroughPosesGoal,
    ComputePathToPose, ComputePathToPoseGoal, DriveOnHeading, DriveOnHeadingGoal, FollowPath,
    FollowPathGoal, Spin, SpinGoal,
};
use crate::nav2::convert::pose_stamped;

/// Implements [`SimAction`] for a newer goal layout (Kilted's, main's) as the Jazzy
/// action's, its goal made Jazzy's by `$to_jazzy`; `$record` notes the new fields in the
/// stats (the sim reads none: the world never lets the robot into an occupied cell, and
/// its planner plans straight to the goal).
macro_rules! kilted_as_jazzy {
    ($kilted:ty, $jazzy:ty, $to_jazzy:expr, $record:expr) => {
        impl SimAction for $kilted {
            const XML: &'static str = <$jazzy as SimAction>::XML;
            fn put(goal: &Self::Goal, bb: &mut Blackboard) {
                <$jazzy as SimAction>::put(&$to_jazzy(goal), bb);
            }
            fn result(
                bb: &Blackboard,
                code: u16,
                message: String,
                elapsed: Duration,
            ) -> Self::Result {
                <$jazzy as SimAction>::result(bb, code, message, elapsed)
            }
            fn counts(stats: &mut SimStats) -> &mut ServerCounts {
                <$jazzy as SimAction>::counts(stats)
            }
            fn record(goal: &Self::Goal, stats: &mut SimStats) {
                $record(goal, stats);
            }
        }
    };
}

kilted_as_jazzy!(
    kilted::Spin,
    Spin,
    |g: &kilted::SpinGoal| SpinGoal {
        target_yaw: g.target_yaw,
        time_allowance: g.time_allowance,
    },
    |g: &kilted::SpinGoal, stats: &mut SimStats| {
        stats.disable_collision_checks = Some(g.disable_collision_checks);
    }
);
kilted_as_jazzy!(
    kilted::BackUp,
    BackUp,
    |g: &kilted::BackUpGoal| BackUpGoal {
        target: g.target,
        speed: g.speed,
        time_allowance: g.time_allowance,
    },
    |g: &kilted::BackUpGoal, stats: &mut SimStats| {
        stats.disable_collision_checks = Some(g.disable_collision_checks);
    }
);
kilted_as_jazzy!(
    kilted::DriveOnHeading,
    DriveOnHeading,
    |g: &kilted::DriveOnHeadingGoal| DriveOnHeadingGoal {
        target: g.target,
        speed: g.speed,
        time_allowance: g.time_allowance,
    },
    |g: &kilted::DriveOnHeadingGoal, stats: &mut SimStats| {
        stats.disable_collision_checks = Some(g.disable_collision_checks);
    }
);
kilted_as_jazzy!(
    main::ComputePathToPose,
    ComputePathToPose,
    |g: &main::ComputePathToPoseGoal| ComputePathToPoseGoal {
        goal: g.goal.clone(),
        start: g.start.clone(),
        planner_id: g.planner_id.clone(),
        use_start: g.use_start,
    },
    |g: &main::ComputePathToPoseGoal, stats: &mut SimStats| {
        stats.viapoints = Some(g.viapoints.len());
    }
);
/// Main's FollowPath: Jazzy's, but for the path handler (which the sim has not) and the
/// feedback, the sim's tracking feedback with the robot's pose, distance and speed.
impl SimAction for main::FollowPath {
    const XML: &'static str = <FollowPath as SimAction>::XML;
    fn put(goal: &Self::Goal, bb: &mut Blackboard) {
        let jazzy = FollowPathGoal {
            path: goal.path.clone(),
            controller_id: goal.controller_id.clone(),
            goal_checker_id: goal.goal_checker_id.clone(),
            progress_checker_id: goal.progress_checker_id.clone(),
        };
        <FollowPath as SimAction>::put(&jazzy, bb);
    }
    fn result(bb: &Blackboard, code: u16, message: String, elapsed: Duration) -> Self::Result {
        <FollowPath as SimAction>::result(bb, code, message, elapsed)
    }
    fn feedback(bb: &Blackboard, sim: &Nav2Sim) -> Option<main::FollowPathFeedback> {
        let old = <FollowPath as SimAction>::feedback(bb, sim)?;
        let t = bb
            .get::<TrackingFeedback>("tracking_feedback")
            .unwrap_or_default();
        Some(main::FollowPathFeedback {
            tracking_feedback: main::TrackingFeedback {
                header: pose_stamped(sim.world.robot()).header,
                position_tracking_error: t.position_tracking_error as f32,
                heading_tracking_error: t.heading_tracking_error as f32,
                current_path_index: u32::try_from(t.current_path_index).unwrap_or(u32::MAX),
                robot_pose: pose_stamped(sim.world.robot()),
                distance_to_goal: old.distance_to_goal,
                speed: old.speed,
                remaining_path_length: t.remaining_path_length as f32,
            },
        })
    }
    fn counts(stats: &mut SimStats) -> &mut ServerCounts {
        <FollowPath as SimAction>::counts(stats)
    }
}

kilted_as_jazzy!(
    kilted::ComputePathThroughPoses,
    ComputePathThroughPoses,
    |g: &kilted::ComputePathThroughPosesGoal| ComputePathThroughPosesGoal {
        goals: g.goals.goals.clone(),
        start: g.start.clone(),
        planner_id: g.planner_id.clone(),
        use_start: g.use_start,
    },
    |_: &kilted::ComputePathThroughPosesGoal, _: &mut SimStats| {}
);
