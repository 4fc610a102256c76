//! The systems of [`TreeSystems`](crate::TreeSystems) and the observer that lets agents go.

use std::sync::{Arc, Mutex, PoisonError};

use bevy_asset::{AssetEvent, AssetId, Assets};
use bevy_ecs::change_detection::DetectChangesMut;
use bevy_ecs::component::Component;
use bevy_ecs::entity::Entity;
use bevy_ecs::lifecycle::{Discard, Insert};
use bevy_ecs::message::{Message, MessageReader, MessageWriter};
use bevy_ecs::observer::On;
use bevy_ecs::query::Changed;
use bevy_ecs::query::QueryItem;
use bevy_ecs::system::{Commands, Local, Query, Res, ResMut, StaticSystemParam, SystemParamItem};
use bevy_tasks::{ComputeTaskPool, TaskPool};
use neurotree::crowd::{
    Crowd, FrameReport, FrameStatus, InPlaceFrame, MemberId, ThreadPool, Visit,
};
use neurotree::{ReloadError, Status};

use bevy_diagnostic::Diagnostics;
use bevy_time::{Time, Virtual};

use crate::agent::{AgentSummary, TreeAgent, TreeSource};
use crate::asset::TreeAsset;
use crate::awake::AwakeAgents;
use crate::context::AgentContext;
use crate::crowd::AgentCrowd;
use crate::events::{FailureReason, TreeFailed, TreeFinished, TreeReloaded};

/// Puts the agents whose component was inserted since the last frame, and those still
/// waiting for their tree asset, in the crowd.
pub(crate) fn join<C: AgentContext>(
    mut crowd: ResMut<AgentCrowd<C>>,
    mut agents: Query<&mut TreeAgent<C>>,
    trees: Option<Res<Assets<TreeAsset<C>>>>,
) {
    let crowd = &mut *crowd;
    if crowd.waiting.is_empty() {
        return;
    }
    let mut waiting = std::mem::take(&mut crowd.waiting);
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

/// A ticked agent whose root did not return Running, or whose tick ended with an error.
#[derive(Clone, Copy)]
pub(crate) struct Finished {
    member: MemberId,
    entity: Entity,
    /// `None` for an error.
    status: Option<Status>,
}

/// Finished agents gathered by one batch of `par_iter_mut`, added to the frame's list when
/// the batch ends: one lock per batch rather than one per agent.
struct Gathered<'a> {
    into: &'a Mutex<Vec<Finished>>,
    batch: Vec<Finished>,
}

impl Drop for Gathered<'_> {
    fn drop(&mut self) {
        if !self.batch.is_empty() {
            let mut into = self.into.lock().unwrap_or_else(PoisonError::into_inner);
            into.append(&mut self.batch);
        }
    }
}

