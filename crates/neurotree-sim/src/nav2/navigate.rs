//! NavigateToPose and NavigateThroughPoses: another navigator, asked to take the robot
//! somewhere (as an application tree such as Nav2's docking example asks Nav2's own).
//!
//! Stateful actions. Ports: `goal` (NavigateToPose) or `goals` (NavigateThroughPoses),
//! `behavior_tree`, `server_name`, `server_timeout`; outputs `error_code_id`, `error_msg`.
//!
//! - The tick from Idle plans from the robot to the goal (through the goals in order) on
//!   the global costmap, as ComputePathToPose does, and starts following the path: Running.
//!   No goal, or no path: Failure UNKNOWN (9000, or 9100 through poses) with the
//!   planner's message.
//! - Later ticks: Running while the robot drives; Success at the path's end (error code
//!   0). Blocked by an obstacle, the navigator plans again from where the robot is, as
//!   Nav2's default navigator replans; when no path is left: Failure UNKNOWN. An empty
//!   battery: Failure UNKNOWN. A motion stopped by someone else: Success, as Nav2's node
//!   ends when its goal is cancelled.
//! - Halt stops the motion.
//!
//! Nav2's server runs a whole navigator tree (`behavior_tree` picks which); the simulated
//! one plans and follows, replanning when blocked, and reads `behavior_tree` nowhere.
//! Without a `goal`, Nav2's node logs an error and still sends a goal at the origin; the
//! simulated one fails at once (UNKNOWN), which is what such a goal usually comes to.

use neurotree_core::{Handle, StatefulAction, Status};

use super::codes::navigate as code;
use super::{planner, ports, Nav2Context};
use crate::MotionStatus;
use neurotree_nav2::robotics::{Path, Pose2D};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

/// Which navigator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    ToPose,
    ThroughPoses,
}

fn ports(goal: PortSpec) -> Vec<PortSpec> {
    vec![
        goal,
        PortSpec::input::<String>("behavior_tree").describe("The navigator's tree (unused)."),
        PortSpec::input::<String>("server_name").describe("Action server name (unused)."),
        PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
        PortSpec::output::<u16>("error_code_id").describe("0, or the navigator's error code."),
        PortSpec::output::<String>("error_msg").describe("Why it failed; empty on success."),
    ]
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_stateful(
        "NavigateToPose",
        ports(PortSpec::input::<Pose2D>("goal").describe("Where to go.")),
        || Navigate::new(Kind::ToPose),
    )?;
    r.describe(
        "NavigateToPose",
        "Takes the robot to `goal`, replanning when blocked.",
    );
    r.register_stateful(
        "NavigateThroughPoses",
        ports(PortSpec::input::<Vec<Pose2D>>("goals").describe("The poses to pass, in order.")),
        || Navigate::new(Kind::ThroughPoses),
    )?;
    r.describe(
        "NavigateThroughPoses",
        "Takes the robot through each of `goals`, replanning when blocked.",
    );
    Ok(())
}

/// A navigator node: see the [module documentation](self).
struct Navigate {
    kind: Kind,
    /// The goals still ahead, the last one the destination.
    goals: Vec<Pose2D>,
}

impl Navigate {
    fn new(kind: Kind) -> Self {
        Self {
            kind,
            goals: Vec::new(),
        }
    }

    fn unknown(&self) -> u16 {
        match self.kind {
            Kind::ToPose => code::TO_POSE_UNKNOWN,
            Kind::ThroughPoses => code::THROUGH_POSES_UNKNOWN,
        }
    }

    /// Plans from the robot through the goals not passed yet and starts following.
    fn plan_and_follow<C: Nav2Context>(&mut self, h: &mut Handle<'_, C>) -> Result<(), String> {
        let sim = h.ctx_mut().nav2_mut();
        let robot = sim.world.robot();
        let tolerance = sim.params.goal_tolerance;
        // Goals already within reach are passed.
        while self.goals.len() > 1 && self.goals[0].distance(&robot) <= tolerance {
            self.goals.remove(0);
        }
        let Some((goal, via)) = self.goals.split_last() else {
            return Err("no goal".into());
        };
        let path: Path = planner::plan_through(&mut sim.world, robot, via, *goal)
            .map_err(|(_, _, message)| message)?;
        sim.world.follow(path, sim.params.speed);
        Ok(())
    }

    fn fail<C>(&self, h: &mut Handle<'_, C>, message: String) -> Status {
        ports::fail(h, self.unknown(), "navigation failed", message)
    }
}

