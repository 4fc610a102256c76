//! `nav2_msgs`: the actions and services of Nav2's servers that the navigator calls.
//!
//! Each action is a type that names it ([`RosAction`]) and three messages: `…Goal`,
//! `…Result` (with the server's error codes as constants) and `…Feedback`.
//!
//! The planner's, controller's and behaviors' actions have Jazzy's layout, and [`kilted`]
//! has the goals Kilted changed (Spin's, BackUp's, DriveOnHeading's,
//! ComputePathThroughPoses's), which main keeps. The actions and services Jazzy does not
//! have, or whose every part Kilted and main changed (NavigateThroughPoses takes
//! `nav_msgs/Goals` and reports waypoint statuses), have Nav2 main's layout: the route
//! server's, the docking server's, FollowObject, AssistedTeleop, GetCosts and Toggle.
//!
//! [`main`] has the costmap clearing services as main changed them (`plugins`, `success`),
//! ComputePathToPose's goal with `viapoints` and FollowPath's goal (`path_handler_id`) and
//! feedback (a `TrackingFeedback`). Main changed more than this crate follows:
//! NavigateToPose's feedback the tracking errors, ComputePathThroughPoses's result
//! `last_reached_index`; those messages have Kilted's layout here.

use serde::{Deserialize, Serialize};

use super::builtin_interfaces::Duration;
use super::geometry_msgs::{Point, PoseStamped};
use super::nav_msgs::{Goals, Path};
use super::std_msgs::Empty;
use super::std_msgs::Header;
use crate::interface::messages;
use crate::{RosAction, RosService};

/// Implements `Message` for the parts of actions and services.
macro_rules! parts {
    ($($ty:ident),+ $(,)?) => { $(impl ros2_client::Message for $ty {})+ };
}

/// Declares an action type named as its Rust struct.
macro_rules! action {
    ($(#[$doc:meta])* $name:ident: $goal:ident, $result:ident, $feedback:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug)]
        pub struct $name;
        impl RosAction for $name {
            type Goal = $goal;
            type Result = $result;
            type Feedback = $feedback;
            const TYPE: (&'static str, &'static str) = ("nav2_msgs", stringify!($name));
        }
        parts!($goal, $result, $feedback);
    };
}

action!(
    /// `nav2_msgs/action/ComputePathToPose`: the planner server's path to a pose.
    ComputePathToPose: ComputePathToPoseGoal, ComputePathToPoseResult, ComputePathToPoseFeedback
);

/// The goal of [`ComputePathToPose`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ComputePathToPoseGoal {
    /// Where the path ends.
    pub goal: PoseStamped,
    /// Where it starts, when `use_start`.
    pub start: PoseStamped,
    /// Which planner plugin; empty for the only one.
    pub planner_id: String,
    /// `false`: start at the robot's current pose.
    pub use_start: bool,
}

/// The result of [`ComputePathToPose`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ComputePathToPoseResult {
    /// The path found.
    pub path: Path,
    /// How long planning took.
    pub planning_time: Duration,
    /// 0, or one of the constants.
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl ComputePathToPoseResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// An error without a code of its own.
    pub const UNKNOWN: u16 = 200;
    /// No planner plugin has `planner_id`.
    pub const INVALID_PLANNER: u16 = 201;
    /// A transform was missing.
    pub const TF_ERROR: u16 = 202;
    /// The start is off the map.
    pub const START_OUTSIDE_MAP: u16 = 203;
    /// The goal is off the map.
    pub const GOAL_OUTSIDE_MAP: u16 = 204;
    /// The start is in an obstacle.
    pub const START_OCCUPIED: u16 = 205;
    /// The goal is in an obstacle.
    pub const GOAL_OCCUPIED: u16 = 206;
    /// Planning took too long.
    pub const TIMEOUT: u16 = 207;
    /// No path joins start and goal.
    pub const NO_VALID_PATH: u16 = 208;
}

/// The feedback of [`ComputePathToPose`]: none (one placeholder byte on the wire).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ComputePathToPoseFeedback {
    /// Always 0.
    pub structure_needs_at_least_one_member: u8,
}

action!(
    /// `nav2_msgs/action/ComputePathThroughPoses`: the planner server's path through poses.
    ComputePathThroughPoses: ComputePathThroughPosesGoal, ComputePathThroughPosesResult,
    ComputePathThroughPosesFeedback
);

/// The goal of [`ComputePathThroughPoses`] (Jazzy's: the goals as an array of poses).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ComputePathThroughPosesGoal {
    /// The poses to pass, in order.
    pub goals: Vec<PoseStamped>,
    /// Where it starts, when `use_start`.
    pub start: PoseStamped,
    /// Which planner plugin; empty for the only one.
    pub planner_id: String,
    /// `false`: start at the robot's current pose.
    pub use_start: bool,
}

/// The result of [`ComputePathThroughPoses`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ComputePathThroughPosesResult {
    /// The path found.
    pub path: Path,
    /// How long planning took.
    pub planning_time: Duration,
    /// 0, or one of the constants.
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl ComputePathThroughPosesResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// An error without a code of its own.
    pub const UNKNOWN: u16 = 300;
    /// No path joins the poses.
    pub const NO_VALID_PATH: u16 = 308;
    /// No goals were given.
    pub const NO_VIAPOINTS_GIVEN: u16 = 309;
}

