//! The tracing observer: each status change is an event with the node's path and statuses,
//! as a subscriber sees it.

#![cfg(feature = "tracing")]

use crate::patrol;

use std::fmt::Write as _;
use std::sync::{Arc, Mutex};

use neurotree::observe::TracingObserver;
use tracing::field::{Field, Visit};
use tracing::span::{Attributes, Id, Record};
use tracing::{Event, Level, Metadata, Subscriber};

/// Keeps every event as `LEVEL target message field=value ...`.
#[derive(Clone, Default)]
struct Capture(Arc<Mutex<Vec<String>>>);

struct Line(String);

impl Visit for Line {
    fn record_str(&mut self, field: &Field, value: &str) {
        let _ = write!(self.0, " {}={value}", field.name());
    }
    fn record_u64(&mut self, field: &Field, value: u64) {
        let _ = write!(self.0, " {}={value}", field.name());
    }
    fn record_debug(&mut self, field: &Field, value: &dyn std::fmt::Debug) {
        if field.name() == "message" {
            let _ = write!(self.0, " {value:?}");
        } else {
            let _ = write!(self.0, " {}={value:?}", field.name());
        }
    }
}

impl Subscriber for Capture {
    fn enabled(&self, _: &Metadata<'_>) -> bool {
        true
    }
    fn new_span(&self, _: &Attributes<'_>) -> Id {
        Id::from_u64(1)
    }
    fn record(&self, _: &Id, _: &Record<'_>) {}
    fn record_follows_from(&self, _: &Id, _: &Id) {}
    fn event(&self, event: &Event<'_>) {
        let meta = event.metadata();
        let mut line = Line(format!("{} {}", meta.level(), meta.target()));
        event.record(&mut line);
        self.0.lock().unwrap().push(line.0);
    }
    fn enter(&self, _: &Id) {}
    fn exit(&self, _: &Id) {}
}

fn capture(level: Option<Level>) -> Vec<String> {
    let sub = Capture::default();
    tracing::subscriber::with_default(sub.clone(), || {
        let (mut tree, clock) = patrol::start();
        let observer = TracingObserver::new(tree.blueprint());
        tree.set_observer(match level {
            Some(level) => observer.level(level),
            None => observer,
        });
        patrol::run(&mut tree, &clock);
    });

    sub.0.lock().unwrap().clone()
}

#[test]
fn status_changes_are_debug_events_with_path_and_statuses() {
    let events = capture(None);
    assert_eq!(
        events[..4],
        [
            "DEBUG neurotree status change node=patrol node_id=0 from=IDLE to=RUNNING time_us=100000",
            "DEBUG neurotree status change node=patrol/battery_ok node_id=1 from=IDLE to=SUCCESS time_us=100000",
            "DEBUG neurotree status change node=patrol/route node_id=2 from=IDLE to=RUNNING time_us=100000",
            "DEBUG neurotree status change node=patrol/route/once node_id=3 from=IDLE to=RUNNING time_us=100000",
        ]
    );
    assert!(events.contains(
        &"DEBUG neurotree status change node=patrol/route/move node_id=5 from=RUNNING to=IDLE time_us=200000"
            .to_string()
    ));
    // The patrol's 33 changes, and one TRACE event per tick.
    let changes = events
        .iter()
        .filter(|e| e.contains("status change"))
        .count();
    assert_eq!(changes, 33);
    let ticks: Vec<&String> = events.iter().filter(|e| e.contains("tick end")).collect();
    assert_eq!(ticks.len(), 5);
    assert_eq!(
        ticks[1],
        "TRACE neurotree tick end status=FAILURE time_us=200000"
    );
}

#[test]
fn the_level_is_chosen() {
    let events = capture(Some(Level::INFO));
    assert_eq!(
        events[0],
        "INFO neurotree status change node=patrol node_id=0 from=IDLE to=RUNNING time_us=100000"
    );
    assert_eq!(events.iter().filter(|e| e.starts_with("INFO ")).count(), 33);
}
