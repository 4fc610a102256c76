//! Crowds: many trees, each with its own context, ticked frame by frame on all cores.
//!
//! A [`Crowd`] holds members: each is a [`Tree`] (its node state and its blackboard) and a
//! context `C` of its own, instances of one or several shared [`Blueprint`]s. A call of
//! [`Crowd::frame`] ticks the members due in that frame in parallel, with rayon, and
//! reports what happened.
//!
//! - **Threads.** Frames run in rayon's global pool, whose size follows `RAYON_NUM_THREADS`
//!   (all cores by default), or in a pool of the crowd's own ([`Crowd::with_threads`],
//!   [`Crowd::with_pool`]). A crowd made with one thread of its own runs its frames on the
//!   caller's thread (unless it has a budget): handing a frame to the pool's one worker
//!   would cost a thread's wake-up and gain nothing.
//! - **Same results on any number of threads.** A member's tick touches only its tree and
//!   its context, and every choice the crowd makes (who is due, who the budget picks) is
//!   made from the members alone, in slot order: one thread or many give the same statuses,
//!   blackboards and contexts, provided the contexts share nothing mutable (or share it in
//!   a way that does not depend on order) and the clock is one like
//!   [`ManualClock`](crate::ManualClock) that moves only between frames.
//! - **Intervals.** A member is due every `interval`-th frame, with a phase that spreads the
//!   members of one interval over the frames ([`MemberMut::set_interval`]). A level-of-detail
//!   hook ([`Crowd::set_level_of_detail`]) chooses each member's interval every frame from
//!   its context: a member far from the camera ticks every 8th frame.
//! - **Budget.** [`Crowd::set_budget`] caps a frame's ticks in node visits (see
//!   [Budget](#budget) below). Due ticks past the cap wait for the next frames,
//!   those that waited longest first, and [`FrameReport::behind`] tells how far behind the
//!   crowd is.
//! - **Membership.** Members join ([`Crowd::add`]) and leave ([`Crowd::remove`], which halts
//!   the running actions of the member's tree once) between frames.
//! - **Many at once.** [`Crowd::for_each_mut`] changes the members a list of ids names (a
//!   frame's events, each written into a member's blackboard, which wakes it) on the
//!   crowd's threads, between frames; [`Crowd::frame_with`] does the same and then runs
//!   the frame, in one trip to the crowd's threads.
//! - **In the caller's order.** [`Crowd::frame_in_place`] opens a frame whose members the
//!   caller visits one by one, from its own threads and in the order of its own data
//!   ([`InPlaceFrame`]): a game engine fills each context, has it ticked and reads it back
//!   in one visit, rather than in three passes over the crowd.
//! - **Results.** [`Member::status`] is what the member did in the last frame: not due,
//!   deferred, or ticked with a status or an error; [`Member::tree`] gives
//!   [`Tree::last_failure`] for a member that failed.
//!
//! A frame allocates nothing once the crowd has run a few frames (the queue of deferred
//! members has reached its size), beyond what rayon does to share the work out, and an
//! error, which the member's tree keeps ([`Tree::last_error`]).
//!
//! # Budget
//!
//! The budget counts node visits rather than time, so that it picks the same members on
//! any machine, under any load and with any number of threads; a budget in wall time could
//! not, and none is offered. A tick is charged the blueprint's nodes for each pass of its
//! root, the most the pass can visit: the engine keeps no count of the nodes it visits (its
//! loops over conditions do not even store their statuses), and an observer on every member
//! to count them would cost more than the ticks it counted. A member is expected to cost
//! what its last tick cost, and one pass when it joins.
//!
//! The schedules of all members sit in a table apart from their trees, so that a frame
//! reads a few bytes of each awake member not due and leaves its tree alone; a
//! level-of-detail hook reads each member's context too. A sleeping member is not visited
//! at all (see [`sleep`](crate::tree::sleep) and the crowd's wake timers in
//! [`CrowdWaker`]'s module).
//!
//! # Example
//!
//! ```
//! use std::sync::Arc;
//! use std::time::Duration;
//! use neurotree::crowd::{Crowd, FrameStatus};
//! use neurotree::prelude::*;
//!
//! struct Villager { distance: u32, steps: u32 }
//!
//! let walk = Blueprint::<Villager>::builder()
//!     .action("walk", |v: &mut Villager| {
//!         v.steps += 1;
//!         Status::Success
//!     })
//!     .build_shared()?;
//!
//! let clock = ManualClock::new();
//! let mut crowd = Crowd::new(clock.clone()).with_threads(2)?;
//! for i in 0..1000 {
//!     crowd.add(Arc::clone(&walk), Villager { distance: i, steps: 0 });
//! }
//! // Villagers farther than 500 m walk every 8th frame.
//! crowd.set_level_of_detail(|v: &Villager| if v.distance > 500 { 8 } else { 1 });
//! for _ in 0..16 {
//!     let report = crowd.frame();
//!     assert_eq!(report.errors, 0);
//!     clock.advance(Duration::from_millis(16));
//! }
//! let steps = |i: usize| crowd.iter().nth(i).unwrap().context().steps;
//! assert_eq!((steps(0), steps(999)), (16, 2));
//! assert!(crowd.iter().all(|m| m.status() != FrameStatus::Deferred));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod hold;
mod in_place;
mod member;
mod run;
mod schedule;
mod sleep;
mod span;
mod visit;

