//! A survey drone on tokio: take off, fly the waypoints and survey each one, return home and
//! land, with a battery failsafe that takes over whenever the charge reaches the reserve.
//!
//! ```text
//! drone (Fallback)
//! ├── mission (ReactiveSequence)
//! │   ├── battery_above_reserve (Condition)    re-checked on every tick
//! │   └── flight_plan (Sequence)
//! │       ├── takeoff (AsyncAction)
//! │       ├── waypoint_0 (Sequence)
//! │       │   ├── fly_to (AsyncAction)
//! │       │   └── survey (AsyncAction)         image processing runs as a tokio task
//! │       ├── waypoint_1 …
//! │       ├── return_home (AsyncAction)
//! │       └── land (AsyncAction)
//! └── failsafe (ForceFailure)
//!     └── return_and_land (Sequence)
//!         ├── return_home (AsyncAction)
//!         └── land (AsyncAction)
//! ```
//!
//! Every action is an `async` block that awaits tokio timers (the drone moves one step per
//! 100 ms) or a spawned task. When the battery reaches the reserve, the reactive mission
//! halts what is running: the flight's future is dropped, so the drone stops where it is,
//! and a survey's processing task is aborted with it. The failsafe then flies home and
//! lands, and the mission ends in Failure even though the drone is safe.
//!
//! The runner ticks every 100 ms, and at once whenever an action's timer or task wakes it.
//! Time is simulated (tokio's paused clock), so the flight runs at once:
//!
//! ```text
//! cargo run -p neurotree --example drone_mission
//! cargo run -p neurotree --example drone_mission -- --low-battery
//! ```

use std::fmt::Write as _;
use std::future::Future;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::Duration;

use neurotree::render::render_unicode;
use neurotree::runtime::tokio::{spawn_abort_on_drop, tick_until_done, TokioClock};
use neurotree::{Blueprint, Handle, Status, Tree};
use tokio::time::{sleep, Instant};

/// How often the runner ticks when nothing wakes it; also the drone's control step.
pub const TICK_PERIOD: Duration = Duration::from_millis(100);
/// Vertical speed, metres per second.
const CLIMB_MPS: f64 = 2.0;
/// Horizontal speed, metres per second.
const CRUISE_MPS: f64 = 5.0;
/// Battery used per second in the air, percent.
const DRAIN_PCT_PER_S: f64 = 1.0;
/// How long processing a waypoint's images takes.
pub const SURVEY_TIME: Duration = Duration::from_secs(2);

/// A position in metres: east, north, up; home is the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// East.
    pub x: f64,
    /// North.
    pub y: f64,
    /// Up.
    pub z: f64,
}

impl Point {
    /// The point at `x`, `y`, `z`.
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        Self { x, y, z }
    }

    fn distance(self, to: Point) -> f64 {
        ((to.x - self.x).powi(2) + (to.y - self.y).powi(2) + (to.z - self.z).powi(2)).sqrt()
    }
}

/// What the mission is asked to do.
#[derive(Clone, Debug, PartialEq)]
pub struct MissionConfig {
    /// The waypoints to survey, in order (east, north), flown at `altitude`.
    pub waypoints: Vec<(f64, f64)>,
    /// Cruise altitude, metres.
    pub altitude: f64,
    /// Battery charge at takeoff, percent.
    pub battery_pct: f64,
    /// The failsafe takes over when the charge is no longer above this, percent.
    pub reserve_pct: f64,
}

impl Default for MissionConfig {
    /// Three waypoints of a 40 m × 30 m field, on a full battery: a 44 s flight.
    fn default() -> Self {
        Self {
            waypoints: vec![(40.0, 0.0), (40.0, 30.0), (0.0, 30.0)],
            altitude: 10.0,
            battery_pct: 100.0,
            reserve_pct: 25.0,
        }
    }
}

impl MissionConfig {
    /// The same field on half a battery: the reserve is reached while surveying the
    /// second waypoint.
    pub fn low_battery() -> Self {
        Self {
            battery_pct: 50.0,
            reserve_pct: 27.75,
            ..Self::default()
        }
    }
}

