//! Pick and place: Colledanchise & Ögren's tree, with actions that take several ticks.
//!
//! A gantry robot on a rail must find an object, move over it, grasp it, carry it to the
//! place spot and put it down. The tree is the pick-and-place example of Colledanchise &
//! Ögren's *Behavior Trees in Robotics and AI*: a goal check, then a ReactiveSequence of
//! "condition, or the action that makes it true" pairs. Because the sequence is reactive,
//! every tick re-checks the conditions of the steps already done: if the object slips out
//! of the gripper on the way, the move is halted and the robot grasps it again where it
//! fell.
//!
//! ```text
//! pick_and_place (Fallback)
//! ├── object_placed (Condition)
//! └── place_the_object (ReactiveSequence)
//!     ├── find (Fallback)       object_found      | find_object
//!     ├── approach (Fallback)   object_in_reach   | approach_object
//!     ├── grasp (Fallback)      object_grasped    | retry 3 × grasp_object
//!     ├── transport (Fallback)  at_place          | move_to_place
//!     └── place_object
//! ```
//!
//! Every action is a [`StatefulAction`]: `on_start` begins the work, `on_running` carries
//! it on over later ticks, `on_halted` records an interruption. The world is scripted (how
//! many grasps fail, when the object slips) and the clock is a [`ManualClock`], so every
//! run is the same.
//!
//! Run it with `cargo run -p neurotree --example pick_and_place [SCENARIO]`, where SCENARIO
//! is `first-try`, `grasp-retries`, `grasp-gives-up` or `object-slips` (all of them without
//! an argument).

use std::fmt;
use std::sync::Arc;
use std::time::Duration;

use neurotree::render::LastTickStatuses;
use neurotree::{
    Blueprint, Handle, ManualClock, NodeStatus, StatefulAction, Status, TickError, Tree,
};

/// The cell of the rail where the object lies at the start (the robot starts at 0).
pub const OBJECT_START: i32 = 3;
/// The cell where the object must be put down.
pub const PLACE_SPOT: i32 = 7;
/// Ticks a scan of the work area takes.
pub const SCAN_TICKS: u32 = 2;
/// Grasps tried before giving up.
pub const GRASP_ATTEMPTS: i32 = 3;
/// Simulated time between two ticks.
pub const TICK: Duration = Duration::from_millis(100);
/// A run stops after this many ticks whatever happens.
pub const MAX_TICKS: u32 = 100;

/// What the world does during a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// How many grasps, from the first, close on nothing.
    pub failed_grasps: u32,
    /// When the carried object slips out of the gripper, if it does.
    pub slip_at: Option<Duration>,
}

/// The scenarios `main` knows by name.
pub fn scenarios() -> [(&'static str, Scenario); 4] {
    let failing = |n| Scenario {
        failed_grasps: n,
        slip_at: None,
    };
    [
        ("first-try", failing(0)),
        ("grasp-retries", failing(2)),
        ("grasp-gives-up", failing(3)),
        (
            "object-slips",
            Scenario {
                failed_grasps: 0,
                slip_at: Some(Duration::from_millis(550)),
            },
        ),
    ]
}

/// What a run produced.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The root's status on the last tick.
    pub status: Status,
    /// Ticks made.
    pub ticks: u32,
    /// Grasps tried.
    pub grasp_attempts: u32,
    /// The actions halted while running, in order.
    pub halted: Vec<String>,
    /// Where the robot ended.
    pub robot_at: i32,
    /// Where the object ended.
    pub object_at: i32,
    /// Whether it lies on the place spot, released.
    pub placed: bool,
}

/// The robot, the object and the script: the context `C` the leaves receive.
#[derive(Debug)]
pub struct Workcell {
    robot: i32,
    /// Where the object is; it moves with the gripper while held.
    object: i32,
    object_seen: bool,
    holding: bool,
    placed: bool,
    failed_grasps: u32,
    slip_at: Option<Duration>,
    grasp_attempts: u32,
    halted: Vec<String>,
    /// What happened during the current tick, for the log.
    events: Vec<String>,
}

impl Workcell {
    fn new(scenario: &Scenario) -> Self {
        Self {
            robot: 0,
            object: OBJECT_START,
            object_seen: false,
            holding: false,
            placed: false,
            failed_grasps: scenario.failed_grasps,
            slip_at: scenario.slip_at,
            grasp_attempts: 0,
            halted: Vec::new(),
            events: Vec::new(),
        }
    }

