//! Motion commands and how a step carries them out.
//!
//! The robot does one thing at a time, as a real base does with its velocity command: follow
//! a path, spin on the spot, back up, or wait. A new command replaces the current one;
//! [`GridWorld::stop`] cancels it. Commands run only inside [`GridWorld::step`], for the
//! step's `dt`, so a tree that stops ticking a motion must stop it, or the robot drives on.
//!
//! Following a path moves the robot straight from waypoint to waypoint at its speed, several
//! waypoints in one step if the distance allows, and arrives exactly on the last waypoint
//! (heading included). Before moving towards a waypoint in another cell it checks that cell
//! against the ground truth: if it is occupied the robot stays where it is, the motion ends
//! [`Blocked`](MotionStatus::Blocked), and the robot's costmaps learn the cell (it bumped
//! into it). Driving stops when the battery is empty.

use std::f64::consts::PI;
use std::fmt;
use std::time::Duration;

use super::grid::Cell;
use super::world::GridWorld;
use neurotree_nav2::robotics::{Path, Pose2D};

/// Where the current (or last) motion command stands.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MotionStatus {
    /// No command, or it was stopped.
    #[default]
    Idle,
    /// Under way.
    Active,
    /// Completed: at the path's end, turned, backed up or waited.
    Succeeded,
    /// Ended in front of an occupied cell.
    Blocked(Cell),
    /// Ended because the battery is empty.
    BatteryEmpty,
}

impl fmt::Display for MotionStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MotionStatus::Idle => f.write_str("idle"),
            MotionStatus::Active => f.write_str("moving"),
            MotionStatus::Succeeded => f.write_str("done"),
            MotionStatus::Blocked(cell) => write!(f, "blocked at {cell}"),
            MotionStatus::BatteryEmpty => f.write_str("battery empty"),
        }
    }
}

/// What the robot was last commanded to do, so that Nav2's cancel nodes stop only the
/// motion of their own behavior.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionKind {
    /// Following a path ([`GridWorld::follow`]).
    Follow,
    /// Turning on the spot ([`GridWorld::spin`]).
    Spin,
    /// Driving backwards ([`GridWorld::back_up`]).
    BackUp,
    /// Driving straight on ([`GridWorld::drive_on_heading`]).
    DriveOnHeading,
    /// Standing still ([`GridWorld::wait`]).
    Wait,
}

/// A command and what is left of it.
#[derive(Clone, Debug, Default, PartialEq)]
enum Command {
    #[default]
    None,
    Follow {
        path: Path,
        speed: f64,
        /// The waypoint being driven to.
        next: usize,
    },
    Spin {
        /// Radians still to turn, signed.
        left: f64,
        rate: f64,
    },
    BackUp {
        /// Metres still to go.
        left: f64,
        speed: f64,
        /// Along the heading rather than opposite to it.
        forward: bool,
    },
    Wait {
        left: Duration,
    },
}

/// The robot's current command and its status.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Motion {
    command: Command,
    status: MotionStatus,
}

impl GridWorld {
    fn command(&mut self, command: Command) {
        self.motion = Motion {
            command,
            status: MotionStatus::Active,
        };
    }

    /// Starts following `path` at `speed` metres per second.
    pub fn follow(&mut self, path: Path, speed: f64) {
        self.command(Command::Follow {
            path,
            speed: finite(speed).abs(),
            next: 0,
        });
    }

    /// Starts turning on the spot by `angle` radians (positive is counter-clockwise) at
    /// `rate` radians per second.
    pub fn spin(&mut self, angle: f64, rate: f64) {
        self.command(Command::Spin {
            left: finite(angle),
            rate: finite(rate).abs(),
        });
    }

    /// Starts driving backwards, opposite to the heading, for `distance` metres at `speed`
    /// metres per second.
    pub fn back_up(&mut self, distance: f64, speed: f64) {
        self.command(Command::BackUp {
            left: finite(distance).abs(),
            speed: finite(speed).abs(),
            forward: false,
        });
    }

    /// Starts driving straight along the heading, without turning, for `distance` metres at
    /// `speed` metres per second: Nav2's DriveOnHeading.
    pub fn drive_on_heading(&mut self, distance: f64, speed: f64) {
        self.command(Command::BackUp {
            left: finite(distance).abs(),
            speed: finite(speed).abs(),
            forward: true,
        });
    }

    /// Starts standing still for `duration` (the robot charges if it is on the charger).
    pub fn wait(&mut self, duration: Duration) {
        self.command(Command::Wait { left: duration });
    }

    /// Cancels the command; the robot stays where it is.
    pub fn stop(&mut self) {
        self.stops += 1;
        self.motion = Motion::default();
    }

    /// Where the current (or last) command stands.
    pub fn motion_status(&self) -> MotionStatus {
        self.motion.status
    }

