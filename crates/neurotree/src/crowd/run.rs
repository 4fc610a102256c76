//! A frame without a budget: every awake member due is ticked, the threads sharing the
//! awake members out by [`Span`]s, so that members that bunch in a few slots are shared as
//! evenly as members spread over the crowd.

use neurotree_core::hint::prefetch;

use super::member::Tally;
use super::schedule::CHUNK;
use super::sleep::{self, Ahead, BITS};
use super::span::{self, Bits, Span};
use super::{Crowd, TickMode};

impl<C: Send> Crowd<C> {
    /// Ticks every awake member due in `frame`, and every member owed from earlier frames;
    /// sleeping members are not visited. With `inline`, on the caller's thread alone.
    /// Returns the members awake before the frame's ticks, beside the tally.
    pub(super) fn run_all(&mut self, frame: u64, inline: bool) -> (usize, Tally) {
        self.backlog.clear();
        let mode = self.mode;
        let Self {
            plans,
            bodies,
            contexts,
            awake,
            timers,
            work,
            ..
        } = self;
        span::count_awake(&mut awake.bits[..plans.len().div_ceil(BITS)], work);
        let before = work.last().map_or(0, |&n| n as usize);
        let bits = Bits {
            awake: &mut awake.bits,
            fallen: &mut timers.fallen,
        };
        let whole = Span::whole(plans, bodies, contexts, Some(bits), work);
        let tally = if inline {
            tick_span(whole, frame, mode)
        } else {
            whole.fold_leaves(&|span| tick_span(span, frame, mode), &Tally::add)
        };
        (before, tally)
    }
}

/// Ticks the awake members of `span` due in `frame`, in slot order.
fn tick_span<C: Send>(span: Span<'_, C>, frame: u64, mode: TickMode) -> Tally {
    let mut tally = Tally::default();
    let Some(bits) = span.bits else {
        return tally;
    };
    let pieces = span
        .plans
        .chunks_mut(CHUNK)
        .zip(span.bodies.chunks_mut(CHUNK))
        .zip(span.contexts.chunks_mut(CHUNK))
        .zip(bits.awake.chunks_mut(CHUNK / BITS))
        .zip(bits.fallen.chunks_mut(CHUNK / BITS));
    // Written before read: cleared once per span, not per chunk.
    let mut slots = [0u16; CHUNK];
    for ((((plans, bodies), contexts), words), fallen) in pieces {
        sleep::for_each_awake_ahead(words, &mut slots, |i, step| {
            match step {
                Ahead::Far => {
                    prefetch(&plans[i]);
                    prefetch(&bodies[i]);
                    prefetch(&contexts[i]);
                    return true;
                }
                Ahead::Near => {
                    if let Some(body) = &bodies[i] {
                        body.tree.prefetch_state();
                    }
                    return true;
                }
                Ahead::Tick => {}
            }
            let plan = &mut plans[i];
            if !plan.present() {
                return false;
            }
            let due = plan.plan(frame) || plan.is_owed();
            // The body is touched only when due.
            let (true, Some(body), Some(ctx)) = (due, &mut bodies[i], &mut contexts[i]) else {
                return true;
            };
            tally.due += 1;
            plan.tick(body, ctx, mode, &mut tally);
            sleep::stays_awake(plan, i, fallen)
        });
    }
    tally
}