use std::collections::VecDeque;
use std::sync::Arc;

use rayon::prelude::*;

use crate::{Blueprint, Clock, Tree};
pub use in_place::{InPlaceFrame, Visit, Visitor, PART};
use member::{Body, Plan};
pub use member::{Contexts, FrameStatus, Member, MemberId, MemberMut, TickMode};
pub use rayon::{ThreadPool, ThreadPoolBuildError, ThreadPoolBuilder};
pub use sleep::CrowdWaker;
pub use visit::{SHARED_IN_FRAME, SHARED_VISITS};

/// A level-of-detail hook: a member's interval, from its context.
type Lod<C> = dyn Fn(&C) -> u32 + Send + Sync;

/// Many trees with contexts of their own, ticked frame by frame in parallel.
///
/// Dropping a crowd drops its trees without halting them, as dropping a [`Tree`] does:
/// call [`Crowd::halt_all`] first if running actions must hear of it.
pub struct Crowd<C> {
    /// Each slot's tree, `None` in an empty slot.
    bodies: Vec<Option<Body<C>>>,
    /// Each slot's context, beside `bodies` rather than in them, so that what reads every
    /// member's context (a level-of-detail hook, a game engine copying its data in and out)
    /// reads them packed together.
    contexts: Vec<Option<C>>,
    /// Each slot's schedule, beside `bodies`.
    plans: Vec<Plan>,
    /// Empty slots, reused last-freed first.
    free: Vec<u32>,
    len: usize,
    clock: Arc<dyn Clock>,
    pool: Option<Arc<ThreadPool>>,
    lod: Option<Box<Lod<C>>>,
    budget: Option<u64>,
    mode: TickMode,
    /// Frames run so far: the number of the next frame.
    frames: u64,
    /// Members added so far: the default phase of the next one.
    added: u64,
    /// Slots of the members owed a tick, in the order they fell due.
    backlog: VecDeque<u32>,
    chunks: Vec<schedule::Chunk>,
    /// Wakes queued from other threads (see [`CrowdWaker`]).
    waker: CrowdWaker,
    /// Which members are awake: the only ones a frame visits.
    awake: sleep::Awake,
    /// When sleeping members wake on their own.
    timers: sleep::Timers,
    /// Members no frame ticks until released ([`Crowd::hold`]).
    held: hold::Held,
    /// The ids [`Crowd::for_each_mut`] visits, sorted by word of slots.
    visits: visit::Visits,
    /// The awake members before each word of slots, by which a frame's threads share them.
    work: Vec<u32>,
    /// A bit per slot of the members an [`InPlaceFrame`] visited, kept between frames for
    /// its room.
    seen: Vec<u64>,
    /// Frames without a budget run on the caller's thread (see
    /// [`runs_inline`](Self::runs_inline)).
    on_caller: bool,
}