    /// The kind of the current (or last, unless stopped) command; `None` after a stop.
    pub fn motion_kind(&self) -> Option<MotionKind> {
        match &self.motion.command {
            Command::None => None,
            Command::Follow { .. } => Some(MotionKind::Follow),
            Command::Spin { .. } => Some(MotionKind::Spin),
            Command::BackUp { forward: false, .. } => Some(MotionKind::BackUp),
            Command::BackUp { forward: true, .. } => Some(MotionKind::DriveOnHeading),
            Command::Wait { .. } => Some(MotionKind::Wait),
        }
    }

    /// The path of the current (or last, unless stopped) follow command.
    pub fn followed_path(&self) -> Option<&Path> {
        match &self.motion.command {
            Command::Follow { path, .. } => Some(path),
            _ => None,
        }
    }

    /// The waypoints of the followed path still ahead, while it is being followed.
    pub fn path_ahead(&self) -> &[Pose2D] {
        match (&self.motion.command, self.motion.status) {
            (Command::Follow { path, next, .. }, MotionStatus::Active) => {
                path.poses.get(*next..).unwrap_or_default()
            }
            _ => &[],
        }
    }

    /// Runs the command for `dt`; returns `true` if the robot moved or turned.
    pub(super) fn advance_motion(&mut self, dt: Duration) -> bool {
        let seconds = dt.as_secs_f64();
        if self.motion.status != MotionStatus::Active {
            return false;
        }
        let mut command = std::mem::take(&mut self.motion.command);
        let (status, moved) = match &mut command {
            Command::None => (MotionStatus::Idle, false),
            Command::Follow { path, speed, next } => self.drive(path, next, *speed * seconds),
            Command::Spin { left, rate } => self.turn(left, *rate * seconds),
            Command::BackUp {
                left,
                speed,
                forward,
            } => {
                let sign = if *forward { -1.0 } else { 1.0 };
                self.reverse(left, *speed * seconds, sign)
            }
            Command::Wait { left } => {
                *left = left.saturating_sub(dt);
                (done_if(left.is_zero()), false)
            }
        };
        self.motion = Motion { command, status };
        moved
    }

    /// Drives along `path` from waypoint `next` for up to `budget` metres.
    fn drive(&mut self, path: &Path, next: &mut usize, mut budget: f64) -> (MotionStatus, bool) {
        let mut moved = false;
        while *next < path.poses.len() {
            let target = path.poses[*next];
            let here = self.robot_cell();
            let cell = self.map.cell_at(&target);
            match cell {
                Some(c) if c == here || !self.truth().is_occupied(c) => {}
                Some(c) => return (self.bump(c), moved),
                // A waypoint off the map: the edge of the map is a wall.
                None => return (MotionStatus::Blocked(here), moved),
            }
            let distance = self.robot.distance(&target);
            let reach = budget.min(self.battery.range());
            if distance > 0.0 && reach <= 0.0 {
                let status = if self.battery.is_empty() {
                    MotionStatus::BatteryEmpty
                } else {
                    MotionStatus::Active
                };
                return (status, moved);
            }
            if distance > 0.0 {
                self.robot.theta = (target.y - self.robot.y).atan2(target.x - self.robot.x);
            }
            let step = distance.min(reach);
            if step >= distance {
                // Arrive exactly, so that positions do not drift with rounding.
                self.robot.x = target.x;
                self.robot.y = target.y;
                *next += 1;
            } else {
                let f = step / distance;
                self.robot.x += (target.x - self.robot.x) * f;
                self.robot.y += (target.y - self.robot.y) * f;
            }
            moved |= step > 0.0;
            self.travelled += step;
            self.battery.drain(step, 0.0);
            budget -= step;
        }
        if let Some(last) = path.goal() {
            self.robot.theta = last.theta;
        }
        (MotionStatus::Succeeded, moved)
    }

    /// The robot touched the occupied `cell`: its costmaps learn it.
    fn bump(&mut self, cell: Cell) -> MotionStatus {
        // Walls are in the costmaps already.
        if !self.map.is_wall(cell) {
            self.global.mark(cell);
            self.local.mark(cell);
        }
        MotionStatus::Blocked(cell)
    }

    /// Turns by up to `budget` radians of what is `left`.
    fn turn(&mut self, left: &mut f64, budget: f64) -> (MotionStatus, bool) {
        if self.battery.is_empty() && *left != 0.0 {
            return (MotionStatus::BatteryEmpty, false);
        }
        let turn = left.abs().min(budget).copysign(*left);
        self.robot.theta = normalize(self.robot.theta + turn);
        self.battery.drain(0.0, turn);
        // The last turn is `left` itself, so this reaches exactly zero.
        *left -= turn;
        (done_if(*left == 0.0), turn != 0.0)
    }

