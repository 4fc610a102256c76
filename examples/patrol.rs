//! Patrol: a battery-aware patrol with an emergency stop, driving a small simulated robot.
//!
//! The robot patrols the four corners of a room, scanning before each leg. When its battery
//! is low it drives back to the charger and charges until full; an emergency stop, pressed
//! at a scripted time, halts whatever is running and shuts the robot down.
//!
//! ```text
//! robot (ReactiveFallback)              the emergency branch is re-checked every tick
//! ├── emergency (Sequence)
//! │   ├── estop_pressed (Condition)
//! │   └── emergency_stop (Action)
//! └── main_patrol (Fallback)            patrol while the battery lasts, else recharge
//!     ├── normal_operation (Sequence)
//!     │   ├── battery_ok (Condition)
//!     │   ├── scan_area (Action)
//!     │   └── move_patrol (StatefulAction)
//!     └── low_battery_protocol (Sequence)
//!         ├── navigate_to_base (StatefulAction)
//!         └── charge_battery (StatefulAction)
//! ```
//!
//! A patrol tree often puts `emergency_stop` last, as the fallback of last resort; here it
//! comes first under a ReactiveFallback, the "emergency handler checked first" pattern, so
//! that pressing the button halts a move in progress within one tick.
//!
//! The moves and the charge are [`StatefulAction`]s (started once, updated on later ticks,
//! stopped when halted) that run one step per tick; a halt reaches them through `on_halted`.
//!
//! The tree is built twice, with the fluent builder ([`patrol_tree`]) and with the `tree!`
//! macro ([`patrol_tree_from_macro`]); the two are the same tree. The robot's world runs
//! on a [`ManualClock`], so every run is the same.
//!
//! Run it with `cargo run -p neurotree --example patrol [normal|low-battery|emergency-stop]`
//! (all three scenarios without an argument).

use std::fmt;
use std::sync::Arc;
use std::time::Duration;

use neurotree::render::LastTickStatuses;
use neurotree::{
    tree, Blueprint, Handle, ManualClock, NodeStatus, StatefulAction, Status, TickError, Tree,
};

/// A cell of the room's grid, `(x, y)`.
pub type Cell = (i32, i32);

/// The corners the robot visits, in order, again and again.
pub const WAYPOINTS: [Cell; 4] = [(4, 0), (4, 4), (0, 4), (0, 0)];
/// Where the charger stands (and the robot starts).
pub const CHARGER: Cell = (0, 0);
/// Battery (percent) at or below which the robot stops patrolling: `battery_ok` holds above it.
pub const LOW_BATTERY: u32 = 20;
/// Battery (percent) one cell of motion costs. A leg (4 cells) costs 4%, so a robot that
/// finds its battery low after a leg still has more than 16%, enough for the 8 cells from
/// the farthest corner to the charger.
pub const MOVE_COST: u32 = 1;
/// Battery (percent) one tick on the charger adds.
pub const CHARGE_RATE: u32 = 20;
/// Simulated time between two ticks.
pub const TICK: Duration = Duration::from_millis(100);
/// A run stops after this many ticks whatever happens.
pub const MAX_TICKS: u32 = 200;

/// What the world does during a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// Battery (percent) at the start.
    pub battery: u32,
    /// The run ends once the robot has reached this many waypoints.
    pub legs: usize,
    /// When someone presses the emergency stop, if anyone does.
    pub estop_at: Option<Duration>,
}