/// The feedback of [`ComputePathThroughPoses`]: none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ComputePathThroughPosesFeedback {
    /// Always 0.
    pub structure_needs_at_least_one_member: u8,
}

action!(
    /// `nav2_msgs/action/SmoothPath`: the smoother server smooths a path.
    SmoothPath: SmoothPathGoal, SmoothPathResult, SmoothPathFeedback
);

/// The goal of [`SmoothPath`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SmoothPathGoal {
    /// The path to smooth.
    pub path: Path,
    /// Which smoother plugin; empty for the only one.
    pub smoother_id: String,
    /// How long smoothing may take.
    pub max_smoothing_duration: Duration,
    /// Fail if the smoothed path collides.
    pub check_for_collisions: bool,
}

/// The result of [`SmoothPath`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SmoothPathResult {
    /// The smoothed path.
    pub path: Path,
    /// How long smoothing took.
    pub smoothing_duration: Duration,
    /// Whether it finished within `max_smoothing_duration`.
    pub was_completed: bool,
    /// 0, or one of the constants.
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl SmoothPathResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// An error without a code of its own.
    pub const UNKNOWN: u16 = 500;
    /// The smoothed path collides.
    pub const SMOOTHED_PATH_IN_COLLISION: u16 = 503;
    /// The path is empty.
    pub const INVALID_PATH: u16 = 505;
}

/// The feedback of [`SmoothPath`]: none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SmoothPathFeedback {
    /// Always 0.
    pub structure_needs_at_least_one_member: u8,
}

action!(
    /// `nav2_msgs/action/FollowPath`: the controller server drives along a path.
    FollowPath: FollowPathGoal, FollowPathResult, FollowPathFeedback
);

/// The goal of [`FollowPath`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FollowPathGoal {
    /// The path to follow.
    pub path: Path,
    /// Which controller plugin; empty for the only one.
    pub controller_id: String,
    /// Which goal checker plugin; empty for the only one.
    pub goal_checker_id: String,
    /// Which progress checker plugin; empty for the only one.
    pub progress_checker_id: String,
}

/// The result of [`FollowPath`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FollowPathResult {
    /// Nothing.
    pub result: Empty,
    /// 0, or one of the constants.
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl FollowPathResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// An error without a code of its own.
    pub const UNKNOWN: u16 = 100;
    /// No controller plugin has `controller_id`.
    pub const INVALID_CONTROLLER: u16 = 101;
    /// A transform was missing.
    pub const TF_ERROR: u16 = 102;
    /// The path is empty or unusable.
    pub const INVALID_PATH: u16 = 103;
    /// The progress checker ran out of patience.
    pub const PATIENCE_EXCEEDED: u16 = 104;
    /// The robot stopped making progress.
    pub const FAILED_TO_MAKE_PROGRESS: u16 = 105;
    /// The controller found no safe command.
    pub const NO_VALID_CONTROL: u16 = 106;
    /// The controller took too long.
    pub const CONTROLLER_TIMED_OUT: u16 = 107;
}

/// The feedback of [`FollowPath`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FollowPathFeedback {
    /// Meters left to the path's end.
    pub distance_to_goal: f32,
    /// Current speed, m/s.
    pub speed: f32,
}

action!(
    /// `nav2_msgs/action/Spin`: the behavior server turns the robot in place.
    Spin: SpinGoal, SpinResult, SpinFeedback
);

/// The goal of [`Spin`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SpinGoal {
    /// How far to turn, radians (signed).
    pub target_yaw: f32,
    /// How long it may take.
    pub time_allowance: Duration,
}

/// The result of [`Spin`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SpinResult {
    /// How long it took.
    pub total_elapsed_time: Duration,
    /// 0, or one of the constants.
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl SpinResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// An error without a code of its own.
    pub const UNKNOWN: u16 = 700;
    /// It took longer than `time_allowance`.
    pub const TIMEOUT: u16 = 701;
    /// A transform was missing.
    pub const TF_ERROR: u16 = 702;
    /// Turning would collide.
    pub const COLLISION_AHEAD: u16 = 703;
}

/// The feedback of [`Spin`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SpinFeedback {
    /// Radians turned so far.
    pub angular_distance_traveled: f32,
}

action!(
    /// `nav2_msgs/action/BackUp`: the behavior server drives the robot backwards.
    BackUp: BackUpGoal, BackUpResult, BackUpFeedback
);

/// The goal of [`BackUp`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BackUpGoal {
    /// How far, as a point in the robot's frame (x negative to back up).
    pub target: Point,
    /// m/s.
    pub speed: f32,
    /// How long it may take.
    pub time_allowance: Duration,
}

/// The result of [`BackUp`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BackUpResult {
    /// How long it took.
    pub total_elapsed_time: Duration,
    /// 0, or one of the constants.
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl BackUpResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// An error without a code of its own.
    pub const UNKNOWN: u16 = 710;
    /// It took longer than `time_allowance`.
    pub const TIMEOUT: u16 = 711;
    /// A transform was missing.
    pub const TF_ERROR: u16 = 712;
    /// The goal was unusable.
    pub const INVALID_INPUT: u16 = 713;
    /// Backing up would collide.
    pub const COLLISION_AHEAD: u16 = 714;
}

/// The feedback of [`BackUp`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BackUpFeedback {
    /// Meters driven so far.
    pub distance_traveled: f32,
}

