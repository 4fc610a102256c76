//! The systems of [`TreeSystems`](crate::TreeSystems) and the observer that lets agents go.

use std::sync::Arc;

use bevy_asset::{AssetEvent, AssetId, Assets};
use bevy_ecs::entity::Entity;
use bevy_ecs::lifecycle::Remove;
use bevy_ecs::message::{MessageReader, MessageWriter};
use bevy_ecs::observer::On;
use bevy_ecs::system::{Commands, Local, ParamSet, Query, Res, ResMut, StaticSystemParam};
use neurotree::crowd::FrameStatus;
use neurotree::{ReloadError, Status};

use crate::agent::{TreeAgent, TreeSource};
use crate::asset::TreeAsset;
use crate::context::AgentContext;
use crate::crowd::AgentCrowd;
use crate::events::{FailureReason, TreeFailed, TreeFinished, TreeReloaded};

/// The agents spawned since the last run of a system.
type AddedAgents<'w, 's, C> = Query<'w, 's, Entity, bevy_ecs::query::Added<TreeAgent<C>>>;

/// Puts the agents spawned since the last frame, and those still waiting for their tree
/// asset, in the crowd.
pub(crate) fn join<C: AgentContext>(
    mut crowd: ResMut<AgentCrowd<C>>,
    mut agents: ParamSet<(AddedAgents<C>, Query<&mut TreeAgent<C>>)>,
    trees: Option<Res<Assets<TreeAsset<C>>>>,
) {
    let crowd = &mut *crowd;
    crowd.waiting.extend(agents.p0().iter());
    if crowd.waiting.is_empty() {
        return;
    }
    let mut waiting = std::mem::take(&mut crowd.waiting);
    let mut agents = agents.p1();
    waiting.retain(|&entity| {
        let Ok(mut agent) = agents.get_mut(entity) else {
            // Despawned, or its component removed, before it joined.
            return false;
        };
        if agent.member().is_some() {
            return false;
        }
        let blueprint = match agent.source() {
            TreeSource::Blueprint(blueprint) => Arc::clone(blueprint),
            TreeSource::Asset(handle) => match trees.as_ref().and_then(|t| t.get(handle)) {
                Some(tree) => Arc::clone(tree.blueprint()),
                None => return true,
            },
        };
        let Some(context) = agent.take_context() else {
            return false;
        };
        let interval = agent.interval();
        let crowd_ = crowd.crowd_mut();
        let id = crowd_.add(blueprint, context);
        if let Some(mut member) = crowd_.get_mut(id) {
            member.set_interval(interval);
        }
        crowd.join(entity, id);
        agent.joined(id);
        false
    });
    crowd.waiting = waiting;
}

/// Loads every agent's context from its components, runs a frame of the crowd, writes the
/// ticked agents' contexts back, and reports what their trees did.
pub(crate) fn tick<C: AgentContext>(
    mut crowd: ResMut<AgentCrowd<C>>,
    mut agents: Query<(Entity, &TreeAgent<C>, C::Components)>,
    shared: StaticSystemParam<C::Shared>,
    mut finished: MessageWriter<TreeFinished>,
    mut commands: Commands,
) {
    let crowd = &mut *crowd;
    {
        let members = crowd.crowd_mut();
        for (_, agent, components) in agents.iter() {
            let Some(id) = agent.member() else { continue };
            if let Some(mut member) = members.get_mut(id) {
                member.context_mut().load(components, &shared);
            }
        }
    }
    crowd.frame();
    let report_finished = crowd.report_finished;
    let members = crowd.crowd_mut();
    for (entity, agent, mut components) in agents.iter_mut() {
        let Some(member) = agent.member().and_then(|id| members.get(id)) else {
            continue;
        };
        let status = match member.status() {
            FrameStatus::NotDue | FrameStatus::Deferred => continue,
            FrameStatus::Ticked(status) => status,
            FrameStatus::Error => {
                member.context().store(&mut components);
                if let Some(error) = member.error() {
                    let reason = FailureReason::Error(error.clone());
                    commands.trigger(TreeFailed { entity, reason });
                }
                continue;
            }
        };
        member.context().store(&mut components);
        if status == Status::Running {
            continue;
        }
        if report_finished {
            finished.write(TreeFinished { entity, status });
        }
        if status == Status::Failure {
            if let Some(failure) = member.tree().last_failure() {
                let reason = FailureReason::Failed(failure);
                commands.trigger(TreeFailed { entity, reason });
            }
        }
    }
}

/// Reloads the trees of the agents whose tree asset changed, keeping the state of the
/// nodes that did not change. An agent whose tree is halting is reloaded in a later frame.
pub(crate) fn reload<C: AgentContext>(
    mut changes: MessageReader<AssetEvent<TreeAsset<C>>>,
    mut pending: Local<Vec<AssetId<TreeAsset<C>>>>,
    trees: Res<Assets<TreeAsset<C>>>,
    mut crowd: ResMut<AgentCrowd<C>>,
    agents: Query<(Entity, &TreeAgent<C>)>,
    mut reloaded: MessageWriter<TreeReloaded>,
) {
    for change in changes.read() {
        if let AssetEvent::Modified { id } = change {
            if !pending.contains(id) {
                pending.push(*id);
            }
        }
    }
    if pending.is_empty() {
        return;
    }
    let members = crowd.crowd_mut();
    pending.retain(|&id| {
        let Some(tree) = trees.get(id) else {
            return false;
        };
        let mut again = false;
        for (entity, agent) in agents.iter() {
            if agent.asset() != Some(id) {
                continue;
            }
            let Some(mut member) = agent.member().and_then(|m| members.get_mut(m)) else {
                continue;
            };
            let (instance, context) = member.tree_and_context_mut();
            if Arc::ptr_eq(instance.blueprint(), tree.blueprint()) {
                continue;
            }
            match instance.reload(Arc::clone(tree.blueprint()), context) {
                Ok(report) => {
                    reloaded.write(TreeReloaded { entity, report });
                }
                Err(ReloadError::Halting) => again = true,
                // A refusal this plugin does not know yet: leave the tree as it is.
                Err(_) => {}
            }
        }
        again
    });
}

/// Takes an agent out of the crowd when its component goes (or its entity is despawned),
/// halting its running actions once.
pub(crate) fn leave<C: AgentContext>(
    removed: On<Remove<TreeAgent<C>>>,
    agents: Query<&TreeAgent<C>>,
    mut crowd: ResMut<AgentCrowd<C>>,
) {
    // Remove observers run while the component is still there.
    if let Some(member) = agents.get(removed.entity).ok().and_then(TreeAgent::member) {
        crowd.leave(member);
    }
}
