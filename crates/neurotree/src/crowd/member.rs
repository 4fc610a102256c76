//! One member of a crowd: its tree, its context, and its place in the schedule.

use crate::{Status, TickError, Tree};

/// `owed_since` of a member that is owed no tick.
pub(super) const NOT_OWED: u64 = u64::MAX;

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

/// A tree ticked with its own context, as one member of a [`Crowd`](super::Crowd).
pub struct Member<C> {
    pub(super) tree: Tree<C>,
    pub(super) ctx: C,
    pub(super) id: MemberId,
    pub(super) interval: u32,
    pub(super) phase: u32,
    /// The frame since which the member is owed a tick the budget held back, or [`NOT_OWED`].
    pub(super) owed_since: u64,
    /// Visits its next tick is expected to cost: what its last one cost.
    pub(super) cost: u32,
    /// Picked by the budget for this frame's tick.
    pub(super) picked: bool,
    pub(super) status: FrameStatus,
    /// Boxed: errors are rare, and most members should not pay their size.
    pub(super) error: Option<Box<TickError>>,
}

impl<C> Member<C> {
    pub(super) fn new(tree: Tree<C>, ctx: C, id: MemberId, interval: u32, phase: u32) -> Self {
        let cost = nodes(&tree);
        Self {
            tree,
            ctx,
            id,
            interval: interval.max(1),
            phase,
            owed_since: NOT_OWED,
            cost,
            picked: false,
            status: FrameStatus::NotDue,
            error: None,
        }
    }

    /// Its id in the crowd.
    pub fn id(&self) -> MemberId {
        self.id
    }

    /// Its tree, for its blackboard, its stored statuses or [`Tree::last_failure`].
    pub fn tree(&self) -> &Tree<C> {
        &self.tree
    }

    /// Its tree, to seed its blackboard or attach an observer between frames.
    pub fn tree_mut(&mut self) -> &mut Tree<C> {
        &mut self.tree
    }

    /// Its context.
    pub fn context(&self) -> &C {
        &self.ctx
    }

    /// Its context, to change between frames.
    pub fn context_mut(&mut self) -> &mut C {
        &mut self.ctx
    }

    /// What it did in the last frame.
    pub fn status(&self) -> FrameStatus {
        self.status
    }

    /// The error its last tick ended with, kept until its next tick.
    pub fn error(&self) -> Option<&TickError> {
        self.error.as_deref()
    }

    /// It is due every `interval`-th frame (1: every frame).
    pub fn interval(&self) -> u32 {
        self.interval
    }

    /// Sets its interval (at least 1); a level-of-detail hook overrides it every frame.
    pub fn set_interval(&mut self, interval: u32) {
        self.interval = interval.max(1);
    }

    /// Its phase: it is due in the frames `f` where `(f + phase) % interval == 0`, so that
    /// members of one interval with different phases spread over the frames.
    pub fn phase(&self) -> u32 {
        self.phase
    }

    /// Sets its phase.
    pub fn set_phase(&mut self, phase: u32) {
        self.phase = phase;
    }

    /// `true` while it waits for a tick the budget held back.
    pub fn is_owed(&self) -> bool {
        self.owed_since != NOT_OWED
    }

    /// Whether its interval makes it due in `frame`, after the level-of-detail hook, if
    /// any, chose the interval from its context.
    #[inline]
    pub(super) fn plan(&mut self, frame: u64, lod: Option<&super::Lod<C>>) -> bool {
        if let Some(lod) = lod {
            self.interval = lod(&self.ctx).max(1);
        }
        self.picked = false;
        self.status = FrameStatus::NotDue;
        (frame + u64::from(self.phase)) % u64::from(self.interval) == 0
    }

    /// Ticks it and returns the visits charged: the blueprint's nodes for each pass of the
    /// root (the most a pass can visit).
    #[inline]
    pub(super) fn tick(&mut self, mode: TickMode) -> Tally {
        let result = match mode {
            TickMode::ExactlyOnce => self.tree.tick_exactly_once(&mut self.ctx),
            TickMode::Once => self.tree.tick_once(&mut self.ctx),
        };
        let passes = match mode {
            TickMode::ExactlyOnce => 1,
            TickMode::Once => self.tree.last_passes().max(1),
        };
        let visits = nodes(&self.tree).saturating_mul(passes);
        self.cost = visits;
        self.owed_since = NOT_OWED;
        self.picked = false;
        let mut tally = Tally {
            ticked: 1,
            visits: u64::from(visits),
            ..Tally::default()
        };
        match result {
            Ok(status) => {
                self.status = FrameStatus::Ticked(status);
                tally.failures = u64::from(status == Status::Failure);
                if self.error.is_some() {
                    self.error = None;
                }
            }
            Err(error) => {
                self.status = FrameStatus::Error;
                self.error = Some(Box::new(error));
                tally.errors = 1;
            }
        }
        tally
    }
}

impl<C> core::fmt::Debug for Member<C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Member")
            .field("id", &self.id)
            .field("interval", &self.interval)
            .field("phase", &self.phase)
            .field("status", &self.status)
            .finish_non_exhaustive()
    }
}

/// The nodes of a tree's blueprint, as visits.
fn nodes<C>(tree: &Tree<C>) -> u32 {
    u32::try_from(tree.blueprint().len()).unwrap_or(u32::MAX)
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
}

impl Tally {
    pub(super) fn add(self, o: Tally) -> Tally {
        Tally {
            due: self.due + o.due,
            ticked: self.ticked + o.ticked,
            visits: self.visits + o.visits,
            failures: self.failures + o.failures,
            errors: self.errors + o.errors,
        }
    }
}