impl<C: Nav2Context> StatefulAction<C> for Navigate {
    /// The goals still ahead; the kind is the factory's, the motion the world's.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&self.goals))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|goals| self.goals = goals)
            .is_some()
    }

    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        let read = match self.kind {
            Kind::ToPose => {
                ports::optional::<Pose2D, C>(h, "goal").map(|g| g.into_iter().collect())
            }
            Kind::ThroughPoses => ports::or(h, "goals", Vec::new()),
        };
        self.goals = match read {
            Ok(goals) => goals,
            Err(e) => return self.fail(h, e.to_string()),
        };
        match self.plan_and_follow(h) {
            Ok(()) => Status::Running,
            Err(message) => self.fail(h, message),
        }
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        match h.ctx().nav2().world.motion_status() {
            MotionStatus::Active => Status::Running,
            MotionStatus::Succeeded | MotionStatus::Idle => ports::succeed(h),
            MotionStatus::Blocked(_) => match self.plan_and_follow(h) {
                Ok(()) => Status::Running,
                Err(message) => self.fail(h, message),
            },
            MotionStatus::BatteryEmpty => self.fail(h, "the battery is empty".into()),
        }
    }

    fn on_halted(&mut self, h: &mut Handle<'_, C>) {
        h.ctx_mut().nav2_mut().world.stop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;
    use crate::{Cell, GridWorld, TimedObstacle};
    use std::time::Duration;
    use Status::{Failure as F, Success as S};

    const HALL: &str = "
        .....
        R....
        .....";

    #[test]
    fn navigates_to_the_pose_and_around_an_obstacle_met_on_the_way() {
        let world = GridWorld::parse(HALL, 1.0)
            .unwrap()
            .with_timed_obstacle(TimedObstacle::new(
                Cell::new(3, 1),
                Duration::from_millis(500),
            ));
        let mut b = Bench::with_world(
            world,
            r#"<NavigateToPose goal="{goal}" error_code_id="{code}"/>"#,
        );
        b.set_goal(Pose2D::new(4.5, 1.5, 0.0));
        let run = b.run(200);
        // 4 m at 1 m/s, blocked in front of the obstacle, then round it: 61 ticks.
        assert_eq!(run.len(), 61);
        assert_eq!(run.last(), Some(&S));
        assert!(b.sim.world.robot().distance(&Pose2D::new(4.5, 1.5, 0.0)) < 1e-9);
        assert_eq!(b.get::<u16>("code"), 0);
        // Planned at the start and once more when blocked.
        assert_eq!(b.sim.world.plan_count(), 2);
    }

    #[test]
    fn an_unreachable_goal_fails_with_the_navigators_unknown_code() {
        let mut b = Bench::new(
            "R.#.",
            r#"<NavigateToPose goal="{goal}" error_code_id="{code}" error_msg="{msg}"/>"#,
        );
        b.set_goal(Pose2D::new(3.5, 0.5, 0.0));
        assert_eq!(b.run(5), [F]);
        assert_eq!(b.get::<u16>("code"), code::TO_POSE_UNKNOWN);
        assert_eq!(
            b.get::<String>("msg"),
            "no path from (0.50, 0.50) to (3.50, 0.50)"
        );
        let mut b = Bench::new(
            "R",
            r#"<NavigateThroughPoses goals="{goals}" error_code_id="{code}"/>"#,
        );
        b.set("goals", Vec::<Pose2D>::new());
        assert_eq!(b.run(5), [F]);
        assert_eq!(b.get::<u16>("code"), code::THROUGH_POSES_UNKNOWN);
    }

    #[test]
    fn navigates_through_each_pose_and_halting_stops() {
        let mut b = Bench::new(HALL, r#"<NavigateThroughPoses goals="{goals}"/>"#);
        let via = Pose2D::new(2.5, 2.5, 0.0);
        let end = Pose2D::new(4.5, 0.5, 0.0);
        b.set("goals", vec![via, end]);
        let run = b.run(200);
        // √2 + 1 m to the first pose, 2√2 m on to the second: 5.24 m, seen at tick 54.
        assert_eq!(run.len(), 54);
        assert_eq!(run.last(), Some(&S));
        assert!(b.sim.world.robot().distance(&end) < 1e-9);
        let mut b = Bench::new(HALL, r#"<NavigateToPose goal="{goal}"/>"#);
        b.set_goal(end);
        b.run(3);
        b.tree.halt(&mut b.sim);
        assert_eq!(b.sim.world.motion_status(), MotionStatus::Idle);
        assert_eq!(b.sim.world.stop_count(), 1);
    }
}
