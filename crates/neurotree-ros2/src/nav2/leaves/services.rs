//! Nav2's service nodes over ROS 2: the costmap clearings, CheckPoseOccupancy and
//! RemoveInCollisionGoals, ToggleCollisionMonitor and ReinitializeGlobalLocalization.

use super::*;

/// A clearing leaf: ClearEntireCostmap, ClearCostmapAroundRobot, ClearCostmapExceptRegion
/// or ClearCostmapAroundPose, in the layout `S` of a release. As Nav2 main's, an answer
/// that the plugins were not cleared fails the node.
pub(super) struct Clear<S>(PhantomData<fn() -> S>);

impl<S> Default for Clear<S> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

impl<C: 'static, S: ClearLayout> ServiceSpec<C> for Clear<S> {
    type Service = S;

    fn ports() -> Vec<PortSpec> {
        let mut ports = Vec::new();
        if S::POSE {
            ports.push(PortSpec::input::<Pose2D>("pose").describe("The square's centre."));
        }
        if S::SQUARE {
            ports.push(
                PortSpec::input::<f64>("reset_distance")
                    .default_value("1.0")
                    .describe("The square's side, in metres."),
            );
        }
        ports.push(PortSpec::input::<Vec<String>>("plugins").describe(
            "The costmap plugins to clear; empty for all (sent in Nav2 main's layout only).",
        ));
        ports
    }

    fn request(&mut self, h: &mut Handle<'_, C>) -> Result<S::Request, String> {
        let pose = if S::POSE {
            pose_stamped(required(h, "pose")?)
        } else {
            PoseStamped::default()
        };
        let distance: f64 = optional(h, "reset_distance")?.unwrap_or(1.0);
        let plugins: Vec<String> = optional(h, "plugins")?.unwrap_or_default();
        Ok(S::request(pose, distance, plugins))
    }

    fn on_response(&mut self, h: &mut Handle<'_, C>, response: &S::Response) -> Status {
        if S::cleared(response) {
            Status::Success
        } else {
            emit(
                h,
                "error_msg",
                "the costmap did not clear its layers".to_owned(),
            );
            Status::Failure
        }
    }
}

/// Registers the four clearing leaves in the layouts `E`, `A`, `X` and `P`.
pub(super) fn register_clearings<C: 'static, E, A, X, P>(
    registry: &mut Registry<C>,
    ros: &RosNode,
) -> Result<(), RegistryError>
where
    E: ClearLayout,
    A: ClearLayout,
    X: ClearLayout,
    P: ClearLayout,
{
    register_service(
        registry,
        "ClearEntireCostmap",
        ros,
        "local_costmap/clear_entirely_local_costmap",
        Clear::<E>::default,
        "Asks the costmap server `service_name` to forget every obstacle.",
    )?;
    register_service(
        registry,
        "ClearCostmapAroundRobot",
        ros,
        "local_costmap/clear_around_local_costmap",
        Clear::<A>::default,
        "Asks the costmap server `service_name` to forget the obstacles around the robot.",
    )?;
    register_service(
        registry,
        "ClearCostmapExceptRegion",
        ros,
        "local_costmap/clear_except_local_costmap",
        Clear::<X>::default,
        "Asks the costmap server `service_name` to forget the obstacles away from the robot.",
    )?;
    register_service(
        registry,
        "ClearCostmapAroundPose",
        ros,
        "local_costmap/clear_around_pose_local_costmap",
        Clear::<P>::default,
        "Asks the costmap server `service_name` to forget the obstacles around `pose`.",
    )
}

pub(super) fn cost_ports() -> Vec<PortSpec> {
    vec![
        PortSpec::input::<f64>("cost_threshold")
            .default_value("254.0")
            .describe("The cost from which a pose counts as in collision."),
        PortSpec::input::<bool>("use_footprint")
            .default_value("true")
            .describe("The cost under the robot's footprint rather than at the point."),
        PortSpec::input::<bool>("consider_unknown_as_obstacle")
            .default_value("false")
            .describe("Count an unknown cost (255) as in collision."),
    ]
}

/// How the cost nodes judge a cost, from their ports.
#[derive(Clone, Copy, Debug)]
pub(super) struct CostRule {
    threshold: f64,
    unknown_is_obstacle: bool,
}

impl Default for CostRule {
    fn default() -> Self {
        Self {
            threshold: 254.0,
            unknown_is_obstacle: false,
        }
    }
}

impl CostRule {
    fn read<C>(h: &Handle<'_, C>) -> Result<(Self, bool), String> {
        let rule = Self {
            threshold: optional(h, "cost_threshold")?.unwrap_or(254.0),
            unknown_is_obstacle: optional(h, "consider_unknown_as_obstacle")?.unwrap_or(false),
        };
        Ok((rule, optional(h, "use_footprint")?.unwrap_or(true)))
    }

    /// As Nav2's nodes: unknown (255) is free unless told otherwise; else the threshold.
    fn in_collision(&self, cost: f32) -> bool {
        let unknown_free = cost == 255.0 && !self.unknown_is_obstacle;
        !(unknown_free || f64::from(cost) < self.threshold)
    }
}

