//! Following a path and staying on it: TruncatePath, IsWithinPathTrackingBounds and
//! PathExpiringTimer.
//!
//! - **TruncatePath**: a sync action. Ports: `input_path`, `distance` (default 1.0); output
//!   `output_path`. As Nav2's `truncate_path_action.cpp`:
//!   - An empty path is written as it is. Success.
//!   - Otherwise poses are dropped from the end while the last one is less than `distance`
//!     metres (straight line) from the path's end, keeping at least two; the new last pose
//!     is turned to face the old end. Success.
//!   - Used to follow a goal from a distance (`follow_point.xml`).
//! - **IsWithinPathTrackingBounds**: a condition. Ports: `tracking_feedback` (FollowPath's
//!   [`TrackingFeedback`]), `max_error_left`, `max_error_right`, `max_error_heading`
//!   (default 0.5, 0.5, 3.14). As Nav2's `is_within_path_tracking_bounds_condition.cpp`:
//!   - No feedback yet (the controller has not started): Success.
//!   - Success when the signed position error is within `max_error_left` (left of the path,
//!     or on it) or `max_error_right` (right of it), and the heading error within
//!     `max_error_heading`; else Failure.
//! - **PathExpiringTimer**: a condition. Ports: `seconds` (default 1.0), `path`. As Nav2's
//!   `path_expiring_timer_condition.cpp`:
//!   - The node's first tick reads `seconds` and the path, starts the timer: Failure.
//!   - Later ticks restart the timer when the path differs from the last one read; Failure
//!     until `seconds` have passed since the timer started, then Success, and the timer
//!     starts again. The timer runs on the tree's clock, and is kept for the tree's life,
//!     as Nav2 keeps it in the node.

use std::time::Duration;

use neurotree_core::{Category, Handle, StatefulAction, Status};

use super::{ports, Nav2Context, TrackingFeedback};
use neurotree_nav2::robotics::{Path, Pose2D};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_action("TruncatePath", truncate_ports(), truncate_path::<C>)?;
    r.describe(
        "TruncatePath",
        "Drops the poses within `distance` of the path's end, facing the new end to it.",
    );
    r.register_condition(
        "IsWithinPathTrackingBounds",
        bounds_ports(),
        within_bounds::<C>,
    )?;
    r.describe(
        "IsWithinPathTrackingBounds",
        "Succeeds while the robot tracks its path within the given errors.",
    );
    r.register_stateful_as(
        "PathExpiringTimer",
        Category::Condition,
        vec![
            PortSpec::input::<f64>("seconds")
                .default_value("1.0")
                .describe("Seconds a path may stay the same before the timer expires."),
            PortSpec::input::<Path>("path").describe("The path whose change restarts the timer."),
        ],
        PathExpiringTimer::default,
    )?;
    r.describe(
        "PathExpiringTimer",
        "Succeeds once the path has stayed the same for `seconds`.",
    );
    Ok(())
}

/// Nav2's default `max_error_heading`: the number 3.14 its model gives, not π.
#[allow(clippy::approx_constant)]
const MAX_ERROR_HEADING: f64 = 3.14;

fn truncate_ports() -> Vec<PortSpec> {
    vec![
        PortSpec::input::<Path>("input_path").describe("The path to truncate."),
        PortSpec::input::<f64>("distance")
            .default_value("1.0")
            .describe("Metres dropped from the end of the path."),
        PortSpec::output::<Path>("output_path").describe("The truncated path."),
    ]
}

fn bounds_ports() -> Vec<PortSpec> {
    vec![
        PortSpec::input::<f64>("max_error_left")
            .default_value("0.5")
            .describe("Metres the robot may be left of the path."),
        PortSpec::input::<f64>("max_error_right")
            .default_value("0.5")
            .describe("Metres the robot may be right of the path."),
        PortSpec::input::<f64>("max_error_heading")
            .default_value("3.14")
            .describe("Radians the robot's heading may differ from the path's."),
        PortSpec::input::<TrackingFeedback>("tracking_feedback")
            .describe("FollowPath's tracking feedback."),
    ]
}

/// TruncatePath: see the [module documentation](self).
fn truncate_path<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let read = ports::or(h, "input_path", Path::default())
        .and_then(|path| Ok((path, ports::or(h, "distance", 1.0)?)));
    let Ok((mut path, distance)) = read else {
        return Status::Failure;
    };
    let Some(end) = path.poses.last().copied() else {
        ports::emit(h, "output_path", path);
        return Status::Success;
    };
    while path.poses.len() > 2
        && path
            .poses
            .last()
            .is_some_and(|p| p.distance(&end) < distance)
    {
        path.poses.pop();
    }
    if let Some(last) = path.poses.last_mut() {
        let angle = (end.y - last.y).atan2(end.x - last.x);
        *last = Pose2D::new(last.x, last.y, if angle.is_finite() { angle } else { 0.0 });
    }
    ports::emit(h, "output_path", path);
    Status::Success
}

/// IsWithinPathTrackingBounds: see the [module documentation](self).
fn within_bounds<C: Nav2Context>(h: &Handle<'_, C>) -> bool {
    let read = (|| {
        let feedback = ports::optional::<TrackingFeedback, C>(h, "tracking_feedback")?;
        let left: f64 = ports::or(h, "max_error_left", 0.5)?;
        let right: f64 = ports::or(h, "max_error_right", 0.5)?;
        let heading: f64 = ports::or(h, "max_error_heading", MAX_ERROR_HEADING)?;
        Ok::<_, neurotree_core::PortError>((feedback, left, right, heading))
    })();
    let Ok((feedback, left, right, heading)) = read else {
        return false;
    };
    let Some(feedback) = feedback else {
        return true;
    };
    let error = feedback.position_tracking_error;
    let within_position = if error >= 0.0 {
        error <= left
    } else {
        -error <= right
    };
    within_position && feedback.heading_tracking_error.abs() <= heading
}

