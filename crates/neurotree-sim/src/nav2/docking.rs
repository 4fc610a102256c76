//! Docking: the docks the docking server knows, DockRobot and UndockRobot.
//!
//! A [`Dock`] has an id, a type and a pose: the robot is docked when it stands on that pose,
//! having driven onto it along the pose's heading from the dock's staging pose,
//! [`Dock::staging_distance`] metres before it. A dock on the world's charger cell is a
//! charging dock. Docks are given with [`Nav2Sim::with_dock`](super::Nav2Sim::with_dock).
//!
//! - **DockRobot**: a stateful action. Ports `use_dock_id` (default true), `dock_id`,
//!   `dock_pose`, `dock_type`, `max_staging_time` (default 1000 s),
//!   `navigate_to_staging_pose` (default true); outputs `success`, `num_retries` (always 0),
//!   `error_code_id`, `error_msg`. As Nav2's docking server:
//!   - The dock: the one of id `dock_id` (DOCK_NOT_IN_DB 901 when none has it), or with
//!     `use_dock_id` false a dock at `dock_pose` of type `dock_type` (DOCK_NOT_VALID 902
//!     when no known dock has that type).
//!   - With `navigate_to_staging_pose`, a path to the staging pose is planned and followed
//!     (FAILED_TO_STAGE 903 when there is none, when the robot is blocked on the way, or
//!     past `max_staging_time`); then the robot drives straight onto the dock
//!     (FAILED_TO_CONTROL 905 when blocked).
//!   - On a charging dock the battery must then charge, or be full (FAILED_TO_CHARGE 906
//!     otherwise). Success: `success` true, error code 0; the dock's type becomes the
//!     current one, for UndockRobot.
//!   - An empty battery on the way: UNKNOWN 999. Halt stops the motion.
//! - **UndockRobot**: a stateful action. Ports `dock_type`, `max_undocking_time` (default
//!   30 s); outputs `success`, `error_code_id`, `error_msg`. The type is `dock_type`, or
//!   the current one when empty; no type, or one no dock has: DOCK_NOT_VALID 902. The robot
//!   must stand on a dock of that type (Nav2's server leaves the goal without a result then;
//!   here: DOCK_NOT_VALID 902). It backs straight off to the staging pose: Success;
//!   blocked, or past `max_undocking_time`: FAILED_TO_CONTROL 905, as Nav2's server counts
//!   an undocking timeout. Halt stops the motion.
//!
//! Nav2's server detects the dock with a sensor and servoes onto it; the simulated robot
//! knows the dock's pose, so it never needs a retry.

use std::time::Duration;

use neurotree_core::{Handle, StatefulAction, Status};

use super::codes::docking as code;
use super::{planner, ports, Nav2Context, Nav2Sim};
use crate::MotionStatus;
use neurotree_nav2::robotics::Pose2D;
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

/// How close to a pose counts as standing on it, in metres.
const ON_POSE: f64 = 0.05;

/// A dock the docking server knows: see the [module documentation](self).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Dock {
    /// Its id, for DockRobot's `dock_id`.
    pub id: String,
    /// Its type (Nav2's dock plugin), for `dock_type`.
    pub dock_type: String,
    /// Where the robot stands when docked, facing the way it drove on.
    pub pose: Pose2D,
    /// How far before the dock the staging pose is, in metres.
    pub staging_distance: f64,
}

impl Dock {
    /// Dock `id` of type `dock_type` at `pose`, its staging pose one metre before it.
    pub fn new(id: &str, dock_type: &str, pose: Pose2D) -> Self {
        Self {
            id: id.to_string(),
            dock_type: dock_type.to_string(),
            pose,
            staging_distance: 1.0,
        }
    }

    /// Where the robot goes before driving onto the dock: `staging_distance` back along
    /// the dock's heading, facing the dock.
    pub fn staging_pose(&self) -> Pose2D {
        let (sin, cos) = self.pose.theta.sin_cos();
        Pose2D::new(
            self.pose.x - self.staging_distance * cos,
            self.pose.y - self.staging_distance * sin,
            self.pose.theta,
        )
    }
}

