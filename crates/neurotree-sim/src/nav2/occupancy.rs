//! Asking the global costmap about poses: CheckPoseOccupancy and RemoveInCollisionGoals.
//!
//! Both call Nav2's costmap service `get_cost_global_costmap`, which the simulated costmap
//! answers cell by cell: cost 254 (lethal) for a wall or a sensed obstacle, 0 for a free
//! cell. A pose off the map makes the call fail, as Nav2's costmap answers `success = false`
//! for a point outside it. The robot is as big as a cell, so `use_footprint` gives the
//! same answer as the point; the grid knows every cell, so no cost is 255 (unknown) and
//! `consider_unknown_as_obstacle` changes nothing.
//!
//! - **CheckPoseOccupancy**: a sync action. Ports `pose`, `cost_threshold` (default 254),
//!   `use_footprint`, `consider_unknown_as_obstacle`, `service_name`, `server_timeout`.
//!   As Nav2's `check_pose_occupancy_action.cpp`: Success when the pose's cost is at least
//!   `cost_threshold` (occupied); Failure when it is below, or the call failed.
//! - **RemoveInCollisionGoals**: a sync action. Ports `input_goals`, `cost_threshold`
//!   (default 254) and the same others; outputs `output_goals`,
//!   `output_waypoint_statuses`. As Nav2's `remove_in_collision_goals_action.cpp`: no goals
//!   are written back as they are, Failure (Nav2's node sends no request, and its service
//!   node fails then); otherwise the goals whose cost is below the
//!   threshold are written, Success (an empty list when all are in collision); a failed
//!   call writes the goals unchanged, Failure. Waypoint statuses are not kept (see
//!   [RemovePassedGoals](super::through_poses)).

use neurotree_core::{Handle, Status};

use super::{ports, Nav2Context, Nav2Sim};
use crate::CostmapLayer;
use neurotree_nav2::robotics::Pose2D;
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

/// Nav2's cost of a lethal cell.
pub const LETHAL: f64 = 254.0;

fn cost_ports() -> Vec<PortSpec> {
    vec![
        PortSpec::input::<f64>("cost_threshold")
            .default_value("254.0")
            .describe("The cost from which a pose counts as occupied."),
        PortSpec::input::<bool>("use_footprint")
            .default_value("true")
            .describe("Check the robot's footprint (the same as the point: a robot is a cell)."),
        PortSpec::input::<bool>("consider_unknown_as_obstacle")
            .default_value("false")
            .describe("Count unknown cost as occupied (no cell of the grid is unknown)."),
        PortSpec::input::<String>("service_name").describe("Costmap service name (unused)."),
        PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
    ]
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    let mut check = vec![PortSpec::input::<Pose2D>("pose").describe("The pose to check.")];
    check.extend(cost_ports());
    r.register_action("CheckPoseOccupancy", check, check_pose_occupancy::<C>)?;
    r.describe(
        "CheckPoseOccupancy",
        "Succeeds when the global costmap holds `pose` occupied.",
    );
    let mut remove =
        vec![PortSpec::input::<Vec<Pose2D>>("input_goals").describe("The goals to check.")];
    let mut costs = cost_ports();
    // Nav2's order: the three cost ports, the statuses, then the service's.
    let service = costs.split_off(3);
    remove.extend(costs);
    remove.push(
        PortSpec::input::<String>("input_waypoint_statuses")
            .describe("Waypoint statuses (not kept)."),
    );
    remove.extend(service);
    remove.extend([
        PortSpec::output::<Vec<Pose2D>>("output_goals").describe("The goals not in collision."),
        PortSpec::output::<String>("output_waypoint_statuses")
            .describe("Waypoint statuses (not written)."),
    ]);
    r.register_action(
        "RemoveInCollisionGoals",
        remove,
        remove_in_collision_goals::<C>,
    )?;
    r.describe(
        "RemoveInCollisionGoals",
        "Drops the goals the global costmap holds occupied.",
    );
    Ok(())
}

