//! Planning over ROS 2: ComputePathToPose, ComputePathThroughPoses and SmoothPath, clients of
//! the planner and smoother servers.

use super::*;

/// ComputePathToPose: the planner server's path from the robot (or `start`) to `goal`.
pub(super) struct ComputePath<A>(PhantomData<fn() -> A>);

impl<A> Default for ComputePath<A> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

/// ComputePathToPose's goal in the layout of a release (main's adds `viapoints`).
pub(super) trait ComputePathLayout: RosAction<Result = ComputePathToPoseResult> {
    fn goal(
        goal: PoseStamped,
        start: PoseStamped,
        viapoints: Vec<PoseStamped>,
        planner_id: String,
        use_start: bool,
    ) -> Self::Goal;
}

impl ComputePathLayout for ComputePathToPose {
    fn goal(
        goal: PoseStamped,
        start: PoseStamped,
        _: Vec<PoseStamped>,
        planner_id: String,
        use_start: bool,
    ) -> ComputePathToPoseGoal {
        ComputePathToPoseGoal {
            goal,
            start,
            planner_id,
            use_start,
        }
    }
}

impl ComputePathLayout for main::ComputePathToPose {
    fn goal(
        goal: PoseStamped,
        start: PoseStamped,
        viapoints: Vec<PoseStamped>,
        planner_id: String,
        use_start: bool,
    ) -> main::ComputePathToPoseGoal {
        main::ComputePathToPoseGoal {
            goal,
            start,
            viapoints,
            planner_id,
            use_start,
        }
    }
}

impl<C: 'static, A: ComputePathLayout> ActionSpec<C> for ComputePath<A> {
    type Action = A;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<Pose2D>("goal").describe("Where the path ends."),
            PortSpec::input::<Pose2D>("start").describe("Where it starts, instead of the robot."),
            PortSpec::input::<bool>("use_start").describe("Use `start` (true when it is given)."),
            PortSpec::input::<Vec<Pose2D>>("viapoints")
                .describe("Poses the path passes on its way (sent in Nav2 main's layout only)."),
            PortSpec::input::<String>("planner_id")
                .default_value("")
                .describe("The planner plugin; empty for the only one."),
            server_name_port(),
            PortSpec::output::<Path>("path").describe("The path found."),
            error_code_port("planner"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<A::Goal, String> {
        let goal: Pose2D = required(h, "goal")?;
        let start: Option<Pose2D> = optional(h, "start")?;
        let use_start = optional::<C, bool>(h, "use_start")?.unwrap_or(start.is_some());
        let viapoints: Vec<Pose2D> = optional(h, "viapoints")?.unwrap_or_default();
        Ok(A::goal(
            pose_stamped(goal),
            pose_stamped(start.unwrap_or_default()),
            viapoints.into_iter().map(pose_stamped).collect(),
            optional(h, "planner_id")?.unwrap_or_default(),
            use_start && start.is_some(),
        ))
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &ComputePathToPoseResult) -> Status {
        if result.error_code == ComputePathToPoseResult::NONE {
            emit(h, "path", path_2d(&result.path));
        }
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&ComputePathToPoseResult>,
    ) -> Status {
        // As Nav2's node does: no path rather than a stale one.
        emit(h, "path", Path::default());
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, ComputePathToPoseResult::UNKNOWN, error, server)
    }
}

/// ComputePathThroughPoses: the planner server's path from the robot (or `start`) through
/// each of `goals`.
pub(super) struct ComputeThrough<A>(PhantomData<fn() -> A>);

impl<A> Default for ComputeThrough<A> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

/// ComputePathThroughPoses's goal in the layout of a release.
pub(super) trait ThroughPosesLayout:
    RosAction<Result = ComputePathThroughPosesResult>
{
    fn goal(
        goals: Vec<PoseStamped>,
        start: PoseStamped,
        planner_id: String,
        use_start: bool,
    ) -> Self::Goal;
}