/// PathExpiringTimer: see the [module documentation](self).
#[derive(Default)]
struct PathExpiringTimer {
    /// The period, the last path and the timer's start, once the first tick read them.
    started: Option<(f64, Path, Duration)>,
}

impl<C: Nav2Context> StatefulAction<C> for PathExpiringTimer {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&self.started))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode::<Option<(f64, Path, Duration)>>(state)
            .map(|saved| self.started = saved)
            .is_some()
    }

    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        let now = h.now();
        let path = ports::or(h, "path", Path::default()).unwrap_or_default();
        let Some((period, last, start)) = &mut self.started else {
            let period = ports::or(h, "seconds", 1.0).unwrap_or(1.0);
            self.started = Some((period, path, now));
            return Status::Failure;
        };
        if *last != path {
            *last = path;
            *start = now;
        }
        if now.saturating_sub(*start).as_secs_f64() < *period {
            return Status::Failure;
        }
        *start = now;
        Status::Success
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.on_start(h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;

    fn path(points: &[(f64, f64)]) -> Path {
        Path::new(
            points
                .iter()
                .map(|&(x, y)| Pose2D::new(x, y, 0.0))
                .collect(),
        )
    }

    #[test]
    fn truncate_path_drops_the_last_metre_and_faces_the_end() {
        let mut bench = Bench::new(
            "R....",
            r#"<TruncatePath distance="1.0" input_path="{in}" output_path="{out}"/>"#,
        );
        let input = path(&[(0.5, 0.5), (1.0, 0.5), (1.5, 0.5), (2.0, 0.5), (2.5, 0.5)]);
        bench.set("in", input);
        assert_eq!(bench.tick(), Status::Success);
        let out: Path = bench.get("out");
        assert_eq!(out.len(), 3);
        assert_eq!((out.poses[2].x, out.poses[2].theta), (1.5, 0.0));
        // Never fewer than two poses, facing the old end (straight up here).
        bench.set("in", path(&[(0.5, 0.5), (0.5, 0.7), (0.5, 0.9)]));
        assert_eq!(bench.tick(), Status::Success);
        let out: Path = bench.get("out");
        assert_eq!(out.len(), 2);
        assert!((out.poses[1].theta - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
    }

    #[test]
    fn the_path_expiring_timer_expires_on_a_path_that_stays_the_same() {
        use Status::{Failure as F, Success as S};
        let mut bench = Bench::new("R....", r#"<PathExpiringTimer seconds="0.3" path="{p}"/>"#);
        let a = path(&[(0.5, 0.5), (1.5, 0.5)]);
        bench.set("p", a.clone());
        // Ticks 100 ms apart: the first starts the timer, the fourth sees 0.3 s, and so on.
        let tick = |bench: &mut Bench| {
            let status = bench.tick();
            bench.sim.step();
            status
        };
        let run: Vec<Status> = (0..8).map(|_| tick(&mut bench)).collect();
        assert_eq!(run, [F, F, F, S, F, F, S, F]);
        // A new path restarts the timer.
        bench.set("p", path(&[(0.5, 0.5), (2.5, 0.5)]));
        let run: Vec<Status> = (0..4).map(|_| tick(&mut bench)).collect();
        assert_eq!(run, [F, F, F, S]);
    }

    #[test]
    fn the_position_error_is_to_the_path_not_to_its_poses() {
        let diagonal = path(&[(0.5, 0.5), (1.5, 1.5), (2.5, 2.5)]);
        // Halfway between two poses, on the line: 0.35 m from either pose, on the path.
        let on = TrackingFeedback::new(&diagonal, &Pose2D::new(1.0, 1.0, 0.0));
        assert!(on.tracking_error > 0.35 && on.position_tracking_error.abs() < 1e-9);
        // Above the line is its left, below is its right.
        let left = TrackingFeedback::new(&diagonal, &Pose2D::new(1.0, 1.2, 0.0));
        let right = TrackingFeedback::new(&diagonal, &Pose2D::new(1.2, 1.0, 0.0));
        assert!(left.position_tracking_error > 0.1 && right.position_tracking_error < -0.1);
        assert!((on.heading_tracking_error + std::f64::consts::FRAC_PI_4).abs() < 1e-9);
    }

    #[test]
    fn tracking_bounds_pass_without_feedback_and_check_each_side() {
        let leaf = r#"<IsWithinPathTrackingBounds tracking_feedback="{fb}" max_error_left="0.2" max_error_right="0.4" max_error_heading="1.0"/>"#;
        let mut bench = Bench::new("R....", leaf);
        assert_eq!(bench.tick(), Status::Success);
        let along = path(&[(0.0, 0.5), (1.0, 0.5), (2.0, 0.5)]);
        let feedback =
            |x: f64, y: f64, theta: f64| TrackingFeedback::new(&along, &Pose2D::new(x, y, theta));
        for (fb, expected) in [
            (feedback(1.0, 0.5, 0.0), Status::Success),
            (feedback(1.0, 0.8, 0.0), Status::Failure), // 0.3 m left
            (feedback(1.0, 0.2, 0.0), Status::Success), // 0.3 m right
            (feedback(1.0, 0.0, 0.0), Status::Failure), // 0.5 m right
            (feedback(1.0, 0.5, 1.2), Status::Failure), // heading off
            (feedback(1.0, 0.5, -0.9), Status::Success),
        ] {
            bench.set("fb", fb);
            assert_eq!(bench.tick(), expected, "{fb:?}");
        }
    }
}
