//! PathLongerOnApproach: tick the child when a new path near the goal is much longer.

use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeStatus};

use crate::robotics::{Path, Pose2D};
use neurotree_core::nodes::semantics::{first, Order, Semantics, Statuses};

/// PathLongerOnApproach's semantics: its child's statuses, or SUCCESS without ticking it.
pub const SEMANTICS: Semantics = Semantics::new(Order::in_turn(Statuses::ANY), |_, c| {
    first(c).or(Statuses::SUCCESS)
});

/// PathLongerOnApproach: tick the child when, close to the goal, the planner's new path to
/// the same goal is much longer than the old one (something blocks the way); otherwise
/// succeed without ticking it, as Nav2's `path_longer_on_approach.cpp` does.
///
/// Ports `path` (a [`Path`]), `prox_len` (3.0) and `length_factor` (2.0). The paths are the
/// ones the tree plans: nothing but the `path` port is read, so the node runs the same with
/// or without a world. Each tick:
///
/// - Read `path` as the new path (a path that cannot be read leaves the last one read).
/// - A new goal (either path empty, or their last poses differ) makes this a first look,
///   unless the previous tick already was one.
/// - If the new path has a different number of poses but ends at the same position, the old
///   path is shorter than `prox_len`, the new one longer than `length_factor` times the old
///   one, and this is not a first look: tick the child. Running or Skipped passes through
///   (the old path is kept, so the next tick asks again); Success or Failure replaces the old
///   path with the new one, resets the child and passes through.
/// - Otherwise: the new path becomes the old one, the next look is not a first one,
///   Success.
#[derive(Debug)]
pub struct PathLongerOnApproach {
    new_path: Vec<Pose2D>,
    old_path: Vec<Pose2D>,
    first_time: bool,
}

impl Default for PathLongerOnApproach {
    fn default() -> Self {
        Self {
            new_path: Vec::new(),
            old_path: Vec::new(),
            first_time: true,
        }
    }
}

impl PathLongerOnApproach {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder).
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "PathLongerOnApproach",
            Arity::One,
            Box::new(|| Box::new(PathLongerOnApproach::default())),
        )
    }
}

/// Metres along `poses`, as Nav2's `calculate_path_length`.
fn length(poses: &[Pose2D]) -> f64 {
    poses.windows(2).map(|w| w[0].distance(&w[1])).sum()
}

/// Nav2's `isPathUpdated`: both paths have poses, not as many, and end at the same position.
fn path_updated(new: &[Pose2D], old: &[Pose2D]) -> bool {
    match (new.last(), old.last()) {
        (Some(n), Some(o)) => new.len() != old.len() && n.x == o.x && n.y == o.y,
        _ => false,
    }
}

impl<C> CustomNode<C> for PathLongerOnApproach {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(
            &self.new_path,
            &self.old_path,
            self.first_time,
        )))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(new_path, old_path, first_time)| {
                self.new_path = new_path;
                self.old_path = old_path;
                self.first_time = first_time;
            })
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        match super::port_value::<C, Path>(node, "path") {
            Ok(Some(path)) => self.new_path = path.poses,
            Ok(None) => {}
            Err(e) => {
                node.fail(e);
                return NodeStatus::Failure;
            }
        }
        let Some(prox_len) = super::port_or(node, "prox_len", 3.0) else {
            return NodeStatus::Failure;
        };
        let Some(length_factor) = super::port_or(node, "length_factor", 2.0) else {
            return NodeStatus::Failure;
        };
        if !self.first_time {
            let new_goal = match (self.old_path.last(), self.new_path.last()) {
                (Some(old), Some(new)) => old != new,
                _ => true,
            };
            if new_goal {
                self.first_time = true;
            }
        }
        node.set_running();
        let old_length = length(&self.old_path);
        if path_updated(&self.new_path, &self.old_path)
            && old_length < prox_len
            && length(&self.new_path) > length_factor * old_length
            && !self.first_time
        {
            let status = node.tick_child(0);
            if status.is_completed() {
                self.old_path.clone_from(&self.new_path);
                node.reset_children();
            }
            return status;
        }
        self.old_path.clone_from(&self.new_path);
        self.first_time = false;
        NodeStatus::Success
    }
}
