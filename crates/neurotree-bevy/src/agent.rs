//! The component that makes an entity an agent: the tree it runs, and its place in the crowd.

use std::sync::Arc;

use bevy_asset::{AssetId, Handle};
use bevy_ecs::component::Component;
use bevy_ecs::reflect::ReflectComponent;
use bevy_reflect::utility::GenericTypePathCell;
use bevy_reflect::{Reflect, TypePath};
use neurotree::crowd::{FrameStatus, MemberId};
use neurotree::{AwakeReason, Blueprint, NodeId, Status, Tree};

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
///
/// It implements `Reflect` (registered by the plugin), and brings an [`AgentSummary`]
/// component along, which Bevy's inspectors show: the tree's name, what it did last frame,
/// whether it sleeps and why not. The summary is a component of its own, so that the frame's
/// pass over the agents, which reads this component, does not carry it through the caches.
#[derive(Component, Reflect)]
#[reflect(Component, type_path = false, from_reflect = false)]
#[require(AgentSummary)]
pub struct TreeAgent<C: AgentContext> {
    #[reflect(ignore)]
    source: TreeSource<C>,
    /// The context until the agent joins; the crowd holds it from then on.
    #[reflect(ignore)]
    context: Option<C>,
    #[reflect(ignore)]
    interval: u32,
    #[reflect(ignore)]
    member: Option<MemberId>,
}

// By hand: the context type needs no `TypePath` of its own.
impl<C: AgentContext> TypePath for TreeAgent<C> {
    fn type_path() -> &'static str {
        static CELL: GenericTypePathCell = GenericTypePathCell::new();
        CELL.get_or_insert::<Self, _>(|| {
            format!("neurotree_bevy::TreeAgent<{}>", std::any::type_name::<C>())
        })
    }

    fn short_type_path() -> &'static str {
        static CELL: GenericTypePathCell = GenericTypePathCell::new();
        CELL.get_or_insert::<Self, _>(|| {
            let context = std::any::type_name::<C>();
            let short = context.rsplit("::").next().unwrap_or(context);
            format!("TreeAgent<{short}>")
        })
    }

    fn type_ident() -> Option<&'static str> {
        Some("TreeAgent")
    }

    fn crate_name() -> Option<&'static str> {
        Some("neurotree_bevy")
    }

    fn module_path() -> Option<&'static str> {
        Some("neurotree_bevy")
    }
}

/// What an agent's tree is and did, for Bevy's inspectors: a component every
/// [`TreeAgent`] brings along, kept up to date after each frame by
/// [`TreeSystems::Tick`](crate::TreeSystems::Tick) while
/// [`AgentCrowd::set_summaries`](crate::AgentCrowd::set_summaries) is on (by default in
/// debug builds only); left at its default otherwise.
#[derive(Component, Reflect, Clone, Debug, Default, PartialEq, Eq)]
#[reflect(Component)]
pub struct AgentSummary {
    /// The name of the tree's root node (its `name` attribute in a tree file, else its
    /// type); empty until the agent joins the crowd.
    pub tree: String,
    /// What its last frame did: `not_due`, `deferred`, `asleep`, `error`, or the status
    /// its root returned (`running`, `success`, `failure`).
    pub status: &'static str,
    /// Whether its tree sleeps: not ticked until what it waits on happens.
    pub asleep: bool,
    /// Why it is awake (as [`Tree::why_awake`] displays it), empty while it sleeps.
    pub why_awake: String,
    /// The [`AwakeReason::name`](neurotree::AwakeReason::name) of why it is awake, empty
    /// while it sleeps.
    pub awake_reason: &'static str,
    /// The reason and node `why_awake` was written for.
    #[reflect(ignore)]
    written: Option<(AwakeReason, NodeId)>,
}

impl AgentSummary {
    /// Brings the summary up to the member's last frame; allocates only when the reason it
    /// is awake changes.
    pub(crate) fn update<C>(&mut self, tree: &Tree<C>, status: FrameStatus, asleep: bool) {
        self.status = match status {
            FrameStatus::NotDue => "not_due",
            FrameStatus::Deferred => "deferred",
            FrameStatus::Asleep => "asleep",
            FrameStatus::Error => "error",
            FrameStatus::Ticked(Status::Running) => "running",
            FrameStatus::Ticked(Status::Success) => "success",
            FrameStatus::Ticked(Status::Failure) => "failure",
        };
        self.asleep = asleep;
        let reason = if asleep { None } else { tree.awake_reason() };
        if reason != self.written {
            self.written = reason;
            self.awake_reason = reason.map_or("", |(r, _)| r.name());
            self.why_awake = match (reason, tree.why_awake()) {
                (Some(_), Some(why)) => why.to_string(),
                _ => String::new(),
            };
        }
    }
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