action!(
    /// `nav2_msgs/action/DriveOnHeading`: the behavior server drives the robot straight on.
    DriveOnHeading: DriveOnHeadingGoal, DriveOnHeadingResult, DriveOnHeadingFeedback
);

/// The goal of [`DriveOnHeading`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DriveOnHeadingGoal {
    /// How far, as a point in the robot's frame (x negative to drive backwards).
    pub target: Point,
    /// m/s, negative backwards.
    pub speed: f32,
    /// How long it may take.
    pub time_allowance: Duration,
}

/// The result of [`DriveOnHeading`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DriveOnHeadingResult {
    /// How long it took.
    pub total_elapsed_time: Duration,
    /// 0, or one of the constants.
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl DriveOnHeadingResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// An error without a code of its own.
    pub const UNKNOWN: u16 = 720;
    /// It took longer than `time_allowance`.
    pub const TIMEOUT: u16 = 721;
    /// A transform was missing.
    pub const TF_ERROR: u16 = 722;
    /// Driving on would collide.
    pub const COLLISION_AHEAD: u16 = 723;
    /// The goal was unusable.
    pub const INVALID_INPUT: u16 = 724;
}

/// The feedback of [`DriveOnHeading`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DriveOnHeadingFeedback {
    /// Meters driven so far.
    pub distance_traveled: f32,
}

action!(
    /// `nav2_msgs/action/Wait`: the behavior server waits.
    Wait: WaitGoal, WaitResult, WaitFeedback
);

/// The goal of [`Wait`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WaitGoal {
    /// How long.
    pub time: Duration,
}

/// The result of [`Wait`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WaitResult {
    /// How long it took.
    pub total_elapsed_time: Duration,
    /// 0 (no error codes are defined).
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

/// The feedback of [`Wait`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WaitFeedback {
    /// How long is left.
    pub time_left: Duration,
}

/// `nav2_msgs/srv/ClearEntireCostmap`: a costmap forgets every obstacle.
#[derive(Clone, Copy, Debug)]
pub struct ClearEntireCostmap;

impl RosService for ClearEntireCostmap {
    type Request = ClearEntireCostmapRequest;
    type Response = ClearEntireCostmapResponse;
    const TYPE: (&'static str, &'static str) = ("nav2_msgs", "ClearEntireCostmap");
}

/// The request of [`ClearEntireCostmap`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ClearEntireCostmapRequest {
    /// Nothing.
    pub request: Empty,
}

/// The response of [`ClearEntireCostmap`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ClearEntireCostmapResponse {
    /// Nothing.
    pub response: Empty,
}

parts!(ClearEntireCostmapRequest, ClearEntireCostmapResponse);

/// Declares a clearing service whose response is empty.
macro_rules! clearing {
    ($(#[$doc:meta])* $name:ident: $request:ident, $response:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug)]
        pub struct $name;

        impl RosService for $name {
            type Request = $request;
            type Response = $response;
            const TYPE: (&'static str, &'static str) = ("nav2_msgs", stringify!($name));
        }

        #[doc = concat!("The response of [`", stringify!($name), "`].")]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
        pub struct $response {
            /// Nothing.
            pub response: Empty,
        }

        parts!($request, $response);
    };
}

clearing!(
    /// `nav2_msgs/srv/ClearCostmapAroundRobot`: a costmap forgets the obstacles in a square
    /// around the robot.
    ClearCostmapAroundRobot: ClearCostmapAroundRobotRequest, ClearCostmapAroundRobotResponse
);

/// The request of [`ClearCostmapAroundRobot`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ClearCostmapAroundRobotRequest {
    /// The square's side, in metres.
    pub reset_distance: f32,
}

clearing!(
    /// `nav2_msgs/srv/ClearCostmapExceptRegion`: a costmap forgets the obstacles outside a
    /// square around the robot.
    ClearCostmapExceptRegion: ClearCostmapExceptRegionRequest, ClearCostmapExceptRegionResponse
);

/// The request of [`ClearCostmapExceptRegion`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ClearCostmapExceptRegionRequest {
    /// The square's side, in metres.
    pub reset_distance: f32,
}

clearing!(
    /// `nav2_msgs/srv/ClearCostmapAroundPose`: a costmap forgets the obstacles in a square
    /// around a pose.
    ClearCostmapAroundPose: ClearCostmapAroundPoseRequest, ClearCostmapAroundPoseResponse
);

/// The request of [`ClearCostmapAroundPose`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ClearCostmapAroundPoseRequest {
    /// The square's centre.
    pub pose: PoseStamped,
    /// The square's side, in metres.
    pub reset_distance: f64,
}

action!(
    /// `nav2_msgs/action/NavigateToPose`: the BT navigator drives the robot to a pose.
    NavigateToPose: NavigateToPoseGoal, NavigateToPoseResult, NavigateToPoseFeedback
);

/// The goal of [`NavigateToPose`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NavigateToPoseGoal {
    /// Where to go.
    pub pose: PoseStamped,
    /// A behavior tree file to run instead of the navigator's default; empty for it.
    pub behavior_tree: String,
}

/// The result of [`NavigateToPose`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NavigateToPoseResult {
    /// 0, or one of the constants.
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl NavigateToPoseResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// An error without a code of its own (the tree failed).
    pub const UNKNOWN: u16 = 9000;
    /// The goal's `behavior_tree` could not be loaded.
    pub const FAILED_TO_LOAD_BEHAVIOR_TREE: u16 = 9001;
    /// A transform was missing.
    pub const TF_ERROR: u16 = 9002;
    /// Navigation took too long.
    pub const TIMEOUT: u16 = 9003;
}

