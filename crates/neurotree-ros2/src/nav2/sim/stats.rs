//! What the simulated servers saw: counts per server and the world's state, shared with
//! whoever watches a run.

use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use neurotree_nav2::robotics::Pose2D;

/// What one action server saw.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ServerCounts {
    /// Goals accepted.
    pub goals: u32,
    /// Cancel requests for a running goal.
    pub cancels: u32,
    /// Goals that succeeded.
    pub succeeded: u32,
    /// Goals that aborted (failed, or preempted).
    pub aborted: u32,
}

/// What the servers saw, for tests and summaries.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SimStats {
    /// `compute_path_to_pose`.
    pub planner: ServerCounts,
    /// `compute_path_through_poses`.
    pub planner_through_poses: ServerCounts,
    /// `smooth_path`.
    pub smoother: ServerCounts,
    /// `follow_path`.
    pub controller: ServerCounts,
    /// `spin`.
    pub spin: ServerCounts,
    /// `backup`.
    pub backup: ServerCounts,
    /// `drive_on_heading`.
    pub drive_on_heading: ServerCounts,
    /// `wait`.
    pub wait: ServerCounts,
    /// `compute_route`.
    pub route: ServerCounts,
    /// `compute_and_track_route`.
    pub route_tracking: ServerCounts,
    /// `dock_robot`.
    pub dock: ServerCounts,
    /// `undock_robot`.
    pub undock: ServerCounts,
    /// `navigate_through_poses`.
    pub navigate_through_poses: ServerCounts,
    /// `follow_object`.
    pub follow_object: ServerCounts,
    /// `assisted_teleop`.
    pub assisted_teleop: ServerCounts,
    /// Costmap clearings served (entire and regions).
    pub clears: u32,
    /// Cost requests served (`get_cost_` of either costmap).
    pub cost_requests: u32,
    /// Whether the collision monitor is on (`collision_monitor/toggle`).
    pub collision_monitor: bool,
    /// Requests served by `reinitialize_global_localization`.
    pub relocalizations: u32,
    /// The `disable_collision_checks` of the last Spin, BackUp or DriveOnHeading goal in
    /// Kilted's layout; `None` while only Jazzy's (which has no such field) came.
    pub disable_collision_checks: Option<bool>,
    /// How many `viapoints` the last ComputePathToPose goal in main's layout had; `None`
    /// while only the older layout (which has no such field) came.
    pub viapoints: Option<usize>,
    /// Obstacle cells the global costmap remembers.
    pub global_obstacles: usize,
    /// Obstacle cells the local costmap remembers.
    pub local_obstacles: usize,
    /// Where the robot is.
    pub robot: Pose2D,
    /// Simulated time.
    pub time: Duration,
    /// Metres the robot drove.
    pub distance: f64,
    /// Steps the servers have taken: each served what had come and then recorded these
    /// counts, so a reader that sees two more steps than before knows every request made
    /// before it looked is counted.
    pub steps: u64,
}

/// Shared [`SimStats`]: clones read the same counts.
#[derive(Clone, Debug, Default)]
pub struct SimStatsHandle(Arc<Mutex<SimStats>>);

impl SimStatsHandle {
    /// The counts now.
    pub fn get(&self) -> SimStats {
        *self.lock()
    }

    pub(super) fn lock(&self) -> MutexGuard<'_, SimStats> {
        // Plain counters: still meaningful after a panic elsewhere.
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }
}