/// How a mission ended.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// What the tree's root completed with: Failure when the failsafe took over.
    pub status: Status,
    /// The waypoints reached, in order.
    pub visited: Vec<usize>,
    /// The surveys completed: waypoint and objects detected.
    pub surveys: Vec<(usize, u32)>,
    /// Survey processing tasks aborted because their node was halted.
    pub aborted_surveys: u32,
    /// `true` if the failsafe took over.
    pub failsafe: bool,
    /// Where the drone landed, `None` if it did not.
    pub landed_at: Option<Point>,
    /// Battery charge at the end, percent.
    pub battery_pct: f64,
    /// From the start of the takeoff to touchdown (or the end of the run).
    pub flight_time: Duration,
    /// Ticks of the tree.
    pub ticks: u64,
    /// What happened, one line per event, with its time.
    pub log: Vec<String>,
}

/// The simulated drone, shared by the tree's context and the actions' futures.
#[derive(Clone)]
pub struct Drone(Arc<Mutex<DroneState>>);

struct DroneState {
    /// The mission's start, for the log's times.
    origin: Instant,
    pos: Point,
    /// Charge when the drone last took off or landed.
    charge_pct: f64,
    /// When the drone took off, while it is in the air.
    airborne_since: Option<Instant>,
    took_off: Option<Instant>,
    landed: Option<Instant>,
    visited: Vec<usize>,
    surveys: Vec<(usize, u32)>,
    aborted_surveys: u32,
    log: Vec<String>,
}

impl Drone {
    fn new(charge_pct: f64) -> Self {
        Self(Arc::new(Mutex::new(DroneState {
            origin: Instant::now(),
            pos: Point::new(0.0, 0.0, 0.0),
            charge_pct,
            airborne_since: None,
            took_off: None,
            landed: None,
            visited: Vec::new(),
            surveys: Vec::new(),
            aborted_surveys: 0,
            log: Vec::new(),
        })))
    }

    fn state(&self) -> MutexGuard<'_, DroneState> {
        // A panic elsewhere cannot leave the state half-written: every change is one
        // assignment under the lock.
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The charge now: it drains while the drone is in the air.
    pub fn battery_pct(&self) -> f64 {
        self.state().battery_pct()
    }

    fn position(&self) -> Point {
        self.state().pos
    }

    fn log(&self, event: String) {
        let mut s = self.state();
        let at = s.origin.elapsed().as_secs_f64();
        s.log.push(format!("[{at:5.1} s] {event}"));
    }

    fn take_off(&self) {
        let mut s = self.state();
        let now = Instant::now();
        s.airborne_since = Some(now);
        s.took_off.get_or_insert(now);
    }

    fn touch_down(&self) {
        let mut s = self.state();
        s.charge_pct = s.battery_pct();
        s.airborne_since = None;
        s.landed = Some(Instant::now());
    }

    /// Moves up to `step` metres toward `target`.
    fn move_toward(&self, target: Point, step: f64) {
        let mut s = self.state();
        let d = s.pos.distance(target);
        // Within a step (and a rounding error) the drone arrives exactly.
        if d <= step + 1e-9 {
            s.pos = target;
            return;
        }
        let k = step / d;
        s.pos = Point::new(
            s.pos.x + (target.x - s.pos.x) * k,
            s.pos.y + (target.y - s.pos.y) * k,
            s.pos.z + (target.z - s.pos.z) * k,
        );
    }

    fn outcome(&self, status: Status, ticks: u64, failsafe: bool) -> Outcome {
        let s = self.state();
        let end = s.landed.unwrap_or_else(Instant::now);
        Outcome {
            status,
            visited: s.visited.clone(),
            surveys: s.surveys.clone(),
            aborted_surveys: s.aborted_surveys,
            failsafe,
            landed_at: s.landed.map(|_| s.pos),
            battery_pct: s.battery_pct(),
            flight_time: s.took_off.map_or(Duration::ZERO, |t| end - t),
            ticks,
            log: s.log.clone(),
        }
    }
}