/// What one frame did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct FrameReport {
    /// The frame's number, from 0.
    pub frame: u64,
    /// Members due: those whose interval came round, and those owed from earlier frames;
    /// not those asleep.
    pub due: u64,
    /// Members whose tree slept through the frame: not visited (see
    /// [`sleep`](crate::tree::sleep)).
    pub asleep: u64,
    /// Members ticked.
    pub ticked: u64,
    /// Node visits charged for the ticks (see [the budget](self#budget)).
    pub visits: u64,
    /// Members whose root returned Failure.
    pub failures: u64,
    /// Members whose tick ended with an error.
    pub errors: u64,
    /// How far behind the budget left the crowd, after the frame.
    pub behind: Behind,
    /// The members ticked in the frame that stayed awake, by why (see
    /// [`Tree::why_awake`](neurotree_core::Tree::why_awake)); those not ticked are not
    /// counted.
    pub awake: neurotree_core::AwakeCounts,
}

/// How far behind a crowd under a budget is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Behind {
    /// Members owed a tick.
    pub overdue: u64,
    /// Frames the longest-waiting of them has been due without a tick (0 when none is).
    pub frames: u64,
}

impl<C: Send> Crowd<C> {
    /// An empty crowd whose trees read `clock`, running frames in rayon's global pool.
    pub fn new(clock: impl Clock + 'static) -> Self {
        Self::with_shared_clock(Arc::new(clock))
    }

    /// An empty crowd whose trees share `clock`.
    pub fn with_shared_clock(clock: Arc<dyn Clock>) -> Self {
        Self {
            bodies: Vec::new(),
            contexts: Vec::new(),
            plans: Vec::new(),
            free: Vec::new(),
            len: 0,
            clock,
            pool: None,
            lod: None,
            budget: None,
            mode: TickMode::default(),
            frames: 0,
            added: 0,
            backlog: VecDeque::new(),
            chunks: Vec::new(),
            waker: CrowdWaker::default(),
            awake: sleep::Awake::default(),
            timers: sleep::Timers::default(),
            held: hold::Held::default(),
            visits: visit::Visits::default(),
            work: Vec::new(),
            seen: Vec::new(),
            on_caller: false,
        }
    }

    /// Runs frames in a pool of `threads` threads of its own (0: as many as rayon's
    /// default, `RAYON_NUM_THREADS` or the cores). With one thread, a frame without a
    /// budget runs on the caller's thread rather than in the pool (the same ticks, in the
    /// same order, without waking the pool's thread).
    pub fn with_threads(self, threads: usize) -> Result<Self, ThreadPoolBuildError> {
        let pool = ThreadPoolBuilder::new().num_threads(threads).build()?;
        let one = pool.current_num_threads() == 1;
        let mut crowd = self.with_pool(Arc::new(pool));
        crowd.on_caller = one;
        Ok(crowd)
    }

    /// Runs frames in `pool`, which other crowds or work may share: every frame runs in
    /// it, whatever its size, so that its threads' settings apply to the ticks.
    pub fn with_pool(mut self, pool: Arc<ThreadPool>) -> Self {
        self.pool = Some(pool);
        self.on_caller = false;
        self
    }

    /// The threads a frame runs on.
    pub fn threads(&self) -> usize {
        match &self.pool {
            Some(pool) => pool.current_num_threads(),
            None => rayon::current_num_threads(),
        }
    }

    /// Bytes each member takes in the crowd's tables: its `Tree` struct, its context and
    /// its schedule. Its node state is apart ([`Tree::state_bytes`]), and so are its
    /// stateful leaves' objects and its blackboard's entries.
    pub fn slot_bytes(&self) -> usize {
        std::mem::size_of::<Option<Body<C>>>()
            + std::mem::size_of::<Option<C>>()
            + std::mem::size_of::<Plan>()
    }

    /// The clock the crowd's trees read.
    pub fn clock(&self) -> &Arc<dyn Clock> {
        &self.clock
    }

