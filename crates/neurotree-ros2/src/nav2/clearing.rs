//! The costmap clearing services in the layout of each Nav2 release: Jazzy's and Kilted's
//! (an empty response; the whole costmap cleared) and main's (`plugins` in the request, a
//! `success` in the response), for the clearing leaves and the simulator's servers alike.

use crate::msg::geometry_msgs::PoseStamped;
use crate::msg::nav2_msgs::{self, main};
use crate::RosService;

/// A clearing service's request and response, whatever its release.
pub(crate) trait ClearLayout: RosService {
    /// The request has a square (`reset_distance`).
    const SQUARE: bool;
    /// The square is around a pose of the request rather than the robot.
    const POSE: bool;
    /// The request; the fields the layout lacks are left out.
    fn request(pose: PoseStamped, reset_distance: f64, plugins: Vec<String>) -> Self::Request;
    /// The square's side, in metres (0 without a square).
    // The servers' side: the simulated servers read requests and answer.
    #[cfg_attr(not(feature = "sim"), allow(dead_code))]
    fn reset_distance(request: &Self::Request) -> f64;
    /// The square's centre, when the request gives one.
    // The servers' side: the simulated servers read requests and answer.
    #[cfg_attr(not(feature = "sim"), allow(dead_code))]
    fn pose(request: &Self::Request) -> Option<&PoseStamped>;
    /// The answer: `cleared` where the layout can say it.
    // The servers' side: the simulated servers read requests and answer.
    #[cfg_attr(not(feature = "sim"), allow(dead_code))]
    fn response(cleared: bool) -> Self::Response;
    /// Whether the answer says the costmap was cleared (always, in the older layouts).
    fn cleared(response: &Self::Response) -> bool;
}

impl ClearLayout for nav2_msgs::ClearEntireCostmap {
    const SQUARE: bool = false;
    const POSE: bool = false;
    fn request(_: PoseStamped, _: f64, _: Vec<String>) -> Self::Request {
        Self::Request::default()
    }
    fn reset_distance(_: &Self::Request) -> f64 {
        0.0
    }
    fn pose(_: &Self::Request) -> Option<&PoseStamped> {
        None
    }
    fn response(_: bool) -> Self::Response {
        Self::Response::default()
    }
    fn cleared(_: &Self::Response) -> bool {
        true
    }
}

/// The older layouts of the two squares around the robot.
macro_rules! old_square {
    ($service:ty) => {
        impl ClearLayout for $service {
            const SQUARE: bool = true;
            const POSE: bool = false;
            fn request(_: PoseStamped, reset_distance: f64, _: Vec<String>) -> Self::Request {
                Self::Request {
                    reset_distance: reset_distance as f32,
                }
            }
            fn reset_distance(request: &Self::Request) -> f64 {
                f64::from(request.reset_distance)
            }
            fn pose(_: &Self::Request) -> Option<&PoseStamped> {
                None
            }
            fn response(_: bool) -> Self::Response {
                Self::Response::default()
            }
            fn cleared(_: &Self::Response) -> bool {
                true
            }
        }
    };
}

old_square!(nav2_msgs::ClearCostmapAroundRobot);
old_square!(nav2_msgs::ClearCostmapExceptRegion);

impl ClearLayout for nav2_msgs::ClearCostmapAroundPose {
    const SQUARE: bool = true;
    const POSE: bool = true;
    fn request(pose: PoseStamped, reset_distance: f64, _: Vec<String>) -> Self::Request {
        Self::Request {
            pose,
            reset_distance,
        }
    }
    fn reset_distance(request: &Self::Request) -> f64 {
        request.reset_distance
    }
    fn pose(request: &Self::Request) -> Option<&PoseStamped> {
        Some(&request.pose)
    }
    fn response(_: bool) -> Self::Response {
        Self::Response::default()
    }
    fn cleared(_: &Self::Response) -> bool {
        true
    }
}

impl ClearLayout for main::ClearEntireCostmap {
    const SQUARE: bool = false;
    const POSE: bool = false;
    fn request(_: PoseStamped, _: f64, plugins: Vec<String>) -> Self::Request {
        Self::Request { plugins }
    }
    fn reset_distance(_: &Self::Request) -> f64 {
        0.0
    }
    fn pose(_: &Self::Request) -> Option<&PoseStamped> {
        None
    }
    fn response(cleared: bool) -> Self::Response {
        Self::Response { success: cleared }
    }
    fn cleared(response: &Self::Response) -> bool {
        response.success
    }
}

/// Main's layouts of the two squares around the robot.
macro_rules! main_square {
    ($service:ty) => {
        impl ClearLayout for $service {
            const SQUARE: bool = true;
            const POSE: bool = false;
            fn request(_: PoseStamped, reset_distance: f64, plugins: Vec<String>) -> Self::Request {
                Self::Request {
                    reset_distance: reset_distance as f32,
                    plugins,
                }
            }
            fn reset_distance(request: &Self::Request) -> f64 {
                f64::from(request.reset_distance)
            }
            fn pose(_: &Self::Request) -> Option<&PoseStamped> {
                None
            }
            fn response(cleared: bool) -> Self::Response {
                Self::Response { success: cleared }
            }
            fn cleared(response: &Self::Response) -> bool {
                response.success
            }
        }
    };
}

main_square!(main::ClearCostmapAroundRobot);
main_square!(main::ClearCostmapExceptRegion);

impl ClearLayout for main::ClearCostmapAroundPose {
    const SQUARE: bool = true;
    const POSE: bool = true;
    fn request(pose: PoseStamped, reset_distance: f64, plugins: Vec<String>) -> Self::Request {
        Self::Request {
            pose,
            reset_distance,
            plugins,
        }
    }
    fn reset_distance(request: &Self::Request) -> f64 {
        request.reset_distance
    }
    fn pose(request: &Self::Request) -> Option<&PoseStamped> {
        Some(&request.pose)
    }
    fn response(cleared: bool) -> Self::Response {
        Self::Response { success: cleared }
    }
    fn cleared(response: &Self::Response) -> bool {
        response.success
    }
}
