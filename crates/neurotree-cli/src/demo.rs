//! `neurotree demo`: a robot patrols a corridor, and the tree that drives it is drawn with
//! the statuses of every tick.
//!
//! The robot lives on a one-dimensional corridor with a charger at cell 0. It must visit
//! three waypoints in turn. Its tree shows the usual patterns of a robot behavior:
//!
//! - a battery check with a recharge fallback, re-checked every tick by a ReactiveSequence
//!   that halts the patrol leg when the battery runs low;
//! - each leg under a Timeout, retried by a RetryUntilSuccessful;
//! - an obstacle that appears in the corridor: a second ReactiveSequence re-checks the path
//!   every tick and halts the move while the robot waits for it to clear.
//!
//! The tree runs on a [`ManualClock`] advanced by a fixed step per tick, and the obstacle
//! follows a fixed script, so every run is the same.

use std::io::{self, Write};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree::render::LastTickStatuses;
use neurotree::{
    tree, Blueprint, Category, Handle, ManualClock, NodeKind, NodeStatus, Observer, StatefulAction,
    Status, StatusChange, Tree,
};

/// Simulated time between two ticks.
const TICK: Duration = Duration::from_millis(100);
/// Corridor cells, `0..CORRIDOR`.
const CORRIDOR: i32 = 12;
/// Where the charger stands.
const CHARGER: i32 = 0;
/// The cells to visit, in order.
const WAYPOINTS: [i32; 3] = [10, 3, 8];
/// Below this (percent) the robot goes to charge.
const LOW_BATTERY: u32 = 30;
/// Battery (percent) one cell of motion costs.
const STEP_COST: u32 = 3;
/// Battery (percent) one tick on the charger adds.
const CHARGE_RATE: u32 = 25;
/// How long one leg of the patrol may take before it is abandoned and retried.
const LEG_TIMEOUT: Duration = Duration::from_millis(1000);
/// The obstacle's script: at tick `from` it appears at `cell`, at tick `until` it is gone.
const OBSTACLE: Obstacle = Obstacle {
    cell: 6,
    from: 3,
    until: 14,
};

struct Obstacle {
    cell: i32,
    from: u32,
    until: u32,
}

/// How the demo runs.
#[derive(Clone, Debug)]
pub struct DemoOptions {
    /// Stop after this many ticks if the patrol has not ended.
    pub max_ticks: u32,
    /// Pause between frames when animating.
    pub frame_pause: Duration,
    /// Redraw in place (ANSI escapes) and pause between frames; otherwise print each frame
    /// after the previous one, at once.
    pub animate: bool,
    /// Draw the tree with unicode box characters rather than ascii.
    pub unicode: bool,
}

/// What the run achieved.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Summary {
    /// Ticks made.
    pub ticks: u32,
    /// The root's last status.
    pub outcome: Status,
    /// Cells the robot moved.
    pub distance: u32,
    /// Full charges.
    pub charges: u32,
    /// Running actions halted by their parents.
    pub halts: u32,
    /// Waypoints reached.
    pub waypoints: usize,
}

/// The robot and its corridor: the context every leaf of the demo tree receives.
#[derive(Debug)]
pub struct World {
    robot: i32,
    battery: u32,
    obstacle: Option<i32>,
    next_waypoint: usize,
    distance: u32,
    charges: u32,
    /// What happened in the current tick, shown under the corridor.
    events: Events,
}

impl World {
    fn new() -> Self {
        Self {
            robot: 1,
            battery: 60,
            obstacle: None,
            next_waypoint: 0,
            distance: 0,
            charges: 0,
            events: Events::default(),
        }
    }

    /// Applies the obstacle's script before tick number `tick` (1-based).
    fn update(&mut self, tick: u32) {
        if tick == OBSTACLE.from {
            self.obstacle = Some(OBSTACLE.cell);
            self.events
                .note(format!("an obstacle appears at cell {}", OBSTACLE.cell));
        } else if tick == OBSTACLE.until {
            self.obstacle = None;
            self.events.note("the obstacle is gone".into());
        }
    }