impl ThroughPosesLayout for ComputePathThroughPoses {
    fn goal(
        goals: Vec<PoseStamped>,
        start: PoseStamped,
        planner_id: String,
        use_start: bool,
    ) -> ComputePathThroughPosesGoal {
        ComputePathThroughPosesGoal {
            goals,
            start,
            planner_id,
            use_start,
        }
    }
}

impl ThroughPosesLayout for kilted::ComputePathThroughPoses {
    fn goal(
        goals: Vec<PoseStamped>,
        start: PoseStamped,
        planner_id: String,
        use_start: bool,
    ) -> kilted::ComputePathThroughPosesGoal {
        kilted::ComputePathThroughPosesGoal {
            goals: Goals {
                header: pose_stamped(Pose2D::default()).header,
                goals,
            },
            start,
            planner_id,
            use_start,
        }
    }
}

impl<C: 'static, A: ThroughPosesLayout> ActionSpec<C> for ComputeThrough<A> {
    type Action = A;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<Vec<Pose2D>>("goals").describe("The poses to pass, in order."),
            PortSpec::input::<Pose2D>("start").describe("Where it starts, instead of the robot."),
            PortSpec::input::<String>("planner_id")
                .default_value("")
                .describe("The planner plugin; empty for the only one."),
            server_name_port(),
            PortSpec::output::<Path>("path").describe("The path found."),
            error_code_port("planner"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<A::Goal, String> {
        let goals: Vec<Pose2D> = optional(h, "goals")?.unwrap_or_default();
        let start: Option<Pose2D> = optional(h, "start")?;
        Ok(A::goal(
            goals.into_iter().map(pose_stamped).collect(),
            pose_stamped(start.unwrap_or_default()),
            optional(h, "planner_id")?.unwrap_or_default(),
            start.is_some(),
        ))
    }

    fn on_result(
        &mut self,
        h: &mut Handle<'_, C>,
        result: &ComputePathThroughPosesResult,
    ) -> Status {
        if result.error_code == ComputePathThroughPosesResult::NONE {
            emit(h, "path", path_2d(&result.path));
        }
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&ComputePathThroughPosesResult>,
    ) -> Status {
        emit(h, "path", Path::default());
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, ComputePathThroughPosesResult::UNKNOWN, error, server)
    }
}

/// SmoothPath: the smoother server smooths `unsmoothed_path`.
pub(super) struct Smooth;

impl<C: 'static> ActionSpec<C> for Smooth {
    type Action = SmoothPath;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<Path>("unsmoothed_path").describe("The path to smooth."),
            PortSpec::input::<f64>("max_smoothing_duration")
                .default_value("3.0")
                .describe("Seconds smoothing may take."),
            PortSpec::input::<bool>("check_for_collisions")
                .default_value("false")
                .describe("Fail when the smoothed path collides."),
            PortSpec::input::<String>("smoother_id").describe("The smoother plugin."),
            server_name_port(),
            PortSpec::output::<Path>("smoothed_path").describe("The smoothed path."),
            PortSpec::output::<f64>("smoothing_duration").describe("Seconds smoothing took."),
            PortSpec::output::<bool>("was_completed").describe("Smoothing finished in time."),
            error_code_port("smoother"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<SmoothPathGoal, String> {
        let path: Path = required(h, "unsmoothed_path")?;
        let allowed: f64 = optional(h, "max_smoothing_duration")?.unwrap_or(3.0);
        Ok(SmoothPathGoal {
            path: path_msg(&path),
            smoother_id: optional(h, "smoother_id")?.unwrap_or_default(),
            max_smoothing_duration: seconds(allowed),
            check_for_collisions: optional(h, "check_for_collisions")?.unwrap_or(false),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &SmoothPathResult) -> Status {
        if result.error_code == SmoothPathResult::NONE {
            emit(h, "smoothed_path", path_2d(&result.path));
            let took: Duration = result.smoothing_duration.into();
            emit(h, "smoothing_duration", took.as_secs_f64());
            emit(h, "was_completed", result.was_completed);
        }
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&SmoothPathResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, SmoothPathResult::UNKNOWN, error, server)
    }
}
