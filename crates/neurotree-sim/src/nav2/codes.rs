//! Nav2's error codes, as its action definitions number them (`nav2_msgs/action/*.action`),
//! so that the `error_code_id` outputs mean what a Nav2 tree expects and the
//! `WouldA*RecoveryHelp` conditions match them. 0 is "no error" everywhere.

/// No error: what every successful run writes.
pub const NONE: u16 = 0;

/// The planner server (ComputePathToPose).
pub mod compute_path {
    /// A failure of no other kind.
    pub const UNKNOWN: u16 = 200;
    /// The planner id names no planner.
    pub const INVALID_PLANNER: u16 = 201;
    /// The start pose lies outside the map.
    pub const START_OUTSIDE_MAP: u16 = 203;
    /// The goal lies outside the map.
    pub const GOAL_OUTSIDE_MAP: u16 = 204;
    /// The start cell is blocked.
    pub const START_OCCUPIED: u16 = 205;
    /// The goal cell is blocked.
    pub const GOAL_OCCUPIED: u16 = 206;
    /// Planning took too long.
    pub const TIMEOUT: u16 = 207;
    /// No route exists.
    pub const NO_VALID_PATH: u16 = 208;
}

/// The planner server's ComputePathThroughPoses: ComputePathToPose's codes, 100 higher.
pub mod compute_path_through_poses {
    /// A failure of no other kind.
    pub const UNKNOWN: u16 = 300;
    /// Planning took too long.
    pub const TIMEOUT: u16 = 307;
    /// No route exists.
    pub const NO_VALID_PATH: u16 = 308;
    /// No goals were given.
    pub const NO_VIAPOINTS_GIVEN: u16 = 309;
}

/// The controller server (FollowPath).
pub mod follow_path {
    /// A failure of no other kind.
    pub const UNKNOWN: u16 = 100;
    /// The controller id names no controller.
    pub const INVALID_CONTROLLER: u16 = 101;
    /// The path is missing or empty.
    pub const INVALID_PATH: u16 = 103;
    /// The controller gave up waiting.
    pub const PATIENCE_EXCEEDED: u16 = 104;
    /// The robot did not move as commanded.
    pub const FAILED_TO_MAKE_PROGRESS: u16 = 105;
    /// No collision-free command exists: something is in the way.
    pub const NO_VALID_CONTROL: u16 = 106;
}

/// The spin behavior.
pub mod spin {
    /// A failure of no other kind.
    pub const UNKNOWN: u16 = 700;
    /// The time allowance ran out.
    pub const TIMEOUT: u16 = 701;
    /// Turning would hit something.
    pub const COLLISION_AHEAD: u16 = 703;
}

/// The back-up behavior.
pub mod back_up {
    /// A failure of no other kind.
    pub const UNKNOWN: u16 = 710;
    /// The time allowance ran out.
    pub const TIMEOUT: u16 = 711;
    /// The distance and the speed make no motion (a zero speed, or signs that differ).
    pub const INVALID_INPUT: u16 = 713;
    /// Backing up would hit something.
    pub const COLLISION_AHEAD: u16 = 714;
}

/// The drive-on-heading behavior.
pub mod drive_on_heading {
    /// A failure of no other kind.
    pub const UNKNOWN: u16 = 720;
    /// The time allowance ran out.
    pub const TIMEOUT: u16 = 721;
    /// Driving on would hit something.
    pub const COLLISION_AHEAD: u16 = 723;
    /// The distance and the speed make no motion (a zero speed, or signs that differ).
    pub const INVALID_INPUT: u16 = 724;
}

/// The route server (ComputeRoute, ComputeAndTrackRoute).
pub mod route {
    /// A failure of no other kind.
    pub const UNKNOWN: u16 = 400;
    /// The server has no graph.
    pub const NO_VALID_GRAPH: u16 = 402;
    /// A start or goal node id names no node of the graph.
    pub const INDETERMINANT_NODES_ON_GRAPH: u16 = 403;
    /// Routing took too long.
    pub const TIMEOUT: u16 = 404;
    /// No route joins the start and the goal.
    pub const NO_VALID_ROUTE: u16 = 405;
    /// Tracking the route failed.
    pub const OPERATION_FAILED: u16 = 406;
}