/// Runs a frame of the crowd over the agents' components and reports what their trees did.
///
/// Without a budget, each agent is visited once, in the order its components sit in
/// Bevy's tables, on all cores (the plugin's pool, or Bevy's compute pool when asked):
/// its context is loaded, its tree
/// ticked and its context stored while its data is in the cache, and no agent is looked up
/// by its entity. Under a budget, which picks members across the whole crowd before any is
/// ticked, the contexts are loaded first (on one thread), the crowd runs its frame on its
/// own threads, and the ticked agents' contexts are stored after it, on all cores. When
/// fewer than one agent in [`FEW_AWAKE`] is awake, only the awake ones are visited, by
/// entity, on this thread: the sleeping ones cost the frame nothing.
pub(crate) fn tick<C: AgentContext>(
    mut crowd: ResMut<AgentCrowd<C>>,
    mut agents: Query<(Entity, &TreeAgent<C>, C::Components)>,
    shared: StaticSystemParam<C::Shared>,
    mut finished: MessageWriter<TreeFinished>,
    mut commands: Commands,
    (mut collected, mut awake): (Local<Mutex<Vec<Finished>>>, Local<Vec<MemberId>>),
    (time, mut awake_agents, mut diagnostics): (
        Option<Res<Time<Virtual>>>,
        ResMut<AwakeAgents>,
        Diagnostics,
    ),
) where
    for<'w, 's> SystemParamItem<'w, 's, C::Shared>: Sync,
    for<'w, 's> QueryItem<'w, 's, C::Components>: Send,
{
    let crowd = &mut *crowd;
    let virtual_time = time.map(|t| (t.elapsed(), t.is_paused()));
    if !crowd.start_frame(virtual_time) {
        return;
    }
    let report_finished = crowd.report_finished;
    let pool = crowd.pool.clone();
    let shared = &*shared;
    ComputeTaskPool::get_or_init(TaskPool::default);
    let into = &*collected;
    let gather = || Gathered {
        into,
        batch: Vec::new(),
    };
    let (members, entities) = crowd.crowd_and_entities();
    let last = if let Some(frame) = members.frame_in_place() {
        if frame.awake() * FEW_AWAKE < frame.members() {
            visit_awake(
                frame,
                &mut agents,
                entities,
                shared,
                gather(),
                &mut awake,
                report_finished,
            )
        } else if let Some(pool) = &pool {
            visit_all_on(pool, frame, &mut agents, shared, &gather, report_finished)
        } else {
            visit_all(frame, &mut agents, shared, &gather, report_finished)
        }
    } else {
        load_all(crowd, &mut agents, shared);
        let report = crowd.crowd_mut().frame();
        let contexts = crowd.crowd_mut().contexts();
        agents
            .par_iter_mut()
            .for_each_init(gather, |gathered, (entity, agent, mut components)| {
                let Some(member) = agent.member() else { return };
                let Some(status) = contexts.status(member) else {
                    return;
                };
                if !matches!(status, FrameStatus::Ticked(_) | FrameStatus::Error) {
                    return;
                }
                if let Some(context) = contexts.get(member) {
                    context.store(&mut components);
                }
                gathered.note(member, entity, status, report_finished);
            });
        report
    };
    crowd.end_frame(last, virtual_time.is_some());
    *awake_agents = AwakeAgents::of(&last);
    crate::awake::measure(&mut diagnostics, &last);
    // In slot order, so that messages come in the same order on any number of threads.
    let ended = collected.get_mut().unwrap_or_else(PoisonError::into_inner);
    ended.sort_unstable_by_key(|f| f.member.slot());
    report(
        crowd.crowd_mut(),
        ended,
        report_finished,
        &mut finished,
        &mut commands,
    );
}

/// Visits every agent, in the order Bevy stores them, on all cores, and ends the frame.
fn visit_all<'g, C: AgentContext>(
    frame: InPlaceFrame<'_, C>,
    agents: &mut Query<(Entity, &TreeAgent<C>, C::Components)>,
    shared: &SystemParamItem<'_, '_, C::Shared>,
    gather: &(impl Fn() -> Gathered<'g> + Sync),
    report_finished: bool,
) -> FrameReport
where
    for<'w, 's> SystemParamItem<'w, 's, C::Shared>: Sync,
{
    let open = &frame;
    agents.par_iter_mut().for_each_init(
        // Boxed, one box per batch: `for_each_init` moves its state in and out of the
        // call for every agent, and a pointer moves cheaper than the state.
        || Box::new((open.visitor(), gather())),
        |state, (entity, agent, mut components)| {
            let (visitor, gathered) = &mut **state;
            let Some(member) = agent.member() else { return };
            let status = match visitor.visit(member, |c| c.load(&components, shared)) {
                Visit::NotDue => return,
                Visit::Ticked(context, status) => {
                    context.store(&mut components);
                    status
                }
            };
            gathered.note(member, entity, status, report_finished);
        },
    );
    frame.finish()
}