fn server_ports() -> [PortSpec; 5] {
    [
        PortSpec::input::<String>("server_name").describe("Action server name (unused)."),
        PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
        PortSpec::output::<bool>("success").describe("Whether it succeeded."),
        PortSpec::output::<u16>("error_code_id").describe("0, or the docking error code."),
        PortSpec::output::<String>("error_msg").describe("Why it failed; empty on success."),
    ]
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    let mut dock = vec![
        PortSpec::input::<bool>("use_dock_id")
            .default_value("true")
            .describe("Find the dock by `dock_id` rather than `dock_pose`."),
        PortSpec::input::<String>("dock_id").describe("The dock's id."),
        PortSpec::input::<Pose2D>("dock_pose").describe("The dock's pose."),
        PortSpec::input::<String>("dock_type").describe("The dock's type."),
        PortSpec::input::<f64>("max_staging_time")
            .default_value("1000.0")
            .describe("Seconds allowed to reach the staging pose."),
        PortSpec::input::<bool>("navigate_to_staging_pose")
            .default_value("true")
            .describe("Drive to the staging pose first."),
    ];
    let mut server = server_ports().to_vec();
    // Nav2's order: after `success`.
    server.insert(
        3,
        PortSpec::output::<u16>("num_retries").describe("Retries made (always 0)."),
    );
    dock.extend(server);
    r.register_stateful("DockRobot", dock, DockRobot::default)?;
    r.describe(
        "DockRobot",
        "Drives to a dock's staging pose, then onto the dock.",
    );
    let mut undock = vec![
        PortSpec::input::<String>("dock_type")
            .describe("The dock's type; the current one when empty."),
        PortSpec::input::<f64>("max_undocking_time")
            .default_value("30.0")
            .describe("Seconds allowed to undock."),
    ];
    undock.extend(server_ports());
    r.register_stateful("UndockRobot", undock, UndockRobot::default)?;
    r.describe("UndockRobot", "Backs off the dock to its staging pose.");
    Ok(())
}

/// A failure: code, reason, message.
type Failed = (u16, &'static str, String);

fn fail<C>(h: &mut Handle<'_, C>, (code, why, message): Failed) -> Status {
    ports::emit(h, "success", false);
    ports::fail(h, code, why, message)
}

fn succeed<C>(h: &mut Handle<'_, C>) -> Status {
    ports::emit(h, "success", true);
    ports::succeed(h)
}

/// Where DockRobot is.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
enum Phase {
    #[default]
    Idle,
    /// Following a path to the staging pose, since the time given.
    Staging(Duration),
    /// Driving onto the dock.
    Docking,
}

/// DockRobot: see the [module documentation](self).
#[derive(Default)]
struct DockRobot {
    dock: Option<Dock>,
    phase: Phase,
    max_staging: Duration,
}

impl DockRobot {
    fn start<C: Nav2Context>(&mut self, h: &mut Handle<'_, C>) -> Result<(), Failed> {
        let bad = |e: neurotree_core::PortError| (code::UNKNOWN, "bad input", e.to_string());
        let use_id: bool = ports::or(h, "use_dock_id", true).map_err(bad)?;
        let navigate: bool = ports::or(h, "navigate_to_staging_pose", true).map_err(bad)?;
        let staging: f64 = ports::or(h, "max_staging_time", 1000.0).map_err(bad)?;
        self.max_staging = Duration::try_from_secs_f64(staging.max(0.0)).unwrap_or(Duration::MAX);
        let docks = h.ctx().nav2().docks();
        let dock = if use_id {
            let id: String = ports::or(h, "dock_id", String::new()).map_err(bad)?;
            docks.iter().find(|d| d.id == id).cloned().ok_or((
                code::DOCK_NOT_IN_DB,
                "dock not in database",
                format!("no dock has the id `{id}`"),
            ))?
        } else {
            let pose: Pose2D = ports::or(h, "dock_pose", Pose2D::default()).map_err(bad)?;
            let kind: String = ports::or(h, "dock_type", String::new()).map_err(bad)?;
            let known = docks.iter().find(|d| d.dock_type == kind).ok_or((
                code::DOCK_NOT_VALID,
                "dock not valid",
                format!("no dock is of the type `{kind}`"),
            ))?;
            Dock {
                id: String::new(),
                pose,
                ..known.clone()
            }
        };
        let sim = h.ctx_mut().nav2_mut();
        if navigate {
            let staging = dock.staging_pose();
            let from = sim.world.robot();
            let path = planner::plan_through(&mut sim.world, from, &[], staging)
                .map_err(|(_, _, message)| (code::FAILED_TO_STAGE, "failed to stage", message))?;
            sim.world.follow(path, sim.params.speed);
            self.phase = Phase::Staging(h.now());
        } else {
            drive_onto(sim, &dock);
            self.phase = Phase::Docking;
        }
        self.dock = Some(dock);
        Ok(())
    }

    fn progress<C: Nav2Context>(&mut self, h: &mut Handle<'_, C>) -> Result<Status, Failed> {
        let Some(dock) = self.dock.clone() else {
            return Err((code::UNKNOWN, "no dock", "no dock to dock at".into()));
        };
        let now = h.now();
        let sim = h.ctx_mut().nav2_mut();
        let status = sim.world.motion_status();
        if let MotionStatus::BatteryEmpty = status {
            return Err((
                code::UNKNOWN,
                "battery empty",
                "the battery is empty".into(),
            ));
        }
        match (&self.phase, status) {
            (_, MotionStatus::Active) => {
                if let Phase::Staging(since) = self.phase {
                    if now.saturating_sub(since) > self.max_staging {
                        sim.world.stop();
                        let message = "the staging pose was not reached in time".to_string();
                        return Err((code::FAILED_TO_STAGE, "failed to stage", message));
                    }
                }
                Ok(Status::Running)
            }
            (Phase::Staging(_), MotionStatus::Succeeded) => {
                drive_onto(sim, &dock);
                self.phase = Phase::Docking;
                Ok(Status::Running)
            }
            (Phase::Docking, MotionStatus::Succeeded) => {
                let on_charger = sim.world.charger() == sim.world.map().cell_at(&dock.pose);
                let charges = sim.world.is_on_charger();
                if on_charger && !charges {
                    let message = "docked, but the battery does not charge".to_string();
                    return Err((code::FAILED_TO_CHARGE, "failed to charge", message));
                }
                sim.current_dock_type = Some(dock.dock_type.clone());
                let id = dock.id.clone();
                sim.note(|| format!("DockRobot: docked at `{id}`"));
                Ok(Status::Success)
            }
            (Phase::Staging(_), MotionStatus::Blocked(cell)) => Err((
                code::FAILED_TO_STAGE,
                "failed to stage",
                format!("blocked on the way to the staging pose in cell {cell}"),
            )),
            (_, MotionStatus::Blocked(cell)) => Err((
                code::FAILED_TO_CONTROL,
                "failed to control",
                format!("blocked driving onto the dock in cell {cell}"),
            )),
            // Stopped by someone else: cancelled, as Nav2's node ends then.
            _ => Ok(Status::Success),
        }
    }
}

/// Starts the straight drive from where the robot is onto `dock`.
fn drive_onto(sim: &mut Nav2Sim, dock: &Dock) {
    let distance = sim.world.robot().distance(&dock.pose);
    sim.world.drive_on_heading(distance, sim.params.speed);
}

impl<C: Nav2Context> StatefulAction<C> for DockRobot {
    /// The dock, the phase (with when staging began) and the staging time allowed; the
    /// motion itself is the world's, saved with it.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(
            &self.dock,
            &self.phase,
            self.max_staging,
        )))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(dock, phase, max)| {
                (self.dock, self.phase, self.max_staging) = (dock, phase, max)
            })
            .is_some()
    }

    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        ports::emit(h, "num_retries", 0_u16);
        match self.start(h) {
            Ok(()) => Status::Running,
            Err(failed) => fail(h, failed),
        }
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        match self.progress(h) {
            Ok(Status::Success) => succeed(h),
            Ok(status) => status,
            Err(failed) => fail(h, failed),
        }
    }

    fn on_halted(&mut self, h: &mut Handle<'_, C>) {
        h.ctx_mut().nav2_mut().world.stop();
    }
}

