//! A JSON-lines trace: one object per status change and per tick, for scripts.

use std::io::{self, Write};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree_core::{Blueprint, NodeId, NodeStatus, Observer, Reason, StatusChange};
use serde::Serialize;

use super::{lock, micros, Sink};

/// Writes one JSON object per line: one per status change, one per tick end.
///
/// ```text
/// {"tick":1,"time_us":100000,"id":2,"node":"patrol/move","from":"IDLE","to":"RUNNING"}
/// {"tick":1,"time_us":100000,"status":"RUNNING"}
/// ```
///
/// | field | meaning |
/// |---|---|
/// | `tick` | the root pass the line belongs to, from 1 |
/// | `time_us` | the tree's clock, in microseconds |
/// | `id` | the node's [`NodeId`](crate::NodeId) |
/// | `node` | the node's path |
/// | `from`, `to` | the statuses, as BehaviorTree.CPP names them |
/// | `status` | what the root returned, on the line that ends a tick (`SKIPPED` too) |
/// | `reason`, `code` | on a change to `FAILURE` for which the node gave a [`Reason`]: its message and code (only then) |
///
/// [`Tree::tick_once`](crate::Tree::tick_once) makes several passes when a node asks to be
/// woken, and changes made between ticks (by [`Tree::halt`](crate::Tree::halt)) carry the
/// number of the last pass. The statuses are named `IDLE`, `RUNNING`, `SUCCESS`, `FAILURE`.
///
/// `tick`, `node`, `from`, `to` and `status` mean what they mean in the lines of
/// `neurotree run --trace` (whose `tick` counts calls rather than passes, the same unless a
/// node asks to be woken). Keys come in the order above. A handle: clones share the writer;
/// give it a `BufWriter` for a file.
pub struct JsonlTrace<W> {
    state: Arc<Mutex<Jsonl<W>>>,
}

struct Jsonl<W> {
    sink: Sink<W>,
    paths: Vec<String>,
    tick: u64,
    /// The line being written, kept to reuse its buffer.
    line: Vec<u8>,
    /// The reason a node just gave, for its coming change to Failure.
    reason: Option<(NodeId, Reason)>,
}

#[derive(Serialize)]
struct ChangeLine<'a> {
    tick: u64,
    time_us: u64,
    id: u32,
    node: &'a str,
    from: &'static str,
    to: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    reason: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    code: Option<u32>,
}

#[derive(Serialize)]
struct TickLine {
    tick: u64,
    time_us: u64,
    status: &'static str,
}

impl<W> Clone for JsonlTrace<W> {
    fn clone(&self) -> Self {
        Self {
            state: Arc::clone(&self.state),
        }
    }
}

impl<W: Write> JsonlTrace<W> {
    /// A trace of the nodes of `blueprint`, written to `out`.
    pub fn new<C>(blueprint: &Blueprint<C>, out: W) -> Self {
        Self {
            state: Arc::new(Mutex::new(Jsonl {
                sink: Sink::new(out),
                paths: blueprint.paths(),
                tick: 0,
                line: Vec::new(),
                reason: None,
            })),
        }
    }

    /// Flushes the writer, or returns the first error writing met (writing stops at it).
    pub fn flush(&self) -> io::Result<()> {
        lock(&self.state).sink.flush()
    }

    /// Runs `f` on the writer, e.g. to read what a `Vec<u8>` collected.
    pub fn with_writer<R>(&self, f: impl FnOnce(&mut W) -> R) -> R {
        f(&mut lock(&self.state).sink.out)
    }
}

/// Writes `value` as one line, through `line` (a buffer kept to be reused).
fn write_line<W: Write>(sink: &mut Sink<W>, line: &mut Vec<u8>, value: &impl Serialize) {
    line.clear();
    // Serializing these plain structs into a Vec cannot fail.
    let _ = serde_json::to_writer(&mut *line, value);
    line.push(b'\n');
    sink.write_all(line);
}

impl<W: Write + Send> Observer for JsonlTrace<W> {
    fn on_tick_start(&mut self, _now: Duration) {
        lock(&self.state).tick += 1;
    }

    fn on_status_change(&mut self, change: StatusChange) {
        let mut state = lock(&self.state);
        let Jsonl {
            sink,
            paths,
            tick,
            line,
            reason,
        } = &mut *state;
        let given = match reason.take() {
            Some((node, r)) if node == change.node && change.to == NodeStatus::Failure => Some(r),
            _ => None,
        };
        let message = given.as_ref().map(Reason::message);
        let value = ChangeLine {
            tick: *tick,
            time_us: micros(change.at),
            id: change.node.0,
            node: paths.get(change.node.index()).map_or("?", String::as_str),
            from: change.from.as_str(),
            to: change.to.as_str(),
            reason: message.as_deref(),
            code: given.as_ref().map(Reason::code),
        };
        write_line(sink, line, &value);
    }

    fn on_failure_reason(&mut self, node: NodeId, reason: &Reason) {
        lock(&self.state).reason = Some((node, reason.clone()));
    }

    fn on_tick_end(&mut self, status: NodeStatus, now: Duration) {
        let mut state = lock(&self.state);
        let Jsonl {
            sink, tick, line, ..
        } = &mut *state;
        let value = TickLine {
            tick: *tick,
            time_us: micros(now),
            status: status.as_str(),
        };
        write_line(sink, line, &value);
    }
}