/// Visits every agent, in the order Bevy stores them, on `pool`'s threads, and ends the
/// frame. The agents are handed out in runs of [`RUN`], taken from the query as the threads
/// tick the runs before: a list of every agent's components, made afresh each frame, cost a
/// crowd of a million agents more than its ticks (its pages were the system's to clear).
fn visit_all_on<'g, C: AgentContext>(
    pool: &ThreadPool,
    frame: InPlaceFrame<'_, C>,
    agents: &mut Query<(Entity, &TreeAgent<C>, C::Components)>,
    shared: &SystemParamItem<'_, '_, C::Shared>,
    gather: &(impl Fn() -> Gathered<'g> + Sync),
    report_finished: bool,
) -> FrameReport
where
    for<'w, 's> SystemParamItem<'w, 's, C::Shared>: Sync,
    for<'w, 's> QueryItem<'w, 's, C::Components>: Send,
{
    let open = &frame;
    let mut items = agents.iter_mut();
    pool.in_place_scope(|scope| loop {
        let mut run: Vec<_> = items.by_ref().take(RUN).collect();
        if run.is_empty() {
            break;
        }
        scope.spawn(move |_| {
            let mut visitor = open.visitor();
            let mut gathered = gather();
            for (entity, agent, components) in &mut run {
                let Some(member) = agent.member() else {
                    continue;
                };
                let status = match visitor.visit(member, |c| c.load(components, shared)) {
                    Visit::NotDue => continue,
                    Visit::Ticked(context, status) => {
                        context.store(components);
                        status
                    }
                };
                gathered.note(member, *entity, status, report_finished);
            }
        });
    });
    frame.finish()
}

/// Agents in a run of a frame on the plugin's pool: enough that handing a run to a thread
/// costs little beside ticking it, few enough that the threads share a frame evenly and a
/// run's list stays in the cache.
const RUN: usize = 2048;

/// Visits the agents awake in `frame` by their entity, on this thread, and ends the frame:
/// when most agents sleep, cheaper than walking every agent's components. `awake` is room
/// for their ids.
fn visit_awake<C: AgentContext>(
    frame: InPlaceFrame<'_, C>,
    agents: &mut Query<(Entity, &TreeAgent<C>, C::Components)>,
    entities: &[Option<Entity>],
    shared: &SystemParamItem<'_, '_, C::Shared>,
    mut gathered: Gathered<'_>,
    awake: &mut Vec<MemberId>,
    report_finished: bool,
) -> FrameReport {
    frame.awake_members(awake);
    let mut visitor = frame.visitor();
    for &member in awake.iter() {
        let Some(entity) = entities.get(member.slot()).copied().flatten() else {
            continue;
        };
        let Ok((entity, _, mut components)) = agents.get_mut(entity) else {
            continue;
        };
        let status = match visitor.visit(member, |c| c.load(&components, shared)) {
            Visit::NotDue => continue,
            Visit::Ticked(context, status) => {
                context.store(&mut components);
                status
            }
        };
        gathered.note(member, entity, status, report_finished);
    }
    drop((visitor, gathered));
    frame.finish()
}

/// Below one agent awake in this many, a frame visits the awake agents by entity rather
/// than walking every agent's components.
const FEW_AWAKE: usize = 8;

/// Loads every agent's context from its components, for a frame under a budget.
fn load_all<C: AgentContext>(
    crowd: &mut AgentCrowd<C>,
    agents: &mut Query<(Entity, &TreeAgent<C>, C::Components)>,
    shared: &SystemParamItem<'_, '_, C::Shared>,
) {
    let (members, entities) = crowd.crowd_and_entities();
    for mut member in members.iter_mut() {
        let Some(entity) = entities.get(member.id().slot()).copied().flatten() else {
            continue;
        };
        if let Ok((_, _, components)) = agents.get_mut(entity) {
            member.context_mut().load(&components, shared);
        }
    }
}

impl Gathered<'_> {
    /// Keeps a ticked agent for the report if its root failed, its tick ended with an
    /// error, or (when asked) its root succeeded.
    #[inline(always)]
    fn note(&mut self, member: MemberId, entity: Entity, status: FrameStatus, finished: bool) {
        let status = match status {
            FrameStatus::Ticked(status) => Some(status),
            FrameStatus::Error => None,
            FrameStatus::NotDue | FrameStatus::Deferred | FrameStatus::Asleep => return,
        };
        let report = match status {
            Some(Status::Running) => false,
            Some(Status::Failure) | None => true,
            Some(_) => finished,
        };
        if report {
            self.batch.push(Finished {
                member,
                entity,
                status,
            });
        }
    }
}