/// The feedback of [`NavigateToPose`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NavigateToPoseFeedback {
    /// Where the robot is.
    pub current_pose: PoseStamped,
    /// How long the navigation has run.
    pub navigation_time: Duration,
    /// How long it may still take, at the current speed.
    pub estimated_time_remaining: Duration,
    /// Recoveries run so far for this goal.
    pub number_of_recoveries: i16,
    /// Metres left along the path.
    pub distance_remaining: f32,
}

/// `nav2_msgs/msg/RouteNode`: a node of the route graph.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RouteNode {
    /// Its id in the graph.
    pub nodeid: u16,
    /// Where it is.
    pub position: Point,
}

/// `nav2_msgs/msg/RouteEdge`: an edge of the route graph, by its ends' positions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RouteEdge {
    /// Its id in the graph.
    pub edgeid: u16,
    /// Where it starts.
    pub start: Point,
    /// Where it ends.
    pub end: Point,
}

/// `nav2_msgs/msg/Route`: the nodes of a route in order and the edges between them.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Route {
    /// Frame and time.
    pub header: Header,
    /// The route's cost.
    pub route_cost: f32,
    /// The nodes, start first.
    pub nodes: Vec<RouteNode>,
    /// The edges joining them, one fewer.
    pub edges: Vec<RouteEdge>,
}

/// `nav2_msgs/msg/WaypointStatus`: how one of several goals went.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WaypointStatus {
    /// One of the constants.
    pub waypoint_status: u8,
    /// Its index among the goals.
    pub waypoint_index: u32,
    /// The goal.
    pub waypoint_pose: PoseStamped,
    /// The error code it failed with, or 0.
    pub error_code: u16,
    /// Why it failed, for people.
    pub error_msg: String,
}

impl WaypointStatus {
    /// Not reached yet.
    pub const PENDING: u8 = 0;
    /// Reached.
    pub const COMPLETED: u8 = 1;
    /// Left out.
    pub const SKIPPED: u8 = 2;
    /// Failed.
    pub const FAILED: u8 = 3;
}

messages!("nav2_msgs": RouteNode, RouteEdge, Route, WaypointStatus);

/// Declares the goal of a route action: both route actions take the same fields.
macro_rules! route_goal {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
        pub struct $name {
            /// The start node, without `use_poses`.
            pub start_id: u16,
            /// Where to start, with `use_poses` and `use_start`.
            pub start: PoseStamped,
            /// The goal node, without `use_poses`.
            pub goal_id: u16,
            /// Where to go, with `use_poses`.
            pub goal: PoseStamped,
            /// Start at `start` rather than at the robot.
            pub use_start: bool,
            /// Use the poses rather than the node ids.
            pub use_poses: bool,
        }
    };
}

action!(
    /// `nav2_msgs/action/ComputeRoute`: the route server's route on its graph.
    ComputeRoute: ComputeRouteGoal, ComputeRouteResult, ComputeRouteFeedback
);

route_goal!(
    /// The goal of [`ComputeRoute`].
    ComputeRouteGoal
);

/// The result of [`ComputeRoute`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ComputeRouteResult {
    /// How long routing took.
    pub planning_time: Duration,
    /// The route's path.
    pub path: Path,
    /// The route.
    pub route: Route,
    /// 0, or one of the constants.
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl ComputeRouteResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// An error without a code of its own.
    pub const UNKNOWN: u16 = 400;
    /// A transform was missing.
    pub const TF_ERROR: u16 = 401;
    /// The server has no graph.
    pub const NO_VALID_GRAPH: u16 = 402;
    /// The start or goal is not on the graph.
    pub const INDETERMINANT_NODES_ON_GRAPH: u16 = 403;
    /// Routing took too long.
    pub const TIMEOUT: u16 = 404;
    /// No route joins start and goal.
    pub const NO_VALID_ROUTE: u16 = 405;
    /// An edge scorer was misused.
    pub const INVALID_EDGE_SCORER_USE: u16 = 407;
}

/// The feedback of [`ComputeRoute`]: none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ComputeRouteFeedback {
    /// Always 0.
    pub structure_needs_at_least_one_member: u8,
}

action!(
    /// `nav2_msgs/action/ComputeAndTrackRoute`: the route server's route, then the robot
    /// tracked along it.
    ComputeAndTrackRoute: ComputeAndTrackRouteGoal, ComputeAndTrackRouteResult,
    ComputeAndTrackRouteFeedback
);

route_goal!(
    /// The goal of [`ComputeAndTrackRoute`].
    ComputeAndTrackRouteGoal
);

/// The result of [`ComputeAndTrackRoute`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ComputeAndTrackRouteResult {
    /// How long the tracking took.
    pub execution_duration: Duration,
    /// 0, or one of the constants.
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl ComputeAndTrackRouteResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// An error without a code of its own.
    pub const UNKNOWN: u16 = 400;
    /// The server has no graph.
    pub const NO_VALID_GRAPH: u16 = 402;
    /// The start or goal is not on the graph.
    pub const INDETERMINANT_NODES_ON_GRAPH: u16 = 403;
    /// No route joins start and goal.
    pub const NO_VALID_ROUTE: u16 = 405;
    /// An operation on the route failed.
    pub const OPERATION_FAILED: u16 = 406;
}