/// UndockRobot: see the [module documentation](self).
#[derive(Default)]
struct UndockRobot {
    started: Duration,
    allowed: Duration,
}

impl UndockRobot {
    fn start<C: Nav2Context>(&mut self, h: &mut Handle<'_, C>) -> Result<(), Failed> {
        let bad = |e: neurotree_core::PortError| (code::UNKNOWN, "bad input", e.to_string());
        let given: String = ports::or(h, "dock_type", String::new()).map_err(bad)?;
        let seconds: f64 = ports::or(h, "max_undocking_time", 30.0).map_err(bad)?;
        self.allowed = Duration::try_from_secs_f64(seconds.max(0.0)).unwrap_or(Duration::MAX);
        self.started = h.now();
        let sim = h.ctx_mut().nav2_mut();
        let kind = if given.is_empty() {
            sim.current_dock_type.clone().unwrap_or_default()
        } else {
            given
        };
        let not_valid = |message: String| (code::DOCK_NOT_VALID, "dock not valid", message);
        if !sim.docks().iter().any(|d| d.dock_type == kind) {
            return Err(not_valid(format!(
                "no dock information to undock from (`{kind}`)"
            )));
        }
        let robot = sim.world.robot();
        let dock = sim
            .docks()
            .iter()
            .find(|d| d.dock_type == kind && d.pose.distance(&robot) <= ON_POSE)
            .cloned()
            .ok_or_else(|| not_valid(format!("the robot is on no dock of the type `{kind}`")))?;
        sim.world.back_up(dock.staging_distance, sim.params.speed);
        Ok(())
    }
}

