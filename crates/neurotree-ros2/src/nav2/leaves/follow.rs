//! FollowPath over ROS 2: a client of the controller server.

use super::*;

/// FollowPath: the controller server drives along `path`.
pub(super) struct Follow<A: RosAction> {
    /// The goal sent last, to tell a new path or plugin from it.
    sent: Option<A::Goal>,
}

impl<A: RosAction> Default for Follow<A> {
    fn default() -> Self {
        Self { sent: None }
    }
}

/// FollowPath's goal and feedback in the layout of a release (main's names a path handler
/// and gives a tracking feedback).
pub(super) trait FollowLayout:
    RosAction<Result = FollowPathResult, Goal: PartialEq>
{
    /// The goal: the path, then the controller, goal checker, progress checker and path
    /// handler ids.
    fn goal(path: NavPath, ids: [String; 4]) -> Self::Goal;
    fn path(goal: &Self::Goal) -> &NavPath;
    fn tracking(feedback: &Self::Feedback) -> Option<TrackingFeedback>;
}

impl FollowLayout for FollowPath {
    fn goal(
        path: NavPath,
        [controller, goal_checker, progress_checker, _]: [String; 4],
    ) -> FollowPathGoal {
        FollowPathGoal {
            path,
            controller_id: controller,
            goal_checker_id: goal_checker,
            progress_checker_id: progress_checker,
        }
    }
    fn path(goal: &FollowPathGoal) -> &NavPath {
        &goal.path
    }
    fn tracking(_: &Self::Feedback) -> Option<TrackingFeedback> {
        None
    }
}

impl FollowLayout for main::FollowPath {
    fn goal(
        path: NavPath,
        [controller, goal_checker, progress_checker, handler]: [String; 4],
    ) -> main::FollowPathGoal {
        main::FollowPathGoal {
            path,
            controller_id: controller,
            goal_checker_id: goal_checker,
            progress_checker_id: progress_checker,
            path_handler_id: handler,
        }
    }
    fn path(goal: &main::FollowPathGoal) -> &NavPath {
        &goal.path
    }
    fn tracking(feedback: &main::FollowPathFeedback) -> Option<TrackingFeedback> {
        let t = &feedback.tracking_feedback;
        let (x, y) = (
            f64::from(t.position_tracking_error),
            f64::from(t.heading_tracking_error),
        );
        Some(TrackingFeedback {
            current_path_index: t.current_path_index as usize,
            remaining_path_length: f64::from(t.remaining_path_length),
            // The message does not carry the distance to the nearest pose: the distance to
            // the path stands for it.
            tracking_error: x.abs(),
            position_tracking_error: x,
            heading_tracking_error: y,
        })
    }
}

impl<A: FollowLayout> Follow<A> {
    fn read<C>(h: &Handle<'_, C>, path: NavPath) -> Result<A::Goal, String> {
        let id =
            |port: &str| -> Result<String, String> { Ok(optional(h, port)?.unwrap_or_default()) };
        Ok(A::goal(
            path,
            [
                id("controller_id")?,
                id("goal_checker_id")?,
                id("progress_checker_id")?,
                id("path_handler_id")?,
            ],
        ))
    }
}

impl<C: 'static, A: FollowLayout> ActionSpec<C> for Follow<A> {
    type Action = A;

    fn ports() -> Vec<PortSpec> {
        let plugin = |name: &str, what: &str| {
            PortSpec::input::<String>(name).describe(&format!("The {what} plugin."))
        };
        vec![
            PortSpec::input::<Path>("path").describe("The path to follow."),
            plugin("controller_id", "controller"),
            plugin("goal_checker_id", "goal checker"),
            plugin("progress_checker_id", "progress checker"),
            plugin(
                "path_handler_id",
                "path handler (sent in Nav2 main's layout only)",
            ),
            server_name_port(),
            PortSpec::output::<TrackingFeedback>("tracking_feedback")
                .describe("The controller's tracking feedback (in Nav2 main's layout only)."),
            error_code_port("controller"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<A::Goal, String> {
        let path: Path = required(h, "path")?;
        let goal = Self::read(h, path_msg(&path))?;
        self.sent = Some(goal.clone());
        Ok(goal)
    }

    fn updated_goal(&mut self, h: &mut Handle<'_, C>) -> Option<A::Goal> {
        // As Nav2's `on_wait_for_result`: a new non-empty path, or another plugin.
        let sent = self.sent.as_ref()?;
        let path = match optional::<C, Path>(h, "path").ok().flatten() {
            Some(path) if !path.poses.is_empty() => path_msg(&path),
            _ => A::path(sent).clone(),
        };
        let goal = Self::read(h, path).ok()?;
        if goal == *sent {
            return None;
        }
        self.sent = Some(goal.clone());
        Some(goal)
    }

    fn on_feedback(&mut self, h: &mut Handle<'_, C>, feedback: &A::Feedback) -> Status {
        if let Some(tracking) = A::tracking(feedback) {
            emit(h, "tracking_feedback", tracking);
        }
        Status::Running
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &FollowPathResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&FollowPathResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, FollowPathResult::UNKNOWN, error, server)
    }
}
