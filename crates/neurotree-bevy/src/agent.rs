//! The component that makes an entity an agent: the tree it runs, and its place in the crowd.

use std::sync::Arc;

use bevy_asset::{AssetId, Handle};
use bevy_ecs::component::Component;
use neurotree::crowd::MemberId;
use neurotree::Blueprint;

use crate::asset::TreeAsset;
use crate::context::AgentContext;

/// An agent's tree instance: which blueprint it runs, with which context, how often.
///
/// The instance itself (its node state and blackboard) lives in the
/// [`AgentCrowd`](crate::AgentCrowd) resource, which ticks every agent's tree in one
/// parallel pass; this component names it. An agent joins the crowd in the first frame
/// after it is spawned in which its tree is available (at once for a blueprint, once
/// loaded for an asset), and leaves it when the component is removed or replaced or the
/// entity despawned, which halts its running actions once.
#[derive(Component)]
pub struct TreeAgent<C: AgentContext> {
    source: TreeSource<C>,
    /// The context until the agent joins; the crowd holds it from then on.
    context: Option<C>,
    interval: u32,
    member: Option<MemberId>,
}

/// Where an agent's blueprint comes from.
pub(crate) enum TreeSource<C: AgentContext> {
    Blueprint(Arc<Blueprint<C>>),
    Asset(Handle<TreeAsset<C>>),
}

impl<C: AgentContext> TreeAgent<C> {
    /// An agent running an instance of `blueprint` with `context`.
    pub fn new(blueprint: Arc<Blueprint<C>>, context: C) -> Self {
        Self::with_source(TreeSource::Blueprint(blueprint), context)
    }

    /// An agent running the tree of a loaded [`TreeAsset`], reloaded when the asset
    /// changes.
    pub fn from_asset(tree: Handle<TreeAsset<C>>, context: C) -> Self {
        Self::with_source(TreeSource::Asset(tree), context)
    }

    fn with_source(source: TreeSource<C>, context: C) -> Self {
        Self {
            source,
            context: Some(context),
            interval: 1,
            member: None,
        }
    }

    /// Ticks the agent every `interval`-th frame (1, the default: every frame); agents
    /// of one interval are spread over the frames.
    pub fn with_interval(mut self, interval: u32) -> Self {
        self.interval = interval.max(1);
        self
    }

    /// Its id in the crowd, once it has joined.
    pub fn member(&self) -> Option<MemberId> {
        self.member
    }

    /// The tree asset it runs, if it runs one.
    pub fn asset(&self) -> Option<AssetId<TreeAsset<C>>> {
        match &self.source {
            TreeSource::Asset(handle) => Some(handle.id()),
            TreeSource::Blueprint(_) => None,
        }
    }

    pub(crate) fn source(&self) -> &TreeSource<C> {
        &self.source
    }

    pub(crate) fn interval(&self) -> u32 {
        self.interval
    }

    /// Hands the context over to the crowd, once.
    pub(crate) fn take_context(&mut self) -> Option<C> {
        self.context.take()
    }

    pub(crate) fn joined(&mut self, member: MemberId) {
        self.member = Some(member);
    }
}
