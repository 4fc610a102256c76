//! DistanceController: tick the child again each time the robot has moved a distance.

use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeStatus};

use crate::robotics::Pose2D;
use neurotree_core::nodes::semantics::{first, Order, Semantics, Statuses};

/// DistanceController's semantics: its child's statuses, RUNNING while the robot has not
/// moved enough, FAILURE without a pose.
pub const SEMANTICS: Semantics =
    Semantics::new(Order::again(Statuses::ANY, Statuses::ANY), |_, c| {
        first(c).or(Statuses::RUNNING).or(Statuses::FAILURE)
    });

/// The blackboard entry the distance and speed controllers read the robot's pose from.
pub const ROBOT_POSE: &str = "robot_pose";

/// DistanceController: tick the child once per run, then again each time the robot has
/// travelled `distance` metres since the child last succeeded, as Nav2's
/// `distance_controller.cpp` does.
///
/// Ports `distance` (default 1.0), `global_frame` and `robot_base_frame`.
///
/// Nav2 looks the robot's pose up in TF; here it is the blackboard entry `robot_pose`
/// ([`ROBOT_POSE`]), a [`Pose2D`] (or its text, `x;y;theta`) that the world writes. The frame
/// ports are accepted and not used, as there is one frame. Where Nav2's lookup fails, the
/// node fails: without a `robot_pose` entry (under `neurotree run`, unless `--set
/// robot_pose=0;0` gives one) the node returns Failure on every tick and never ticks the
/// child.
///
/// - On the tick from Idle: remember the pose as the start (Failure without a pose), and
///   read `distance`.
/// - Every tick: read the pose (Failure without one); tick the child on the run's first
///   tick, while it is Running, or once the robot is `distance` from the start; otherwise
///   Running without ticking it.
/// - Child Running or Skipped passes through; Success remembers the pose as the new start
///   and passes; Failure passes.
///
/// "Later" ticks need a parent that keeps the completed node as it is (a PipelineSequence).
#[derive(Debug, Default)]
pub struct DistanceController {
    start: Pose2D,
    distance: f64,
    first: bool,
}

impl DistanceController {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder).
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "DistanceController",
            Arity::One,
            Box::new(|| Box::new(DistanceController::default())),
        )
    }
}

/// The robot's pose from the blackboard: `Ok(None)` when there is none.
pub(crate) fn robot_pose<C>(node: &mut NodeCtx<'_, '_, C>) -> Result<Option<Pose2D>, String> {
    super::goals::entry_owned::<C, Pose2D>(node, ROBOT_POSE)
}

impl<C> CustomNode<C> for DistanceController {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(
            self.start,
            self.distance,
            self.first,
        )))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(start, distance, first)| {
                self.start = start;
                self.distance = distance;
                self.first = first;
            })
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        node.reset_completed_children_after_tick();
        let pose = match robot_pose(node) {
            Ok(pose) => pose,
            Err(e) => {
                node.fail(e);
                return NodeStatus::Failure;
            }
        };
        if !node.previous_status().is_active() {
            let Some(distance) = super::port_or(node, "distance", 1.0) else {
                return NodeStatus::Failure;
            };
            self.distance = distance;
            let Some(start) = pose else {
                return NodeStatus::Failure;
            };
            self.start = start;
            self.first = true;
        }
        node.set_running();
        let Some(current) = pose else {
            return NodeStatus::Failure;
        };
        let travelled = self.start.distance(&current);
        if !(self.first
            || node.child_status(0) == NodeStatus::Running
            || travelled >= self.distance)
        {
            return NodeStatus::Running;
        }
        self.first = false;
        let status = node.tick_child(0);
        if status == NodeStatus::Success {
            // The pose is read again after the child, which may have moved the robot.
            match robot_pose(node) {
                Ok(Some(pose)) => self.start = pose,
                Ok(None) => return NodeStatus::Failure,
                Err(e) => {
                    node.fail(e);
                    return NodeStatus::Failure;
                }
            }
        }
        status
    }
}