impl DroneState {
    fn battery_pct(&self) -> f64 {
        let used = self
            .airborne_since
            .map_or(0.0, |t| t.elapsed().as_secs_f64() * DRAIN_PCT_PER_S);
        (self.charge_pct - used).max(0.0)
    }
}

/// The tree's context: the drone and the mission's rules.
pub struct Mission {
    /// The drone the actions fly.
    pub drone: Drone,
    /// See [`MissionConfig::reserve_pct`].
    pub reserve_pct: f64,
    /// Set when the failsafe starts.
    pub failsafe: bool,
}

/// Logs that a flight was stopped if it is dropped before it arrives: dropping is how a
/// halted async action stops.
struct StopGuard {
    drone: Drone,
    what: String,
    arrived: bool,
}

impl Drop for StopGuard {
    fn drop(&mut self) {
        if !self.arrived {
            let p = self.drone.position();
            self.drone.log(format!(
                "{} halted: hovering at ({:.1}, {:.1}, {:.1})",
                self.what, p.x, p.y, p.z
            ));
        }
    }
}

/// Flies to `target` at `speed`, one step per [`TICK_PERIOD`]; dropped, the drone stops.
async fn fly(drone: Drone, what: String, target: Point, speed: f64) -> Status {
    let step = speed * TICK_PERIOD.as_secs_f64();
    let mut guard = StopGuard {
        drone,
        what,
        arrived: false,
    };
    // Arrival puts the drone exactly on the target.
    while guard.drone.position() != target {
        sleep(TICK_PERIOD).await;
        guard.drone.move_toward(target, step);
    }
    guard.arrived = true;
    Status::Success
}

fn takeoff(h: &mut Handle<'_, Mission>, altitude: f64) -> impl Future<Output = Status> + use<> {
    let drone = h.ctx().drone.clone();
    async move {
        drone.log(format!(
            "takeoff to {altitude} m, battery {:.1}%",
            drone.battery_pct()
        ));
        drone.take_off();
        let status = fly(
            drone.clone(),
            "takeoff".into(),
            Point::new(0.0, 0.0, altitude),
            CLIMB_MPS,
        )
        .await;
        drone.log(format!("at {altitude} m"));
        status
    }
}

fn fly_to(
    h: &mut Handle<'_, Mission>,
    index: usize,
    target: Point,
) -> impl Future<Output = Status> + use<> {
    let drone = h.ctx().drone.clone();
    async move {
        let what = format!("flight to waypoint {index}");
        let status = fly(drone.clone(), what, target, CRUISE_MPS).await;
        drone.state().visited.push(index);
        drone.log(format!(
            "waypoint {index} reached, battery {:.1}%",
            drone.battery_pct()
        ));
        status
    }
}

/// Counts a processing task as aborted if it is dropped before it finished.
struct AbortGuard {
    drone: Drone,
    finished: bool,
}

impl Drop for AbortGuard {
    fn drop(&mut self) {
        if !self.finished {
            self.drone.state().aborted_surveys += 1;
            self.drone.log("survey processing aborted".into());
        }
    }
}

/// The camera's image processing: a task of its own, as real processing would be.
async fn process_images(drone: Drone, index: usize) -> u32 {
    let mut guard = AbortGuard {
        drone,
        finished: false,
    };
    sleep(SURVEY_TIME).await;
    guard.finished = true;
    // A stand-in for what the images show.
    (index as u32 * 3 + 2) % 5
}

fn survey(h: &mut Handle<'_, Mission>, index: usize) -> impl Future<Output = Status> + use<> {
    let drone = h.ctx().drone.clone();
    async move {
        drone.log(format!("surveying waypoint {index}"));
        // Halting the node drops this future and the handle in it, which aborts the task.
        let processing = spawn_abort_on_drop(process_images(drone.clone(), index));
        match processing.await {
            Ok(found) => {
                drone.state().surveys.push((index, found));
                drone.log(format!("waypoint {index}: {found} objects found"));
                Status::Success
            }
            Err(_) => Status::Failure,
        }
    }
}

