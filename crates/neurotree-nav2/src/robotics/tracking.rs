//! How a robot tracks its path: what Nav2's controller reports as FollowPath's feedback
//! (`nav2_msgs/TrackingFeedback`), and what IsWithinPathTrackingBounds checks.

use super::{Path, Pose2D};

/// How the robot tracks its path: FollowPath's `tracking_feedback` output.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TrackingFeedback {
    /// The index of the path pose nearest the robot.
    pub current_path_index: usize,
    /// Metres of path from that pose to the end.
    pub remaining_path_length: f64,
    /// Metres from the robot to that pose.
    pub tracking_error: f64,
    /// Metres from the robot to the path (the nearest segment at that pose), signed as
    /// Nav2's `position_tracking_error`: positive (or zero) when the robot is left of the
    /// path, negative when it is right of it.
    pub position_tracking_error: f64,
    /// The robot's heading less the path's heading at that pose, in radians in [-π, π]:
    /// Nav2's `heading_tracking_error`.
    pub heading_tracking_error: f64,
}

/// The signed distance from `robot` to the segment `a`–`b` (positive on its left) and the
/// segment's direction.
fn cross_track(a: &Pose2D, b: &Pose2D, robot: &Pose2D) -> (f64, f64) {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let length2 = dx * dx + dy * dy;
    if length2 == 0.0 {
        return (a.distance(robot), a.theta);
    }
    let t = (((robot.x - a.x) * dx + (robot.y - a.y) * dy) / length2).clamp(0.0, 1.0);
    let (px, py) = (a.x + t * dx, a.y + t * dy);
    let distance = ((robot.x - px).powi(2) + (robot.y - py).powi(2)).sqrt();
    let cross = dx * (robot.y - a.y) - dy * (robot.x - a.x);
    let sign = if cross < 0.0 { -1.0 } else { 1.0 };
    (sign * distance, dy.atan2(dx))
}

/// A feedback has no text form: a tree gets one from FollowPath, never from a literal.
impl neurotree_core::FromPortStr for TrackingFeedback {
    fn from_port_str(_text: &str) -> Result<Self, ()> {
        Err(())
    }
}

impl TrackingFeedback {
    /// The feedback for a robot at `robot` on `path`.
    pub fn new(path: &Path, robot: &Pose2D) -> Self {
        let index = path.closest_index(robot).unwrap_or(0);
        let tracking_error = path.poses.get(index).map_or(0.0, |p| p.distance(robot));
        // The nearest of the segments that meet at that pose, as Nav2 measures the error
        // to the path rather than to its poses.
        let segments = [
            index.checked_sub(1).map(|i| (i, index)),
            Some((index, index + 1)),
        ];
        let nearest = segments
            .into_iter()
            .flatten()
            .filter(|(_, b)| *b < path.poses.len())
            .map(|(a, b)| cross_track(&path.poses[a], &path.poses[b], robot))
            .min_by(|x, y| x.0.abs().total_cmp(&y.0.abs()));
        let (position, heading) = match nearest {
            Some((signed, direction)) => {
                let turn = (robot.theta - direction + std::f64::consts::PI)
                    .rem_euclid(std::f64::consts::TAU)
                    - std::f64::consts::PI;
                (signed, turn)
            }
            None => (tracking_error, 0.0),
        };
        Self {
            current_path_index: index,
            remaining_path_length: path.from_index(index).length(),
            tracking_error,
            position_tracking_error: position,
            heading_tracking_error: heading,
        }
    }
}
