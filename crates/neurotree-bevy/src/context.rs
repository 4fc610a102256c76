//! The typed context an agent's leaves receive: what they read and write of its entity.

use bevy_ecs::query::{IterQueryData, QueryItem};
use bevy_ecs::system::{ReadOnlySystemParam, SystemParamItem};

/// An agent's context: the values its leaves read and write, copied from its entity's
/// components before each frame in which it is ticked and written back after its tick.
///
/// The crowd ticks agents on all cores while Bevy's world is borrowed by the tick system,
/// so a leaf cannot reach the world itself; instead each agent's context takes what its
/// tree needs from the components named by [`Components`](AgentContext::Components)
/// ([`load`](AgentContext::load)) and gives back what the tree changed
/// ([`store`](AgentContext::store), called only for agents ticked in that frame). What
/// all agents see alike (a player's position, the time of day) comes from
/// [`Shared`](AgentContext::Shared), any read-only system parameter. The context is also
/// the agent's own memory: fields not copied from components persist.
///
/// `Components` must not name the [`TreeAgent`](crate::TreeAgent) component itself. An
/// agent whose entity lacks one of them has no context to load and is not ticked (under a
/// budget, which ticks the crowd's members apart from the components, it is ticked with
/// the context it kept).
pub trait AgentContext: Send + Sync + 'static {
    /// The components the context is made from: `&T` to read, `&mut T` to write back.
    type Components: IterQueryData + 'static;

    /// What every agent's context may read of the world besides its own components: a
    /// `Res<'static, T>`, a `Query<'static, 'static, ...>` or a tuple of them; `()` for
    /// nothing. Contexts are loaded on several threads at once, so its items must be `Sync`
    /// (as `Res` and `Query` are).
    type Shared: ReadOnlySystemParam + 'static;

    /// Copies what the leaves read from the entity's components and the shared data,
    /// before a frame in which the agent is due (every frame, with a level-of-detail
    /// hook, which reads the context, or a budget). The components come as the query
    /// gives them (`Mut<T>` for `&mut T`), borrowed to read.
    fn load(
        &mut self,
        components: &QueryItem<'_, '_, Self::Components>,
        shared: &SystemParamItem<'_, '_, Self::Shared>,
    );

    /// Writes what the leaves changed back to the entity's components, after a frame in
    /// which the agent was ticked. Writing only what changed (`Mut::set_if_neq`) leaves
    /// Bevy's change detection quiet for agents that did nothing, and their memory
    /// untouched.
    fn store(&self, components: &mut QueryItem<'_, '_, Self::Components>);
}
