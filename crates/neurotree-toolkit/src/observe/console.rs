//! A line per status change, for a person watching a run.

use std::fmt::Write as _;
use std::io::{self, Write};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use anstyle::{AnsiColor, Style};
use neurotree_core::{Blueprint, NodeId, NodeStatus, Observer, Reason, StatusChange};

use super::{lock, Sink};

/// Writes `[time] path PREV -> NEW` for every status change:
///
/// ```text
/// [0.100s] patrol IDLE -> RUNNING
/// [0.100s] patrol/battery_ok IDLE -> SUCCESS
/// [0.100s] patrol/move IDLE -> RUNNING
/// ```
///
/// A change to FAILURE for which the node gave a reason ends with it, and its code if it has
/// one: `[0.100s] go/follow_path RUNNING -> FAILURE: blocked (error 106)`.
///
/// The time is the tree's clock, in seconds with milliseconds. With colour on, the time is
/// dimmed and each status has its colour (Running yellow, Success green, Failure red,
/// Idle dimmed); off, the lines are plain text. [`ConsoleLogger::stderr`] colours when
/// standard error is a terminal that supports it (and `NO_COLOR` is unset);
/// [`ConsoleLogger::new`] writes plain lines to any writer unless told
/// [`colored`](Self::colored).
///
/// A handle: clones share the writer. Each line goes to the writer in one `write_all`.
///
/// ```
/// use neurotree::observe::ConsoleLogger;
/// use neurotree::{Blueprint, ManualClock, Status, Tree};
///
/// let blueprint = Blueprint::<()>::builder()
///     .inverter("not", |i| i.always_failure("fail"))
///     .build_shared()
///     .unwrap();
/// let log = ConsoleLogger::new(&blueprint, Vec::new());
/// let mut tree = Tree::with_clock(blueprint, ManualClock::new());
/// tree.set_observer(log.clone());
/// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
/// let text = log.with_writer(|out| String::from_utf8(out.clone()).unwrap());
/// assert_eq!(
///     text,
///     "[0.000s] not IDLE -> RUNNING\n\
///      [0.000s] not/fail IDLE -> FAILURE\n\
///      [0.000s] not/fail FAILURE -> IDLE\n\
///      [0.000s] not RUNNING -> SUCCESS\n\
///      [0.000s] not SUCCESS -> IDLE\n"
/// );
/// ```
pub struct ConsoleLogger<W> {
    state: Arc<Mutex<Console<W>>>,
}

struct Console<W> {
    sink: Sink<W>,
    paths: Vec<String>,
    colored: bool,
    /// The line being written, kept to reuse its buffer.
    line: String,
    /// The reason given for the coming change of this node to Failure.
    reason: Option<(NodeId, Reason)>,
}

impl<W> Clone for ConsoleLogger<W> {
    fn clone(&self) -> Self {
        Self {
            state: Arc::clone(&self.state),
        }
    }
}

impl ConsoleLogger<anstream::Stderr> {
    /// A logger on standard error, coloured where the terminal supports it (not when
    /// piped, nor with `NO_COLOR` set; `CLICOLOR_FORCE` forces it).
    pub fn stderr<C>(blueprint: &Blueprint<C>) -> Self {
        // The stream removes the styles where colour is off, so they are always written.
        Self::new(blueprint, anstream::stderr()).colored(true)
    }
}

impl<W: Write> ConsoleLogger<W> {
    /// A logger writing plain lines to `out`, naming the nodes of `blueprint`.
    pub fn new<C>(blueprint: &Blueprint<C>, out: W) -> Self {
        Self {
            state: Arc::new(Mutex::new(Console {
                sink: Sink::new(out),
                paths: blueprint.paths(),
                colored: false,
                line: String::new(),
                reason: None,
            })),
        }
    }

