//! GoalUpdater: pass on the goal, or a newer one that was sent while navigating.

use std::time::Duration;

use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeStatus, PortValue};

use crate::robotics::Pose2D;
use neurotree_core::nodes::semantics::{first, Order, Semantics, Statuses};

/// GoalUpdater's semantics: its child's statuses.
pub const SEMANTICS: Semantics = Semantics::new(Order::in_turn(Statuses::ANY), |_, c| {
    first(c).or(Statuses::FAILURE)
});

/// The blackboard entry that plays Nav2's `goal_update` topic.
pub const GOAL_UPDATE: &str = "goal_update";
/// The blackboard entry that plays Nav2's `goals_update` topic.
pub const GOALS_UPDATE: &str = "goals_update";

/// GoalUpdater: write `output_goal` and `output_goals` (the inputs, or the updates received
/// since), then tick the child, as Nav2's `goal_updater_node.cpp` does.
///
/// Ports `input_goal`, `input_goals` (in), `output_goal`, `output_goals` (out).
///
/// Nav2 subscribes to the topics `goal_update` and `goals_update` and keeps the last
/// message of each; here the last message is the blackboard entry of that name
/// ([`GOAL_UPDATE`], a [`Pose2D`]; [`GOALS_UPDATE`], a `Vec<Pose2D>`), and its time stamp is
/// the time the entry was written (the tree's clock for a node, 0 for a value set before the
/// run). Each tick:
///
/// - `output_goal`: the `goal_update` entry if there is one and it was written no earlier
///   than `input_goal`'s entry (an older update is ignored, as Nav2 ignores a message
///   stamped before the goal); else `input_goal`.
/// - `output_goals`: likewise with `goals_update`, except that an empty update is ignored.
/// - Then the child is ticked and its status returned; a completed child is reset.
///
/// An input that cannot be read is Nav2's empty value (the origin, no goals), stamped 0; an
/// input given as a literal is stamped 0. Nav2 ignores an update whose stamp is zero; here a
/// value written at time 0 is an update like any other (a blackboard write always has a
/// time). Without the update entries (`neurotree run`), the outputs are the inputs.
#[derive(Debug, Default)]
pub struct GoalUpdater;

impl GoalUpdater {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder).
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "GoalUpdater",
            Arity::One,
            Box::new(|| Box::new(GoalUpdater)),
        )
    }
}

/// When the entry that port `port` is bound to was last written (0 for a literal).
fn port_stamp<C>(node: &mut NodeCtx<'_, '_, C>, port: &str) -> Duration {
    let scope = node.scope();
    match node
        .ports()
        .iter()
        .find(|p| p.name == port)
        .map(|p| &p.value)
    {
        Some(PortValue::Entry(key)) => node
            .blackboard()
            .info_in(scope, key)
            .map_or(Duration::ZERO, |i| i.stamp),
        _ => Duration::ZERO,
    }
}

/// The update in entry `key` and when it was written, if there is one.
fn update<C, T>(node: &mut NodeCtx<'_, '_, C>, key: &str) -> Result<Option<(T, Duration)>, String>
where
    T: neurotree_core::FromPortStr + std::any::Any + Clone,
{
    let Some(value) = super::goals::entry_owned::<C, T>(node, key)? else {
        return Ok(None);
    };
    let scope = node.scope();
    let stamp = node
        .blackboard()
        .info_in(scope, key)
        .map_or(Duration::ZERO, |i| i.stamp);
    Ok(Some((value, stamp)))
}

impl GoalUpdater {
    fn write<C>(node: &mut NodeCtx<'_, '_, C>) -> Result<(), String> {
        let goal = super::port_value::<C, Pose2D>(node, "input_goal")?.unwrap_or_default();
        let goals = super::port_value::<C, Vec<Pose2D>>(node, "input_goals")?.unwrap_or_default();
        let goal_stamp = port_stamp(node, "input_goal");
        let goals_stamp = port_stamp(node, "input_goals");
        let goal = match update::<C, Pose2D>(node, GOAL_UPDATE)? {
            Some((received, stamp)) if stamp >= goal_stamp => received,
            _ => goal,
        };
        let goals = match update::<C, Vec<Pose2D>>(node, GOALS_UPDATE)? {
            Some((received, stamp)) if !received.is_empty() && stamp >= goals_stamp => received,
            _ => goals,
        };
        super::write_output(node, "output_goal", goal)?;
        super::write_output(node, "output_goals", goals)
    }
}

impl<C> CustomNode<C> for GoalUpdater {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(Vec::new())
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        node.reset_completed_children_after_tick();
        if let Err(e) = Self::write(node) {
            node.fail(e);
            return NodeStatus::Failure;
        }
        node.tick_child(0)
    }
}
