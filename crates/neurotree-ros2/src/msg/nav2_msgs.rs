//! `nav2_msgs`: the actions and services of Nav2's servers that the navigator calls (Jazzy).
//!
//! Each action is a type that names it ([`RosAction`]) and three messages: `…Goal`,
//! `…Result` (with the server's error codes as constants) and `…Feedback`.

use serde::{Deserialize, Serialize};

use super::builtin_interfaces::Duration;
use super::geometry_msgs::{Point, PoseStamped};
use super::nav_msgs::Path;
use super::std_msgs::Empty;
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