    fn waypoint(&self) -> Option<i32> {
        WAYPOINTS.get(self.next_waypoint).copied()
    }

    /// The cell the robot would enter next on its way to `target`.
    fn next_cell(&self, target: i32) -> i32 {
        self.robot + (target - self.robot).signum()
    }

    fn path_clear(&self) -> bool {
        match self.waypoint() {
            Some(target) => Some(self.next_cell(target)) != self.obstacle,
            None => true,
        }
    }

    /// One line: the corridor, then the battery and the goal.
    fn line(&self) -> String {
        let cells: String = (0..CORRIDOR)
            .map(|c| {
                if c == self.robot {
                    'R'
                } else if Some(c) == self.obstacle {
                    '#'
                } else if c == CHARGER {
                    'C'
                } else if Some(c) == self.waypoint() {
                    '*'
                } else {
                    '.'
                }
            })
            .collect();
        let goal = match self.waypoint() {
            Some(cell) => format!(
                "waypoint {}/{} at cell {cell}",
                self.next_waypoint + 1,
                WAYPOINTS.len()
            ),
            None => "patrol done".into(),
        };
        format!("|{cells}|  battery {:>3}%  {goal}", self.battery)
    }
}

/// The notes of the current tick, in the order things happened: the world and the
/// observer both write here.
#[derive(Clone, Debug, Default)]
struct Events(Arc<Mutex<Vec<String>>>);

impl Events {
    fn note(&self, text: String) {
        self.lock().push(text);
    }

