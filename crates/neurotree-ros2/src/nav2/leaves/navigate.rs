//! Other navigators and following over ROS 2: NavigateToPose, NavigateThroughPoses and
//! FollowObject.

use super::*;

/// NavigateToPose: another navigator (Nav2's, or a [`Navigator`](super::Navigator)) takes
/// the robot to `goal`.
pub(super) struct Navigate;

impl<C: 'static> ActionSpec<C> for Navigate {
    type Action = NavigateToPose;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<Pose2D>("goal").describe("Where to go."),
            PortSpec::input::<String>("behavior_tree")
                .describe("The navigator's tree to run; empty for its default."),
            server_name_port(),
            error_code_port("navigator"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<NavigateToPoseGoal, String> {
        let goal: Pose2D = required(h, "goal")?;
        Ok(NavigateToPoseGoal {
            pose: pose_stamped(goal),
            behavior_tree: optional(h, "behavior_tree")?.unwrap_or_default(),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &NavigateToPoseResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&NavigateToPoseResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, NavigateToPoseResult::UNKNOWN, error, server)
    }
}

/// NavigateThroughPoses: another navigator takes the robot through `goals`.
pub(super) struct NavigateThrough;

impl<C: 'static> ActionSpec<C> for NavigateThrough {
    type Action = NavigateThroughPoses;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<Vec<Pose2D>>("goals").describe("The poses to pass, in order."),
            PortSpec::input::<String>("behavior_tree")
                .describe("The navigator's tree to run; empty for its default."),
            server_name_port(),
            error_code_port("navigator"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<NavigateThroughPosesGoal, String> {
        let goals: Vec<Pose2D> = required(h, "goals")?;
        Ok(NavigateThroughPosesGoal {
            poses: goals_msg(&goals),
            behavior_tree: optional(h, "behavior_tree")?.unwrap_or_default(),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &NavigateThroughPosesResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&NavigateThroughPosesResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, NavigateThroughPosesResult::UNKNOWN, error, server)
    }
}

/// FollowObject: the following server keeps the robot behind the object whose pose comes
/// on `pose_topic`.
pub(super) struct FollowTarget;

impl<C: 'static> ActionSpec<C> for FollowTarget {
    type Action = FollowObject;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<String>("pose_topic")
                .default_value("dynamic_pose")
                .describe("The topic of the object's pose."),
            PortSpec::input::<f64>("max_duration")
                .default_value("0.0")
                .describe("Seconds to follow; 0 follows until stopped."),
            PortSpec::input::<String>("tracked_frame")
                .describe("The object's frame, when `pose_topic` is empty."),
            server_name_port(),
            PortSpec::output::<f64>("total_elapsed_time").describe("Seconds followed."),
            error_code_port("following"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<FollowObjectGoal, String> {
        let secs: f64 = optional(h, "max_duration")?.unwrap_or(0.0);
        Ok(FollowObjectGoal {
            pose_topic: optional(h, "pose_topic")?.unwrap_or_else(|| "dynamic_pose".into()),
            tracked_frame: optional(h, "tracked_frame")?.unwrap_or_default(),
            max_duration: seconds(secs),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &FollowObjectResult) -> Status {
        let took: Duration = result.total_elapsed_time.into();
        emit(h, "total_elapsed_time", took.as_secs_f64());
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&FollowObjectResult>,
    ) -> Status {
        // Nav2's node writes the time followed when aborted and when cancelled.
        if let Some(result) = result {
            let took: Duration = result.total_elapsed_time.into();
            emit(h, "total_elapsed_time", took.as_secs_f64());
        }
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, FollowObjectResult::UNKNOWN, error, server)
    }
}