/// The feedback of [`ComputeAndTrackRoute`]: where along the route the robot is.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ComputeAndTrackRouteFeedback {
    /// The last node reached.
    pub last_node_id: u16,
    /// The node driven to.
    pub next_node_id: u16,
    /// The edge driven on.
    pub current_edge_id: u16,
    /// The route.
    pub route: Route,
    /// The route's path.
    pub path: Path,
    /// The route operations run.
    pub operations_triggered: Vec<String>,
    /// The route was computed again.
    pub rerouted: bool,
}

action!(
    /// `nav2_msgs/action/DockRobot`: the docking server docks the robot.
    DockRobot: DockRobotGoal, DockRobotResult, DockRobotFeedback
);

/// The goal of [`DockRobot`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DockRobotGoal {
    /// Dock at `dock_id` rather than at `dock_pose`.
    pub use_dock_id: bool,
    /// The dock's id in the server's database.
    pub dock_id: String,
    /// The dock's pose, without `use_dock_id`.
    pub dock_pose: PoseStamped,
    /// The dock's type, without `use_dock_id`.
    pub dock_type: String,
    /// Seconds to reach the staging pose.
    pub max_staging_time: f32,
    /// Drive to the staging pose first (else the robot is there already).
    pub navigate_to_staging_pose: bool,
}

impl Default for DockRobotGoal {
    /// The message's defaults: by id, 1000 s to stage, navigating there.
    fn default() -> Self {
        Self {
            use_dock_id: true,
            dock_id: String::new(),
            dock_pose: PoseStamped::default(),
            dock_type: String::new(),
            max_staging_time: 1000.0,
            navigate_to_staging_pose: true,
        }
    }
}

/// The result of [`DockRobot`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DockRobotResult {
    /// Docked.
    pub success: bool,
    /// 0, or one of the constants.
    pub error_code: u16,
    /// Retries made.
    pub num_retries: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl Default for DockRobotResult {
    /// The message's defaults (`success` true).
    fn default() -> Self {
        Self {
            success: true,
            error_code: 0,
            num_retries: 0,
            error_msg: String::new(),
        }
    }
}

impl DockRobotResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// No dock of that id.
    pub const DOCK_NOT_IN_DB: u16 = 901;
    /// The dock is not valid (no plugin of its type).
    pub const DOCK_NOT_VALID: u16 = 902;
    /// The staging pose was not reached.
    pub const FAILED_TO_STAGE: u16 = 903;
    /// The dock was not detected.
    pub const FAILED_TO_DETECT_DOCK: u16 = 904;
    /// Driving onto the dock failed.
    pub const FAILED_TO_CONTROL: u16 = 905;
    /// The battery did not charge.
    pub const FAILED_TO_CHARGE: u16 = 906;
    /// Docking took too long.
    pub const TIMEOUT: u16 = 907;
    /// An error without a code of its own.
    pub const UNKNOWN: u16 = 999;
}

/// The feedback of [`DockRobot`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DockRobotFeedback {
    /// The docking state (NAV_TO_STAGING_POSE 1, …, WAIT_FOR_CHARGE 4).
    pub state: u16,
    /// How long docking has run.
    pub docking_time: Duration,
    /// Retries made.
    pub num_retries: u16,
}

action!(
    /// `nav2_msgs/action/UndockRobot`: the docking server backs the robot off its dock.
    UndockRobot: UndockRobotGoal, UndockRobotResult, UndockRobotFeedback
);

/// The goal of [`UndockRobot`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UndockRobotGoal {
    /// The dock's type; empty for the one the server docked at.
    pub dock_type: String,
    /// Seconds undocking may take.
    pub max_undocking_time: f32,
}

impl Default for UndockRobotGoal {
    /// The message's default: 30 s.
    fn default() -> Self {
        Self {
            dock_type: String::new(),
            max_undocking_time: 30.0,
        }
    }
}

/// The result of [`UndockRobot`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UndockRobotResult {
    /// Undocked.
    pub success: bool,
    /// 0, or one of the constants.
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl Default for UndockRobotResult {
    /// The message's defaults (`success` true).
    fn default() -> Self {
        Self {
            success: true,
            error_code: 0,
            error_msg: String::new(),
        }
    }
}

impl UndockRobotResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// The dock is not valid.
    pub const DOCK_NOT_VALID: u16 = 902;
    /// Backing off failed.
    pub const FAILED_TO_CONTROL: u16 = 905;
    /// Undocking took too long.
    pub const TIMEOUT: u16 = 907;
    /// An error without a code of its own.
    pub const UNKNOWN: u16 = 999;
}

/// The feedback of [`UndockRobot`]: none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct UndockRobotFeedback {
    /// Always 0.
    pub structure_needs_at_least_one_member: u8,
}

action!(
    /// `nav2_msgs/action/NavigateThroughPoses`: a navigator drives the robot through poses
    /// (Nav2 main's layout).
    NavigateThroughPoses: NavigateThroughPosesGoal, NavigateThroughPosesResult,
    NavigateThroughPosesFeedback
);

/// The goal of [`NavigateThroughPoses`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NavigateThroughPosesGoal {
    /// The poses to pass, in order.
    pub poses: Goals,
    /// A behavior tree to run instead of the navigator's default; empty for it.
    pub behavior_tree: String,
}