    /// Backs up by up to `budget` metres of what is `left`.
    /// Drives straight opposite to the heading (`sign` 1) or along it (`sign` -1).
    fn reverse(&mut self, left: &mut f64, budget: f64, sign: f64) -> (MotionStatus, bool) {
        let step = left.min(budget).min(self.battery.range());
        if step <= 0.0 && *left > 0.0 {
            return (MotionStatus::BatteryEmpty, false);
        }
        let to = Pose2D::new(
            self.robot.x - sign * step * self.robot.theta.cos(),
            self.robot.y - sign * step * self.robot.theta.sin(),
            self.robot.theta,
        );
        let here = self.robot_cell();
        match self.map.cell_at(&to) {
            Some(c) if c == here || !self.truth().is_occupied(c) => {}
            Some(c) => return (self.bump(c), false),
            None => return (MotionStatus::Blocked(here), false),
        }
        self.robot = to;
        self.travelled += step;
        self.battery.drain(step, 0.0);
        *left -= step;
        (done_if(*left <= 0.0), step > 0.0)
    }
}

/// `value`, or 0 for NaN and infinities, so that a bad command moves nothing.
fn finite(value: f64) -> f64 {
    if value.is_finite() {
        value
    } else {
        0.0
    }
}

fn done_if(done: bool) -> MotionStatus {
    if done {
        MotionStatus::Succeeded
    } else {
        MotionStatus::Active
    }
}

