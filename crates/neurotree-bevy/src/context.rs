//! The typed context an agent's leaves receive: what they read and write of its entity.

use bevy_ecs::query::{IterQueryData, QueryItem};

/// An agent's context: the values its leaves read and write, copied from its entity's
/// components before each frame and written back after it.
///
/// The crowd ticks agents on all cores while Bevy's world is borrowed by the tick system,
/// so a leaf cannot reach the world itself; instead each agent's context takes what its
/// tree needs from the components named by [`Components`](AgentContext::Components)
/// ([`load`](AgentContext::load)) and gives back what the tree changed
/// ([`store`](AgentContext::store), called only for agents ticked in that frame). The
/// context is also the agent's own memory: fields not copied from components persist.
///
/// `Components` must not name the [`TreeAgent`](crate::TreeAgent) component itself.
pub trait AgentContext: Send + Sync + 'static {
    /// The components the context is made from: `&T` to read, `&mut T` to write back.
    type Components: IterQueryData + 'static;

    /// Copies what the leaves read from the entity's components, before every frame.
    fn load(&mut self, components: &QueryItem<'_, '_, Self::Components>);

    /// Writes what the leaves changed back to the entity's components, after a frame in
    /// which the agent was ticked.
    fn store(&self, components: &mut QueryItem<'_, '_, Self::Components>);
}
