//! ComputePathToPose: the planner server, as A* on the global costmap.
//!
//! Sync action. Ports: `goal`, `start` (optional), `use_start` (optional), `viapoints`
//! (optional), `planner_id`; outputs `path`, `error_code_id`, `error_msg`.
//!
//! - A* on the global costmap from `start` (the robot when absent, or when `use_start` is
//!   false) through `viapoints` to `goal`.
//! - Success: writes `path` and error code 0.
//! - Failure: writes an empty `path` and the planner's error code: START_OUTSIDE_MAP 203,
//!   GOAL_OUTSIDE_MAP 204, GOAL_OCCUPIED 206, NO_VALID_PATH 208 (UNKNOWN 200 for an
//!   unreadable goal).
//!
//! Nav2's planner runs as an action server, so its node is Running for a while; the grid
//! planner answers within the tick, so the node completes at once, which keeps the tick
//! counts of a run easy to follow. Any `planner_id` is accepted: the world has one planner.

use neurotree_core::{Handle, Status};

use super::codes::compute_path as code;
use super::{ports, Nav2Context};
use crate::CostmapLayer;
use neurotree_nav2::robotics::{Path, Pose2D};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

/// The ports of `nav2_tree_nodes.xml`, in its order.
fn ports() -> Vec<PortSpec> {
    vec![
        PortSpec::input::<Pose2D>("start")
            .describe("Start pose, used instead of the robot's when `use_start` is not false."),
        PortSpec::input::<bool>("use_start").describe("Whether to use `start`."),
        PortSpec::input::<Pose2D>("goal").describe("Goal pose."),
        PortSpec::input::<Vec<Pose2D>>("viapoints")
            .describe("Intermediate poses to pass through, in order, before the goal."),
        PortSpec::input::<String>("planner_id")
            .default_value("")
            .describe("Planner plugin to use; the simulation has one and accepts any id."),
        PortSpec::input::<String>("server_name").describe("Action server name (unused)."),
        PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
        PortSpec::output::<Path>("path").describe("The path planned; empty after a failure."),
        PortSpec::output::<u16>("error_code_id").describe("0, or the planner's error code."),
        PortSpec::output::<String>("error_msg").describe("Why planning failed; empty on success."),
    ]
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_action("ComputePathToPose", ports(), compute_path_to_pose::<C>)?;
    r.describe(
        "ComputePathToPose",
        "Plans a path on the global costmap from the robot (or `start`) to `goal`.",
    );
    Ok(())
}

/// One run of the node: see the [module documentation](self).
fn compute_path_to_pose<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let goal = match ports::optional::<Pose2D, C>(h, "goal") {
        Ok(Some(goal)) => goal,
        Ok(None) => {
            let message = "no goal: bind `goal` to a pose".into();
            return failed(h, code::UNKNOWN, "no goal", message);
        }
        Err(e) => return failed(h, code::UNKNOWN, "bad input", e.to_string()),
    };
    let inputs = ports::optional::<Pose2D, C>(h, "start").and_then(|start| {
        let use_start = ports::or(h, "use_start", true)?;
        let viapoints = ports::or(h, "viapoints", Vec::new())?;
        Ok((start.filter(|_| use_start), viapoints))
    });
    let (start, viapoints) = match inputs {
        Ok(inputs) => inputs,
        Err(e) => return failed(h, code::UNKNOWN, "bad input", e.to_string()),
    };
    let planned = {
        let world = &mut h.ctx_mut().nav2_mut().world;
        let start = start.unwrap_or_else(|| world.robot());
        plan_through(world, start, &viapoints, goal)
    };
    let path = match planned {
        Ok(path) => path,
        Err((code, why, message)) => return failed(h, code, why, message),
    };
    // The path this one replaces, if the output is bound to an entry that holds one.
    let previous = ports::optional::<Path, C>(h, "path").ok().flatten();
    let replaced = previous.as_ref() != Some(&path);
    let (poses, length) = (path.len(), path.length());
    let sim = h.ctx_mut().nav2_mut();
    sim.count_plan(replaced);
    sim.note(|| format!("ComputePathToPose: a path of {poses} poses, {length:.1} m"));
    ports::emit(h, "path", path);
    ports::succeed(h)
}

/// A failed run: an empty path, as Nav2's node writes, and the error.
fn failed<C>(h: &mut Handle<'_, C>, code: u16, why: &'static str, message: String) -> Status {
    ports::emit(h, "path", Path::default());
    ports::fail(h, code, why, message)
}

