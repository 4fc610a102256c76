//! What `run --studio` keeps of each tick beside the tree's state, so that a page can go
//! back to a tick and fork the run there: the clock and the counts of the summary.

use super::*;
use neurotree::Clock;

/// The run around the tree: its manual clock and its record of ticks and halts.
pub(super) struct RunWorld {
    pub(super) clock: ManualClock,
    pub(super) record: Arc<Mutex<Record>>,
}

/// The clock and the counts after one tick.
#[cfg_attr(not(feature = "studio"), allow(dead_code))]
pub(super) struct SavedCounts {
    clock: Duration,
    tick: u32,
    ticks: Vec<u32>,
    halts: Vec<u32>,
}

#[cfg_attr(not(feature = "studio"), allow(dead_code))]
impl RunWorld {
    pub(super) fn save(&self) -> SavedCounts {
        let r = self.record.lock().unwrap_or_else(|e| e.into_inner());
        SavedCounts {
            clock: self.clock.now(),
            tick: r.tick,
            ticks: r.ticks.clone(),
            halts: r.halts.clone(),
        }
    }

    pub(super) fn restore(&mut self, saved: &SavedCounts) {
        self.clock.set(saved.clock);
        let mut r = self.record.lock().unwrap_or_else(|e| e.into_inner());
        r.tick = saved.tick;
        r.ticks.clone_from(&saved.ticks);
        r.halts.clone_from(&saved.halts);
        r.trace.clear();
        r.reason = None;
    }
}

#[cfg(feature = "studio")]
impl neurotree_studio::World<()> for RunWorld {
    type Saved = SavedCounts;

    fn save(&self, _: &Tree<()>) -> Result<SavedCounts, String> {
        Ok(RunWorld::save(self))
    }

    fn restore(&mut self, saved: &SavedCounts) {
        RunWorld::restore(self, saved);
    }
}
