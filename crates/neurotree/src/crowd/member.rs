//! One member of a crowd: its tree and context, and apart from them its schedule.
//!
//! The schedule of every member sits in one compact table ([`Plan`]), so that deciding who
//! is due reads a few bytes per member and leaves the trees of members not due untouched:
//! a frame in which one member in eight is due then costs little more than their ticks.

use std::sync::Arc;

use crate::{Clock, Status, TickError, Tree};

/// Names a member of a [`Crowd`](super::Crowd) for as long as it stays in it: the id of a
/// removed member never names the member that takes its place.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MemberId {
    pub(super) index: u32,
    pub(super) generation: u32,
}

impl MemberId {
    /// The member's slot: ids of members present at the same time have different slots,
    /// so a program can index its own per-member tables with it.
    pub fn slot(self) -> usize {
        self.index as usize
    }
}

/// What a member did in the last frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FrameStatus {
    /// Its interval skipped it (or the crowd has run no frame since it joined).
    NotDue,
    /// It was due, but the frame's budget left it for a later frame.
    Deferred,
    /// It was ticked, and its root returned this.
    Ticked(Status),
    /// It was ticked, and the tick ended with an error: [`Member::error`] says which.
    Error,
    /// Its tree [sleeps](crate::tree::sleep) and nothing it waits on happened: it was not
    /// ticked, nor visited. A member is Asleep from the frame after the tick that put it to
    /// sleep until its next tick, whether or not its interval came round.
    Asleep,
}

/// How a crowd ticks each due member.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TickMode {
    /// One pass of the root ([`Tree::tick_exactly_once`]), as a game loop gives each agent
    /// one tick per frame: a node that yields waits for the next frame.
    #[default]
    ExactlyOnce,
    /// [`Tree::tick_once`]: passes are repeated at once while a node asks to be woken.
    Once,
}

/// What a member owns besides its context: its tree, which also keeps the error of its
/// last tick ([`Tree::last_error`]), so that a member pays nothing for errors it never had.
pub(super) struct Body<C> {
    pub(super) tree: Tree<C>,
}

/// A slot's schedule, in 32 bytes: two to a cache line, as a frame reads the schedule of
/// every awake member.
#[derive(Clone, Copy, Debug)]
pub(super) struct Plan {
    /// When its sleeping tree wakes, in clock nanoseconds; [`AWAKE`](super::sleep::AWAKE)
    /// while it is awake, `u64::MAX` while it waits only for a wake (see [`super::sleep`]).
    pub(super) sleeps_until: u64,
    pub(super) interval: u32,
    pub(super) phase: u32,
    /// Visits its next tick is expected to cost: what its last one cost.
    pub(super) cost: u32,
    /// Tells the ids of the slot's successive members apart.
    pub(super) generation: u32,
    /// While [`OWED`] is set, the frame since which the member is owed a tick the budget
    /// held back, its low 32 bits: a member owed for fewer than 2^32 frames (two years at
    /// 60 frames a second) is told apart exactly, and the schedule keeps 4 bytes.
    owed_since: u32,
    pub(super) status: FrameStatus,
    /// [`PRESENT`], [`PICKED`] and [`OWED`].
    flags: u8,
}

// Two schedules to a cache line.
const _: () = assert!(std::mem::size_of::<Plan>() == 32);

/// The slot holds a member.
const PRESENT: u8 = 1;
/// Picked by the budget for this frame's tick.
const PICKED: u8 = 2;
/// Owed a tick the budget held back.
const OWED: u8 = 4;
/// Its tree had a halt handle when it last fell asleep: the crowd watches the tree's wake
/// signal while it sleeps. Kept here so that the frame after, which marks the member
/// asleep, need not read the tree, elsewhere in memory.
const HALT_HANDLE: u8 = 8;

impl Plan {
    pub(super) fn new(generation: u32) -> Self {
        Self {
            sleeps_until: super::sleep::AWAKE,
            interval: 1,
            phase: 0,
            cost: 0,
            generation,
            owed_since: 0,
            status: FrameStatus::NotDue,
            flags: 0,
        }
    }

    /// A schedule for a member joining the slot, due as its phase says.
    pub(super) fn joining(generation: u32, phase: u32, cost: u32) -> Self {
        Self {
            phase,
            cost,
            flags: PRESENT,
            ..Self::new(generation)
        }
    }