    /// Adds a member: a fresh instance of `blueprint` on the crowd's clock, ticked with
    /// `ctx`, due every frame. Its phase is the number of members added before it, so that
    /// members given a longer interval spread over the frames.
    pub fn add(&mut self, blueprint: Arc<Blueprint<C>>, ctx: C) -> MemberId {
        let tree = Tree::with_shared_clock(blueprint, Arc::clone(&self.clock));
        self.add_tree(tree, ctx)
    }

    /// Adds a member made by the caller: a tree with a seeded blackboard or an observer.
    ///
    /// The tree is moved onto the crowd's clock ([`Tree::set_shared_clock`]), whatever
    /// clock it was made with: the crowd wakes its sleeping members by its own clock, so a
    /// member on another would sleep past its deadlines. Add a tree that has not run, or
    /// one halted, since its Running time-based nodes keep the readings of its old clock.
    pub fn add_tree(&mut self, mut tree: Tree<C>, ctx: C) -> MemberId {
        tree.set_shared_clock(Arc::clone(&self.clock));
        let phase = self.added as u32;
        self.added += 1;
        let index = match self.free.pop() {
            Some(index) => index,
            None => {
                let index = u32::try_from(self.plans.len()).expect("at most 2^32 members");
                self.plans.push(Plan::new(0));
                self.bodies.push(None);
                self.contexts.push(None);
                self.awake.grow(self.plans.len());
                index
            }
        };
        let plan = &mut self.plans[index as usize];
        *plan = Plan::joining(plan.generation, phase, member::nodes(&tree));
        self.bodies[index as usize] = Some(Body { tree });
        self.contexts[index as usize] = Some(ctx);
        self.awake.set(index as usize);
        self.len += 1;
        MemberId {
            index,
            generation: plan.generation,
        }
    }

    /// Removes a member, halting its tree first (each Running stateful action gets its one
    /// `on_halted`), and gives back its tree and context; `None` if `id` names no member.
    /// An action whose halt takes ticks leaves the tree [halting](Tree::is_halting): call
    /// [`Tree::tick_halt`] until it returns `true`.
    pub fn remove(&mut self, id: MemberId) -> Option<(Tree<C>, C)> {
        self.get(id)?;
        let i = id.index as usize;
        let mut body = self.bodies[i].take()?;
        let mut ctx = self.contexts[i].take()?;
        let plan = &mut self.plans[i];
        let owed = plan.is_owed();
        *plan = Plan::new(plan.generation.wrapping_add(1));
        self.awake.clear(i);
        self.timers.forget_fallen(i);
        self.free.push(id.index);
        self.len -= 1;
        if owed {
            self.backlog.retain(|&s| s != id.index);
        }
        body.tree.halt(&mut ctx);
        Some((body.tree, ctx))
    }

    /// Halts every member's tree, as [`Crowd::remove`] would, keeping the members. A
    /// halted tree starts over at its next tick, so every member is woken: the next frame
    /// in which it is due ticks it, as a fresh member.
    pub fn halt_all(&mut self) {
        for (slot, plan) in self.plans.iter_mut().enumerate() {
            if plan.present() {
                self.awake.wake(plan, slot);
            }
        }
        let halt = |bodies: &mut [Option<Body<C>>], contexts: &mut [Option<C>]| {
            bodies
                .par_iter_mut()
                .zip(contexts.par_iter_mut())
                .for_each(|(b, c)| {
                    if let (Some(b), Some(c)) = (b, c) {
                        b.tree.halt(c);
                    }
                })
        };
        match &self.pool {
            Some(pool) => pool.install(|| halt(&mut self.bodies, &mut self.contexts)),
            None => halt(&mut self.bodies, &mut self.contexts),
        }
    }