impl<C: Nav2Context> StatefulAction<C> for UndockRobot {
    /// When undocking began and how long it may take; the motion is the world's.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(self.started, self.allowed)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(started, allowed)| (self.started, self.allowed) = (started, allowed))
            .is_some()
    }

    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        match self.start(h) {
            Ok(()) => Status::Running,
            Err(failed) => fail(h, failed),
        }
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        let late = h.now().saturating_sub(self.started) > self.allowed;
        let sim = h.ctx_mut().nav2_mut();
        let failed = match sim.world.motion_status() {
            MotionStatus::Active if late => {
                sim.world.stop();
                (
                    code::FAILED_TO_CONTROL,
                    "failed to control",
                    "undocking timed out".to_string(),
                )
            }
            MotionStatus::Active => return Status::Running,
            MotionStatus::Succeeded => {
                sim.current_dock_type = None;
                sim.note(|| "UndockRobot: undocked".to_string());
                return succeed(h);
            }
            MotionStatus::Blocked(cell) => (
                code::FAILED_TO_CONTROL,
                "failed to control",
                format!("blocked backing off the dock in cell {cell}"),
            ),
            MotionStatus::BatteryEmpty => (
                code::UNKNOWN,
                "battery empty",
                "the battery is empty".to_string(),
            ),
            MotionStatus::Idle => return succeed(h),
        };
        fail(h, failed)
    }

    fn on_halted(&mut self, h: &mut Handle<'_, C>) {
        h.ctx_mut().nav2_mut().world.stop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;
    use crate::{Battery, GridWorld};
    use Status::{Failure as F, Success as S};

    /// A corridor with the charger at its west end; the dock faces west.
    fn docked_world(level: f64) -> GridWorld {
        GridWorld::parse("#C...R#", 1.0)
            .unwrap()
            .with_battery(Battery::at(level))
    }

    fn dock() -> Dock {
        Dock::new(
            "home",
            "charging_dock",
            Pose2D::new(1.5, 0.5, std::f64::consts::PI),
        )
    }

    fn bench(world: GridWorld, xml: &str) -> Bench {
        let mut b = Bench::with_world(world, xml);
        b.sim.docks.push(dock());
        b
    }

    #[test]
    fn the_staging_pose_is_before_the_dock_facing_it() {
        let staging = dock().staging_pose();
        assert!((staging.x - 2.5).abs() < 1e-9 && (staging.y - 0.5).abs() < 1e-9);
        assert_eq!(staging.theta, std::f64::consts::PI);
    }

    #[test]
    fn docking_drives_to_the_staging_pose_then_onto_the_charger() {
        let mut b = bench(
            docked_world(50.0),
            r#"<DockRobot dock_id="home" success="{ok}" error_code_id="{code}"/>"#,
        );
        let run = b.run(200);
        assert_eq!(run.last(), Some(&S), "{run:?}");
        // Three metres to the staging pose at 1 m/s, seen at tick 31, then one onto the
        // dock: ten steps and a rounding hair, seen at tick 43.
        assert_eq!(run.len(), 43);
        assert!(b.sim.world.robot().distance(&dock().pose) < 1e-9);
        assert!(b.get::<bool>("ok"));
        assert_eq!(b.get::<u16>("code"), 0);
        assert_eq!(b.sim.current_dock_type.as_deref(), Some("charging_dock"));
    }

    #[test]
    fn an_unknown_dock_fails_at_once() {
        let mut b = bench(
            docked_world(50.0),
            r#"<DockRobot dock_id="elsewhere" success="{ok}" error_code_id="{code}"/>"#,
        );
        assert_eq!(b.run(5), [F]);
        assert_eq!(b.get::<u16>("code"), code::DOCK_NOT_IN_DB);
        assert!(!b.get::<bool>("ok"));
        let mut b = bench(
            docked_world(50.0),
            r#"<DockRobot use_dock_id="false" dock_pose="1.5;0.5" dock_type="other" error_code_id="{code}"/>"#,
        );
        assert_eq!(b.run(5), [F]);
        assert_eq!(b.get::<u16>("code"), code::DOCK_NOT_VALID);
    }

    #[test]
    fn undocking_backs_off_to_the_staging_pose() {
        let mut world = docked_world(50.0);
        world.set_robot(dock().pose).unwrap();
        let mut b = bench(
            world,
            r#"<UndockRobot dock_type="{type}" error_code_id="{code}"/>"#,
        );
        b.set("type", "charging_dock".to_string());
        let run = b.run(50);
        // One metre at 1 m/s: ten steps and a rounding hair.
        assert_eq!((run.len(), run.last()), (12, Some(&S)));
        assert!(b.sim.world.robot().distance(&dock().staging_pose()) < 1e-9);
        // Off the dock, and no current type: nothing to undock from.
        b.set("type", String::new());
        b.tree.halt(&mut b.sim);
        assert_eq!(b.run(5), [F]);
        assert_eq!(b.get::<u16>("code"), code::DOCK_NOT_VALID);
    }
}
