//! Spin, Wait, BackUp and DriveOnHeading: Nav2's behaviors, as the world's motions.
//!
//! All four are stateful actions.
//!
//! - **Spin**, ports `spin_dist` (default 1.57) and `time_allowance` (default 10): turns on the
//!   spot by `spin_dist` radians at the spin rate. Success when turned; Failure TIMEOUT 701
//!   past the time allowance, UNKNOWN 700 with an empty battery. Halt stops the motion.
//! - **Wait**, port `wait_duration` (default 1.0): stands still for `wait_duration` seconds.
//!   Success; halt stops the wait.
//! - **BackUp**, ports `backup_dist` (default 0.15), `backup_speed` (default 0.025) and
//!   `time_allowance` (default 10): drives backwards `backup_dist` metres at `backup_speed`.
//!   Success; Failure COLLISION_AHEAD 714 against a wall or an obstacle, TIMEOUT 711 past the
//!   time allowance, INVALID_INPUT 713 for a zero speed or a number that is not finite. Halt
//!   stops the motion.
//! - **DriveOnHeading**, ports `dist_to_travel` (default 0.15), `speed` (default 0.025) and
//!   `time_allowance` (default 10): drives straight on, without turning, `dist_to_travel`
//!   metres at `speed` (backwards when both are negative). Success; Failure
//!   COLLISION_AHEAD 723, TIMEOUT 721, INVALID_INPUT 724 for a zero speed, signs that
//!   differ or a number that is not finite, as Nav2's `drive_on_heading.hpp` checks. Halt
//!   stops the motion.
//!
//! Each starts its motion on the tick from Idle (Running) and reads the motion's outcome
//! on later ticks, after the world has stepped. A motion stopped by someone else (CancelSpin,
//! CancelWait, ... — see [`cancels`](super::cancels)) ends the node with Success and error
//! code 0, as Nav2's nodes end when their goal is cancelled (`on_cancelled`).

use std::time::Duration;

use neurotree_core::{Handle, StatefulAction, Status};

use super::codes::{back_up, drive_on_heading, spin};
use super::{ports, Nav2Context};
use crate::MotionStatus;
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

/// Which behavior a [`Behavior`] node is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Spin,
    Wait,
    BackUp,
    DriveOnHeading,
}

impl Kind {
    /// The codes for a failure of no other kind, for a timeout and for a collision. Wait
    /// reports none: it cannot collide or run late, and only fails when another motion
    /// replaced it.
    fn codes(self) -> (u16, u16, u16) {
        match self {
            Kind::Spin => (spin::UNKNOWN, spin::TIMEOUT, spin::COLLISION_AHEAD),
            Kind::BackUp => (back_up::UNKNOWN, back_up::TIMEOUT, back_up::COLLISION_AHEAD),
            Kind::DriveOnHeading => (
                drive_on_heading::UNKNOWN,
                drive_on_heading::TIMEOUT,
                drive_on_heading::COLLISION_AHEAD,
            ),
            Kind::Wait => (0, 0, 0),
        }
    }
}

/// The ports every behavior ends with.
fn server_ports(what: &str) -> [PortSpec; 4] {
    [
        PortSpec::input::<String>("server_name").describe("Action server name (unused)."),
        PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
        PortSpec::output::<u16>("error_code_id").describe(&format!("0, or the {what} error code.")),
        PortSpec::output::<String>("error_msg").describe("Why it failed; empty on success."),
    ]
}

fn time_allowance() -> PortSpec {
    PortSpec::input::<f64>("time_allowance")
        .default_value("10.0")
        .describe("Seconds the behavior may take before it fails.")
}