/// The same angle in (-π, π].
fn normalize(angle: f64) -> f64 {
    let a = angle.rem_euclid(2.0 * PI);
    if a > PI {
        a - 2.0 * PI
    } else {
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Battery, GridWorld, TimedObstacle};

    const HALF: Duration = Duration::from_millis(500);

    fn corridor() -> GridWorld {
        GridWorld::parse("R....", 1.0).unwrap()
    }

    fn straight(world: &GridWorld, to_x: f64) -> Path {
        let from = world.robot();
        Path::new(vec![from, Pose2D::new(to_x, 0.5, 0.0)])
    }

    fn steps(world: &mut GridWorld, n: usize) -> Vec<MotionStatus> {
        (0..n).map(|_| world.step(HALF)).collect()
    }

    use MotionStatus::{Active as A, Succeeded as Done};

    #[test]
    fn following_arrives_exactly_and_drains_by_distance() {
        let mut w = corridor();
        let path = w.plan(w.robot(), Pose2D::new(4.5, 0.5, 1.0)).unwrap();
        assert_eq!(path.len(), 5);
        w.follow(path, 1.0);
        assert_eq!(steps(&mut w, 8), [A, A, A, A, A, A, A, Done]);
        assert_eq!(w.robot(), Pose2D::new(4.5, 0.5, 1.0));
        assert_eq!(w.distance_travelled(), 4.0);
        assert_eq!(w.battery().level(), 96.0);
        assert_eq!(w.now(), Duration::from_secs(4));
        // Done stays done; nothing moves any more.
        assert_eq!(w.step(HALF), Done);
        assert_eq!(w.distance_travelled(), 4.0);
    }

    #[test]
    fn blocked_when_the_next_cell_is_truly_occupied() {
        // The obstacle is out of sensing range, so the costmaps do not know it in advance.
        let mut w = corridor()
            .with_sensing_radius(0.0)
            .with_timed_obstacle(TimedObstacle::new(Cell::new(2, 0), Duration::ZERO));
        assert!(!w
            .costmap(crate::CostmapLayer::Global)
            .is_marked(Cell::new(2, 0)));
        let path = Path::new(
            (0..5)
                .map(|x| Pose2D::new(f64::from(x) + 0.5, 0.5, 0.0))
                .collect(),
        );
        w.follow(path, 1.0);
        // Standing before the obstacle at the end of the second step, it is blocked then.
        assert_eq!(
            steps(&mut w, 2),
            [A, MotionStatus::Blocked(Cell::new(2, 0))]
        );
        assert_eq!(w.robot(), Pose2D::new(1.5, 0.5, 0.0));
        assert_eq!(w.distance_travelled(), 1.0);
        // The bump taught both costmaps.
        assert!(w
            .costmap(crate::CostmapLayer::Global)
            .is_marked(Cell::new(2, 0)));
        assert!(w
            .costmap(crate::CostmapLayer::Local)
            .is_marked(Cell::new(2, 0)));
        assert_eq!(w.step(HALF), MotionStatus::Blocked(Cell::new(2, 0)));
        assert_eq!(w.robot(), Pose2D::new(1.5, 0.5, 0.0));
    }

    #[test]
    fn spinning_turns_by_the_angle_and_stops() {
        let mut w = corridor();
        w.spin(-PI / 2.0, 1.0);
        assert_eq!(steps(&mut w, 4), [A, A, A, Done]);
        assert!(
            (w.robot().theta + PI / 2.0).abs() < 1e-12,
            "{}",
            w.robot().theta
        );
        assert_eq!((w.robot().x, w.robot().y), (0.5, 0.5));
        assert!((w.battery().level() - (100.0 - 0.1 * PI / 2.0)).abs() < 1e-12);
        w.spin(2.0 * PI, 100.0);
        assert_eq!(w.step(HALF), Done);
        assert!((w.robot().theta + PI / 2.0).abs() < 1e-12);
    }

    #[test]
    fn backing_up_goes_against_the_heading_until_a_wall() {
        let mut w = corridor();
        w.follow(straight(&w, 3.5), 2.0);
        assert_eq!(w.step(Duration::from_secs(2)), Done);
        w.back_up(1.0, 0.5);
        assert_eq!(steps(&mut w, 4), [A, A, A, Done]);
        assert_eq!(w.robot(), Pose2D::new(2.5, 0.5, 0.0));
        assert_eq!(w.distance_travelled(), 4.0);
        // Three metres back would leave the map at x = 0: the robot (a point) reaches the
        // edge, and the next half metre is blocked.
        w.back_up(3.0, 1.0);
        assert_eq!(steps(&mut w, 5), [A, A, A, A, A]);
        assert_eq!(w.robot(), Pose2D::new(0.0, 0.5, 0.0));
        assert_eq!(w.step(HALF), MotionStatus::Blocked(Cell::new(0, 0)));
        assert_eq!(w.robot(), Pose2D::new(0.0, 0.5, 0.0));
    }

    #[test]
    fn commands_with_nan_or_infinite_numbers_move_nothing() {
        let mut w = corridor();
        w.follow(straight(&w, 4.5), f64::NAN);
        w.step(HALF);
        w.spin(f64::INFINITY, 1.0);
        assert_eq!(w.step(HALF), Done);
        w.back_up(1.0, f64::NEG_INFINITY);
        w.step(Duration::MAX);
        assert_eq!(w.robot(), Pose2D::new(0.5, 0.5, 0.0));
        assert_eq!(w.distance_travelled(), 0.0);
    }

    #[test]
    fn waiting_passes_time_without_moving() {
        let mut w = corridor();
        w.wait(Duration::from_millis(1200));
        assert_eq!(steps(&mut w, 3), [A, A, Done]);
        assert_eq!(w.robot(), Pose2D::new(0.5, 0.5, 0.0));
        assert_eq!(w.distance_travelled(), 0.0);
    }

    #[test]
    fn stop_cancels_the_motion_where_it_is() {
        let mut w = corridor();
        w.follow(straight(&w, 4.5), 1.0);
        assert_eq!(w.step(HALF), A);
        w.stop();
        assert_eq!((w.motion_status(), w.stop_count()), (MotionStatus::Idle, 1));
        assert_eq!(w.followed_path(), None);
        assert_eq!(steps(&mut w, 2), [MotionStatus::Idle, MotionStatus::Idle]);
        assert_eq!(w.robot(), Pose2D::new(1.0, 0.5, 0.0));
    }

    #[test]
    fn an_empty_battery_ends_the_motion() {
        let mut w = corridor().with_battery(Battery::at(1.5));
        w.follow(straight(&w, 4.5), 1.0);
        // The charge runs out on reaching x = 2 in the third step.
        assert_eq!(steps(&mut w, 3), [A, A, MotionStatus::BatteryEmpty]);
        assert_eq!(w.robot(), Pose2D::new(2.0, 0.5, 0.0));
        assert_eq!(w.battery().level(), 0.0);
        w.spin(1.0, 1.0);
        assert_eq!(w.step(HALF), MotionStatus::BatteryEmpty);
        w.back_up(1.0, 1.0);
        assert_eq!(w.step(HALF), MotionStatus::BatteryEmpty);
    }

    #[test]
    fn the_battery_charges_on_the_charger_while_standing() {
        let mut w = GridWorld::parse("R.C", 1.0)
            .unwrap()
            .with_battery(Battery::at(50.0));
        w.follow(straight(&w, 2.5), 1.0);
        assert_eq!(steps(&mut w, 4), [A, A, A, Done]);
        // Arriving does not charge: the robot moved in that step.
        assert_eq!(w.battery().level(), 48.0);
        assert!(!w.is_charging());
        w.wait(Duration::from_secs(10));
        w.step(Duration::from_secs(2));
        assert!(w.is_charging());
        assert_eq!(w.battery().level(), 58.0);
        w.step(Duration::from_secs(20));
        assert_eq!(w.battery().level(), 100.0);
        w.step(HALF);
        assert!(!w.is_charging());
    }
}