/// The scenarios `main` knows by name.
pub fn scenarios() -> [(&'static str, Scenario); 3] {
    let normal = Scenario {
        battery: 100,
        legs: 4,
        estop_at: None,
    };
    [
        ("normal", normal.clone()),
        (
            "low-battery",
            Scenario {
                battery: 28,
                ..normal.clone()
            },
        ),
        (
            "emergency-stop",
            Scenario {
                estop_at: Some(Duration::from_millis(600)),
                ..normal
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
    /// The waypoints reached, in order.
    pub visited: Vec<Cell>,
    /// Scans made.
    pub scans: u32,
    /// Full charges.
    pub charges: u32,
    /// The actions halted while running, in order.
    pub halted: Vec<String>,
    /// Whether the emergency stop shut the robot down.
    pub emergency_stopped: bool,
    /// Where the robot ended.
    pub position: Cell,
    /// Its battery (percent) at the end.
    pub battery: u32,
}

/// The simulated robot: the context `C` that every leaf of the tree receives.
#[derive(Debug)]
pub struct Robot {
    position: Cell,
    battery: u32,
    next_waypoint: usize,
    estop_pressed: bool,
    shut_down: bool,
    visited: Vec<Cell>,
    scans: u32,
    charges: u32,
    halted: Vec<String>,
    /// What happened during the current tick, for the log.
    events: Vec<String>,
}

impl Robot {
    fn new(battery: u32) -> Self {
        Self {
            position: CHARGER,
            battery,
            next_waypoint: 0,
            estop_pressed: false,
            shut_down: false,
            visited: Vec::new(),
            scans: 0,
            charges: 0,
            halted: Vec::new(),
            events: Vec::new(),
        }
    }

    fn note(&mut self, event: impl Into<String>) {
        self.events.push(event.into());
    }
}

fn estop_pressed(robot: &Robot) -> bool {
    robot.estop_pressed
}

fn emergency_stop(robot: &mut Robot) -> Status {
    robot.shut_down = true;
    robot.note("EMERGENCY STOP: motors off");
    Status::Success
}

fn battery_ok(robot: &Robot) -> bool {
    robot.battery > LOW_BATTERY
}

fn scan_area(robot: &mut Robot) -> Status {
    robot.scans += 1;
    let at = robot.position;
    robot.note(format!("scanning around {at:?}"));
    Status::Success
}

/// Where a [`Drive`] goes.
#[derive(Clone, Copy, Debug)]
enum Destination {
    /// The next waypoint of the patrol, which becomes the one after on arrival.
    NextWaypoint,
    Charger,
}

/// Drives one cell per tick (along x, then along y) towards its destination, paying
/// [`MOVE_COST`] per cell; fails when the battery cannot pay for the next cell.
struct Drive {
    to: Destination,
    target: Cell,
}

impl Drive {
    fn new(to: Destination) -> Self {
        Self {
            to,
            target: CHARGER,
        }
    }
}

impl StatefulAction<Robot> for Drive {
    fn on_start(&mut self, h: &mut Handle<'_, Robot>) -> Status {
        let robot = h.ctx_mut();
        self.target = match self.to {
            Destination::NextWaypoint => WAYPOINTS[robot.next_waypoint],
            Destination::Charger => CHARGER,
        };
        let target = self.target;
        robot.note(format!("heading for {target:?}"));
        self.on_running(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, Robot>) -> Status {
        let robot = h.ctx_mut();
        if robot.position != self.target {
            if robot.battery < MOVE_COST {
                robot.note("the battery is empty");
                return Status::Failure;
            }
            robot.position = step_towards(robot.position, self.target);
            robot.battery -= MOVE_COST;
        }
        if robot.position != self.target {
            return Status::Running;
        }
        if let Destination::NextWaypoint = self.to {
            robot.visited.push(self.target);
            robot.next_waypoint = (robot.next_waypoint + 1) % WAYPOINTS.len();
        }
        let target = self.target;
        robot.note(format!("reached {target:?}"));
        Status::Success
    }

    fn on_halted(&mut self, h: &mut Handle<'_, Robot>) {
        record_halt(h);
    }
}

/// The cell after `from` on the way to `to`: x first, then y.
fn step_towards(from: Cell, to: Cell) -> Cell {
    if from.0 != to.0 {
        (from.0 + (to.0 - from.0).signum(), from.1)
    } else {
        (from.0, from.1 + (to.1 - from.1).signum())
    }
}

/// Charges [`CHARGE_RATE`] per tick until full; fails off the charger.
struct Charge;

impl StatefulAction<Robot> for Charge {
    fn on_start(&mut self, h: &mut Handle<'_, Robot>) -> Status {
        if h.ctx().position != CHARGER {
            h.ctx_mut().note("not on the charger");
            return Status::Failure;
        }
        h.ctx_mut().note("docked: charging");
        self.on_running(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, Robot>) -> Status {
        let robot = h.ctx_mut();
        robot.battery = (robot.battery + CHARGE_RATE).min(100);
        if robot.battery < 100 {
            return Status::Running;
        }
        robot.charges += 1;
        robot.note("fully charged");
        Status::Success
    }

    fn on_halted(&mut self, h: &mut Handle<'_, Robot>) {
        record_halt(h);
    }
}

fn record_halt(h: &mut Handle<'_, Robot>) {
    let name = h.name().to_string();
    let robot = h.ctx_mut();
    let at = robot.position;
    robot.note(format!("{name} halted at {at:?}"));
    robot.halted.push(name);
}

/// The patrol tree, built with the fluent builder.
pub fn patrol_tree() -> Arc<Blueprint<Robot>> {
    let blueprint = Blueprint::builder()
        .reactive_fallback("robot", |root| {
            root.sequence("emergency", |s| {
                s.condition("estop_pressed", estop_pressed)
                    .action("emergency_stop", emergency_stop)
            })
            .fallback("main_patrol", |f| {
                f.sequence("normal_operation", |s| {
                    s.condition("battery_ok", battery_ok)
                        .action("scan_area", scan_area)
                        .stateful("move_patrol", || Drive::new(Destination::NextWaypoint))
                })
                .sequence("low_battery_protocol", |s| {
                    s.stateful("navigate_to_base", || Drive::new(Destination::Charger))
                        .stateful("charge_battery", || Charge)
                })
            })
        })
        .build_shared();
    // A fixed tree whose controls all have children: building it cannot fail.
    blueprint.expect("the patrol tree is valid")
}

/// The same tree, written with the `tree!` macro.
pub fn patrol_tree_from_macro() -> Arc<Blueprint<Robot>> {
    let blueprint = tree! {
        reactive_fallback("robot") {
            sequence("emergency") {
                condition("estop_pressed", estop_pressed),
                action("emergency_stop", emergency_stop),
            },
            fallback("main_patrol") {
                sequence("normal_operation") {
                    condition("battery_ok", battery_ok),
                    action("scan_area", scan_area),
                    stateful("move_patrol", || Drive::new(Destination::NextWaypoint)),
                },
                sequence("low_battery_protocol") {
                    stateful("navigate_to_base", || Drive::new(Destination::Charger)),
                    stateful("charge_battery", || Charge),
                },
            },
        }
    };
    // As for `patrol_tree`: a fixed, valid tree.
    Arc::new(blueprint.expect("the patrol tree is valid"))
}

/// Runs `scenario` until the robot has reached `legs` waypoints, shuts down or fails,
/// passing each line of a readable log to `log`.
pub fn run(scenario: &Scenario, mut log: impl FnMut(&str)) -> Result<Outcome, TickError> {
    let blueprint = patrol_tree();
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(Arc::clone(&blueprint), clock.clone());
    let seen = LastTickStatuses::new();
    tree.set_observer(seen.clone());
    let mut robot = Robot::new(scenario.battery);

    let mut status = Status::Running;
    let mut ticks = 0;
    let mut drawn_running = Vec::new();
    while ticks < MAX_TICKS {
        if !robot.estop_pressed && scenario.estop_at.is_some_and(|at| tree.now() >= at) {
            robot.estop_pressed = true;
            robot.note("someone presses the emergency stop");
        }
        ticks += 1;
        status = tree.tick_once(&mut robot)?;
        log(&format!(
            "tick {ticks:>3}  t = {:.1} s  robot at {:?}  battery {:>3}%  -> {status}",
            tree.now().as_secs_f64(),
            robot.position,
            robot.battery,
        ));
        for event in robot.events.drain(..) {
            log(&format!("          {event}"));
        }
        let done = robot.shut_down
            || status == Status::Failure
            || (status == Status::Success && robot.visited.len() >= scenario.legs);
        // Draw the tree when other nodes are running than at the last drawing, and at the end.
        let running = running_nodes(&seen);
        if done || (status == Status::Running && running != drawn_running) {
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
        visited: robot.visited,
        scans: robot.scans,
        charges: robot.charges,
        halted: robot.halted,
        emergency_stopped: robot.shut_down,
        position: robot.position,
        battery: robot.battery,
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
        writeln!(f, "  visited    {:?}", self.visited)?;
        writeln!(f, "  scans      {}", self.scans)?;
        writeln!(f, "  charges    {}", self.charges)?;
        writeln!(f, "  halted     {:?}", self.halted)?;
        writeln!(f, "  e-stopped  {}", self.emergency_stopped)?;
        write!(
            f,
            "  ended at   {:?} with {}% battery",
            self.position, self.battery
        )
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
