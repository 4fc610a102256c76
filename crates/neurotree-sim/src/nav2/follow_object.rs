//! FollowObject: following a moving object, kept at a distance.
//!
//! A stateful action. Ports `pose_topic` (default `dynamic_pose`, unused), `max_duration`
//! (default 0: no limit), `tracked_frame` (unused), `server_name`, `server_timeout`;
//! outputs `total_elapsed_time` (seconds), `error_code_id`, `error_msg`.
//!
//! The object is wherever [`Nav2Sim::set_object`](super::Nav2Sim::set_object) last put it,
//! as Nav2's following server reads it from `pose_topic`.
//!
//! - The tick from Idle: the object not seen: Failure FAILED_TO_DETECT_OBJECT 902. Else
//!   the robot heads for a point [`FOLLOW_DISTANCE`] short of the object: Running.
//! - Later ticks: Running, planning again whenever the object moved more than 0.1 m since
//!   the last plan or the robot was blocked; standing still within the distance. The object
//!   lost: FAILED_TO_DETECT_OBJECT 902; no path to it: FAILED_TO_CONTROL 903.
//! - With `max_duration` above 0, Success once that many seconds have passed; without, it
//!   follows until halted or cancelled (CancelFollowObject: Success at the next tick, as
//!   Nav2's `on_cancelled`). Halt stops the motion.

use std::time::Duration;

use neurotree_core::{Handle, StatefulAction, Status};

use super::codes::follow_object as code;
use super::{planner, ports, GoalState, Nav2Context};
use crate::MotionStatus;
use neurotree_nav2::robotics::{Path, Pose2D};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

/// How far from the object the robot keeps, in metres (Nav2's `desired_distance`).
pub const FOLLOW_DISTANCE: f64 = 1.0;

/// How far the object may move before the robot plans again, in metres.
const MOVED: f64 = 0.1;

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_stateful(
        "FollowObject",
        vec![
            PortSpec::input::<String>("pose_topic")
                .default_value("dynamic_pose")
                .describe("Topic of the object's pose (unused: the world gives it)."),
            PortSpec::input::<f64>("max_duration")
                .default_value("0.0")
                .describe("Seconds to follow; 0 follows until stopped."),
            PortSpec::input::<String>("tracked_frame").describe("Object frame (unused)."),
            PortSpec::input::<String>("server_name").describe("Action server name (unused)."),
            PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
            PortSpec::output::<f64>("total_elapsed_time").describe("Seconds followed."),
            PortSpec::output::<u16>("error_code_id").describe("0, or the following error code."),
            PortSpec::output::<String>("error_msg").describe("Why it failed; empty on success."),
        ],
        FollowObject::default,
    )?;
    r.describe(
        "FollowObject",
        "Follows the moving object, a metre behind it.",
    );
    Ok(())
}

/// FollowObject: see the [module documentation](self).
#[derive(Default)]
struct FollowObject {
    started: Duration,
    max: Option<Duration>,
    /// Where the object was when the robot last planned.
    planned_for: Option<Pose2D>,
}

/// A failure: code, reason, message.
type Failed = (u16, &'static str, String);

impl FollowObject {
    /// Plans towards `object` unless the robot is near enough already.
    fn head_for<C: Nav2Context>(
        &mut self,
        h: &mut Handle<'_, C>,
        object: Pose2D,
    ) -> Result<(), Failed> {
        self.planned_for = Some(object);
        let sim = h.ctx_mut().nav2_mut();
        let robot = sim.world.robot();
        if robot.distance(&object) <= FOLLOW_DISTANCE {
            if sim.world.motion_status() == MotionStatus::Active {
                sim.world.stop();
            }
            return Ok(());
        }
        let path = planner::plan_through(&mut sim.world, robot, &[], object)
            .map_err(|(_, _, message)| (code::FAILED_TO_CONTROL, "failed to control", message))?;
        let short = short_of(path, FOLLOW_DISTANCE);
        sim.world.follow(short, sim.params.speed);
        Ok(())
    }

    fn elapsed<C>(&self, h: &mut Handle<'_, C>) -> Duration {
        let elapsed = h.now().saturating_sub(self.started);
        ports::emit(h, "total_elapsed_time", elapsed.as_secs_f64());
        elapsed
    }

    fn end<C: Nav2Context>(&mut self, h: &mut Handle<'_, C>, status: Result<(), Failed>) -> Status {
        let sim = h.ctx_mut().nav2_mut();
        sim.goals.following = GoalState::Idle;
        if sim.world.motion_status() == MotionStatus::Active {
            sim.world.stop();
        }
        match status {
            Ok(()) => ports::succeed(h),
            Err((code, why, message)) => ports::fail(h, code, why, message),
        }
    }
}

/// `path` ending `distance` metres (along it) before its end; just its first pose when it
/// is not longer than that.
fn short_of(mut path: Path, distance: f64) -> Path {
    let mut left = distance;
    while path.poses.len() > 1 {
        let n = path.poses.len();
        let (a, b) = (path.poses[n - 2], path.poses[n - 1]);
        let length = a.distance(&b);
        if length > left {
            let t = (length - left) / length;
            let heading = (b.y - a.y).atan2(b.x - a.x);
            path.poses[n - 1] = Pose2D::new(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), heading);
            return path;
        }
        left -= length;
        path.poses.pop();
    }
    path
}