/// The result of [`NavigateThroughPoses`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NavigateThroughPosesResult {
    /// 0, or one of the constants.
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
    /// How each pose went.
    pub waypoint_statuses: Vec<WaypointStatus>,
}

impl NavigateThroughPosesResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// An error without a code of its own (the tree failed).
    pub const UNKNOWN: u16 = 9100;
    /// The goal's `behavior_tree` could not be loaded.
    pub const FAILED_TO_LOAD_BEHAVIOR_TREE: u16 = 9101;
    /// A transform was missing.
    pub const TF_ERROR: u16 = 9102;
    /// Navigation took too long.
    pub const TIMEOUT: u16 = 9103;
}

/// The feedback of [`NavigateThroughPoses`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NavigateThroughPosesFeedback {
    /// Where the robot is.
    pub current_pose: PoseStamped,
    /// How long the navigation has run.
    pub navigation_time: Duration,
    /// How long it may still take.
    pub estimated_time_remaining: Duration,
    /// Recoveries run so far.
    pub number_of_recoveries: i16,
    /// Metres left along the path.
    pub distance_remaining: f32,
    /// Metres off the path.
    pub position_tracking_error: f32,
    /// Radians off the path's heading.
    pub heading_tracking_error: f32,
    /// Poses not yet passed.
    pub number_of_poses_remaining: i16,
    /// How each pose went so far.
    pub waypoint_statuses: Vec<WaypointStatus>,
}

action!(
    /// `nav2_msgs/action/FollowObject`: the following server keeps the robot behind a
    /// moving object.
    FollowObject: FollowObjectGoal, FollowObjectResult, FollowObjectFeedback
);

/// The goal of [`FollowObject`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FollowObjectGoal {
    /// The topic the object's pose comes on.
    pub pose_topic: String,
    /// The object's frame, when `pose_topic` is empty.
    pub tracked_frame: String,
    /// How long to follow; zero for as long as it is not stopped.
    pub max_duration: Duration,
}

/// The result of [`FollowObject`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FollowObjectResult {
    /// How long it followed.
    pub total_elapsed_time: Duration,
    /// 0, or one of the constants.
    pub error_code: u16,
    /// Retries made.
    pub num_retries: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl FollowObjectResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// A transform was missing.
    pub const TF_ERROR: u16 = 901;
    /// The object was not seen.
    pub const FAILED_TO_DETECT_OBJECT: u16 = 902;
    /// Driving after it failed.
    pub const FAILED_TO_CONTROL: u16 = 903;
    /// Following took too long.
    pub const TIMEOUT: u16 = 904;
    /// An error without a code of its own.
    pub const UNKNOWN: u16 = 999;
}

/// The feedback of [`FollowObject`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FollowObjectFeedback {
    /// The following state (INITIAL_PERCEPTION 1, CONTROLLING 2, …).
    pub state: u16,
    /// How long it has followed.
    pub following_time: Duration,
    /// Retries made.
    pub num_retries: u16,
}

action!(
    /// `nav2_msgs/action/AssistedTeleop`: the behavior server passes a person's velocity
    /// commands on, slowed before obstacles, for a while.
    AssistedTeleop: AssistedTeleopGoal, AssistedTeleopResult, AssistedTeleopFeedback
);

/// The goal of [`AssistedTeleop`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AssistedTeleopGoal {
    /// How long the person may drive; past it, the behavior fails with TIMEOUT.
    pub time_allowance: Duration,
}

/// The result of [`AssistedTeleop`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AssistedTeleopResult {
    /// How long it ran.
    pub total_elapsed_time: Duration,
    /// 0, or one of the constants.
    pub error_code: u16,
    /// What went wrong, for people.
    pub error_msg: String,
}

impl AssistedTeleopResult {
    /// No error.
    pub const NONE: u16 = 0;
    /// An error without a code of its own.
    pub const UNKNOWN: u16 = 730;
    /// The time allowance ran out.
    pub const TIMEOUT: u16 = 731;
    /// A transform was missing.
    pub const TF_ERROR: u16 = 732;
}

/// The feedback of [`AssistedTeleop`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AssistedTeleopFeedback {
    /// How long it has run.
    pub current_teleop_duration: Duration,
}

/// `nav2_msgs/srv/GetCosts`: a costmap's costs at poses (Nav2's `get_cost_<costmap>`).
#[derive(Clone, Copy, Debug)]
pub struct GetCosts;

impl RosService for GetCosts {
    type Request = GetCostsRequest;
    type Response = GetCostsResponse;
    const TYPE: (&'static str, &'static str) = ("nav2_msgs", "GetCosts");
}

/// The request of [`GetCosts`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GetCostsRequest {
    /// The cost under the robot's footprint at each pose, rather than at its point.
    pub use_footprint: bool,
    /// The poses.
    pub poses: Vec<PoseStamped>,
}

/// The response of [`GetCosts`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GetCostsResponse {
    /// One cost a pose, 0 (free) to 254 (lethal), 255 unknown.
    pub costs: Vec<f32>,
    /// `false` when a pose was off the costmap.
    pub success: bool,
}

/// `nav2_msgs/srv/Toggle`: a switch (the collision monitor's `toggle`).
#[derive(Clone, Copy, Debug)]
pub struct Toggle;

