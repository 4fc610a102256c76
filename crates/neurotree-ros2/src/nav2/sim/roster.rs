//! Which servers the simulator runs for a Nav2 release: the planning servers and the
//! servers that move the robot, each in the release's action layout, and both costmaps'
//! clearing services in its service layout.

use neurotree_nav2::Nav2Release;
use neurotree_sim::nav2::Nav2Sim;
use neurotree_toolkit::Registry;

use super::clearings::{Clearings, ServeClearings};
use super::served::{Served, Serving};
use super::teleop::Teleop;
use crate::msg::nav2_msgs::{
    kilted, main, BackUp, ClearCostmapAroundPose, ClearCostmapAroundRobot,
    ClearCostmapExceptRegion, ClearEntireCostmap, ComputeAndTrackRoute, ComputePathThroughPoses,
    ComputePathToPose, ComputeRoute, DockRobot, DriveOnHeading, FollowObject, FollowPath,
    NavigateThroughPoses, SmoothPath, Spin, UndockRobot, Wait,
};
use crate::nav2::NavigatorError;
use crate::{Ros2Error, RosNode};

/// The planner, the smoother and the route server: they plan, and move nothing.
pub(super) fn planning_servers(
    ros: &RosNode,
    registry: &Registry<Nav2Sim>,
    release: Nav2Release,
) -> Result<Vec<Box<dyn Serving>>, NavigatorError> {
    let jazzy = release == Nav2Release::Jazzy;
    let through_poses = "compute_path_through_poses";
    Ok(vec![
        if release == Nav2Release::Main {
            Box::new(Served::<main::ComputePathToPose>::new(
                ros,
                "compute_path_to_pose",
                registry,
            )?)
        } else {
            Box::new(Served::<ComputePathToPose>::new(
                ros,
                "compute_path_to_pose",
                registry,
            )?)
        },
        if jazzy {
            Box::new(Served::<ComputePathThroughPoses>::new(
                ros,
                through_poses,
                registry,
            )?)
        } else {
            Box::new(Served::<kilted::ComputePathThroughPoses>::new(
                ros,
                through_poses,
                registry,
            )?)
        },
        Box::new(Served::<SmoothPath>::new(ros, "smooth_path", registry)?),
        Box::new(Served::<ComputeRoute>::new(ros, "compute_route", registry)?),
        Box::new(Served::<ComputeAndTrackRoute>::new(
            ros,
            "compute_and_track_route",
            registry,
        )?),
    ])
}

/// The controller, the behaviors, the docking server, the navigator through poses, the
/// following server and assisted teleoperation: the servers that move the robot.
pub(super) fn motion_servers(
    ros: &RosNode,
    registry: &Registry<Nav2Sim>,
    release: Nav2Release,
) -> Result<Vec<Box<dyn Serving>>, NavigatorError> {
    let jazzy = release == Nav2Release::Jazzy;
    let behaviors: [Box<dyn Serving>; 3] = if jazzy {
        [
            Box::new(Served::<Spin>::new(ros, "spin", registry)?),
            Box::new(Served::<BackUp>::new(ros, "backup", registry)?),
            Box::new(Served::<DriveOnHeading>::new(
                ros,
                "drive_on_heading",
                registry,
            )?),
        ]
    } else {
        [
            Box::new(Served::<kilted::Spin>::new(ros, "spin", registry)?),
            Box::new(Served::<kilted::BackUp>::new(ros, "backup", registry)?),
            Box::new(Served::<kilted::DriveOnHeading>::new(
                ros,
                "drive_on_heading",
                registry,
            )?),
        ]
    };
    let [spin, backup, drive_on_heading] = behaviors;
    Ok(vec![
        if release == Nav2Release::Main {
            Box::new(Served::<main::FollowPath>::new(
                ros,
                "follow_path",
                registry,
            )?)
        } else {
            Box::new(Served::<FollowPath>::new(ros, "follow_path", registry)?)
        },
        spin,
        backup,
        drive_on_heading,
        Box::new(Served::<Wait>::new(ros, "wait", registry)?),
        Box::new(Served::<DockRobot>::new(ros, "dock_robot", registry)?),
        Box::new(Served::<UndockRobot>::new(ros, "undock_robot", registry)?),
        Box::new(Served::<NavigateThroughPoses>::new(
            ros,
            "navigate_through_poses",
            registry,
        )?),
        Box::new(Served::<FollowObject>::new(ros, "follow_object", registry)?),
        Box::new(Teleop::new(ros)?),
    ])
}

/// Both costmaps' clearing services.
pub(super) fn clearing_servers(
    ros: &RosNode,
    release: Nav2Release,
) -> Result<Vec<Box<dyn ServeClearings>>, Ros2Error> {
    if release == Nav2Release::Main {
        Clearings::<
            main::ClearEntireCostmap,
            main::ClearCostmapAroundRobot,
            main::ClearCostmapExceptRegion,
            main::ClearCostmapAroundPose,
        >::both(ros)
    } else {
        Clearings::<
            ClearEntireCostmap,
            ClearCostmapAroundRobot,
            ClearCostmapExceptRegion,
            ClearCostmapAroundPose,
        >::both(ros)
    }
}