impl<C: Nav2Context> StatefulAction<C> for FollowObject {
    /// When following began, its limit and where the object was at the last plan; the
    /// object, the motion and the server's goal are the world's, saved with it.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(
            self.started,
            self.max,
            self.planned_for,
        )))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(started, max, planned_for)| {
                (self.started, self.max, self.planned_for) = (started, max, planned_for);
            })
            .is_some()
    }

    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.started = h.now();
        let seconds = ports::or(h, "max_duration", 0.0_f64).unwrap_or(0.0);
        self.max =
            (seconds > 0.0).then(|| Duration::try_from_secs_f64(seconds).unwrap_or(Duration::MAX));
        self.elapsed(h);
        let Some(object) = h.ctx().nav2().object() else {
            let lost = (
                code::FAILED_TO_DETECT_OBJECT,
                "object not detected",
                "the object is not seen".into(),
            );
            return self.end(h, Err(lost));
        };
        h.ctx_mut().nav2_mut().goals.following = GoalState::Active;
        match self.head_for(h, object) {
            Ok(()) => Status::Running,
            Err(failed) => self.end(h, Err(failed)),
        }
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        let elapsed = self.elapsed(h);
        let sim = h.ctx().nav2();
        if sim.goals.following == GoalState::Cancelled || self.max.is_some_and(|max| elapsed >= max)
        {
            return self.end(h, Ok(()));
        }
        let Some(object) = sim.object() else {
            let lost = (
                code::FAILED_TO_DETECT_OBJECT,
                "object not detected",
                "the object was lost".into(),
            );
            return self.end(h, Err(lost));
        };
        let moved = !self
            .planned_for
            .is_some_and(|p| p.distance(&object) <= MOVED);
        let blocked = matches!(sim.world.motion_status(), MotionStatus::Blocked(_));
        if moved || blocked {
            if let Err(failed) = self.head_for(h, object) {
                return self.end(h, Err(failed));
            }
        }
        Status::Running
    }

    fn on_halted(&mut self, h: &mut Handle<'_, C>) {
        let sim = h.ctx_mut().nav2_mut();
        sim.goals.following = GoalState::Idle;
        sim.world.stop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;
    use Status::{Failure as F, Running as R, Success as S};

    const CORRIDOR: &str = "R.........";

    #[test]
    fn follows_the_object_a_metre_behind_for_its_duration() {
        let mut b = Bench::new(
            CORRIDOR,
            r#"<FollowObject max_duration="8.0" total_elapsed_time="{t}" error_code_id="{code}"/>"#,
        );
        b.sim.set_object(Some(Pose2D::new(3.5, 0.5, 0.0)));
        let mut seen = Vec::new();
        for tick in 0..100 {
            // The object walks east at 0.5 m/s from t = 2 s to 6 s.
            if (20..60).contains(&tick) {
                let x = 3.5 + 0.05 * f64::from(tick - 19);
                b.sim.set_object(Some(Pose2D::new(x, 0.5, 0.0)));
            }
            let status = b.tick();
            seen.push(status);
            if status != R {
                break;
            }
            b.sim.step();
        }
        // 8 s in 0.1 s ticks: the 81st tick sees the duration over.
        assert_eq!(seen.len(), 81);
        assert_eq!(seen.last(), Some(&S));
        assert_eq!(b.get::<f64>("t"), 8.0);
        assert_eq!(b.get::<u16>("code"), 0);
        // The object stopped at x = 5.5; the last plan was for 5.45 (its last step of
        // 0.05 m was too small to plan again), so the robot stands a metre short of that.
        let robot = b.sim.world.robot();
        assert!((robot.x - 4.45).abs() < 1e-9, "{robot:?}");
    }

    #[test]
    fn an_object_not_seen_fails_and_a_cancel_succeeds() {
        let mut b = Bench::new(CORRIDOR, r#"<FollowObject error_code_id="{code}"/>"#);
        assert_eq!(b.run(3), [F]);
        assert_eq!(b.get::<u16>("code"), code::FAILED_TO_DETECT_OBJECT);
        b.sim.set_object(Some(Pose2D::new(5.5, 0.5, 0.0)));
        assert_eq!(b.run(3), [R, R, R]);
        b.sim.goals.following = GoalState::Cancelled;
        assert_eq!(b.tick(), S);
        assert_eq!(b.sim.goals.following, GoalState::Idle);
        // Lost while following.
        assert_eq!(b.tick(), R);
        b.sim.set_object(None);
        assert_eq!(b.tick(), F);
        assert_eq!(b.get::<u16>("code"), code::FAILED_TO_DETECT_OBJECT);
    }
}