    /// The slot holds a member.
    #[inline]
    pub(super) fn present(&self) -> bool {
        self.flags & PRESENT != 0
    }

    /// Picked by the budget for this frame's tick.
    #[inline]
    pub(super) fn picked(&self) -> bool {
        self.flags & PICKED != 0
    }

    /// Picks the member for this frame's tick.
    #[inline]
    pub(super) fn pick(&mut self) {
        self.flags |= PICKED;
    }

    /// Owed a tick the budget held back.
    #[inline]
    pub(super) fn is_owed(&self) -> bool {
        self.flags & OWED != 0
    }

    /// Its tree had a halt handle when it fell asleep in its last tick.
    #[inline]
    pub(super) fn fell_asleep_with_halt_handle(&self) -> bool {
        self.flags & HALT_HANDLE != 0
    }

    /// Owed a tick since `frame` exactly: it fell due in `frame`.
    #[inline]
    pub(super) fn owed_since_frame(&self, frame: u64) -> bool {
        self.is_owed() && self.owed_since == frame as u32
    }

    /// Marks the member owed a tick since `frame`.
    #[inline]
    pub(super) fn owe(&mut self, frame: u64) {
        self.flags |= OWED;
        self.owed_since = frame as u32;
    }

    /// Forgets the tick it was owed, and its pick: it is held, and ticks as a fresh member
    /// once released.
    #[inline]
    pub(super) fn forgive(&mut self) {
        self.flags &= !(OWED | PICKED);
    }

    /// Frames it has been owed a tick by `frame` (0 if it is owed none).
    pub(super) fn owed_for(&self, frame: u64) -> u64 {
        if self.is_owed() {
            u64::from((frame as u32).wrapping_sub(self.owed_since))
        } else {
            0
        }
    }

    /// `true` if the member sleeps through this frame; marks it so.
    #[inline]
    pub(super) fn sleeps_through(&mut self) -> bool {
        if self.sleeps_until != super::sleep::AWAKE {
            self.status = FrameStatus::Asleep;
            return true;
        }
        false
    }

    /// Lets the level-of-detail hook, if any, choose the member's interval from its
    /// context.
    #[inline]
    pub(super) fn choose_interval<C>(&mut self, ctx: Option<&C>, lod: Option<&super::Lod<C>>) {
        if let (Some(lod), Some(ctx)) = (lod, ctx) {
            self.interval = lod(ctx).max(1);
        }
    }

    /// Whether the member's interval makes it due in `frame`; forgets the last frame's
    /// status.
    #[inline]
    pub(super) fn plan(&mut self, frame: u64) -> bool {
        self.flags &= !PICKED;
        self.status = FrameStatus::NotDue;
        let at = frame.wrapping_add(u64::from(self.phase));
        let interval = u64::from(self.interval);
        // Powers of two, the usual intervals, without a division.
        if interval.is_power_of_two() {
            at & (interval - 1) == 0
        } else {
            at % interval == 0
        }
    }

    /// Ticks the member and counts it in `tally`, charging it the blueprint's nodes for
    /// each pass of the root (the most a pass can visit). Counted in place: a tally is
    /// 88 bytes, which a tally returned and added copied twice per tick.
    #[inline]
    pub(super) fn tick<C>(
        &mut self,
        body: &mut Body<C>,
        ctx: &mut C,
        mode: TickMode,
        tally: &mut Tally,
    ) {
        let result = match mode {
            TickMode::ExactlyOnce => body.tree.tick_exactly_once(ctx),
            TickMode::Once => body.tree.tick_once(ctx),
        };
        let passes = match mode {
            TickMode::ExactlyOnce => 1,
            TickMode::Once => body.tree.last_passes().max(1),
        };
        let visits = nodes(&body.tree).saturating_mul(passes);
        self.cost = visits;
        self.sleeps_until = super::sleep::sleeps_until(&body.tree);
        self.flags &= !(OWED | PICKED | HALT_HANDLE);
        if self.sleeps_until != super::sleep::AWAKE && body.tree.has_halt_handle() {
            self.flags |= HALT_HANDLE;
        }
        tally.ticked += 1;
        tally.visits += u64::from(visits);
        tally.awake.count(&body.tree);
        match result {
            Ok(status) => {
                self.status = FrameStatus::Ticked(status);
                tally.failures += u64::from(status == Status::Failure);
            }
            // The tree keeps the error until its next tick.
            Err(error) => {
                self.status = FrameStatus::Error;
                tally.errors += 1;
                let_go(error);
            }
        }
    }
}

