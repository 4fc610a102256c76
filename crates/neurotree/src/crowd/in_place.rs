//! A frame ticked member by member by the caller, in the order of the caller's own data.
//!
//! [`Crowd::frame`] walks the members in slot order; a game engine whose agents' data sits
//! in its own tables (Bevy's archetypes) would then copy every context in before the frame
//! and out after it, reaching each agent's data by its id, three passes over memory. An
//! [`InPlaceFrame`] lets the engine walk its own tables instead, on its own threads, and
//! for each agent fill the context, tick the member and read the context back in one
//! visit, while the agent's data is in the cache.
//!
//! The members' tables are split into parts of [`PART`] slots, each behind a lock that a
//! [`Visitor`] takes when it first visits a member of the part and keeps until it visits a
//! member of another: walked in (about) slot order, a thread takes a lock per
//! [`PART`] members, and two threads meet only at the edges of their shares.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

use super::member::{Body, FrameStatus, Plan, Tally, TickMode};
use super::sleep::{stays_awake, Awake, BITS};
use super::{Crowd, FrameReport, Lod, MemberId};

/// Slots behind one lock of an [`InPlaceFrame`].
pub const PART: usize = 1024;

/// A frame of a [`Crowd`] whose members the caller visits one by one
/// ([`Crowd::frame_in_place`]), from any number of threads, in any order.
///
/// Each member is visited at most once per frame; a member not visited is not ticked (its
/// status is [`FrameStatus::NotDue`], or [`FrameStatus::Deferred`] while a budget's deferred
/// tick is still owed to it). The frame ends with [`finish`](Self::finish), which
/// reports as [`Crowd::frame`] does. Since a member's tick touches only its tree and its
/// context, the results do not depend on the order of the visits nor on the threads.
pub struct InPlaceFrame<'c, C> {
    frame: u64,
    mode: TickMode,
    lod: Option<&'c Lod<C>>,
    parts: Vec<Mutex<Part<'c, C>>>,
    frames: &'c mut u64,
    len: usize,
    /// The queue of members a budget owes a tick, when it holds any: those the caller does
    /// not visit are still owed one after the frame. A frame dropped unfinished leaves the
    /// queue as it was, naming members it ticked, which the next budget's pick passes over.
    backlog: Option<&'c mut VecDeque<u32>>,
    /// Members asleep through the frame.
    asleep: u64,
}

/// One lock's share of the crowd's tables.
struct Part<'c, C> {
    plans: &'c mut [Plan],
    bodies: &'c mut [Option<Body<C>>],
    contexts: &'c mut [Option<C>],
    /// The part's words of the awake set.
    words: &'c [AtomicU64],
    /// A bit per slot of its members that fell asleep in this frame.
    fallen: &'c mut [u64],
    /// A bit per slot of its members visited in this frame: a member is ticked once.
    seen: &'c mut [u64],
    tally: Tally,
    visited: u64,
}

/// Visits members of an [`InPlaceFrame`] on one thread, holding the lock of the part it
/// visited last.
pub struct Visitor<'f, 'c, C> {
    frame: &'f InPlaceFrame<'c, C>,
    held: Option<(usize, MutexGuard<'f, Part<'c, C>>)>,
}

/// What a visit did.
#[derive(Debug)]
pub enum Visit<'v, C> {
    /// The member was not due in this frame, or sleeps (its status is then
    /// [`FrameStatus::Asleep`]), or `id` names no member: not ticked.
    NotDue,
    /// The member was ticked: its context after the tick, and what the tick returned
    /// ([`FrameStatus::Ticked`] or [`FrameStatus::Error`]).
    Ticked(&'v C, FrameStatus),
}

