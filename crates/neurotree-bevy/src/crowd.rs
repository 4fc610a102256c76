//! The resource that holds every agent's tree: one [`Crowd`] per context type.

use std::sync::{Mutex, PoisonError};
use std::time::Duration;

use bevy_ecs::entity::Entity;
use bevy_ecs::resource::Resource;
use std::sync::Arc;

use neurotree::crowd::{Crowd, FrameReport, Member, MemberId, MemberMut, ThreadPool};
use neurotree::ManualClock;

use crate::agent::TreeAgent;

/// The clock's step per frame when no virtual time is there to follow.
pub(crate) const DEFAULT_STEP: Duration = Duration::from_nanos(1_000_000_000 / 60);
use crate::context::AgentContext;

/// The agents' trees and contexts, ticked frame by frame on all cores by
/// [`TreeSystems::Tick`](crate::TreeSystems::Tick).
///
/// The trees read a [`ManualClock`] that the tick system sets, before each frame, to the
/// app's virtual time (`Time<Virtual>`, from Bevy's `TimePlugin`): pausing or slowing the
/// virtual time pauses or slows the trees, and no frame runs while it is paused. Without
/// `TimePlugin`, or with [`NeuroTreePlugin::with_step`](crate::NeuroTreePlugin::with_step),
/// the clock moves by a fixed step after each frame, so that `Delay`, `Timeout` and
/// `Sleep` count frames and runs repeat exactly.
#[derive(Resource)]
pub struct AgentCrowd<C: Send> {
    /// A `Mutex` only because a resource must be `Sync` and a tree is not: it is only
    /// ever reached through `&mut`, so it is never locked.
    crowd: Mutex<Crowd<C>>,
    clock: ManualClock,
    /// `None`: follow the virtual time, or 1/60 s per frame without one.
    step: Option<Duration>,
    /// Each slot's entity, to say whose tree did what.
    entities: Vec<Option<Entity>>,
    /// Agents spawned whose tree is not yet available.
    pub(crate) waiting: Vec<Entity>,
    last: FrameReport,
    /// Write a [`TreeFinished`](crate::TreeFinished) for each root that returned Success or
    /// Failure.
    pub(crate) report_finished: bool,
    /// Keep each agent's [`AgentSummary`](crate::AgentSummary) up to date.
    pub(crate) summaries: bool,
    /// The pool frames without a budget run on; `None`: Bevy's compute task pool.
    pub(crate) pool: Option<Arc<ThreadPool>>,
    /// The studio's page stood the whole crowd still: no frame runs.
    pub(crate) stands_still: bool,
}

impl<C: AgentContext> AgentCrowd<C> {
    pub(crate) fn new(
        crowd: Crowd<C>,
        clock: ManualClock,
        step: Option<Duration>,
        pool: Option<Arc<ThreadPool>>,
    ) -> Self {
        Self {
            crowd: Mutex::new(crowd),
            clock,
            step,
            entities: Vec::new(),
            waiting: Vec::new(),
            last: FrameReport::default(),
            report_finished: true,
            summaries: cfg!(debug_assertions),
            pool,
            stands_still: false,
        }
    }

    /// The crowd, to set a level-of-detail hook, a budget or a tick mode, or to reach a
    /// member's tree.
    pub fn crowd_mut(&mut self) -> &mut Crowd<C> {
        self.crowd.get_mut().unwrap_or_else(PoisonError::into_inner)
    }

    /// The agent's member of the crowd: its tree, its context, what it did last frame.
    pub fn member(&mut self, agent: &TreeAgent<C>) -> Option<Member<'_, C>> {
        let id = agent.member()?;
        self.crowd_mut().get(id)
    }

    /// The agent's member of the crowd, to change between frames.
    pub fn member_mut(&mut self, agent: &TreeAgent<C>) -> Option<MemberMut<'_, C>> {
        let id = agent.member()?;
        self.crowd_mut().get_mut(id)
    }

    /// The entity of a member.
    pub fn entity(&self, member: MemberId) -> Option<Entity> {
        self.entities.get(member.slot()).copied().flatten()
    }

    /// The threads a frame without a budget runs on: the plugin's own pool's (one per core
    /// by default), or, with [`NeuroTreePlugin::on_compute_pool`](crate::NeuroTreePlugin::on_compute_pool),
    /// Bevy's compute task pool's (1 until that pool exists).
    pub fn threads(&self) -> usize {
        match &self.pool {
            Some(pool) => pool.current_num_threads(),
            None => bevy_tasks::ComputeTaskPool::try_get().map_or(1, |p| p.thread_num()),
        }
    }

    /// The clock the trees read.
    pub fn clock(&self) -> &ManualClock {
        &self.clock
    }

    /// What the last frame did.
    pub fn last_frame(&self) -> FrameReport {
        self.last
    }

    /// Writes a [`TreeFinished`](crate::TreeFinished) message for each agent whose root
    /// returned Success or Failure (on by default); a game whose trees finish every frame
    /// may turn it off and read [`Member::status`] instead.
    pub fn set_report_finished(&mut self, on: bool) {
        self.report_finished = on;
    }

    /// Keeps each agent's [`AgentSummary`](crate::AgentSummary) up to date after each
    /// frame, for Bevy's inspectors: on by default in debug builds (`debug_assertions`), off in release
    /// builds, since it is a pass over every agent per frame on one thread, asleep or not
    /// (4 to 13 ms a frame for 100,000 agents on a loaded 2-core machine).
    pub fn set_summaries(&mut self, on: bool) {
        self.summaries = on;
    }

    /// The crowd, and each slot's entity.
    pub(crate) fn crowd_and_entities(&mut self) -> (&mut Crowd<C>, &[Option<Entity>]) {
        let crowd = self.crowd.get_mut().unwrap_or_else(PoisonError::into_inner);
        (crowd, &self.entities)
    }

    pub(crate) fn join(&mut self, entity: Entity, member: MemberId) {
        let slot = member.slot();
        if self.entities.len() <= slot {
            self.entities.resize(slot + 1, None);
        }
        self.entities[slot] = Some(entity);
    }

    pub(crate) fn leave(&mut self, member: MemberId) {
        if self.crowd_mut().remove(member).is_some() {
            self.entities[member.slot()] = None;
        }
    }

    /// Before a frame: `false` if none is to run (the virtual time is paused); else sets
    /// the clock to the virtual time, if it follows it.
    pub(crate) fn start_frame(&mut self, virtual_time: Option<(Duration, bool)>) -> bool {
        if self.stands_still {
            return false;
        }
        match virtual_time {
            Some((_, true)) => false,
            Some((elapsed, false)) => {
                if self.step.is_none() {
                    self.clock.set(elapsed);
                }
                true
            }
            None => true,
        }
    }

    /// After a frame: keeps its report and moves a clock of fixed steps on.
    pub(crate) fn end_frame(&mut self, report: FrameReport, follows_time: bool) {
        self.last = report;
        match self.step {
            Some(step) => self.clock.advance(step),
            None if !follows_time => self.clock.advance(DEFAULT_STEP),
            None => {}
        }
    }
}