/// CheckPoseOccupancy: Success when the costmap's cost at `pose` is at least
/// `cost_threshold`; Failure when it is below, or the costmap could not answer.
#[derive(Default)]
pub(super) struct PoseOccupancy {
    rule: CostRule,
}

impl<C: 'static> ServiceSpec<C> for PoseOccupancy {
    type Service = GetCosts;

    fn ports() -> Vec<PortSpec> {
        let mut ports = vec![PortSpec::input::<Pose2D>("pose").describe("The pose to check.")];
        ports.extend(cost_ports());
        ports
    }

    fn request(&mut self, h: &mut Handle<'_, C>) -> Result<GetCostsRequest, String> {
        let (rule, use_footprint) = CostRule::read(h)?;
        self.rule = rule;
        Ok(GetCostsRequest {
            use_footprint,
            poses: vec![pose_stamped(required(h, "pose")?)],
        })
    }

    fn on_response(&mut self, h: &mut Handle<'_, C>, response: &GetCostsResponse) -> Status {
        match (response.success, response.costs.first()) {
            (true, Some(cost)) if self.rule.in_collision(*cost) => Status::Success,
            (true, Some(_)) => Status::Failure,
            _ => {
                emit(
                    h,
                    "error_msg",
                    "the costmap could not give the cost".to_owned(),
                );
                Status::Failure
            }
        }
    }
}

/// RemoveInCollisionGoals: writes `input_goals` less those whose cost is at least
/// `cost_threshold` to `output_goals`. As Nav2's node, no goals sends no request and
/// fails (writing them back), and a call the costmap could not answer writes them back
/// unchanged and fails. Waypoint statuses are declared and not kept.
#[derive(Default)]
pub(super) struct InCollisionGoals {
    rule: CostRule,
    goals: Vec<Pose2D>,
}

impl<C: 'static> ServiceSpec<C> for InCollisionGoals {
    type Service = GetCosts;

    fn ports() -> Vec<PortSpec> {
        let mut ports =
            vec![PortSpec::input::<Vec<Pose2D>>("input_goals").describe("The goals to check.")];
        ports.extend(cost_ports());
        ports.extend([
            PortSpec::input::<String>("input_waypoint_statuses")
                .describe("The goals' statuses (not kept)."),
            PortSpec::output::<Vec<Pose2D>>("output_goals").describe("The goals not in collision."),
            PortSpec::output::<String>("output_waypoint_statuses")
                .describe("The statuses with the removed goals skipped (not written)."),
        ]);
        ports
    }

    fn request(&mut self, h: &mut Handle<'_, C>) -> Result<GetCostsRequest, String> {
        let (rule, use_footprint) = CostRule::read(h)?;
        self.rule = rule;
        self.goals = optional(h, "input_goals")?.unwrap_or_default();
        if self.goals.is_empty() {
            emit(h, "output_goals", Vec::<Pose2D>::new());
            return Err("no goals to check".into());
        }
        Ok(GetCostsRequest {
            use_footprint,
            poses: self.goals.iter().copied().map(pose_stamped).collect(),
        })
    }

    fn on_response(&mut self, h: &mut Handle<'_, C>, response: &GetCostsResponse) -> Status {
        if !response.success || response.costs.len() != self.goals.len() {
            emit(h, "output_goals", self.goals.clone());
            emit(
                h,
                "error_msg",
                "the costmap could not give the costs".to_owned(),
            );
            return Status::Failure;
        }
        let kept: Vec<Pose2D> = self
            .goals
            .iter()
            .zip(&response.costs)
            .filter(|(_, cost)| !self.rule.in_collision(**cost))
            .map(|(goal, _)| *goal)
            .collect();
        emit(h, "output_goals", kept);
        Status::Success
    }
}

/// ToggleCollisionMonitor: turns the collision monitor on or off; Success once it
/// answered, whatever it answered, as Nav2's node.
pub(super) struct ToggleMonitor;

impl<C: 'static> ServiceSpec<C> for ToggleMonitor {
    type Service = Toggle;

    fn ports() -> Vec<PortSpec> {
        vec![PortSpec::input::<bool>("enable")
            .default_value("true")
            .describe("Turn the collision monitor on (true) or off.")]
    }

    fn request(&mut self, h: &mut Handle<'_, C>) -> Result<ToggleRequest, String> {
        Ok(ToggleRequest {
            enable: optional(h, "enable")?.unwrap_or(true),
        })
    }

    fn on_response(&mut self, _h: &mut Handle<'_, C>, _: &ToggleResponse) -> Status {
        Status::Success
    }
}

/// ReinitializeGlobalLocalization: asks the localization to start over; Success once it
/// answered.
pub(super) struct Relocalize;

impl<C: 'static> ServiceSpec<C> for Relocalize {
    type Service = EmptyService;

    fn request(&mut self, _h: &mut Handle<'_, C>) -> Result<EmptyRequest, String> {
        Ok(EmptyRequest::default())
    }

    fn on_response(&mut self, _h: &mut Handle<'_, C>, _: &EmptyResponse) -> Status {
        Status::Success
    }
}