/// Writes a [`TreeFinished`] for each agent of `ended` (if asked), and triggers a
/// [`TreeFailed`] with its reason for each failure and error.
fn report<C: AgentContext>(
    members: &Crowd<C>,
    ended: &mut Vec<Finished>,
    report_finished: bool,
    finished: &mut MessageWriter<TreeFinished>,
    commands: &mut Commands,
) {
    for done in ended.drain(..) {
        let Some(member) = members.get(done.member) else {
            continue;
        };
        let entity = done.entity;
        let reason = match done.status {
            Some(status) => {
                if report_finished {
                    finished.write(TreeFinished { entity, status });
                }
                if status != Status::Failure {
                    continue;
                }
                member.tree().last_failure().map(FailureReason::Failed)
            }
            None => member.error().cloned().map(FailureReason::Error),
        };
        if let Some(reason) = reason {
            commands.trigger(TreeFailed { entity, reason });
        }
    }
}

/// Brings each agent's [`AgentSummary`](crate::agent::AgentSummary) up to the last frame,
/// for Bevy's inspectors, unless the app turned summaries off. A sleeping agent's costs a
/// look at its member; only a new reason to be awake allocates.
pub(crate) fn summarize<C: AgentContext>(
    mut crowd: ResMut<AgentCrowd<C>>,
    mut agents: Query<(&TreeAgent<C>, &mut AgentSummary)>,
) {
    if !crowd.summaries {
        return;
    }
    let members = crowd.crowd_mut();
    for (agent, mut summary) in &mut agents {
        let Some(member) = agent.member().and_then(|id| members.get(id)) else {
            continue;
        };
        let tree = member.tree();
        let asleep = tree.is_asleep();
        // Not marked changed: a frame would otherwise mark every agent's summary.
        let summary = summary.bypass_change_detection();
        if summary.tree.is_empty() {
            let blueprint = tree.blueprint();
            if let Some(root) = blueprint.ids().next() {
                summary.tree = blueprint.name(root).to_string();
            }
        }
        summary.update(tree, member.status(), asleep);
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

/// Wakes the agents whose component `T` was inserted or changed since the last frame.
pub(crate) fn wake_on_change<C: AgentContext, T: Component>(
    mut crowd: ResMut<AgentCrowd<C>>,
    changed: Query<&TreeAgent<C>, Changed<T>>,
) {
    let members = crowd.crowd_mut();
    for agent in &changed {
        if let Some(member) = agent.member() {
            members.wake(member);
        }
    }
}

/// A system that wakes the agent each message `M` names through `target`.
// The type is the system's parameters, as Bevy spells them.
#[allow(clippy::type_complexity)]
pub(crate) fn wake_on_message<C: AgentContext, M: Message>(
    target: fn(&M) -> Entity,
) -> impl FnMut(MessageReader<M>, ResMut<AgentCrowd<C>>, Query<&TreeAgent<C>>) {
    move |mut messages, mut crowd, agents| {
        let members = crowd.crowd_mut();
        for message in messages.read() {
            if let Some(member) = agents.get(target(message)).ok().and_then(TreeAgent::member) {
                members.wake(member);
            }
        }
    }
}

/// Has an agent join the crowd in the next frame, when its component is inserted (also in
/// place of another, which [`leave`] has taken out).
pub(crate) fn arrive<C: AgentContext>(
    inserted: On<Insert<TreeAgent<C>>>,
    mut crowd: ResMut<AgentCrowd<C>>,
) {
    crowd.waiting.push(inserted.entity);
}

/// Takes an agent out of the crowd when its component goes (or its entity is despawned),
/// halting its running actions once.
pub(crate) fn leave<C: AgentContext>(
    discarded: On<Discard<TreeAgent<C>>>,
    agents: Query<&TreeAgent<C>>,
    mut crowd: ResMut<AgentCrowd<C>>,
) {
    // Discard observers run while the old component is still there: on its removal, its
    // entity's despawn, or its replacement by a new one.
    if let Some(member) = agents
        .get(discarded.entity)
        .ok()
        .and_then(TreeAgent::member)
    {
        crowd.leave(member);
    }
}