/// Drops the error a tick returned, which its tree keeps a copy of: out of line, so that
/// the code of a member's tick, run for every awake member, holds no drop of an error.
#[cold]
#[inline(never)]
fn let_go(error: TickError) {
    drop(error);
}

/// The nodes of a tree's blueprint, as visits.
pub(super) fn nodes<C>(tree: &Tree<C>) -> u32 {
    u32::try_from(tree.blueprint().len()).unwrap_or(u32::MAX)
}

/// A member of a [`Crowd`](super::Crowd), to read: its tree, its context, its schedule and
/// what it did in the last frame.
pub struct Member<'a, C> {
    pub(super) id: MemberId,
    pub(super) body: &'a Body<C>,
    pub(super) ctx: &'a C,
    pub(super) plan: &'a Plan,
}

/// A member of a [`Crowd`](super::Crowd), to change between frames.
pub struct MemberMut<'a, C> {
    pub(super) id: MemberId,
    pub(super) body: &'a mut Body<C>,
    pub(super) ctx: &'a mut C,
    pub(super) plan: &'a mut Plan,
    pub(super) awake: &'a super::sleep::Awake,
    /// The crowd's clock, which a tree put in its place is moved onto.
    pub(super) clock: &'a Arc<dyn Clock>,
}

impl<'a, C> MemberMut<'a, C> {
    /// Member `id` in its slot's tables, if it is still the one there.
    #[inline]
    pub(super) fn of(
        id: MemberId,
        plan: &'a mut Plan,
        body: &'a mut Option<Body<C>>,
        ctx: &'a mut Option<C>,
        awake: &'a super::sleep::Awake,
        clock: &'a Arc<dyn Clock>,
    ) -> Option<Self> {
        if plan.generation != id.generation {
            return None;
        }
        Some(Self {
            id,
            body: body.as_mut()?,
            ctx: ctx.as_mut()?,
            plan,
            awake,
            clock,
        })
    }
}

impl<'a, C> Member<'a, C> {
    /// Its id in the crowd.
    pub fn id(&self) -> MemberId {
        self.id
    }

    /// Its tree, for its blackboard, its stored statuses or [`Tree::last_failure`].
    pub fn tree(&self) -> &'a Tree<C> {
        &self.body.tree
    }

    /// Its context.
    pub fn context(&self) -> &'a C {
        self.ctx
    }

    /// What it did in the last frame.
    pub fn status(&self) -> FrameStatus {
        self.plan.status
    }

    /// The error its last tick ended with, kept until its next tick.
    pub fn error(&self) -> Option<&'a TickError> {
        self.body.tree.last_error()
    }

    /// It is due every `interval`-th frame (1: every frame).
    pub fn interval(&self) -> u32 {
        self.plan.interval
    }

    /// Its phase: it is due in the frames `f` where `(f + phase) % interval == 0`, so that
    /// members of one interval with different phases spread over the frames.
    pub fn phase(&self) -> u32 {
        self.plan.phase
    }

    /// `true` while it waits for a tick the budget held back.
    pub fn is_owed(&self) -> bool {
        self.plan.is_owed()
    }
}