fn collision_checks() -> PortSpec {
    PortSpec::input::<bool>("disable_collision_checks")
        .default_value("false")
        .describe("Unused: the world never lets the robot into an occupied cell.")
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    let mut spin_ports = vec![
        PortSpec::input::<f64>("spin_dist")
            .default_value("1.57")
            .describe("Radians to turn, counter-clockwise when positive."),
        time_allowance(),
        PortSpec::input::<bool>("is_recovery")
            .default_value("true")
            .describe("Whether the spin counts as a recovery (unused)."),
        collision_checks(),
    ];
    spin_ports.extend(server_ports("spin"));
    r.register_stateful("Spin", spin_ports, || Behavior::new(Kind::Spin))?;
    r.describe("Spin", "Turns on the spot by `spin_dist` radians.");

    let mut wait_ports = vec![PortSpec::input::<f64>("wait_duration")
        .default_value("1.0")
        .describe("Seconds to wait.")];
    wait_ports.extend(server_ports("wait"));
    r.register_stateful("Wait", wait_ports, || Behavior::new(Kind::Wait))?;
    r.describe("Wait", "Stands still for `wait_duration` seconds.");

    let mut back_up_ports = vec![
        PortSpec::input::<f64>("backup_dist")
            .default_value("0.15")
            .describe("Metres to drive backwards."),
        PortSpec::input::<f64>("backup_speed")
            .default_value("0.025")
            .describe("Metres per second."),
        time_allowance(),
        collision_checks(),
    ];
    back_up_ports.extend(server_ports("back-up"));
    r.register_stateful("BackUp", back_up_ports, || Behavior::new(Kind::BackUp))?;
    r.describe("BackUp", "Drives backwards `backup_dist` metres.");

    let mut drive_ports = vec![
        PortSpec::input::<f64>("dist_to_travel")
            .default_value("0.15")
            .describe("Metres to drive straight on."),
        PortSpec::input::<f64>("speed")
            .default_value("0.025")
            .describe("Metres per second."),
        time_allowance(),
        collision_checks(),
    ];
    drive_ports.extend(server_ports("drive-on-heading"));
    r.register_stateful("DriveOnHeading", drive_ports, || {
        Behavior::new(Kind::DriveOnHeading)
    })?;
    r.describe(
        "DriveOnHeading",
        "Drives straight on `dist_to_travel` metres.",
    );
    Ok(())
}

/// A behavior node: see the [module documentation](self).
struct Behavior {
    kind: Kind,
    /// When the motion started, on the tree's clock.
    started: Duration,
    /// How long it may take; `None` for Wait, which takes exactly its time.
    allowance: Option<Duration>,
}

impl Behavior {
    fn new(kind: Kind) -> Self {
        Self {
            kind,
            started: Duration::ZERO,
            allowance: None,
        }
    }

    /// Fails with `code`, the reason `why` and `message` (no code for Wait: only the
    /// message, and the reason without a code).
    fn fail<C>(
        &self,
        h: &mut Handle<'_, C>,
        code: u16,
        why: &'static str,
        message: String,
    ) -> Status {
        if self.kind == Kind::Wait {
            ports::emit(h, "error_msg", message);
            return h.fail_with(0, why);
        }
        ports::fail(h, code, why, message)
    }

    /// Reads the ports and starts the motion; `Err` says why it cannot.
    fn start<C: Nav2Context>(
        &mut self,
        h: &mut Handle<'_, C>,
    ) -> Result<(), (u16, &'static str, String)> {
        let unknown = self.kind.codes().0;
        let read = |e: neurotree_core::PortError| (unknown, "bad input", e.to_string());
        self.allowance = match self.kind {
            Kind::Wait => None,
            Kind::Spin | Kind::BackUp | Kind::DriveOnHeading => {
                let seconds: f64 = ports::or(h, "time_allowance", 10.0).map_err(read)?;
                Some(Duration::try_from_secs_f64(seconds.max(0.0)).unwrap_or(Duration::MAX))
            }
        };
        self.started = h.now();
        let spin_rate = h.ctx().nav2().params.spin_rate;
        match self.kind {
            Kind::Spin => {
                let angle: f64 = ports::or(h, "spin_dist", 1.57).map_err(read)?;
                h.ctx_mut().nav2_mut().world.spin(angle, spin_rate);
            }
            Kind::Wait => {
                let seconds: f64 = ports::or(h, "wait_duration", 1.0).map_err(read)?;
                let wait = Duration::try_from_secs_f64(seconds.max(0.0)).unwrap_or(Duration::MAX);
                h.ctx_mut().nav2_mut().world.wait(wait);
            }
            Kind::BackUp => {
                let distance: f64 = ports::or(h, "backup_dist", 0.15).map_err(read)?;
                let speed: f64 = ports::or(h, "backup_speed", 0.025).map_err(read)?;
                if !distance.is_finite() || !speed.is_finite() || speed == 0.0 {
                    return Err((
                        back_up::INVALID_INPUT,
                        "invalid input",
                        format!("cannot back up {distance} m at {speed} m/s"),
                    ));
                }
                h.ctx_mut()
                    .nav2_mut()
                    .world
                    .back_up(distance.abs(), speed.abs());
            }
            Kind::DriveOnHeading => {
                let distance: f64 = ports::or(h, "dist_to_travel", 0.15).map_err(read)?;
                let speed: f64 = ports::or(h, "speed", 0.025).map_err(read)?;
                if !distance.is_finite()
                    || !speed.is_finite()
                    || speed == 0.0
                    || distance * speed < 0.0
                {
                    return Err((
                        drive_on_heading::INVALID_INPUT,
                        "invalid input",
                        format!("cannot drive {distance} m at {speed} m/s"),
                    ));
                }
                let world = &mut h.ctx_mut().nav2_mut().world;
                if distance < 0.0 {
                    world.back_up(-distance, -speed);
                } else {
                    world.drive_on_heading(distance, speed);
                }
            }
        }
        Ok(())
    }
}

