//! A frame under a budget: who is due, who goes first, who waits.
//!
//! The budget is counted in node visits, so the same inputs pick the same members on any
//! machine and with any number of threads. A tick is charged the blueprint's nodes for each
//! pass of the root, the most a pass can visit: the engine counts no visits without an
//! observer (its fast loops do not even store most statuses), and an observer on every
//! member would cost more than the ticks it watches. Before a frame a member is expected to
//! cost what its last tick cost.
//!
//! The frame runs in three steps: a parallel pass marks who is due and sums their expected
//! cost per chunk of slots; a sequential pass picks, oldest first, what fits (members owed
//! from earlier frames in the order they fell due, then this frame's in slot order) and
//! queues the rest; a second parallel pass ticks the picked members. A chunk whose due
//! members all fit is picked whole, so the sequential pass walks chunks, not members, until
//! the budget runs out.

use rayon::prelude::*;

use super::member::{FrameStatus, Tally};
use super::sleep::{for_each_awake, stays_awake, BITS};
use super::Crowd;

/// Slots per chunk: large enough that the sequential pass is short next to the ticks,
/// small enough that the threads share the work evenly.
pub(super) const CHUNK: usize = 1024;

/// What the first pass learnt of one chunk of slots, and what the second is to tick.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Chunk {
    /// Expected visits of the members that fell due this frame.
    cost: u64,
    /// Members that fell due this frame.
    fresh: u32,
    /// Every member that fell due this frame fits: tick them all.
    all: bool,
    /// Members owed from earlier frames picked in this one.
    owed: bool,
}

impl<C: Send> Crowd<C> {
    /// Runs frame `frame` within `budget` visits; sleeping members are not visited.
    pub(super) fn run_budgeted(&mut self, frame: u64, budget: u64) -> Tally {
        let chunks = self.plans.len().div_ceil(CHUNK);
        if self.chunks.len() != chunks {
            self.chunks.resize(chunks, Chunk::default());
        }
        self.plans
            .par_chunks_mut(CHUNK)
            .zip(self.awake.bits.par_chunks_mut(CHUNK / BITS))
            .zip(self.chunks.par_iter_mut())
            .for_each(|((plans, words), chunk)| {
                *chunk = Chunk::default();
                for_each_awake(words, |i| {
                    let plan = &mut plans[i];
                    if !plan.present() {
                        return false;
                    }
                    let due = plan.plan(frame);
                    if plan.is_owed() {
                        plan.status = FrameStatus::Deferred;
                    } else if due {
                        plan.owe(frame);
                        chunk.cost += u64::from(plan.cost);
                        chunk.fresh += 1;
                    }
                    true
                });
            });
        let fresh: u64 = self.chunks.iter().map(|c| u64::from(c.fresh)).sum();
        let due = self.backlog.len() as u64 + fresh;
        self.pick(frame, budget);
        let mode = self.mode;
        let tally = self
            .plans
            .par_chunks_mut(CHUNK)
            .zip(self.bodies.par_chunks_mut(CHUNK))
            .zip(self.contexts.par_chunks_mut(CHUNK))
            .zip(self.awake.bits.par_chunks_mut(CHUNK / BITS))
            .zip(self.chunks.par_iter())
            .zip(self.timers.fallen.par_chunks_mut(CHUNK / BITS))
            // One chunk per job: awake members bunch (those alerted together), and only
            // jobs this small let the threads share a bunch.
            .with_max_len(1)
            .map(|(((((plans, bodies), contexts), words), chunk), fallen)| {
                let mut tally = Tally::default();
                if chunk.fresh == 0 && !chunk.owed {
                    return tally;
                }
                for_each_awake(words, |i| {
                    let plan = &mut plans[i];
                    let go = plan.picked() || (chunk.all && plan.owed_since_frame(frame));
                    // The body is touched only when picked.
                    let (true, Some(body), Some(ctx)) = (go, &mut bodies[i], &mut contexts[i])
                    else {
                        return true;
                    };
                    plan.tick(body, ctx, mode, &mut tally);
                    stays_awake(plan, i, fallen)
                });
                tally
            })
            .reduce(Tally::default, Tally::add);
        Tally { due, ..tally }
    }

    /// Picks what fits in `budget`, oldest first, and queues the rest. At least one member
    /// is ticked in a frame with any due, so a member that costs more than the whole
    /// budget is not held back for ever.
    fn pick(&mut self, frame: u64, budget: u64) {
        let mut left = budget;
        let mut any = false;
        let Self {
            plans,
            backlog,
            chunks,
            ..
        } = self;
        while let Some(&slot) = backlog.front() {
            let plan = &mut plans[slot as usize];
            // A slot named by a frame in place dropped unfinished (see `InPlaceFrame`): its
            // member was ticked, or left, or fell due afresh in this frame, or comes up a
            // second time. Only a member owed since an earlier frame is the queue's.
            if !plan.present() || !plan.is_owed() || plan.owed_since_frame(frame) || plan.picked() {
                backlog.pop_front();
                continue;
            }
            let cost = u64::from(plan.cost);
            if cost > left && any {
                break;
            }
            left = left.saturating_sub(cost);
            any = true;
            plan.pick();
            chunks[slot as usize / CHUNK].owed = true;
            backlog.pop_front();
        }
        // Once a member does not fit, every later one waits: the queue stays in the order
        // members fell due.
        let mut open = backlog.is_empty();
        for (c, chunk) in chunks.iter_mut().enumerate() {
            if chunk.fresh == 0 {
                continue;
            }
            if open && chunk.cost <= left {
                chunk.all = true;
                left -= chunk.cost;
                any = true;
                continue;
            }
            let start = c * CHUNK;
            let end = (start + CHUNK).min(plans.len());
            for (i, plan) in plans[start..end].iter_mut().enumerate() {
                if !plan.present() || !plan.owed_since_frame(frame) {
                    continue;
                }
                let cost = u64::from(plan.cost);
                if open && (cost <= left || !any) {
                    left = left.saturating_sub(cost);
                    any = true;
                    plan.pick();
                } else {
                    open = false;
                    plan.status = FrameStatus::Deferred;
                    backlog.push_back((start + i) as u32);
                }
            }
        }
    }
}
