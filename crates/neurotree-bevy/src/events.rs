//! What the trees did, told to the rest of the app: messages and observer events.

use bevy_ecs::entity::Entity;
use bevy_ecs::event::EntityEvent;
use bevy_ecs::message::Message;
use neurotree::{Failure, ReloadReport, Status, TickError};

/// A message: an agent's root returned Success or Failure in this frame (Running trees
/// say nothing). Written by [`TreeSystems::Tick`](crate::TreeSystems::Tick).
#[derive(Message, Clone, Copy, Debug, PartialEq, Eq)]
pub struct TreeFinished {
    /// The agent.
    pub entity: Entity,
    /// What its root returned.
    pub status: Status,
}

/// An observer event, triggered for an agent whose root failed or whose tick ended with an
/// error: observe it globally (`app.add_observer`) or on the agent (`.observe(...)`).
#[derive(EntityEvent, Clone, Debug)]
pub struct TreeFailed {
    /// The agent.
    pub entity: Entity,
    /// Why.
    pub reason: FailureReason,
}

/// Why an agent's tree failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FailureReason {
    /// The root returned Failure: the chain of nodes down to the one that decided it, and
    /// the reason a leaf gave, if any.
    Failed(Failure),
    /// The tick ended with an error (the tree has been halted).
    Error(TickError),
}

/// A message: an agent's tree was reloaded because its asset changed.
#[derive(Message, Clone, Copy, Debug, PartialEq, Eq)]
pub struct TreeReloaded {
    /// The agent.
    pub entity: Entity,
    /// Which nodes kept their state, started afresh, or were halted.
    pub report: ReloadReport,
}
