//! Seeing what a tree does: loggers and statistics built on the one [`Observer`](crate::Observer)
//! hook.
//!
//! Each of these is an observer to attach with [`Tree::set_observer`](crate::Tree);
//! to use several at once, attach a tuple `(a, b)` or a `Vec<Box<dyn Observer>>`.
//!
//! | observer | what it gives | for |
//! |---|---|---|
//! | [`ConsoleLogger`] | a line per status change | watching a run |
//! | [`JsonlTrace`] | JSON lines | scripts, diffs between runs |
//! | [`Statistics`] | counts and times per node | finding the busy or failing nodes |
//! | [`Coverage`] | the outcomes seen per node, against those possible | what a test left out |
//! | [`BtlogWriter`] | a `.btlog` file | replay in Groot2 |
//! | `SqliteLogger` (feature `sqlite`) | a SQLite database | querying a run with SQL |
//! | `TracingObserver` (feature `tracing`) | `tracing` events | applications using `tracing` |
//!
//! - [`ConsoleLogger`] prints `[0.100s] root/move IDLE -> RUNNING`, coloured on a terminal.
//! - [`JsonlTrace`] writes one JSON line per status change and per tick.
//! - [`Statistics`] counts ticks, successes, failures, skips, halts and time Running per node.
//! - [`Coverage`] records which [`Outcome`]s (success, failure, running, halted, skipped)
//!   each node was seen with; its [`CoverageReport`] lists the nodes never reached and the
//!   outcomes never seen.
//! - [`BtlogWriter`] writes BehaviorTree.CPP's `.btlog` (FileLogger2) file; [`read_btlog`]
//!   reads it back.
//! - `SqliteLogger` writes BehaviorTree.CPP's SQLite schema.
//! - `TracingObserver` emits `tracing` events, for an application that already collects
//!   `tracing`.
//!
//! They name nodes by their [`path`](crate::Blueprint::path) (`root/patrol/move`) and take
//! their times from the tree's clock, so a run on a [`ManualClock`](crate::ManualClock)
//! logs the same bytes every time.
//!
//! Loggers that keep something to read or flush afterwards (all but the tracing one) are
//! handles: clones share one state, so keep a clone while the tree owns the other. An
//! observer cannot return errors to the tree, so a logger whose output fails keeps the
//! first error, stops writing, and reports the error from its `flush`.
//!
//! ```
//! use neurotree::observe::{JsonlTrace, Statistics};
//! use neurotree::{Blueprint, ManualClock, Status, Tree};
//!
//! let blueprint = Blueprint::<()>::builder()
//!     .sequence("job", |s| s.always_success("prepare").always_failure("work"))
//!     .build_shared()
//!     .unwrap();
//! let mut tree = Tree::with_clock(blueprint.clone(), ManualClock::new());
//! let trace = JsonlTrace::new(&blueprint, Vec::new());
//! let stats = Statistics::new(&blueprint);
//! tree.set_observer((trace.clone(), stats.clone()));
//!
//! assert_eq!(tree.tick_once(&mut ()), Ok(Status::Failure));
//! assert_eq!(stats.by_path("job/work").unwrap().failures, 1);
//! let text = trace.with_writer(|lines| String::from_utf8(lines.clone()).unwrap());
//! assert!(text.starts_with(r#"{"tick":1,"time_us":0,"id":0,"node":"job","from":"IDLE","to":"RUNNING"}"#));
//! ```

mod btlog;
mod console;
mod coverage;
mod jsonl;
mod outcome;
#[cfg(feature = "sqlite")]
mod sqlite;
mod stats;
#[cfg(feature = "tracing")]
mod tracing_observer;

pub use btlog::{
    read_btlog, read_btlog_file, Btlog, BtlogError, BtlogReadError, BtlogRecord, BtlogWriter,
    BTLOG_MAGIC, BTLOG_PROTOCOL,
};
pub use console::ConsoleLogger;
pub use coverage::{possible_outcomes, Coverage, CoverageReport, NodeCoverage};
pub use jsonl::JsonlTrace;
pub use outcome::{Outcome, OutcomeSet};
#[cfg(feature = "sqlite")]
pub use sqlite::{SqliteLogError, SqliteLogger};
pub use stats::{NodeStats, Statistics};
#[cfg(feature = "tracing")]
pub use tracing_observer::TracingObserver;

use std::io;
use std::sync::{Mutex, MutexGuard};
use std::time::Duration;

use neurotree_core::NodeStatus;

/// Locks a logger's state. A panic elsewhere while it was held leaves at worst a line half
/// written, so a poisoned lock is still used.
fn lock<T>(state: &Mutex<T>) -> MutexGuard<'_, T> {
    state.lock().unwrap_or_else(|e| e.into_inner())
}

/// Microseconds of a clock reading, saturating after some 584,000 years.
fn micros(d: Duration) -> u64 {
    u64::try_from(d.as_micros()).unwrap_or(u64::MAX)
}

/// Where a logger writes, and the first error it met there: after an error it writes no
/// more, so that one full disk does not cost an error per status change.
#[derive(Debug)]
struct Sink<W> {
    out: W,
    error: Option<io::Error>,
}

impl<W: io::Write> Sink<W> {
    fn new(out: W) -> Self {
        Self { out, error: None }
    }

    fn write_all(&mut self, bytes: &[u8]) {
        if self.error.is_none()
            && let Err(e) = self.out.write_all(bytes)
        {
            self.error = Some(e);
        }
    }

    /// Flushes, or returns the error met earlier (once: it is then cleared).
    fn flush(&mut self) -> io::Result<()> {
        match self.error.take() {
            Some(e) => Err(e),
            None => self.out.flush(),
        }
    }
}

/// BehaviorTree.CPP's number for a status.
fn status_code(status: NodeStatus) -> u8 {
    match status {
        NodeStatus::Idle => 0,
        NodeStatus::Running => 1,
        NodeStatus::Success => 2,
        NodeStatus::Failure => 3,
        NodeStatus::Skipped => 4,
    }
}

/// The status BehaviorTree.CPP numbers `code`.
fn status_of_code(code: u8) -> Option<NodeStatus> {
    Some(match code {
        0 => NodeStatus::Idle,
        1 => NodeStatus::Running,
        2 => NodeStatus::Success,
        3 => NodeStatus::Failure,
        4 => NodeStatus::Skipped,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_codes_are_bt_cpps_and_round_trip() {
        let all = [
            NodeStatus::Idle,
            NodeStatus::Running,
            NodeStatus::Success,
            NodeStatus::Failure,
            NodeStatus::Skipped,
        ];
        let codes: Vec<u8> = all.iter().map(|s| status_code(*s)).collect();
        assert_eq!(codes, [0, 1, 2, 3, 4]);
        for s in all {
            assert_eq!(status_of_code(status_code(s)), Some(s));
        }
        assert_eq!(status_of_code(5), None);
    }
}