impl<C: Send> Crowd<C> {
    /// Opens a frame whose members the caller visits one by one, in the order of its own
    /// data ([`InPlaceFrame`]); `None` when a budget is set, since the budget picks members
    /// oldest first over the whole crowd before any is ticked: use [`frame`](Self::frame).
    ///
    /// Members owed a tick from frames under a budget are due, as in [`frame`](Self::frame)
    /// without one; those the caller does not visit stay owed, first in line at the next
    /// frame under a budget.
    pub fn frame_in_place(&mut self) -> Option<InPlaceFrame<'_, C>> {
        if self.budget.is_some() {
            return None;
        }
        if self.runs_inline() {
            self.start_sleep_frame(true);
        } else {
            self.in_pool(|crowd| crowd.start_sleep_frame(false));
        }
        let asleep = self.asleep() as u64;
        let Self {
            plans,
            bodies,
            contexts,
            lod,
            mode,
            frames,
            len,
            awake,
            timers,
            seen,
            backlog,
            ..
        } = self;
        // No member seen yet in this frame: a bit per slot, cleared a word per 64 members.
        seen.clear();
        seen.resize(awake.bits.len(), 0);
        let parts = plans
            .chunks_mut(PART)
            .zip(bodies.chunks_mut(PART))
            .zip(contexts.chunks_mut(PART))
            .zip(awake.bits.chunks(PART / BITS))
            .zip(timers.fallen.chunks_mut(PART / BITS))
            .zip(seen.chunks_mut(PART / BITS))
            .map(|(((((plans, bodies), contexts), words), fallen), seen)| {
                Mutex::new(Part {
                    plans,
                    bodies,
                    contexts,
                    words,
                    fallen,
                    seen,
                    tally: Tally::default(),
                    visited: 0,
                })
            })
            .collect();
        Some(InPlaceFrame {
            frame: *frames,
            mode: *mode,
            lod: lod.as_deref(),
            parts,
            frames,
            len: *len,
            backlog: (!backlog.is_empty()).then_some(backlog),
            asleep,
        })
    }
}

impl<'c, C> InPlaceFrame<'c, C> {
    /// A visitor for one thread (or one batch of a parallel walk).
    pub fn visitor(&self) -> Visitor<'_, 'c, C> {
        Visitor {
            frame: self,
            held: None,
        }
    }

    /// The frame's number.
    pub fn number(&self) -> u64 {
        self.frame
    }

    /// Members in the crowd.
    pub fn members(&self) -> usize {
        self.len
    }

    /// Members awake in this frame: those a visit may tick. The others sleep through it,
    /// and need not be visited.
    pub fn awake(&self) -> usize {
        self.len - self.asleep as usize
    }

    /// Puts the ids of the members awake in this frame in `out` (emptied first), in slot
    /// order: a caller whose crowd mostly sleeps visits these alone, reaching their data by
    /// id, rather than walking its whole table. Reads a word per 64 slots.
    pub fn awake_members(&self, out: &mut Vec<MemberId>) {
        out.clear();
        for (p, part) in self.parts.iter().enumerate() {
            let part = part.lock().unwrap_or_else(PoisonError::into_inner);
            for (w, word) in part.words.iter().enumerate() {
                let mut left = word.load(Ordering::Relaxed);
                while left != 0 {
                    let i = w * BITS + left.trailing_zeros() as usize;
                    left &= left - 1;
                    let plan = &part.plans[i];
                    if plan.present() {
                        out.push(MemberId {
                            index: (p * PART + i) as u32,
                            generation: plan.generation,
                        });
                    }
                }
            }
        }
    }

