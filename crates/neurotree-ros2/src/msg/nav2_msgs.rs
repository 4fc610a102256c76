//! `nav2_msgs`: the actions and services of Nav2's servers that the navigator calls.
//!
//! Each action is a type that names it ([`RosAction`](crate::RosAction)) and three messages: `…Goal`,
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
//!
//! The types are generated from `interfaces/nav2_msgs/` (Jazzy's layouts and the others),
//! `interfaces/nav2_msgs/kilted/` and `interfaces/nav2_msgs/main/`: see [`msg`](crate::msg).

include!(concat!(env!("OUT_DIR"), "/nav2_msgs.rs"));

/// The goals Nav2 Kilted changed, as Kilted and main have them: the behaviors' goals gained
/// `disable_collision_checks`, and ComputePathThroughPoses takes its goals as a
/// `nav_msgs/Goals`. Each action has the same ROS 2 name, result and feedback as the Jazzy
/// one of the parent module; only the goal's layout differs, so a client and a server must
/// agree on the release.
pub mod kilted {
    include!(concat!(env!("OUT_DIR"), "/nav2_msgs_kilted.rs"));
}

/// What Nav2 main changed after Kilted that this crate follows: the costmap clearing
/// services (each request names the costmap `plugins` to clear, all of them when empty, and
/// the response says whether they were cleared), ComputePathToPose's goal (with
/// `viapoints`) and FollowPath (a `path_handler_id`, a
/// [`TrackingFeedback`](main::TrackingFeedback)). Each has the same ROS 2 name as the Jazzy
/// one of the parent module.
pub mod main {
    include!(concat!(env!("OUT_DIR"), "/nav2_msgs_main.rs"));

    /// The response of main's clearing services, which all answer `bool success`.
    pub type ClearResponse = ClearEntireCostmapResponse;
}