    /// The world's script, before the tick at `now`: the carried object may slip, once.
    fn update(&mut self, now: Duration) {
        if self.holding && self.slip_at.is_some_and(|at| now >= at) {
            self.slip_at = None;
            self.holding = false;
            let at = self.object;
            self.note(format!("the object slips out of the gripper at cell {at}"));
        }
    }

    fn note(&mut self, event: impl Into<String>) {
        self.events.push(event.into());
    }
}

/// Scans the work area for [`SCAN_TICKS`] ticks, then knows where the object is.
#[derive(Default)]
struct FindObject {
    ticks: u32,
}

impl StatefulAction<Workcell> for FindObject {
    fn on_start(&mut self, h: &mut Handle<'_, Workcell>) -> Status {
        self.ticks = 0;
        h.ctx_mut().note("scanning the work area");
        self.on_running(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, Workcell>) -> Status {
        self.ticks += 1;
        if self.ticks < SCAN_TICKS {
            return Status::Running;
        }
        let cell = h.ctx_mut();
        cell.object_seen = true;
        let at = cell.object;
        cell.note(format!("object seen at cell {at}"));
        Status::Success
    }

    fn on_halted(&mut self, h: &mut Handle<'_, Workcell>) {
        record_halt(h);
    }
}

/// Where a [`Move`] goes.
#[derive(Clone, Copy, Debug)]
enum Target {
    Object,
    PlaceSpot,
}

/// Moves the robot one cell per tick along the rail; a held object moves with it.
struct Move {
    to: Target,
}

impl Move {
    fn target(&self, cell: &Workcell) -> i32 {
        match self.to {
            Target::Object => cell.object,
            Target::PlaceSpot => PLACE_SPOT,
        }
    }
}

impl StatefulAction<Workcell> for Move {
    fn on_start(&mut self, h: &mut Handle<'_, Workcell>) -> Status {
        let target = self.target(h.ctx());
        h.ctx_mut().note(format!("moving to cell {target}"));
        self.on_running(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, Workcell>) -> Status {
        let target = self.target(h.ctx());
        let cell = h.ctx_mut();
        cell.robot += (target - cell.robot).signum();
        if cell.holding {
            cell.object = cell.robot;
        }
        if cell.robot == target {
            Status::Success
        } else {
            Status::Running
        }
    }

    fn on_halted(&mut self, h: &mut Handle<'_, Workcell>) {
        record_halt(h);
    }
}

/// Closes the gripper (one tick), then holds the object, unless the script makes this
/// grasp close on nothing.
struct Grasp;

impl StatefulAction<Workcell> for Grasp {
    fn on_start(&mut self, h: &mut Handle<'_, Workcell>) -> Status {
        let cell = h.ctx_mut();
        cell.grasp_attempts += 1;
        let attempt = cell.grasp_attempts;
        cell.note(format!("grasp {attempt}: closing the gripper"));
        Status::Running
    }

    fn on_running(&mut self, h: &mut Handle<'_, Workcell>) -> Status {
        let cell = h.ctx_mut();
        if cell.failed_grasps > 0 {
            cell.failed_grasps -= 1;
            cell.note("the gripper closed on nothing");
            return Status::Failure;
        }
        cell.holding = true;
        cell.note("object grasped");
        Status::Success
    }

    fn on_halted(&mut self, h: &mut Handle<'_, Workcell>) {
        record_halt(h);
    }
}

/// Lowers the object (one tick), then opens the gripper.
struct Place;

impl StatefulAction<Workcell> for Place {
    fn on_start(&mut self, h: &mut Handle<'_, Workcell>) -> Status {
        h.ctx_mut().note("lowering the object");
        Status::Running
    }

    fn on_running(&mut self, h: &mut Handle<'_, Workcell>) -> Status {
        let cell = h.ctx_mut();
        cell.holding = false;
        cell.placed = cell.object == PLACE_SPOT;
        let at = cell.object;
        cell.note(format!("object released at cell {at}"));
        cell.placed.into()
    }