impl RosService for Toggle {
    type Request = ToggleRequest;
    type Response = ToggleResponse;
    const TYPE: (&'static str, &'static str) = ("nav2_msgs", "Toggle");
}

/// The request of [`Toggle`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ToggleRequest {
    /// On (true) or off.
    pub enable: bool,
}

/// The response of [`Toggle`].
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ToggleResponse {
    /// Switched.
    pub success: bool,
    /// What happened, for people.
    pub message: String,
}

parts!(
    GetCostsRequest,
    GetCostsResponse,
    ToggleRequest,
    ToggleResponse
);

/// The goals Nav2 Kilted changed, as Kilted and main have them: the behaviors' goals gained
/// `disable_collision_checks`, and ComputePathThroughPoses takes its goals as a
/// `nav_msgs/Goals`. Each action has the same ROS 2 name, result and feedback as the Jazzy
/// one of the parent module; only the goal's layout differs, so a client and a server must
/// agree on the release.
pub mod kilted {
    use serde::{Deserialize, Serialize};

    use super::super::builtin_interfaces::Duration;
    use super::super::geometry_msgs::{Point, PoseStamped};
    use super::super::nav_msgs::Goals;
    use super::{
        BackUpFeedback, BackUpResult, ComputePathThroughPosesFeedback,
        ComputePathThroughPosesResult, DriveOnHeadingFeedback, DriveOnHeadingResult, SpinFeedback,
        SpinResult,
    };
    use crate::RosAction;