    /// Ends the frame: members not visited are marked not due (deferred, if still owed a
    /// tick), and the frame is reported.
    pub fn finish(self) -> FrameReport {
        let mut tally = Tally::default();
        let mut visited = 0;
        let mut parts = Vec::new();
        for part in self.parts {
            let part = part.into_inner().unwrap_or_else(PoisonError::into_inner);
            tally = tally.add(part.tally);
            visited += part.visited;
            parts.push((part.plans, part.words, part.seen));
        }
        // Awake members not visited were not due, or stay owed the tick a budget deferred
        // (and are deferred again); sleeping ones keep their status.
        if visited < self.len as u64 {
            for (plans, words, seen) in &mut parts {
                for (w, word) in words.iter().enumerate() {
                    let mut left = word.load(Ordering::Relaxed) & !seen[w];
                    while left != 0 {
                        let plan = &mut plans[w * BITS + left.trailing_zeros() as usize];
                        left &= left - 1;
                        if plan.present() {
                            plan.status = if plan.is_owed() {
                                FrameStatus::Deferred
                            } else {
                                FrameStatus::NotDue
                            };
                        }
                    }
                }
            }
        }
        *self.frames += 1;
        // A member a budget owed a tick is ticked when visited; those not visited stay
        // owed, in the order they fell due, for the next frame under a budget.
        let mut behind = super::Behind::default();
        if let Some(backlog) = self.backlog {
            let plan = |slot: u32| &parts[slot as usize / PART].0[slot as usize % PART];
            backlog.retain(|&slot| plan(slot).is_owed());
            behind = super::Behind {
                overdue: backlog.len() as u64,
                frames: backlog
                    .front()
                    .map_or(0, |&slot| plan(slot).owed_for(*self.frames)),
            };
        }
        FrameReport {
            frame: self.frame,
            due: tally.due,
            asleep: self.asleep,
            ticked: tally.ticked,
            visits: tally.visits,
            failures: tally.failures,
            errors: tally.errors,
            awake: tally.awake,
            behind,
        }
    }
}

impl<'f, 'c, C> Visitor<'f, 'c, C> {
    /// Visits member `id`: if it is due, `load` fills its context from the caller's data,
    /// and the member is ticked; with a level-of-detail hook, `load` runs first, for every
    /// member, since the hook reads the context. Store what the tree changed from the
    /// context [`Visit::Ticked`] gives back.
    pub fn visit(&mut self, id: MemberId, load: impl FnOnce(&mut C)) -> Visit<'_, C> {
        let slot = id.index as usize;
        let index = slot / PART;
        if !matches!(&self.held, Some((i, _)) if *i == index) {
            let Some(part) = self.frame.parts.get(index) else {
                return Visit::NotDue;
            };
            // Drop the old guard before waiting for the new one, so that no thread waits
            // while holding a lock.
            self.held = None;
            let guard = part.lock().unwrap_or_else(PoisonError::into_inner);
            self.held = Some((index, guard));
        }
        let Some((_, part)) = &mut self.held else {
            return Visit::NotDue;
        };
        let part = &mut **part;
        let i = slot % PART;
        let frame = self.frame.frame;
        let plan = &mut part.plans[i];
        let bit = 1u64 << (i % BITS);
        if !plan.present() || plan.generation != id.generation || part.seen[i / BITS] & bit != 0 {
            return Visit::NotDue;
        }
        part.seen[i / BITS] |= bit;
        part.visited += 1;
        let (Some(body), Some(ctx)) = (&mut part.bodies[i], &mut part.contexts[i]) else {
            return Visit::NotDue;
        };
        let lod = self.frame.lod;
        // Without a hook, the schedule alone says whether the member is due, and a member
        // not due is left alone: its context is not even filled.
        let mut load = Some(load);
        if lod.is_some() {
            if let Some(load) = load.take() {
                load(ctx);
            }
            plan.choose_interval(Some(&*ctx), lod);
        }
        if plan.sleeps_through() {
            return Visit::NotDue;
        }
        let due = plan.plan(frame) || plan.is_owed();
        if !due {
            return Visit::NotDue;
        }
        if let Some(load) = load {
            load(ctx);
        }
        part.tally.due += 1;
        plan.tick(body, ctx, self.frame.mode, &mut part.tally);
        if !stays_awake(plan, i, part.fallen) {
            Awake::clear_in(part.words, i);
        }
        Visit::Ticked(ctx, plan.status)
    }
}

impl<C> core::fmt::Debug for InPlaceFrame<'_, C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("InPlaceFrame")
            .field("frame", &self.frame)
            .field("members", &self.len)
            .finish_non_exhaustive()
    }
}

impl<C> core::fmt::Debug for Visitor<'_, '_, C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Visitor")
            .field("part", &self.held.as_ref().map(|(i, _)| *i))
            .finish()
    }
}