    /// Colours the lines with ANSI escape codes (`true`) or not (`false`, the default).
    pub fn colored(self, colored: bool) -> Self {
        lock(&self.state).colored = colored;
        self
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

impl<W: Write + Send> Observer for ConsoleLogger<W> {
    fn on_status_change(&mut self, change: StatusChange) {
        let mut state = lock(&self.state);
        let Console {
            sink,
            paths,
            colored,
            line,
            reason,
        } = &mut *state;
        let given = match reason.take() {
            Some((node, r)) if node == change.node && change.to == NodeStatus::Failure => Some(r),
            _ => None,
        };
        line.clear();
        let path = paths.get(change.node.index()).map_or("?", String::as_str);
        // Writing into a String cannot fail.
        let _ = write_line(line, *colored, change, path, given.as_ref());
        sink.write_all(line.as_bytes());
    }

    fn on_failure_reason(&mut self, node: NodeId, reason: &Reason) {
        lock(&self.state).reason = Some((node, reason.clone()));
    }
}

/// Formats one line, with `reason` at its end if given; the time with integer arithmetic,
/// as this runs on every change.
fn write_line(
    line: &mut String,
    colored: bool,
    change: StatusChange,
    path: &str,
    reason: Option<&Reason>,
) -> std::fmt::Result {
    let time = Time(change.at);
    if colored {
        let dim = Style::new().dimmed();
        let (from, to) = (status_style(change.from), status_style(change.to));
        write!(
            line,
            "{}[{time}]{} {path} {}{}{} -> {}{}{}",
            dim.render(),
            dim.render_reset(),
            from.render(),
            change.from,
            from.render_reset(),
            to.render(),
            change.to,
            to.render_reset(),
        )?;
    } else {
        write!(line, "[{time}] {path} {} -> {}", change.from, change.to)?;
    }
    if let Some(reason) = reason {
        write!(line, ": {reason}")?;
    }
    line.push('\n');
    Ok(())
}

fn status_style(status: NodeStatus) -> Style {
    match status {
        NodeStatus::Idle => Style::new().dimmed(),
        NodeStatus::Running => AnsiColor::Yellow.on_default(),
        NodeStatus::Success => AnsiColor::Green.on_default(),
        NodeStatus::Failure => AnsiColor::Red.on_default(),
        NodeStatus::Skipped => AnsiColor::Cyan.on_default(),
    }
}

/// A clock reading as seconds with milliseconds: `12.345s`.
struct Time(Duration);

impl std::fmt::Display for Time {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}.{:03}s", self.0.as_secs(), self.0.subsec_millis())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_core::NodeId;

    fn change(node: u32, from: NodeStatus, to: NodeStatus, ms: u64) -> StatusChange {
        StatusChange {
            node: NodeId(node),
            from,
            to,
            at: Duration::from_millis(ms),
        }
    }

    #[test]
    fn times_are_seconds_with_milliseconds() {
        assert_eq!(Time(Duration::ZERO).to_string(), "0.000s");
        assert_eq!(
            Time(Duration::from_micros(12_345_999)).to_string(),
            "12.345s"
        );
        assert_eq!(Time(Duration::from_secs(3600)).to_string(), "3600.000s");
    }

    #[test]
    fn coloured_lines_style_the_time_and_each_status() {
        let mut line = String::new();
        let c = change(0, NodeStatus::Running, NodeStatus::Failure, 1500);
        write_line(&mut line, true, c, "a/b", None).unwrap();
        assert_eq!(
            line,
            "\u{1b}[2m[1.500s]\u{1b}[0m a/b \u{1b}[33mRUNNING\u{1b}[0m -> \u{1b}[31mFAILURE\u{1b}[0m\n"
        );
        line.clear();
        let c = change(0, NodeStatus::Idle, NodeStatus::Success, 0);
        write_line(&mut line, true, c, "a", None).unwrap();
        assert_eq!(
            line,
            "\u{1b}[2m[0.000s]\u{1b}[0m a \u{1b}[2mIDLE\u{1b}[0m -> \u{1b}[32mSUCCESS\u{1b}[0m\n"
        );
    }

    #[test]
    fn a_failure_with_a_reason_ends_with_it() {
        let blocked = Reason::new(106, "blocked");
        let mut line = String::new();
        let c = change(0, NodeStatus::Running, NodeStatus::Failure, 1500);
        write_line(&mut line, true, c, "a/b", Some(&blocked)).unwrap();
        assert_eq!(
            line,
            "\u{1b}[2m[1.500s]\u{1b}[0m a/b \u{1b}[33mRUNNING\u{1b}[0m -> \u{1b}[31mFAILURE\u{1b}[0m: blocked (error 106)\n"
        );
    }

    /// Accepts `n` bytes, then fails.
    struct Full(usize);
    impl Write for Full {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            if self.0 == 0 {
                return Err(io::Error::new(io::ErrorKind::StorageFull, "full"));
            }
            let n = buf.len().min(self.0);
            self.0 -= n;
            Ok(n)
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_failing_writer_is_reported_once_by_flush() {
        let bp = Blueprint::<()>::builder()
            .always_success("a")
            .build()
            .unwrap();
        let mut log = ConsoleLogger::new(&bp, Full(10));
        log.on_status_change(change(0, NodeStatus::Idle, NodeStatus::Success, 0));
        log.on_status_change(change(0, NodeStatus::Success, NodeStatus::Idle, 0));
        let err = log.flush().unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::StorageFull);
        // Reported once; the writer is still full, and the next line fails again.
        assert!(log.flush().is_ok());
        log.on_status_change(change(0, NodeStatus::Idle, NodeStatus::Success, 0));
        assert!(log.flush().is_err());
    }
}