    /// Declares an action whose result and feedback are the Jazzy action's.
    macro_rules! goal_only {
        ($(#[$doc:meta])* $name:ident: $goal:ident, $result:ident, $feedback:ident) => {
            $(#[$doc])*
            #[derive(Clone, Copy, Debug)]
            pub struct $name;
            impl RosAction for $name {
                type Goal = $goal;
                type Result = $result;
                type Feedback = $feedback;
                const TYPE: (&'static str, &'static str) = ("nav2_msgs", stringify!($name));
            }
            impl ros2_client::Message for $goal {}
        };
    }

    goal_only!(
        /// `nav2_msgs/action/Spin`, Kilted's goal.
        Spin: SpinGoal, SpinResult, SpinFeedback
    );

    /// The goal of [`Spin`].
    #[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
    pub struct SpinGoal {
        /// Radians to turn.
        pub target_yaw: f32,
        /// How long the behavior may take.
        pub time_allowance: Duration,
        /// Turn without checking for collisions.
        pub disable_collision_checks: bool,
    }

    goal_only!(
        /// `nav2_msgs/action/BackUp`, Kilted's goal.
        BackUp: BackUpGoal, BackUpResult, BackUpFeedback
    );

    /// The goal of [`BackUp`].
    #[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
    pub struct BackUpGoal {
        /// How far to drive back (`x`, metres).
        pub target: Point,
        /// Metres per second.
        pub speed: f32,
        /// How long the behavior may take.
        pub time_allowance: Duration,
        /// Drive without checking for collisions.
        pub disable_collision_checks: bool,
    }

    goal_only!(
        /// `nav2_msgs/action/DriveOnHeading`, Kilted's goal.
        DriveOnHeading: DriveOnHeadingGoal, DriveOnHeadingResult, DriveOnHeadingFeedback
    );

    /// The goal of [`DriveOnHeading`].
    #[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
    pub struct DriveOnHeadingGoal {
        /// How far to drive (`x`, metres; negative backwards).
        pub target: Point,
        /// Metres per second.
        pub speed: f32,
        /// How long the behavior may take.
        pub time_allowance: Duration,
        /// Drive without checking for collisions.
        pub disable_collision_checks: bool,
    }

    goal_only!(
        /// `nav2_msgs/action/ComputePathThroughPoses`, Kilted's goal.
        ComputePathThroughPoses: ComputePathThroughPosesGoal, ComputePathThroughPosesResult,
        ComputePathThroughPosesFeedback
    );

    /// The goal of [`ComputePathThroughPoses`].
    #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
    pub struct ComputePathThroughPosesGoal {
        /// The poses to pass, in order.
        pub goals: Goals,
        /// Where it starts, when `use_start`.
        pub start: PoseStamped,
        /// Which planner plugin; empty for the only one.
        pub planner_id: String,
        /// `false`: start at the robot's current pose.
        pub use_start: bool,
    }
}

/// What Nav2 main changed after Kilted that this crate follows: the costmap clearing
/// services (each request names the costmap `plugins` to clear, all of them when empty, and
/// the response says whether they were cleared), ComputePathToPose's goal (with
/// `viapoints`) and FollowPath (a `path_handler_id`, a [`TrackingFeedback`](main::TrackingFeedback)). Each has the same ROS 2 name as the Jazzy one of the parent module.
pub mod main {
    use serde::{Deserialize, Serialize};

    use super::super::geometry_msgs::PoseStamped;
    use crate::RosService;

    /// Declares a clearing service answered by a [`ClearResponse`].
    macro_rules! clearing_main {
        ($(#[$doc:meta])* $name:ident: $request:ident) => {
            $(#[$doc])*
            #[derive(Clone, Copy, Debug)]
            pub struct $name;

            impl RosService for $name {
                type Request = $request;
                type Response = ClearResponse;
                const TYPE: (&'static str, &'static str) = ("nav2_msgs", stringify!($name));
            }

            impl ros2_client::Message for $request {}
        };
    }

    /// The response of main's clearing services.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
    pub struct ClearResponse {
        /// The plugins were cleared.
        pub success: bool,
    }

    impl ros2_client::Message for ClearResponse {}

    clearing_main!(
        /// `nav2_msgs/srv/ClearEntireCostmap`, main's: a costmap forgets every obstacle.
        ClearEntireCostmap: ClearEntireCostmapRequest
    );

    /// The request of [`ClearEntireCostmap`].
    #[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
    pub struct ClearEntireCostmapRequest {
        /// The plugins to clear; empty for all.
        pub plugins: Vec<String>,
    }

    clearing_main!(
        /// `nav2_msgs/srv/ClearCostmapAroundRobot`, main's.
        ClearCostmapAroundRobot: ClearCostmapAroundRobotRequest
    );

    /// The request of [`ClearCostmapAroundRobot`].
    #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
    pub struct ClearCostmapAroundRobotRequest {
        /// The square's side, in metres.
        pub reset_distance: f32,
        /// The plugins to clear; empty for all.
        pub plugins: Vec<String>,
    }

    clearing_main!(
        /// `nav2_msgs/srv/ClearCostmapExceptRegion`, main's.
        ClearCostmapExceptRegion: ClearCostmapExceptRegionRequest
    );

    /// The request of [`ClearCostmapExceptRegion`].
    #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
    pub struct ClearCostmapExceptRegionRequest {
        /// The square's side, in metres.
        pub reset_distance: f32,
        /// The plugins to clear; empty for all.
        pub plugins: Vec<String>,
    }

    clearing_main!(
        /// `nav2_msgs/srv/ClearCostmapAroundPose`, main's.
        ClearCostmapAroundPose: ClearCostmapAroundPoseRequest
    );

    /// The request of [`ClearCostmapAroundPose`].
    #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
    pub struct ClearCostmapAroundPoseRequest {
        /// The square's centre.
        pub pose: PoseStamped,
        /// The square's side, in metres.
        pub reset_distance: f64,
        /// The plugins to clear; empty for all.
        pub plugins: Vec<String>,
    }

    /// `nav2_msgs/action/ComputePathToPose`, main's goal (with `viapoints`); the result and
    /// feedback are Jazzy's.
    #[derive(Clone, Copy, Debug)]
    pub struct ComputePathToPose;

    impl crate::RosAction for ComputePathToPose {
        type Goal = ComputePathToPoseGoal;
        type Result = super::ComputePathToPoseResult;
        type Feedback = super::ComputePathToPoseFeedback;
        const TYPE: (&'static str, &'static str) = ("nav2_msgs", "ComputePathToPose");
    }

    /// The goal of [`ComputePathToPose`].
    #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
    pub struct ComputePathToPoseGoal {
        /// Where the path ends.
        pub goal: PoseStamped,
        /// Where it starts, when `use_start`.
        pub start: PoseStamped,
        /// Poses the path passes on its way, in order.
        pub viapoints: Vec<PoseStamped>,
        /// Which planner plugin; empty for the only one.
        pub planner_id: String,
        /// `false`: start at the robot's current pose.
        pub use_start: bool,
    }

    impl ros2_client::Message for ComputePathToPoseGoal {}

    /// `nav2_msgs/msg/TrackingFeedback`: how the controller tracks its path.
    #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
    pub struct TrackingFeedback {
        /// When, and the frame of `robot_pose`.
        pub header: super::super::std_msgs::Header,
        /// Metres from the path, positive when the robot is left of it.
        pub position_tracking_error: f32,
        /// Radians between the robot's heading and the path's, positive when rotated right.
        pub heading_tracking_error: f32,
        /// The index of the path pose nearest the robot.
        pub current_path_index: u32,
        /// Where the robot is.
        pub robot_pose: PoseStamped,
        /// Metres straight to the path's end.
        pub distance_to_goal: f32,
        /// Metres per second.
        pub speed: f32,
        /// Metres of path left.
        pub remaining_path_length: f32,
    }

    /// `nav2_msgs/action/FollowPath`, main's: the goal names a path handler, the feedback is
    /// a [`TrackingFeedback`]; the result is Jazzy's.
    #[derive(Clone, Copy, Debug)]
    pub struct FollowPath;

    impl crate::RosAction for FollowPath {
        type Goal = FollowPathGoal;
        type Result = super::FollowPathResult;
        type Feedback = FollowPathFeedback;
        const TYPE: (&'static str, &'static str) = ("nav2_msgs", "FollowPath");
    }

    /// The goal of [`FollowPath`].
    #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
    pub struct FollowPathGoal {
        /// The path to follow.
        pub path: super::Path,
        /// Which controller plugin; empty for the only one.
        pub controller_id: String,
        /// Which goal checker plugin; empty for the only one.
        pub goal_checker_id: String,
        /// Which progress checker plugin; empty for the only one.
        pub progress_checker_id: String,
        /// Which path handler plugin; empty for the only one.
        pub path_handler_id: String,
    }

    /// The feedback of [`FollowPath`].
    #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
    pub struct FollowPathFeedback {
        /// How the controller tracks the path.
        pub tracking_feedback: TrackingFeedback,
    }

    impl ros2_client::Message for FollowPathGoal {}
    impl ros2_client::Message for FollowPathFeedback {}
    impl ros2_client::Message for TrackingFeedback {}
}