impl<C> MemberMut<'_, C> {
    /// Reads it.
    pub fn as_ref(&self) -> Member<'_, C> {
        Member {
            id: self.id,
            body: self.body,
            ctx: self.ctx,
            plan: self.plan,
        }
    }

    /// Its id in the crowd.
    pub fn id(&self) -> MemberId {
        self.id
    }

    /// Its tree, to seed its blackboard or attach an observer between frames. Wakes it,
    /// if it slept (see [`sleep`](crate::tree::sleep)). To put another tree in its place,
    /// use [`replace_tree`](Self::replace_tree), which moves it onto the crowd's clock.
    pub fn tree_mut(&mut self) -> &mut Tree<C> {
        self.wake();
        &mut self.body.tree
    }

    /// Puts `tree` in place of its tree, which is halted (each Running stateful action gets
    /// its `on_halted`) and given back. The new tree is moved onto the crowd's clock, as
    /// [`Crowd::add_tree`](super::Crowd::add_tree) does, and the member is scheduled as a
    /// fresh one: awake, expected to cost one pass. Its last error is now the new tree's
    /// ([`Tree::last_error`]): none for a tree not ticked yet.
    pub fn replace_tree(&mut self, mut tree: Tree<C>) -> Tree<C> {
        self.wake();
        tree.set_shared_clock(Arc::clone(self.clock));
        let mut old = std::mem::replace(&mut self.body.tree, tree);
        old.halt(self.ctx);
        self.plan.cost = nodes(&self.body.tree);
        old
    }

    /// Wakes it: its next due frame ticks it, whatever its tree waits on.
    pub fn wake(&mut self) {
        self.awake.wake(self.plan, self.id.index as usize);
        self.body.tree.wake_up();
    }

    /// `true` while its tree sleeps: frames skip it until it wakes.
    pub fn is_asleep(&self) -> bool {
        self.plan.sleeps_until != super::sleep::AWAKE
    }

    /// Its context, to change between frames.
    pub fn context_mut(&mut self) -> &mut C {
        self.ctx
    }

    /// Its tree and its context together, for what needs both between frames: a
    /// [`Tree::reload`] halts the changed nodes with the member's context.
    pub fn tree_and_context_mut(&mut self) -> (&mut Tree<C>, &mut C) {
        self.wake();
        (&mut self.body.tree, self.ctx)
    }

    /// Sets its interval (at least 1); a level-of-detail hook overrides it every frame.
    pub fn set_interval(&mut self, interval: u32) {
        self.plan.interval = interval.max(1);
    }

    /// Sets its phase (see [`Member::phase`]). In a large crowd with long intervals, phases
    /// by blocks of slots (`slot / 1024`) rather than by slot put the members due together
    /// next to each other in memory: a frame with one member in eight due then costs about
    /// an eighth of a full frame, rather than a fifth.
    pub fn set_phase(&mut self, phase: u32) {
        self.plan.phase = phase;
    }
}

/// Every member's context and last status, to read from many threads at once between
/// frames ([`Crowd::contexts`](super::Crowd::contexts)): a game engine writing what the
/// trees did back into its own data, in parallel.
pub struct Contexts<'a, C> {
    pub(super) plans: &'a [Plan],
    pub(super) contexts: &'a [Option<C>],
}

impl<'a, C> Contexts<'a, C> {
    /// The context of the member `id` names, if it is still in the crowd.
    pub fn get(&self, id: MemberId) -> Option<&'a C> {
        let plan = self.plans.get(id.index as usize)?;
        if plan.generation != id.generation {
            return None;
        }
        self.contexts[id.index as usize].as_ref()
    }

    /// What the member `id` names did in the last frame.
    pub fn status(&self, id: MemberId) -> Option<FrameStatus> {
        let plan = self.plans.get(id.index as usize)?;
        (plan.generation == id.generation && plan.present()).then_some(plan.status)
    }
}

impl<C> Clone for Contexts<'_, C> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<C> Copy for Contexts<'_, C> {}

impl<C> core::fmt::Debug for Contexts<'_, C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Contexts")
            .field("slots", &self.plans.len())
            .finish_non_exhaustive()
    }
}

impl<C> core::fmt::Debug for Member<'_, C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Member")
            .field("id", &self.id)
            .field("interval", &self.plan.interval)
            .field("phase", &self.plan.phase)
            .field("status", &self.plan.status)
            .finish_non_exhaustive()
    }
}

impl<C> core::fmt::Debug for MemberMut<'_, C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        self.as_ref().fmt(f)
    }
}

/// What a part of the frame did, summed over members in any order (so any split over
/// threads gives the same sums).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Tally {
    pub(super) due: u64,
    pub(super) ticked: u64,
    pub(super) visits: u64,
    pub(super) failures: u64,
    pub(super) errors: u64,
    /// Members ticked that stayed awake, by reason.
    pub(super) awake: neurotree_core::AwakeCounts,
}

impl Tally {
    #[inline]
    pub(super) fn add(self, o: Tally) -> Tally {
        Tally {
            due: self.due + o.due,
            ticked: self.ticked + o.ticked,
            visits: self.visits + o.visits,
            failures: self.failures + o.failures,
            errors: self.errors + o.errors,
            awake: self.awake.merged(o.awake),
        }
    }
}
