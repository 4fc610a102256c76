//! Nav2's service nodes over ROS 2 against [`SimServers`](neurotree_ros2::nav2::SimServers):
//! CheckPoseOccupancy and RemoveInCollisionGoals asking the global costmap's
//! `get_cost_global_costmap` (`nav2_msgs/srv/GetCosts`), ToggleCollisionMonitor
//! (`nav2_msgs/srv/Toggle`) and ReinitializeGlobalLocalization (`std_srvs/srv/Empty`).

use crate::common;

use std::time::Duration;

use common::{free_domain, nav2_tree, tick_until_done, Served};
use neurotree_nav2::robotics::Pose2D;
use neurotree_sim::nav2::Nav2Sim;
use neurotree_sim::GridWorld;
use neurotree_toolkit::Status;

/// A row with a wall at x = 2.5; the robot at (0.5, 0.5).
const ROW: &str = "R.#..";

fn at(x: f64) -> Pose2D {
    Pose2D::new(x, 0.5, 0.0)
}

fn serve(domain: u16) -> Served {
    Served::start(
        domain,
        Nav2Sim::new(GridWorld::parse(ROW, 1.0).unwrap()),
        common::TIME_SCALE,
    )
}

const LIMIT: Duration = common::HANG;

pub(crate) fn check_pose_occupancy_succeeds_on_a_wall_and_fails_on_the_floor_and_off_the_map() {
    let domain = free_domain();
    let served = serve(domain.id);
    let mut tree = nav2_tree(
        domain.id,
        r#"<CheckPoseOccupancy pose="{p}" error_msg="{why}"/>"#,
    );
    for (x, expected) in [(2.5, Status::Success), (1.5, Status::Failure)] {
        tree.blackboard_mut().set("p", at(x)).unwrap();
        assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), expected, "{x}");
    }
    tree.blackboard_mut().set("p", at(9.5)).unwrap();
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Failure);
    let why: String = tree.blackboard().get("why").unwrap();
    assert!(why.contains("could not give the cost"), "{why}");
    assert_eq!(served.stats.get().cost_requests, 3);
    // A threshold of 0 counts a free cell as occupied.
    let mut tree = nav2_tree(
        domain.id,
        r#"<CheckPoseOccupancy pose="{p}" cost_threshold="0"/>"#,
    );
    tree.blackboard_mut().set("p", at(1.5)).unwrap();
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Success);
}

pub(crate) fn remove_in_collision_goals_keeps_the_free_goals_and_fails_without_goals_or_an_answer()
{
    let domain = free_domain();
    let served = serve(domain.id);
    let mut tree = nav2_tree(
        domain.id,
        r#"<RemoveInCollisionGoals input_goals="{in}" output_goals="{out}"/>"#,
    );
    let bb = |t: &mut neurotree_toolkit::Tree<()>, goals: Vec<Pose2D>| {
        t.blackboard_mut().set("in", goals).unwrap();
    };
    bb(&mut tree, vec![at(1.5), at(2.5), at(3.5)]);
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Success);
    let out: Vec<Pose2D> = tree.blackboard().get("out").unwrap();
    assert_eq!(out.len(), 2);
    assert!(out[0].distance(&at(1.5)) < 1e-9 && out[1].distance(&at(3.5)) < 1e-9);
    // All in collision: an empty list, and Success.
    bb(&mut tree, vec![at(2.5)]);
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Success);
    assert!(tree
        .blackboard()
        .get::<Vec<Pose2D>>("out")
        .unwrap()
        .is_empty());
    // One goal off the map: the costmap's answer is unsuccessful; the goals stay.
    bb(&mut tree, vec![at(1.5), at(-3.0)]);
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Failure);
    assert_eq!(
        tree.blackboard().get::<Vec<Pose2D>>("out").unwrap().len(),
        2
    );
    assert_eq!(served.stats.get().cost_requests, 3);
    // No goals: no request, Failure, as Nav2's node (`should_send_request_` false).
    bb(&mut tree, vec![]);
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Failure);
    assert!(tree
        .blackboard()
        .get::<Vec<Pose2D>>("out")
        .unwrap()
        .is_empty());
    assert_eq!(served.stats.get().cost_requests, 3);
}

pub(crate) fn toggle_collision_monitor_switches_the_served_monitor_and_relocalization_is_counted() {
    let domain = free_domain();
    let served = serve(domain.id);
    assert!(served.stats.get().collision_monitor);
    let mut tree = nav2_tree(
        domain.id,
        r#"<Sequence>
             <ToggleCollisionMonitor enable="false"/>
             <ReinitializeGlobalLocalization/>
             <ReinitializeGlobalLocalization/>
           </Sequence>"#,
    );
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Success);
    let seen = served.stats.get();
    assert!(!seen.collision_monitor, "{seen:?}");
    assert_eq!(seen.relocalizations, 2, "{seen:?}");
    let mut tree = nav2_tree(domain.id, r#"<ToggleCollisionMonitor/>"#);
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Success);
    assert!(served.stats.get().collision_monitor);
    // A service no one serves: Failure once `wait_for_server_timeout` is over.
    let mut tree = nav2_tree(
        domain.id,
        r#"<ReinitializeGlobalLocalization service_name="amcl_elsewhere" wait_for_server_timeout="300"/>"#,
    );
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Failure);
}
