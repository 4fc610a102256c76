//! A log of what a navigator did, written by its leaves and observers and read by a view.

use std::sync::{Arc, Mutex, MutexGuard};

/// Lines of what happened, in order, written by a navigator's leaves (the simulator's
/// `Nav2Sim::with_log`), by a [`RecoveryCounter`](crate::RecoveryCounter)
/// ([`with_log`](crate::RecoveryCounter::with_log)) and by whatever else reports, and read by
/// a view. Clones share the lines.
#[derive(Clone, Debug, Default)]
pub struct EventLog {
    lines: Arc<Mutex<Vec<String>>>,
}

impl EventLog {
    /// An empty log.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a line.
    pub fn push(&self, line: String) {
        self.lock().push(line);
    }

    /// The lines written since the last call.
    pub fn take(&self) -> Vec<String> {
        std::mem::take(&mut *self.lock())
    }

    fn lock(&self) -> MutexGuard<'_, Vec<String>> {
        // Whole lines only: still readable if a writer panicked.
        self.lines.lock().unwrap_or_else(|e| e.into_inner())
    }
}
