//! A run that does not wait where a page stops it: a crowd, whose frame the other agents
//! share, holds the agent watched (or skips its frames) instead, and asks between frames
//! whether it is to stand still.

use std::sync::atomic::Ordering;

use super::hub::{Hub, Paused};

impl Hub {
    /// Makes breakpoints stand the run still after the tick that met them, instead of
    /// holding the tick there.
    pub fn defer_breaks(&self) {
        self.defer_breaks.store(true, Ordering::Release);
    }

    /// Between ticks, without waiting: whether the run is to stand still now. A run that
    /// stood still goes on once a page continued or stepped it (or the last page left);
    /// one that goes on stops where [`between_ticks`](Self::between_ticks) would hold it,
    /// or after a tick that met a breakpoint. `standing` is what the last call returned.
    pub fn stands(&self, standing: bool) -> bool {
        if standing {
            let mut inner = self.lock();
            if inner.paused.is_some() && self.pages() > 0 {
                return true;
            }
            // A page's continue or step cleared `paused` already; the pages are told the
            // run goes on now, as a held run tells them when it wakes.
            inner.paused = None;
            inner.paused_version += 1;
            drop(inner);
            self.bump();
            // The tick a step or continue asked for.
            return false;
        }
        let broke = self.lock().broke.take();
        let paused = match (broke, self.stop_reason()) {
            (Some(p), _) if self.pages() > 0 => p,
            (_, Some(why)) => Paused {
                why,
                node: None,
                status: None,
            },
            _ => return false,
        };
        let mut inner = self.lock();
        inner.paused = Some(paused);
        inner.paused_version += 1;
        drop(inner);
        self.bump();
        true
    }

    /// `true` when pages sent edits (or travels) not yet applied.
    pub fn has_requests(&self) -> bool {
        !self.lock().requests.is_empty()
    }
}
