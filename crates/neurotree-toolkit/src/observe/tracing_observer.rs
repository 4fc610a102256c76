//! Status changes as `tracing` events, for applications that already collect them.

use std::time::Duration;

use neurotree_core::{Blueprint, NodeStatus, Observer, StatusChange};
use tracing::Level;

use super::micros;

/// The target of every event, to filter them (`RUST_LOG=neurotree=debug`).
const TARGET: &str = "neurotree";

/// Emits every status change as a `tracing` event, and every tick end as a `TRACE` one.
///
/// A status change is an event at the chosen level (`DEBUG` unless told otherwise), with
/// target `neurotree`, message `status change` and the fields `node` (the path), `node_id`,
/// `from`, `to` (BehaviorTree.CPP's names, `IDLE`, `RUNNING`, ...) and `time_us` (the
/// tree's clock). A tick end is a `TRACE` event, message `tick end`, with `status` and
/// `time_us`. Where no subscriber wants them, an event costs a check of its level.
///
/// ```
/// use neurotree::observe::TracingObserver;
/// use neurotree::{Blueprint, ManualClock, Tree};
///
/// let blueprint = Blueprint::<()>::builder().always_success("done").build_shared().unwrap();
/// let mut tree = Tree::with_clock(blueprint.clone(), ManualClock::new());
/// tree.set_observer(TracingObserver::new(&blueprint).level(tracing::Level::INFO));
/// ```
#[derive(Clone, Debug)]
pub struct TracingObserver {
    paths: Vec<String>,
    level: Level,
}

impl TracingObserver {
    /// Events for the nodes of `blueprint`, status changes at `DEBUG`.
    pub fn new<C>(blueprint: &Blueprint<C>) -> Self {
        Self {
            paths: blueprint.paths(),
            level: Level::DEBUG,
        }
    }

    /// The level of the status-change events.
    pub fn level(mut self, level: Level) -> Self {
        self.level = level;
        self
    }
}

/// `tracing::event!` takes its level as a constant, so each level is its own call site.
macro_rules! status_event {
    ($level:expr, $($field:tt)*) => {{
        let level = $level;
        if level == Level::ERROR {
            tracing::event!(target: TARGET, Level::ERROR, $($field)*)
        } else if level == Level::WARN {
            tracing::event!(target: TARGET, Level::WARN, $($field)*)
        } else if level == Level::INFO {
            tracing::event!(target: TARGET, Level::INFO, $($field)*)
        } else if level == Level::DEBUG {
            tracing::event!(target: TARGET, Level::DEBUG, $($field)*)
        } else {
            tracing::event!(target: TARGET, Level::TRACE, $($field)*)
        }
    }};
}

impl Observer for TracingObserver {
    fn on_status_change(&mut self, change: StatusChange) {
        let node = self
            .paths
            .get(change.node.index())
            .map_or("?", String::as_str);
        status_event!(
            self.level,
            node,
            node_id = change.node.0,
            from = change.from.as_str(),
            to = change.to.as_str(),
            time_us = micros(change.at),
            "status change"
        );
    }

    fn on_tick_end(&mut self, status: NodeStatus, now: Duration) {
        tracing::event!(
            target: TARGET,
            Level::TRACE,
            status = status.as_str(),
            time_us = micros(now),
            "tick end"
        );
    }
}