/// The smoother server (SmoothPath).
pub mod smooth_path {
    /// A failure of no other kind.
    pub const UNKNOWN: u16 = 500;
    /// The smoother id names no smoother.
    pub const INVALID_SMOOTHER: u16 = 501;
    /// Smoothing took too long.
    pub const TIMEOUT: u16 = 502;
    /// The smoothed path runs into an obstacle.
    pub const SMOOTHED_PATH_IN_COLLISION: u16 = 503;
    /// The smoother gave up.
    pub const FAILED_TO_SMOOTH_PATH: u16 = 504;
    /// The path is empty.
    pub const INVALID_PATH: u16 = 505;
}

/// The docking server (DockRobot, UndockRobot).
pub mod docking {
    /// The dock id names no dock the server knows.
    pub const DOCK_NOT_IN_DB: u16 = 901;
    /// The dock (or its type) is not one the server can use.
    pub const DOCK_NOT_VALID: u16 = 902;
    /// Navigating to the staging pose failed.
    pub const FAILED_TO_STAGE: u16 = 903;
    /// Driving onto or off the dock failed.
    pub const FAILED_TO_CONTROL: u16 = 905;
    /// The robot docked but the battery does not charge.
    pub const FAILED_TO_CHARGE: u16 = 906;
    /// The time allowed ran out.
    pub const TIMEOUT: u16 = 907;
    /// A failure of no other kind.
    pub const UNKNOWN: u16 = 999;
}

/// The following server (FollowObject).
pub mod follow_object {
    /// The object is not seen.
    pub const FAILED_TO_DETECT_OBJECT: u16 = 902;
    /// Driving after the object failed.
    pub const FAILED_TO_CONTROL: u16 = 903;
}

/// The navigators (NavigateToPose; NavigateThroughPoses's codes are 100 higher).
pub mod navigate {
    /// NavigateToPose: a failure of no other kind.
    pub const TO_POSE_UNKNOWN: u16 = 9000;
    /// NavigateThroughPoses: a failure of no other kind.
    pub const THROUGH_POSES_UNKNOWN: u16 = 9100;
}

/// The codes for which WouldAPlannerRecoveryHelp succeeds: clearing the global costmap may
/// let the planner find a path (ComputePathToPose's and ComputePathThroughPoses's).
pub const PLANNER_RECOVERABLE: [u16; 6] = [
    compute_path::UNKNOWN,
    compute_path::NO_VALID_PATH,
    compute_path::TIMEOUT,
    compute_path_through_poses::UNKNOWN,
    compute_path_through_poses::TIMEOUT,
    compute_path_through_poses::NO_VALID_PATH,
];

/// The codes for which WouldARouteRecoveryHelp succeeds (ComputeRoute's and
/// ComputeAndTrackRoute's, which are the same numbers).
pub const ROUTE_RECOVERABLE: [u16; 3] = [route::UNKNOWN, route::NO_VALID_ROUTE, route::TIMEOUT];

/// The codes for which WouldASmootherRecoveryHelp succeeds.
pub const SMOOTHER_RECOVERABLE: [u16; 4] = [
    smooth_path::UNKNOWN,
    smooth_path::TIMEOUT,
    smooth_path::FAILED_TO_SMOOTH_PATH,
    smooth_path::SMOOTHED_PATH_IN_COLLISION,
];

/// The codes for which WouldAControllerRecoveryHelp succeeds.
pub const CONTROLLER_RECOVERABLE: [u16; 4] = [
    follow_path::UNKNOWN,
    follow_path::PATIENCE_EXCEEDED,
    follow_path::FAILED_TO_MAKE_PROGRESS,
    follow_path::NO_VALID_CONTROL,
];