fn return_home(h: &mut Handle<'_, Mission>, altitude: f64) -> impl Future<Output = Status> + use<> {
    let drone = h.ctx().drone.clone();
    async move {
        drone.log(format!(
            "returning home, battery {:.1}%",
            drone.battery_pct()
        ));
        fly(
            drone,
            "return home".into(),
            Point::new(0.0, 0.0, altitude),
            CRUISE_MPS,
        )
        .await
    }
}

fn land(h: &mut Handle<'_, Mission>) -> impl Future<Output = Status> + use<> {
    let drone = h.ctx().drone.clone();
    async move {
        let here = drone.position();
        let ground = Point::new(here.x, here.y, 0.0);
        let status = fly(drone.clone(), "landing".into(), ground, CLIMB_MPS).await;
        drone.touch_down();
        drone.log(format!("landed, battery {:.1}%", drone.battery_pct()));
        status
    }
}

/// The mission's tree (see the module's picture).
pub fn mission_tree(config: &MissionConfig) -> Arc<Blueprint<Mission>> {
    let altitude = config.altitude;
    let waypoints = config.waypoints.clone();
    Blueprint::<Mission>::builder()
        .fallback("drone", |f| {
            f.reactive_sequence("mission", |m| {
                m.condition("battery_above_reserve", |m: &Mission| {
                    m.drone.battery_pct() > m.reserve_pct
                })
                .sequence("flight_plan", |mut plan| {
                    plan = plan.async_action("takeoff", move |h| takeoff(h, altitude));
                    for (i, &(x, y)) in waypoints.iter().enumerate() {
                        let target = Point::new(x, y, altitude);
                        plan = plan.sequence(&format!("waypoint_{i}"), |w| {
                            w.async_action("fly_to", move |h| fly_to(h, i, target))
                                .async_action("survey", move |h| survey(h, i))
                        });
                    }
                    plan.async_action("return_home", move |h| return_home(h, altitude))
                        .async_action("land", land)
                })
            })
            .force_failure("failsafe", |ff| {
                ff.sequence("return_and_land", |s| {
                    s.async_action("return_home", move |h| {
                        h.ctx_mut().failsafe = true;
                        let drone = h.ctx().drone.clone();
                        drone.log(format!(
                            "FAILSAFE: battery {:.1}% at the {}% reserve",
                            drone.battery_pct(),
                            h.ctx().reserve_pct
                        ));
                        return_home(h, altitude)
                    })
                    .async_action("land", land)
                })
            })
        })
        .build_shared()
        // Built from code with every control given children: no build error can occur.
        .expect("the mission tree is valid")
}

/// Flies the mission on the current tokio runtime and reports how it went.
pub async fn run(config: MissionConfig) -> Outcome {
    let drone = Drone::new(config.battery_pct);
    let mut mission = Mission {
        drone: drone.clone(),
        reserve_pct: config.reserve_pct,
        failsafe: false,
    };
    let mut tree = Tree::with_clock(mission_tree(&config), TokioClock::new());
    let (status, ticks) = match tick_until_done(&mut tree, &mut mission, TICK_PERIOD).await {
        Ok(run) => (run.status, run.ticks),
        Err(e) => {
            drone.log(format!("tick error: {e}"));
            (Status::Failure, 0)
        }
    };
    drone.outcome(status, ticks, mission.failsafe)
}

#[tokio::main(flavor = "current_thread", start_paused = true)]
async fn main() {
    let low_battery = std::env::args().any(|a| a == "--low-battery");
    let config = if low_battery {
        MissionConfig::low_battery()
    } else {
        MissionConfig::default()
    };
    let picture = render_unicode(&Tree::with_clock(mission_tree(&config), TokioClock::new()));
    println!("{picture}");
    let outcome = run(config).await;
    let mut report = String::new();
    for line in &outcome.log {
        let _ = writeln!(report, "{line}");
    }
    let _ = writeln!(
        report,
        "\n{:?} after {} ticks: waypoints {:?}, surveys {:?}, {:.1} s in the air, battery {:.1}%{}",
        outcome.status,
        outcome.ticks,
        outcome.visited,
        outcome.surveys,
        outcome.flight_time.as_secs_f64(),
        outcome.battery_pct,
        if outcome.failsafe { ", failsafe" } else { "" }
    );
    print!("{report}");
}
