//! `neurotree demo`: Nav2's navigator, unchanged, drives a simulated robot across a
//! warehouse; the world and the tree are drawn as it goes.
//!
//! Everything that happens is in a [`DemoRun`]: the warehouse [`Scenario`] of a seed, Nav2's
//! navigator ticked on it, the [`frame`](DemoRun::frame) of each tick. This module paces the
//! frames and picks how to show them. On a terminal that fits a frame, each frame is
//! redrawn in place (ANSI: cursor home, clear); otherwise (a pipe, a file, a small window)
//! frames are printed one after another, in plain text. The pace is simulated seconds per
//! second of watching; with no waiting the run is as fast as the machine.

use std::io::{self, Write};
use std::thread;
use std::time::{Duration, Instant};

mod frame;
mod run;
mod scenario;
mod world;

pub use frame::Layout;
pub use run::{DemoConfig, DemoError, DemoRun, DemoSummary, NAVIGATE_TO_POSE_XML};
pub use scenario::{dock, route_graph, Scenario, DEFAULT_GOAL, PLACING_LOCATION, WAREHOUSE};
pub use world::{DemoSaved, DemoWorld};

/// How `neurotree demo` shows the run.
pub struct DemoOptions {
    /// What to run.
    pub config: DemoConfig,
    /// Simulated seconds per second of watching; `None` for no waiting.
    pub speed: Option<f64>,
    /// Draw every this many ticks (and every tick where something happens).
    pub every: u32,
    /// Draw the frames before the last one; without them only the intro, the last frame
    /// and the summary are shown.
    pub frames_between: bool,
    /// The terminal's columns and rows, when standard output is one.
    pub terminal: Option<(usize, usize)>,
}

/// ANSI: clear to the end of the line, and to the end of the screen.
const CLEAR_LINE: &str = "\x1b[K";
const CLEAR_BELOW: &str = "\x1b[J";

/// Lines a frame may gain from its notes (a tick with much going on has five or six).
const NOTES_ROOM: usize = 6;

/// What watches the demo's tree from outside (the studio): shown the run before its first
/// tick, called before each tick (where it may hold the run) and once at its end.
pub trait DemoWatch {
    /// The hooks to build the tree with, beside the configured faults (a studio's forced
    /// results).
    fn hooks(
        &mut self,
    ) -> Option<neurotree::xml::SharedHookWrapper<neurotree::sim::nav2::Nav2Sim>> {
        None
    }
    /// Before the first tick.
    fn attach(&mut self, _demo: &mut DemoRun) {}
    /// Before each tick.
    fn before_tick(&mut self, _demo: &mut DemoRun) {}
    /// After the last tick.
    fn finish(&mut self, _demo: &mut DemoRun) {}
}

/// Watches nothing: the plain demo.
impl DemoWatch for () {}

/// Runs the demo, frames and summary on `out`; the summary, or `None` if it could not
/// start (the error is on `err`).
pub fn run(
    opts: &DemoOptions,
    out: &mut impl Write,
    err: &mut impl Write,
) -> io::Result<Option<DemoSummary>> {
    run_watched(opts, out, err, &mut ())
}

/// [`run`], with `watch` shown the tree.
pub fn run_watched(
    opts: &DemoOptions,
    out: &mut impl Write,
    err: &mut impl Write,
    watch: &mut dyn DemoWatch,
) -> io::Result<Option<DemoSummary>> {
    let mut demo = match DemoRun::with_hooks(&opts.config, watch.hooks()) {
        Ok(demo) => demo,
        Err(e) => {
            writeln!(err, "{e}")?;
            return Ok(None);
        }
    };
    for warning in demo.warnings() {
        writeln!(err, "{warning}")?;
    }
    let period = opts.config.params.period;
    let mut screen = Screen::new(opts.terminal, &demo);
    writeln!(out, "{}", demo.intro())?;
    let started = Instant::now();
    watch.attach(&mut demo);
    while !demo.is_over() {
        watch.before_tick(&mut demo);
        demo.tick();
        let ticks = demo.ticks();
        // Ticks 1, 1 + N, 1 + 2N, ...: with N = 10, the first tick of every second.
        let on_beat = (ticks - 1) % opts.every.max(1) == 0;
        if !demo.is_over() && (!opts.frames_between || (!on_beat && !demo.is_eventful())) {
            continue;
        }
        if let Some(speed) = opts.speed.filter(|s| *s > 0.0) {
            // Wait for the wall clock to catch up with the simulated time drawn so far,
            // so the pace holds however long the drawing took.
            let simulated = period.saturating_mul(ticks - 1).as_secs_f64() / speed;
            let due = started + Duration::from_secs_f64(simulated);
            thread::sleep(due.saturating_duration_since(Instant::now()));
        }
        screen.draw(out, &demo.frame(screen.layout))?;
    }
    watch.finish(&mut demo);
    let summary = demo.summary();
    if screen.in_place {
        writeln!(out)?;
    }
    writeln!(out, "{summary}")?;
    out.flush()?;
    Ok(Some(summary))
}