impl Nav2Sim {
    /// The cost costmap `layer` gives `pose`, as its `get_cost_` service answers: 254
    /// (lethal) for a wall or a sensed obstacle, 0 for a free cell; `None` off the map.
    pub fn cost(&self, layer: CostmapLayer, pose: &Pose2D) -> Option<f64> {
        let cell = self.world.map().cell_at(pose)?;
        let blocked = self.world.costmap(layer).is_blocked(cell);
        Some(if blocked { LETHAL } else { 0.0 })
    }
}

/// The global costmap's cost at `pose`: 254 or 0; `None` off the map.
pub(super) fn cost_at<C: Nav2Context>(h: &Handle<'_, C>, pose: &Pose2D) -> Option<f64> {
    h.ctx().nav2().cost(CostmapLayer::Global, pose)
}

/// CheckPoseOccupancy: see the [module documentation](self).
fn check_pose_occupancy<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let read = ports::or(h, "pose", Pose2D::default())
        .and_then(|pose| Ok((pose, ports::or(h, "cost_threshold", LETHAL)?)));
    let Ok((pose, threshold)) = read else {
        return Status::Failure;
    };
    match cost_at(h, &pose) {
        Some(cost) if cost >= threshold => Status::Success,
        _ => Status::Failure,
    }
}

/// RemoveInCollisionGoals: see the [module documentation](self).
fn remove_in_collision_goals<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let read = ports::or(h, "input_goals", Vec::<Pose2D>::new())
        .and_then(|goals| Ok((goals, ports::or(h, "cost_threshold", LETHAL)?)));
    let Ok((goals, threshold)) = read else {
        return Status::Failure;
    };
    if goals.is_empty() {
        // Nav2's node sends no request then, and its service node fails.
        ports::emit(h, "output_goals", goals);
        return Status::Failure;
    }
    let costs: Option<Vec<f64>> = goals.iter().map(|g| cost_at(h, g)).collect();
    let Some(costs) = costs else {
        ports::emit(h, "output_goals", goals);
        return Status::Failure;
    };
    let kept: Vec<Pose2D> = goals
        .into_iter()
        .zip(costs)
        .filter(|(_, cost)| *cost < threshold)
        .map(|(goal, _)| goal)
        .collect();
    ports::emit(h, "output_goals", kept);
    Status::Success
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;
    use Status::{Failure as F, Success as S};

    const ROW: &str = "R.#..";

    #[test]
    fn a_pose_is_occupied_on_a_wall_free_on_the_floor_and_unknown_off_the_map() {
        let mut b = Bench::new(ROW, r#"<CheckPoseOccupancy pose="{p}"/>"#);
        for (x, expected) in [(2.5, S), (1.5, F), (9.5, F)] {
            b.set("p", Pose2D::new(x, 0.5, 0.0));
            assert_eq!(b.tick(), expected, "{x}");
        }
        // A threshold of 0 counts every cell on the map as occupied.
        let mut b = Bench::new(
            ROW,
            r#"<CheckPoseOccupancy pose="{p}" cost_threshold="0"/>"#,
        );
        b.set("p", Pose2D::new(1.5, 0.5, 0.0));
        assert_eq!(b.tick(), S);
    }

    #[test]
    fn goals_in_collision_are_removed_and_a_failed_call_keeps_them_all() {
        let mut b = Bench::new(
            ROW,
            r#"<RemoveInCollisionGoals input_goals="{in}" output_goals="{out}"/>"#,
        );
        let at = |x: f64| Pose2D::new(x, 0.5, 0.0);
        b.set("in", vec![at(1.5), at(2.5), at(3.5)]);
        assert_eq!(b.tick(), S);
        assert_eq!(b.get::<Vec<Pose2D>>("out"), [at(1.5), at(3.5)]);
        b.set("in", vec![at(2.5)]);
        assert_eq!(b.tick(), S);
        assert_eq!(b.get::<Vec<Pose2D>>("out"), []);
        b.set("in", vec![at(1.5), at(-3.0)]);
        assert_eq!(b.tick(), F);
        assert_eq!(b.get::<Vec<Pose2D>>("out"), [at(1.5), at(-3.0)]);
        b.set("in", Vec::<Pose2D>::new());
        assert_eq!(b.tick(), F);
        assert_eq!(b.get::<Vec<Pose2D>>("out"), []);
    }
}