impl<C: Nav2Context> StatefulAction<C> for Behavior {
    /// When the motion started and how long it may take; the kind is the factory's.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(
            self.started,
            self.allowance,
        )))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(started, allowance)| (self.started, self.allowance) = (started, allowance))
            .is_some()
    }

    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        match self.start(h) {
            Ok(()) => Status::Running,
            Err((code, why, message)) => self.fail(h, code, why, message),
        }
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        let (unknown, timeout, collision) = self.kind.codes();
        let elapsed = h.now().saturating_sub(self.started);
        if self.allowance.is_some_and(|allowed| elapsed > allowed) {
            h.ctx_mut().nav2_mut().world.stop();
            let message = format!("still going after {:.1} s", elapsed.as_secs_f64());
            return self.fail(h, timeout, "timed out", message);
        }
        match h.ctx().nav2().world.motion_status() {
            MotionStatus::Active => Status::Running,
            MotionStatus::Succeeded => {
                let name = h.name().to_string();
                h.ctx_mut().nav2_mut().note(|| format!("{name}: done"));
                ports::succeed(h)
            }
            MotionStatus::Blocked(cell) => self.fail(
                h,
                collision,
                "collision ahead",
                format!("an obstacle or a wall in cell {cell}"),
            ),
            MotionStatus::BatteryEmpty => {
                self.fail(h, unknown, "battery empty", "the battery is empty".into())
            }
            // Stopped by another (a Cancel node): Nav2's `on_cancelled`.
            MotionStatus::Idle => ports::succeed(h),
        }
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

    use Status::{Failure as F, Running as R, Success as S};

    const ROOM: &str = "
        #####
        #...#
        #.R.#
        #...#
        #####";

    fn bench(xml: &str) -> Bench {
        Bench::new(ROOM, xml)
    }

    #[test]
    fn spin_turns_by_its_angle_at_the_spin_rate() {
        let mut b = bench(r#"<Spin spin_dist="1.57" error_code_id="{code}"/>"#);
        // 1.57 rad at 1 rad/s in 0.1 s steps: done in the 16th step, seen at tick 17.
        let run = b.run(100);
        assert_eq!(run.len(), 17);
        assert_eq!(run.last(), Some(&S));
        assert!((b.sim.world.robot().theta - 1.57).abs() < 1e-9);
        assert_eq!(b.get::<u16>("code"), 0);
        assert_eq!(b.sim.world.stop_count(), 0);
    }

    #[test]
    fn spin_fails_past_its_time_allowance_and_stops() {
        let mut b = bench(r#"<Spin spin_dist="6.0" time_allowance="1.0" error_code_id="{code}"/>"#);
        // Past 1 s: at tick 12, 1.1 s after the start.
        let run = b.run(100);
        assert_eq!(run.len(), 12);
        assert_eq!(run.last(), Some(&F));
        assert_eq!(b.get::<u16>("code"), spin::TIMEOUT);
        assert_eq!(b.reason().as_deref(), Some("timed out (error 701)"));
        assert_eq!(b.sim.world.stop_count(), 1);
    }

    #[test]
    fn wait_stands_still_for_its_duration() {
        let mut b = bench(r#"<Wait wait_duration="0.5"/>"#);
        assert_eq!(b.run(100), [R, R, R, R, R, S]);
        assert_eq!(b.sim.world.now(), Duration::from_millis(500));
        assert_eq!(b.sim.world.distance_travelled(), 0.0);
    }

    #[test]
    fn back_up_drives_backwards_until_a_wall() {
        let mut b =
            bench(r#"<BackUp backup_dist="0.3" backup_speed="0.15" error_code_id="{code}"/>"#);
        assert_eq!(b.run(100).len(), 21);
        let robot = b.sim.world.robot();
        assert!((robot.x - 2.2).abs() < 1e-9 && robot.y == 2.5, "{robot:?}");
        // Facing +x, two metres back is past the wall at x = 1.
        let mut b = bench(
            r#"<BackUp backup_dist="2.0" backup_speed="1.0" error_code_id="{code}" error_msg="{msg}"/>"#,
        );
        let run = b.run(100);
        assert_eq!(run.last(), Some(&F));
        assert_eq!(b.get::<u16>("code"), back_up::COLLISION_AHEAD);
        assert_eq!(b.reason().as_deref(), Some("collision ahead (error 714)"));
        assert_eq!(
            b.get::<String>("msg"),
            "an obstacle or a wall in cell (0, 2)"
        );
        // Stopped 0.1 m before the wall: the next step would have entered it.
        assert!((b.sim.world.robot().x - 1.1).abs() < 1e-9);
    }

    #[test]
    fn back_up_refuses_a_zero_speed() {
        let mut b = bench(r#"<BackUp backup_dist="0.3" backup_speed="0" error_code_id="{code}"/>"#);
        assert_eq!(b.tick(), F);
        assert_eq!(b.get::<u16>("code"), back_up::INVALID_INPUT);
        assert_eq!(b.reason().as_deref(), Some("invalid input (error 713)"));
    }

    #[test]
    fn drive_on_heading_drives_straight_on_until_a_wall() {
        let mut b =
            bench(r#"<DriveOnHeading dist_to_travel="0.3" speed="0.15" error_code_id="{code}"/>"#);
        assert_eq!(b.run(100).last(), Some(&S));
        let robot = b.sim.world.robot();
        // Facing +x from (2.5, 2.5).
        assert!((robot.x - 2.8).abs() < 1e-9 && robot.y == 2.5, "{robot:?}");
        assert_eq!(b.get::<u16>("code"), 0);
        let mut b =
            bench(r#"<DriveOnHeading dist_to_travel="20" speed="1.0" error_code_id="{code}"/>"#);
        assert_eq!(b.run(500).last(), Some(&F));
        assert_eq!(b.get::<u16>("code"), drive_on_heading::COLLISION_AHEAD);
        // Both negative: backwards.
        let mut b = bench(r#"<DriveOnHeading dist_to_travel="-0.3" speed="-0.15"/>"#);
        assert_eq!(b.run(100).last(), Some(&S));
        assert!((b.sim.world.robot().x - 2.2).abs() < 1e-9);
    }

    #[test]
    fn drive_on_heading_refuses_signs_that_differ_and_a_zero_speed() {
        for xml in [
            r#"<DriveOnHeading dist_to_travel="0.3" speed="-0.1" error_code_id="{code}"/>"#,
            r#"<DriveOnHeading dist_to_travel="0.3" speed="0" error_code_id="{code}"/>"#,
        ] {
            let mut b = bench(xml);
            assert_eq!(b.tick(), F);
            assert_eq!(b.get::<u16>("code"), drive_on_heading::INVALID_INPUT);
            assert_eq!(b.reason().as_deref(), Some("invalid input (error 724)"));
        }
    }

    #[test]
    fn an_empty_battery_fails_the_spin() {
        let world = GridWorld::parse(ROOM, 1.0)
            .unwrap()
            .with_battery(Battery::at(0.0));
        let mut b = Bench::with_world(world, r#"<Spin error_code_id="{code}"/>"#);
        assert_eq!(b.run(5), [R, F]);
        assert_eq!(b.get::<u16>("code"), spin::UNKNOWN);
        assert_eq!(b.reason().as_deref(), Some("battery empty (error 700)"));
    }

    #[test]
    fn halting_a_behavior_stops_the_motion_once() {
        for xml in [r#"<Spin/>"#, r#"<Wait wait_duration="5"/>"#, r#"<BackUp/>"#] {
            let mut b = bench(xml);
            assert_eq!(b.run(2), [R, R], "{xml}");
            b.tree.halt(&mut b.sim);
            b.tree.halt(&mut b.sim);
            assert_eq!(b.sim.world.stop_count(), 1, "{xml}");
            assert_eq!(b.sim.world.motion_status(), MotionStatus::Idle, "{xml}");
        }
    }
}