/// Where frames go and in what shape.
struct Screen {
    layout: Layout,
    /// Redraw each frame over the last one.
    in_place: bool,
    /// Lines of the frame drawn last, to go back over.
    drawn: usize,
}

impl Screen {
    /// Side by side when the terminal is wide and tall enough, stacked otherwise; redrawn
    /// in place when a frame fits the terminal's height, else printed one after another.
    fn new(terminal: Option<(usize, usize)>, demo: &DemoRun) -> Self {
        let plain = Self {
            layout: Layout::Stacked,
            in_place: false,
            drawn: 0,
        };
        let Some((columns, rows)) = terminal else {
            return plain;
        };
        let fits = |layout| {
            let frame = demo.frame(layout);
            let width = frame.lines().map(|l| l.chars().count()).max().unwrap_or(0);
            width <= columns && frame.lines().count() + NOTES_ROOM < rows
        };
        for layout in [Layout::SideBySide, Layout::Stacked] {
            if fits(layout) {
                return Self {
                    layout,
                    in_place: true,
                    drawn: 0,
                };
            }
        }
        plain
    }

    /// Draws a frame: over the previous one, or below it.
    fn draw(&mut self, out: &mut impl Write, frame: &str) -> io::Result<()> {
        if !self.in_place {
            writeln!(out, "{frame}")?;
            return out.flush();
        }
        if self.drawn > 0 {
            // Up to the first line of the last frame, at its first column.
            write!(out, "\x1b[{}A\r", self.drawn)?;
        }
        for line in frame.lines() {
            writeln!(out, "{line}{CLEAR_LINE}")?;
        }
        write!(out, "{CLEAR_BELOW}")?;
        self.drawn = frame.lines().count();
        out.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run_with(terminal: Option<(usize, usize)>, every: u32) -> (bool, String, String) {
        let opts = DemoOptions {
            config: DemoConfig::default(),
            speed: None,
            every,
            frames_between: true,
            terminal,
        };
        let (mut out, mut err) = (Vec::new(), Vec::new());
        let ok = run(&opts, &mut out, &mut err)
            .unwrap()
            .is_some_and(|s| s.succeeded());
        let text = |b: Vec<u8>| String::from_utf8(b).unwrap();
        (ok, text(out), text(err))
    }

    #[test]
    fn without_a_terminal_frames_follow_each_other_in_plain_text() {
        let (ok, out, err) = run_with(None, 10);
        assert!(ok && err.is_empty());
        assert!(!out.contains('\x1b'));
        assert_eq!(out.matches("\ntick ").count(), 49);
        assert!(out.ends_with("0.15 m from the goal (36.50, 1.50)\nnavigation succeeded\n\n"));
    }

    #[test]
    fn a_small_terminal_gets_plain_frames_too() {
        let (_, out, _) = run_with(Some((80, 24)), 10);
        assert!(!out.contains('\x1b'));
        assert_eq!(out, run_with(None, 10).1);
    }

    #[test]
    fn a_wide_terminal_gets_frames_side_by_side_redrawn_in_place() {
        let (ok, out, _) = run_with(Some((130, 50)), 10);
        assert!(ok);
        // The first frame is drawn below the intro; each of the 48 others goes back up over
        // the last: its 38 lines of tree, and a line for each note shown below them.
        let ups: Vec<usize> = out
            .split("\x1b[")
            .filter_map(|s| s.split_once("A\r"))
            .filter_map(|(n, _)| n.parse().ok())
            .collect();
        assert_eq!(ups.len(), 48);
        assert_eq!(ups.iter().min(), Some(&38));
        assert_eq!(ups.iter().max(), Some(&43));
        assert!(out.contains("tick 1     t =   0.0 s   RUNNING           [R] NavigateRecovery"));
        assert!(out.contains("\x1b[J\nSummary\n"));
        // A terminal tall enough for the stacked frames only.
        let (_, stacked, _) = run_with(Some((100, 80)), 10);
        assert!(stacked.contains("\x1b[60A\r"), "{stacked}");
        assert!(stacked.contains("tick 1     t =   0.0 s   RUNNING\x1b[K\n"));
    }

    #[test]
    fn a_tree_that_does_not_load_is_reported_on_err() {
        let opts = DemoOptions {
            config: DemoConfig {
                tree: Some("/nonexistent/tree.xml".into()),
                ..DemoConfig::default()
            },
            speed: Some(1.0),
            every: 1,
            frames_between: true,
            terminal: None,
        };
        let (mut out, mut err) = (Vec::new(), Vec::new());
        assert!(run(&opts, &mut out, &mut err).unwrap().is_none());
        assert!(out.is_empty());
        let err = String::from_utf8(err).unwrap();
        assert!(
            err.starts_with("/nonexistent/tree.xml: error: cannot open the file"),
            "{err}"
        );
    }
}