    /// The member `id` names, if it is still in the crowd.
    pub fn get(&self, id: MemberId) -> Option<Member<'_, C>> {
        let plan = self.plans.get(id.index as usize)?;
        if plan.generation != id.generation {
            return None;
        }
        let body = self.bodies[id.index as usize].as_ref()?;
        let ctx = self.contexts[id.index as usize].as_ref()?;
        Some(Member {
            id,
            body,
            ctx,
            plan,
        })
    }

    /// The member `id` names, to change between frames.
    pub fn get_mut(&mut self, id: MemberId) -> Option<MemberMut<'_, C>> {
        let i = id.index as usize;
        MemberMut::of(
            id,
            self.plans.get_mut(i)?,
            &mut self.bodies[i],
            &mut self.contexts[i],
            &self.awake,
            &self.clock,
        )
    }

    /// The members, in slot order.
    pub fn iter(&self) -> impl Iterator<Item = Member<'_, C>> {
        self.plans
            .iter()
            .zip(&self.bodies)
            .zip(&self.contexts)
            .enumerate()
            .filter_map(|(i, ((plan, body), ctx))| {
                let id = MemberId {
                    index: i as u32,
                    generation: plan.generation,
                };
                match (body, ctx) {
                    (Some(body), Some(ctx)) => Some(Member {
                        id,
                        body,
                        ctx,
                        plan,
                    }),
                    _ => None,
                }
            })
    }

    /// The members, in slot order, to change between frames.
    pub fn iter_mut(&mut self) -> impl Iterator<Item = MemberMut<'_, C>> {
        let awake = &self.awake;
        let clock = &self.clock;
        self.plans
            .iter_mut()
            .zip(&mut self.bodies)
            .zip(&mut self.contexts)
            .enumerate()
            .filter_map(|(i, ((plan, body), ctx))| {
                let id = MemberId {
                    index: i as u32,
                    generation: plan.generation,
                };
                match (body, ctx) {
                    (Some(body), Some(ctx)) => Some(MemberMut {
                        id,
                        body,
                        ctx,
                        plan,
                        awake,
                        clock,
                    }),
                    _ => None,
                }
            })
    }

    /// Every member's context and last status, to read from many threads at once.
    pub fn contexts(&self) -> Contexts<'_, C> {
        Contexts {
            plans: &self.plans,
            contexts: &self.contexts,
        }
    }

    /// Calls `f` on every member's id and context, in parallel on the crowd's threads:
    /// to copy data in before a frame, where [`iter_mut`](Self::iter_mut) would do it on
    /// one thread.
    pub fn for_each_context_mut(&mut self, f: impl Fn(MemberId, &mut C) + Send + Sync) {
        let Self {
            plans,
            contexts,
            pool,
            ..
        } = self;
        let mut run = move || {
            plans
                .par_iter()
                .zip(contexts.par_iter_mut())
                .enumerate()
                .with_min_len(1024)
                .for_each(|(i, (plan, ctx))| {
                    if let Some(ctx) = ctx {
                        let id = MemberId {
                            index: i as u32,
                            generation: plan.generation,
                        };
                        f(id, ctx);
                    }
                })
        };
        match pool {
            Some(pool) => pool.install(run),
            None => run(),
        }
    }

    /// The members whose root returned Failure in the last frame; [`Tree::last_failure`]
    /// on their tree says why.
    pub fn failures(&self) -> impl Iterator<Item = Member<'_, C>> {
        self.iter()
            .filter(|m| m.status() == FrameStatus::Ticked(crate::Status::Failure))
    }

    /// The members whose tick ended with an error in the last frame ([`Member::error`]).
    pub fn errors(&self) -> impl Iterator<Item = Member<'_, C>> {
        self.iter().filter(|m| m.status() == FrameStatus::Error)
    }

    /// Members in the crowd.
    pub fn len(&self) -> usize {
        self.len
    }

    /// `true` with no member.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Frames run so far, which is the number of the next frame.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// Sets the hook that chooses each member's interval from its context at the start of
    /// every frame (a result of 0 counts as 1). It runs on the frame's threads, so it must
    /// give the same answer for the same context. It reads every member's context every
    /// frame; without it, a frame reads only the schedules and the members due.
    pub fn set_level_of_detail(&mut self, hook: impl Fn(&C) -> u32 + Send + Sync + 'static) {
        self.lod = Some(Box::new(hook));
    }

    /// Removes the level-of-detail hook: members keep the intervals it last chose.
    pub fn clear_level_of_detail(&mut self) {
        self.lod = None;
    }

    /// Caps each frame's ticks at `visits` node visits (see [the budget](self#budget));
    /// `None` ticks every due member. Members owed when the cap is lifted are ticked in the
    /// next frame.
    pub fn set_budget(&mut self, visits: Option<u64>) {
        self.budget = visits;
    }

    /// The cap on each frame's node visits.
    pub fn budget(&self) -> Option<u64> {
        self.budget
    }

    /// Chooses how each due member is ticked (one pass by default).
    pub fn set_tick_mode(&mut self, mode: TickMode) {
        self.mode = mode;
    }

    /// How each due member is ticked.
    pub fn tick_mode(&self) -> TickMode {
        self.mode
    }

    /// How far behind the budget has left the crowd.
    pub fn behind(&self) -> Behind {
        let frames = self
            .backlog
            .front()
            .map_or(0, |&slot| self.plans[slot as usize].owed_for(self.frames));
        Behind {
            overdue: self.backlog.len() as u64,
            frames,
        }
    }

    /// Runs one frame: ticks the members due in it, in parallel, and reports.
    pub fn frame(&mut self) -> FrameReport {
        self.frame_after(|_: &mut Self, _: bool| {})
    }

    /// Runs one frame after `first` (given whether the frame runs on the caller's thread),
    /// on the frame's threads.
    fn frame_after(&mut self, first: impl FnOnce(&mut Self, bool) + Send) -> FrameReport {
        let frame = self.frames;
        let budget = self.budget;
        let inline = self.runs_inline();
        let run = move |crowd: &mut Self| {
            first(crowd, inline);
            crowd.start_sleep_frame(inline);
            crowd.choose_intervals(inline);
            match budget {
                Some(budget) => (crowd.asleep() as u64, crowd.run_budgeted(frame, budget)),
                None => {
                    // The count of awake members that shares the frame out, made before any
                    // tick, says who sleeps through it without another pass over the bits.
                    let (awake, tally) = crowd.run_all(frame, inline);
                    (crowd.len.saturating_sub(awake) as u64, tally)
                }
            }
        };
        let (asleep, tally) = if inline { run(self) } else { self.in_pool(run) };
        self.frames += 1;
        FrameReport {
            frame,
            due: tally.due,
            asleep,
            ticked: tally.ticked,
            visits: tally.visits,
            failures: tally.failures,
            errors: tally.errors,
            awake: tally.awake,
            behind: self.behind(),
        }
    }

    /// A frame runs on the caller's thread, without the pool: the crowd's own pool has one
    /// thread ([`with_threads`](Self::with_threads)) and there is no budget. Handing a
    /// frame to a pool's one worker and waiting for it costs as much as waking that
    /// worker, tens of microseconds, which is the whole of a frame of a crowd that mostly
    /// sleeps; on the caller's thread the frame ticks the same members in the same order.
    pub(super) fn runs_inline(&self) -> bool {
        self.on_caller && self.budget.is_none()
    }

    /// Runs `f` on the crowd's threads: in its own pool if it has one.
    fn in_pool<R: Send>(&mut self, f: impl FnOnce(&mut Self) -> R + Send) -> R {
        match self.pool.clone() {
            Some(pool) => pool.install(|| f(self)),
            None => f(self),
        }
    }

    /// Has the level-of-detail hook, if any, choose every member's interval from its
    /// context, sleeping members' too (the hook reads every context anyway).
    fn choose_intervals(&mut self, inline: bool) {
        let Some(lod) = self.lod.as_deref() else {
            return;
        };
        if inline {
            for (plan, ctx) in self.plans.iter_mut().zip(&self.contexts) {
                plan.choose_interval(ctx.as_ref(), Some(lod));
            }
            return;
        }
        self.plans
            .par_iter_mut()
            // `_mut` though only read: contexts need not be `Sync`.
            .zip(self.contexts.par_iter_mut())
            .with_min_len(1024)
            .for_each(|(plan, ctx)| plan.choose_interval(ctx.as_ref(), Some(lod)));
    }
}

impl<C> core::fmt::Debug for Crowd<C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Crowd")
            .field("members", &self.len)
            .field("frames", &self.frames)
            .field("budget", &self.budget)
            .field("overdue", &self.backlog.len())
            .finish_non_exhaustive()
    }
}