/// A path from `start` through each of `viapoints` to `goal`, or the planner's error code,
/// reason and message.
pub(super) fn plan_through(
    world: &mut crate::GridWorld,
    start: Pose2D,
    viapoints: &[Pose2D],
    goal: Pose2D,
) -> Result<Path, (u16, &'static str, String)> {
    let map = world.map();
    let at = |p: &Pose2D| format!("({:.2}, {:.2})", p.x, p.y);
    if map.cell_at(&start).is_none() {
        return Err((
            code::START_OUTSIDE_MAP,
            "start outside the map",
            format!("the start {} is off the map", at(&start)),
        ));
    }
    for target in viapoints.iter().chain([&goal]) {
        let Some(cell) = map.cell_at(target) else {
            return Err((
                code::GOAL_OUTSIDE_MAP,
                "goal outside the map",
                format!("{} is off the map", at(target)),
            ));
        };
        if world.costmap(CostmapLayer::Global).is_blocked(cell) {
            return Err((
                code::GOAL_OCCUPIED,
                "goal occupied",
                format!("{} is in blocked cell {cell}", at(target)),
            ));
        }
    }
    let mut poses: Vec<Pose2D> = Vec::new();
    let mut from = start;
    for target in viapoints.iter().chain([&goal]) {
        let Some(leg) = world.plan(from, *target) else {
            return Err((
                code::NO_VALID_PATH,
                "no valid path",
                format!("no path from {} to {}", at(&from), at(target)),
            ));
        };
        // Each leg starts where the last one ended: keep that pose once.
        let skip = usize::from(!poses.is_empty());
        poses.extend(leg.poses.into_iter().skip(skip));
        from = *target;
    }
    Ok(Path::new(poses))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;
    use crate::{Cell, TimedObstacle};

    const MAP: &str = "
        ######
        #R...#
        #.##.#
        #....#
        ######";

    fn bench(xml_ports: &str) -> Bench {
        Bench::new(
            MAP,
            &format!(
                r#"<ComputePathToPose goal="{{goal}}" path="{{path}}" error_code_id="{{code}}" error_msg="{{msg}}" {xml_ports}/>"#
            ),
        )
    }

    #[test]
    fn plans_from_the_robot_writes_the_path_and_counts_replans() {
        let mut b = bench("");
        b.set_goal(Pose2D::new(4.5, 1.5, 0.0));
        assert_eq!(b.tick(), Status::Success);
        let path: Path = b.get("path");
        // Round the wall: east along the top row, then south (six cells either way round;
        // the planner's move order picks this one).
        let cells: Vec<Cell> = path
            .poses
            .iter()
            .filter_map(|p| b.sim.world.map().cell_at(p))
            .collect();
        assert_eq!(
            cells,
            [(1, 3), (2, 3), (3, 3), (4, 3), (4, 2), (4, 1)].map(|(x, y)| Cell::new(x, y))
        );
        assert_eq!(path.poses.first(), Some(&Pose2D::new(1.5, 3.5, 0.0)));
        assert_eq!(path.goal(), Some(Pose2D::new(4.5, 1.5, 0.0)));
        assert_eq!(b.get::<u16>("code"), 0);
        assert_eq!(b.get::<String>("msg"), "");
        assert_eq!((b.sim.plans(), b.sim.replans()), (1, 0));
        // The same path again is no replan; another one is.
        assert_eq!(b.tick(), Status::Success);
        assert_eq!((b.sim.plans(), b.sim.replans()), (2, 0));
        b.set_goal(Pose2D::new(4.5, 2.5, 0.0));
        assert_eq!(b.tick(), Status::Success);
        assert_eq!((b.sim.plans(), b.sim.replans()), (3, 1));
        assert_eq!(b.sim.world.plan_count(), 3);
    }

    #[test]
    fn errors_say_why_with_nav2_codes_and_empty_the_path() {
        let mut b = bench("");
        for (goal, expected) in [
            (Pose2D::new(9.5, 1.5, 0.0), code::GOAL_OUTSIDE_MAP),
            (Pose2D::new(2.5, 2.5, 0.0), code::GOAL_OCCUPIED),
        ] {
            b.set_goal(goal);
            assert_eq!(b.tick(), Status::Failure);
            assert_eq!(b.get::<u16>("code"), expected);
            assert_eq!(b.get::<Path>("path"), Path::default());
        }
        assert_eq!(b.reason().as_deref(), Some("goal occupied (error 206)"));
        assert!(b.get::<String>("msg").contains("blocked cell (2, 2)"));
        // A goal walled in by obstacles the costmap knows.
        let mut b = Bench::with_world(
            crate::GridWorld::parse(MAP, 1.0)
                .unwrap()
                .with_sensing_radius(10.0)
                .with_timed_obstacle(TimedObstacle::new(Cell::new(4, 2), Default::default()))
                .with_timed_obstacle(TimedObstacle::new(Cell::new(3, 1), Default::default())),
            r#"<ComputePathToPose goal="{goal}" path="{path}" error_code_id="{code}"/>"#,
        );
        b.set_goal(Pose2D::new(4.5, 1.5, 0.0));
        assert_eq!(b.tick(), Status::Failure);
        assert_eq!(b.get::<u16>("code"), code::NO_VALID_PATH);
        assert_eq!(b.reason().as_deref(), Some("no valid path (error 208)"));
        // No goal at all.
        let mut b = bench("");
        assert_eq!(b.tick(), Status::Failure);
        assert_eq!(b.get::<u16>("code"), code::UNKNOWN);
        assert_eq!(b.reason().as_deref(), Some("no goal (error 200)"));
        assert_eq!(b.sim.plans(), 0);
    }

    #[test]
    fn start_and_viapoints_shape_the_path() {
        let mut b = bench(r#"start="{start}" viapoints="{via}""#);
        b.set_goal(Pose2D::new(4.5, 3.5, 0.0));
        b.tree
            .blackboard_mut()
            .set("start", Pose2D::new(1.5, 1.5, 0.0))
            .unwrap();
        b.tree
            .blackboard_mut()
            .set("via", vec![Pose2D::new(4.5, 1.5, 0.0)])
            .unwrap();
        assert_eq!(b.tick(), Status::Success);
        let cells: Vec<Cell> = b
            .get::<Path>("path")
            .poses
            .iter()
            .filter_map(|p| b.sim.world.map().cell_at(p))
            .collect();
        assert_eq!(
            cells,
            [
                Cell::new(1, 1),
                Cell::new(2, 1),
                Cell::new(3, 1),
                Cell::new(4, 1),
                Cell::new(4, 2),
                Cell::new(4, 3)
            ]
        );
        // use_start="false": from the robot, top left.
        let mut b = bench(r#"start="1.5;1.5" use_start="false""#);
        b.set_goal(Pose2D::new(2.5, 3.5, 0.0));
        assert_eq!(b.tick(), Status::Success);
        assert_eq!(b.get::<Path>("path").len(), 2);
    }
}
