//! The route server over ROS 2: ComputeRoute and ComputeAndTrackRoute.

use super::*;

/// The route ports both route nodes read.
pub(super) fn route_inputs(server: &str) -> Vec<PortSpec> {
    vec![
        PortSpec::input::<Pose2D>("start").describe("Where to start, with `use_start`."),
        PortSpec::input::<Pose2D>("goal").describe("Where to go, with `use_poses`."),
        PortSpec::input::<u16>("start_id").describe("The start node, without `use_poses`."),
        PortSpec::input::<u16>("goal_id").describe("The goal node, without `use_poses`."),
        PortSpec::input::<bool>("use_start")
            .default_value("false")
            .describe("Start at `start` rather than at the robot."),
        PortSpec::input::<bool>("use_poses")
            .default_value("false")
            .describe("Use `start` and `goal` rather than the node ids."),
        server_name_port(),
        PortSpec::output::<Route>("route").describe("The route; empty after a failure."),
        PortSpec::output::<Path>("path").describe("The route's path; empty after a failure."),
        error_code_port(server),
    ]
}

/// The goal of a route action from the ports, as Nav2's route nodes' `on_tick`: the poses
/// with `use_poses` (`start` only with `use_start`), else the node ids.
pub(super) fn route_goal<C>(h: &Handle<'_, C>) -> Result<ComputeRouteGoal, String> {
    let use_poses: bool = optional(h, "use_poses")?.unwrap_or(false);
    if !use_poses {
        return Ok(ComputeRouteGoal {
            start_id: optional(h, "start_id")?.unwrap_or(0),
            goal_id: optional(h, "goal_id")?.unwrap_or(0),
            ..ComputeRouteGoal::default()
        });
    }
    let goal: Pose2D = required(h, "goal")?;
    let use_start: bool = optional(h, "use_start")?.unwrap_or(false);
    let start = if use_start {
        pose_stamped(required(h, "start")?)
    } else {
        Default::default()
    };
    Ok(ComputeRouteGoal {
        start,
        goal: pose_stamped(goal),
        use_start,
        use_poses: true,
        ..ComputeRouteGoal::default()
    })
}

/// ComputeRoute: the route server's route on its graph, and its path.
pub(super) struct RouteOnce;

impl RouteOnce {
    /// As Nav2's `resetPorts`: no route rather than a stale one.
    fn reset<C>(h: &mut Handle<'_, C>) {
        emit(h, "path", Path::default());
        emit(h, "route", Route::default());
        emit(h, "planning_time", 0.0_f64);
    }
}

impl<C: 'static> ActionSpec<C> for RouteOnce {
    type Action = ComputeRoute;

    fn ports() -> Vec<PortSpec> {
        let mut ports = route_inputs("route");
        ports.push(PortSpec::output::<f64>("planning_time").describe("Seconds routing took."));
        ports
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<ComputeRouteGoal, String> {
        route_goal(h)
    }

    fn on_halt(&mut self, h: &mut Handle<'_, C>) {
        // As Nav2's node's `halt`.
        Self::reset(h);
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &ComputeRouteResult) -> Status {
        if result.error_code == ComputeRouteResult::NONE {
            emit(h, "path", path_2d(&result.path));
            emit(h, "route", route_2d(&result.route));
            let took: Duration = result.planning_time.into();
            emit(h, "planning_time", took.as_secs_f64());
        } else {
            Self::reset(h);
        }
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&ComputeRouteResult>,
    ) -> Status {
        Self::reset(h);
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, ComputeRouteResult::UNKNOWN, error, server)
    }
}

/// ComputeAndTrackRoute: the route server's route, then where the robot is along it, from
/// the server's feedback, until the robot reaches its end.
#[derive(Default)]
pub(super) struct TrackRoute {
    /// The goal sent last, to tell new inputs from it.
    sent: Option<ComputeAndTrackRouteGoal>,
}

impl TrackRoute {
    /// As Nav2's `resetFeedbackAndOutputPorts`, when the goal ends whichever way.
    fn reset<C>(h: &mut Handle<'_, C>) {
        Self::write(h, &ComputeAndTrackRouteFeedback::default());
    }

    fn write<C>(h: &mut Handle<'_, C>, feedback: &ComputeAndTrackRouteFeedback) {
        emit(h, "last_node_id", feedback.last_node_id);
        emit(h, "next_node_id", feedback.next_node_id);
        emit(h, "current_edge_id", feedback.current_edge_id);
        emit(h, "route", route_2d(&feedback.route));
        emit(h, "path", path_2d(&feedback.path));
        emit(h, "rerouted", feedback.rerouted);
    }
}

impl<C: 'static> ActionSpec<C> for TrackRoute {
    type Action = ComputeAndTrackRoute;

    fn ports() -> Vec<PortSpec> {
        let mut ports = route_inputs("route");
        ports.extend([
            PortSpec::output::<f64>("execution_duration").describe("Seconds tracked."),
            PortSpec::output::<u16>("last_node_id").describe("The last node reached."),
            PortSpec::output::<u16>("next_node_id").describe("The next node."),
            PortSpec::output::<u16>("current_edge_id").describe("The edge being driven."),
            PortSpec::output::<bool>("rerouted").describe("The route was computed again."),
        ]);
        ports
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<ComputeAndTrackRouteGoal, String> {
        let goal = route_goal(h)?;
        let goal = ComputeAndTrackRouteGoal {
            start_id: goal.start_id,
            start: goal.start,
            goal_id: goal.goal_id,
            goal: goal.goal,
            use_start: goal.use_start,
            use_poses: goal.use_poses,
        };
        self.sent = Some(goal.clone());
        Ok(goal)
    }

    fn updated_goal(&mut self, h: &mut Handle<'_, C>) -> Option<ComputeAndTrackRouteGoal> {
        // As Nav2's `on_wait_for_result`: other inputs make a new goal.
        let sent = self.sent.as_ref()?;
        let goal = ActionSpec::<C>::goal(&mut TrackRoute::default(), h).ok()?;
        if goal == *sent {
            return None;
        }
        self.sent = Some(goal.clone());
        Some(goal)
    }

    fn on_feedback(
        &mut self,
        h: &mut Handle<'_, C>,
        feedback: &ComputeAndTrackRouteFeedback,
    ) -> Status {
        Self::write(h, feedback);
        Status::Running
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &ComputeAndTrackRouteResult) -> Status {
        Self::reset(h);
        let took: Duration = result.execution_duration.into();
        emit(h, "execution_duration", took.as_secs_f64());
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&ComputeAndTrackRouteResult>,
    ) -> Status {
        Self::reset(h);
        emit(h, "execution_duration", 0.0_f64);
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, ComputeAndTrackRouteResult::UNKNOWN, error, server)
    }
}