    fn take(&self) -> Vec<String> {
        std::mem::take(&mut *self.lock())
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<String>> {
        // The notes are plain strings, whole even if a writer panicked.
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// Where a [`MoveTo`] goes.
#[derive(Clone, Copy)]
enum Goal {
    Waypoint,
    Charger,
}

/// Moves the robot towards its goal: the first tick plans, each later tick moves one cell.
/// It waits in place when the next cell is blocked, and fails when the battery is empty.
struct MoveTo {
    goal: Goal,
}

impl MoveTo {
    fn target(&self, w: &World) -> Option<i32> {
        match self.goal {
            Goal::Waypoint => w.waypoint(),
            Goal::Charger => Some(CHARGER),
        }
    }
}

impl StatefulAction<World> for MoveTo {
    fn on_start(&mut self, h: &mut Handle<'_, World>) -> Status {
        match self.target(h.ctx()) {
            None => Status::Failure,
            Some(target) if target == h.ctx().robot => Status::Success,
            Some(_) => Status::Running,
        }
    }

    fn on_running(&mut self, h: &mut Handle<'_, World>) -> Status {
        let w = h.ctx_mut();
        let Some(target) = self.target(w) else {
            return Status::Failure;
        };
        if w.robot == target {
            return Status::Success;
        }
        if w.battery < STEP_COST {
            w.events.note("the battery is empty".into());
            return Status::Failure;
        }
        let next = w.next_cell(target);
        if Some(next) != w.obstacle {
            w.robot = next;
            w.battery -= STEP_COST;
            w.distance += 1;
        }
        if w.robot == target {
            Status::Success
        } else {
            Status::Running
        }
    }
}

/// Running while the next cell towards the waypoint is blocked.
struct WaitForClear;

impl StatefulAction<World> for WaitForClear {
    fn on_start(&mut self, h: &mut Handle<'_, World>) -> Status {
        h.ctx().events.note("waiting for the path to clear".into());
        self.on_running(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, World>) -> Status {
        if h.ctx().path_clear() {
            Status::Success
        } else {
            Status::Running
        }
    }
}

/// Charges on the charger until full.
struct Charge;

impl StatefulAction<World> for Charge {
    fn on_start(&mut self, h: &mut Handle<'_, World>) -> Status {
        if h.ctx().robot != CHARGER {
            return Status::Failure;
        }
        h.ctx().events.note("charging".into());
        self.on_running(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, World>) -> Status {
        let w = h.ctx_mut();
        w.battery = (w.battery + CHARGE_RATE).min(100);
        if w.battery == 100 {
            w.charges += 1;
            Status::Success
        } else {
            Status::Running
        }
    }
}

/// The robot's behavior.
pub fn robot_tree() -> Arc<Blueprint<World>> {
    let blueprint = tree! {
        repeat("patrol", WAYPOINTS.len() as i32) {
            sequence("leg") {
                reactive_sequence("powered") {
                    fallback("power") {
                        condition("battery_ok", |w: &World| w.battery >= LOW_BATTERY),
                        sequence("recharge") {
                            stateful("go_to_charger", || MoveTo { goal: Goal::Charger }),
                            stateful("charge", || Charge),
                        },
                    },
                    retry("retry_leg", 3) {
                        timeout("leg_timeout", LEG_TIMEOUT) {
                            reactive_sequence("move_safely") {
                                fallback("clear_or_wait") {
                                    condition("path_clear", World::path_clear),
                                    stateful("wait_for_clear", || WaitForClear),
                                },
                                stateful("move_to_waypoint", || MoveTo { goal: Goal::Waypoint }),
                            },
                        },
                    },
                },
                action("next_waypoint", |w: &mut World| {
                    w.events.note(format!("reached waypoint {}", w.next_waypoint + 1));
                    w.next_waypoint += 1;
                    Status::Success
                }),
            },
        }
    };
    // The tree above is fixed and valid: every decorator has one child.
    Arc::new(blueprint.expect("the demo tree is valid"))
}

/// What [`Notes`] reports about a node.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Watched {
    /// An action: its halts are counted.
    Action,
    /// A Timeout: its expiry is noted.
    Timeout,
    Other,
}

/// Turns the status changes worth a line into notes for the frame, and counts the halts of
/// Running actions.
#[derive(Clone)]
struct Notes {
    watched: Arc<[Watched]>,
    names: Arc<[String]>,
    halts: Arc<AtomicU32>,
    events: Events,
}

impl Notes {
    fn new(bp: &Blueprint<World>, events: Events) -> Self {
        let watched = bp
            .ids()
            .map(|id| match bp.kind(id) {
                NodeKind::Timeout(_) => Watched::Timeout,
                kind if kind.category() == Category::Action => Watched::Action,
                _ => Watched::Other,
            })
            .collect();
        let names = bp.ids().map(|id| bp.name(id).to_string()).collect();
        Self {
            watched,
            names,
            halts: Arc::default(),
            events,
        }
    }
}

impl Observer for Notes {
    fn on_status_change(&mut self, c: StatusChange) {
        let name = &self.names[c.node.index()];
        match (self.watched[c.node.index()], c.from, c.to) {
            (Watched::Action, NodeStatus::Running, NodeStatus::Idle) => {
                self.halts.fetch_add(1, Ordering::Relaxed);
                self.events.note(format!("{name} halted"));
            }
            (Watched::Timeout, NodeStatus::Running, NodeStatus::Failure) => {
                self.events.note(format!("{name} ran out of time"));
            }
            _ => {}
        }
    }
}

/// ANSI: cursor home, clear to the end of the line, clear to the end of the screen.
const HOME: &str = "\x1b[H";
const CLEAR_LINE: &str = "\x1b[K";
const CLEAR_BELOW: &str = "\x1b[J";

/// Runs the demo, writing frames and the summary to `out`.
pub fn run(opts: &DemoOptions, out: &mut impl Write) -> io::Result<Summary> {
    let blueprint = robot_tree();
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(Arc::clone(&blueprint), clock.clone());
    let seen = LastTickStatuses::new();
    let mut world = World::new();
    let notes = Notes::new(&blueprint, world.events.clone());
    tree.set_observer((seen.clone(), notes.clone()));

    if opts.animate {
        write!(out, "\x1b[2J")?;
    }
    let mut ticks = 0;
    let mut outcome = Status::Running;
    while ticks < opts.max_ticks {
        ticks += 1;
        world.update(ticks);
        // One pass of the root per tick, so that each frame shows one step of the robot
        // (`tick_once` would also run at once the passes a Repeat or a Retry asks for).
        outcome = tree
            .tick_exactly_once(&mut world)
            .map_err(|e| io::Error::other(format!("the demo tree failed: {e}")))?;
        let events = world.events.take();
        let picture = seen.render(&blueprint, opts.unicode);
        let frame = frame(ticks, tree.now(), &world, &events, &picture);
        if opts.animate {
            write!(out, "{HOME}")?;
            for line in frame.lines() {
                writeln!(out, "{line}{CLEAR_LINE}")?;
            }
            write!(out, "{CLEAR_BELOW}")?;
            out.flush()?;
            std::thread::sleep(opts.frame_pause);
        } else {
            writeln!(out, "{frame}")?;
        }
        if outcome != Status::Running {
            break;
        }
        clock.advance(TICK);
    }

    let summary = Summary {
        ticks,
        outcome,
        distance: world.distance,
        charges: world.charges,
        halts: notes.halts.load(Ordering::Relaxed),
        waypoints: world.next_waypoint,
    };
    write_summary(&summary, out)?;
    Ok(summary)
}

/// One frame: the tick and the time, the corridor, what happened, the tree.
fn frame(tick: u32, now: Duration, world: &World, events: &[String], tree: &str) -> String {
    format!(
        "tick {tick:>3}   t = {:.1} s\n{}\n{}\n\n{tree}",
        now.as_secs_f64(),
        world.line(),
        events.join("; ")
    )
}

fn write_summary(s: &Summary, out: &mut impl Write) -> io::Result<()> {
    writeln!(out, "Summary")?;
    writeln!(out, "  ticks      {}", s.ticks)?;
    writeln!(out, "  outcome    {}", s.outcome)?;
    writeln!(out, "  waypoints  {} of {}", s.waypoints, WAYPOINTS.len())?;
    writeln!(out, "  distance   {} cells", s.distance)?;
    writeln!(out, "  charges    {}", s.charges)?;
    writeln!(out, "  halts      {}", s.halts)?;
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plain(max_ticks: u32) -> (Summary, String) {
        let opts = DemoOptions {
            max_ticks,
            frame_pause: Duration::ZERO,
            animate: false,
            unicode: false,
        };
        let mut out = Vec::new();
        let summary = run(&opts, &mut out).unwrap();
        (summary, String::from_utf8(out).unwrap())
    }

    #[test]
    fn the_patrol_ends_the_same_way_every_time() {
        let (a, text_a) = plain(500);
        let (b, text_b) = plain(500);
        assert_eq!(a, b);
        assert_eq!(text_a, text_b);
        assert_eq!(
            a,
            Summary {
                ticks: 41,
                outcome: Status::Success,
                distance: 27,
                charges: 1,
                halts: 3,
                waypoints: WAYPOINTS.len(),
            }
        );
        assert!(!text_a.contains('\x1b'));
    }

    #[test]
    fn the_story_happens() {
        let (_, text) = plain(500);
        for event in [
            "an obstacle appears at cell 6",
            "leg_timeout ran out of time",
            "move_to_waypoint halted",
            "charging",
            "the obstacle is gone",
            "reached waypoint 3",
        ] {
            assert!(text.contains(event), "missing {event:?}");
        }
    }

    #[test]
    fn a_tick_limit_stops_the_run() {
        let (s, _) = plain(5);
        assert_eq!(s.ticks, 5);
        assert_eq!(s.outcome, Status::Running);
    }

    #[test]
    fn the_corridor_line() {
        let mut w = World::new();
        assert_eq!(
            w.line(),
            "|CR........*.|  battery  60%  waypoint 1/3 at cell 10"
        );
        w.obstacle = Some(6);
        w.robot = 0;
        assert_eq!(&w.line()[..14], "|R.....#...*.|");
    }
}