    fn on_halted(&mut self, h: &mut Handle<'_, Workcell>) {
        record_halt(h);
    }
}

fn record_halt(h: &mut Handle<'_, Workcell>) {
    let name = h.name().to_string();
    let cell = h.ctx_mut();
    cell.note(format!("{name} halted"));
    cell.halted.push(name);
}

/// The pick-and-place tree.
pub fn pick_and_place_tree() -> Arc<Blueprint<Workcell>> {
    let blueprint = Blueprint::builder()
        .fallback("pick_and_place", |root| {
            root.condition("object_placed", |c: &Workcell| c.placed)
                .reactive_sequence("place_the_object", |s| {
                    s.fallback("find", |f| {
                        f.condition("object_found", |c: &Workcell| c.object_seen)
                            .stateful("find_object", FindObject::default)
                    })
                    .fallback("approach", |f| {
                        f.condition("object_in_reach", |c: &Workcell| c.object == c.robot)
                            .stateful("approach_object", || Move { to: Target::Object })
                    })
                    .fallback("grasp", |f| {
                        f.condition("object_grasped", |c: &Workcell| c.holding)
                            .retry("grasp_retry", GRASP_ATTEMPTS, |r| {
                                r.stateful("grasp_object", || Grasp)
                            })
                    })
                    .fallback("transport", |f| {
                        f.condition("at_place", |c: &Workcell| c.robot == PLACE_SPOT)
                            .stateful("move_to_place", || Move {
                                to: Target::PlaceSpot,
                            })
                    })
                    .stateful("place_object", || Place)
                })
        })
        .build_shared();
    // A fixed tree whose controls all have children: building it cannot fail.
    blueprint.expect("the pick-and-place tree is valid")
}

/// Runs `scenario` until the tree completes, passing each line of a readable log to `log`.
pub fn run(scenario: &Scenario, mut log: impl FnMut(&str)) -> Result<Outcome, TickError> {
    let blueprint = pick_and_place_tree();
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(Arc::clone(&blueprint), clock.clone());
    let seen = LastTickStatuses::new();
    tree.set_observer(seen.clone());
    let mut cell = Workcell::new(scenario);

    let mut status = Status::Running;
    let mut ticks = 0;
    let mut drawn_running = Vec::new();
    while ticks < MAX_TICKS {
        cell.update(tree.now());
        ticks += 1;
        status = tree.tick_once(&mut cell)?;
        let held = if cell.holding { " (held)" } else { "" };
        log(&format!(
            "tick {ticks:>3}  t = {:.1} s  robot at {}  object at {}{held}  -> {status}",
            tree.now().as_secs_f64(),
            cell.robot,
            cell.object,
        ));
        for event in cell.events.drain(..) {
            log(&format!("          {event}"));
        }
        let done = status != Status::Running;
        // Draw the tree when other nodes are running than at the last drawing, and at the end.
        let running = running_nodes(&seen);
        if done || running != drawn_running {
            log(&seen.render(&blueprint, true));
            drawn_running = running;
        }
        if done {
            break;
        }
        clock.advance(TICK);
    }

    Ok(Outcome {
        status,
        ticks,
        grasp_attempts: cell.grasp_attempts,
        halted: cell.halted,
        robot_at: cell.robot,
        object_at: cell.object,
        placed: cell.placed,
    })
}

/// Which nodes were Running at the end of the last tick.
fn running_nodes(seen: &LastTickStatuses) -> Vec<bool> {
    let statuses = seen.statuses();
    statuses.iter().map(|s| *s == NodeStatus::Running).collect()
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{} after {} ticks", self.status, self.ticks)?;
        writeln!(f, "  grasps     {}", self.grasp_attempts)?;
        writeln!(f, "  halted     {:?}", self.halted)?;
        writeln!(f, "  robot at   cell {}", self.robot_at)?;
        let placed = if self.placed { ", placed" } else { "" };
        write!(f, "  object at  cell {}{placed}", self.object_at)
    }
}

fn main() -> Result<(), TickError> {
    let wanted = std::env::args().nth(1);
    let all = scenarios();
    if let Some(name) = &wanted
        && !all.iter().any(|(n, _)| n == name)
    {
        let names: Vec<&str> = all.iter().map(|(n, _)| *n).collect();
        eprintln!(
            "unknown scenario `{name}`; try one of: {}",
            names.join(", ")
        );
        std::process::exit(2);
    }
    for (name, scenario) in &all {
        if wanted.as_deref().is_some_and(|w| w != *name) {
            continue;
        }
        println!("=== {name}: {scenario:?}\n");
        let outcome = run(scenario, |line| println!("{line}"))?;
        println!("{outcome}\n");
    }
    Ok(())
}
