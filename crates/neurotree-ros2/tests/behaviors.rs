//! Nav2's behaviors over ROS 2: the navigator's DriveOnHeading leaf, a client of the
//! `drive_on_heading` action, against [`SimServers`] serving the grid world.

use crate::common;

use std::sync::Arc;
use std::time::Duration;

use common::{free_domain, node, tick_until_done, Served};
use neurotree_nav2::robotics::Pose2D;
use neurotree_ros2::msg::nav2_msgs::DriveOnHeadingResult;
use neurotree_ros2::nav2::register_nav2_ros_leaves;
use neurotree_sim::nav2::Nav2Sim;
use neurotree_sim::GridWorld;
use neurotree_toolkit::{Registry, Status, Tree, XmlLoader};

/// A corridor; the robot at its west end, (1.5, 1.5), facing east.
const CORRIDOR: &str = "
    #######
    #R....#
    #######";

/// The simulator serving `world` in `domain`, [`common::TIME_SCALE`] times as fast as real
/// time, until dropped.
fn serve(domain: u16, world: GridWorld) -> Served {
    Served::start(domain, Nav2Sim::new(world), common::TIME_SCALE)
}

/// Runs `xml` (a tree body) with the ROS 2 leaves in `domain` until it ends; its status and
/// the `code` entry.
fn run(domain: u16, xml: &str) -> (Status, u16) {
    let ros = node("bt_navigator", domain);
    let mut registry = Registry::<()>::new();
    register_nav2_ros_leaves(&mut registry, &ros).unwrap();
    let mut loader = XmlLoader::new(&registry);
    let file =
        format!(r#"<root BTCPP_format="4"><BehaviorTree ID="T">{xml}</BehaviorTree></root>"#);
    loader.load_str(&file, "drive.xml").unwrap();
    let mut tree = Tree::new(Arc::new(loader.build_main().unwrap()));
    let status = tick_until_done(&mut tree, &mut (), common::HANG);
    let code = tree.blackboard().get::<u16>("code").unwrap_or(u16::MAX);
    (status, code)
}

pub(crate) fn drive_on_heading_drives_the_served_robot_straight_on() {
    let domain = free_domain();
    let served = serve(domain.id, GridWorld::parse(CORRIDOR, 1.0).unwrap());
    let (status, code) = run(
        domain.id,
        r#"<DriveOnHeading dist_to_travel="2.0" speed="1.0" error_code_id="{code}"/>"#,
    );
    assert_eq!((status, code), (Status::Success, 0));
    let seen = served.stats.get();
    assert_eq!(seen.drive_on_heading.goals, 1, "{seen:?}");
    assert_eq!(seen.drive_on_heading.succeeded, 1, "{seen:?}");
    assert!(
        seen.robot.distance(&Pose2D::new(3.5, 1.5, 0.0)) < 1e-6,
        "{seen:?}"
    );
}

pub(crate) fn drive_on_heading_into_the_wall_fails_with_the_servers_collision_code() {
    let domain = free_domain();
    let served = serve(domain.id, GridWorld::parse(CORRIDOR, 1.0).unwrap());
    let (status, code) = run(
        domain.id,
        r#"<DriveOnHeading dist_to_travel="9.0" speed="2.0" error_code_id="{code}"/>"#,
    );
    assert_eq!(
        (status, code),
        (Status::Failure, DriveOnHeadingResult::COLLISION_AHEAD)
    );
    let seen = served.stats.get();
    assert_eq!(seen.drive_on_heading.aborted, 1, "{seen:?}");
    // Stopped before the wall at x = 6.
    assert!(seen.robot.x < 6.0 && seen.robot.x > 5.0, "{seen:?}");
}

pub(crate) fn a_spin_cancelled_by_someone_else_succeeds_as_nav2s_does() {
    let domain = free_domain();
    let served = serve(domain.id, GridWorld::parse(CORRIDOR, 1.0).unwrap());
    let ros = node("bt_navigator", domain.id);
    let mut registry = Registry::<()>::new();
    register_nav2_ros_leaves(&mut registry, &ros).unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            r#"<root BTCPP_format="4"><BehaviorTree ID="T">
                 <Spin spin_dist="6.0" time_allowance="60" error_code_id="{code}"/>
               </BehaviorTree></root>"#,
            "spin.xml",
        )
        .unwrap();
    let mut tree = Tree::new(Arc::new(loader.build_main().unwrap()));
    let other = node("other_client", domain.id);
    let canceller = other
        .action_client::<neurotree_ros2::msg::nav2_msgs::Spin>("spin")
        .unwrap();
    let until = std::time::Instant::now() + common::HANG;
    let mut cancelled = false;
    let status = loop {
        let status = tree.tick_once(&mut ()).unwrap();
        if status != Status::Running || std::time::Instant::now() > until {
            break status;
        }
        let seen = served.stats.get();
        if !cancelled && seen.spin.goals == 1 && seen.robot.theta > 0.2 {
            canceller.cancel_all_goals().unwrap();
            cancelled = true;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    assert_eq!(status, Status::Success);
    assert_eq!(tree.blackboard().get::<u16>("code").unwrap(), 0);
    let seen = served.stats.get();
    assert_eq!((seen.spin.cancels, seen.spin.succeeded), (1, 0), "{seen:?}");
    assert!(seen.robot.theta < 6.0, "{seen:?}");
}

pub(crate) fn cancel_spin_asks_the_server_to_cancel_and_the_spin_succeeds() {
    let domain = free_domain();
    let served = serve(domain.id, GridWorld::parse(CORRIDOR, 1.0).unwrap());
    // The spin runs (a minute of simulated time, seconds of the test's); a second in,
    // CancelSpin asks the server to cancel every spin goal.
    let (status, code) = run(
        domain.id,
        r#"<Parallel success_count="2" failure_count="1">
             <Spin spin_dist="60.0" time_allowance="120" error_code_id="{code}"/>
             <Delay delay_msec="1000"><CancelSpin/></Delay>
           </Parallel>"#,
    );
    assert_eq!((status, code), (Status::Success, 0));
    let seen = served.stats.get();
    assert_eq!((seen.spin.cancels, seen.spin.succeeded), (1, 0), "{seen:?}");
    // With nothing to cancel, the server still answers.
    let (status, _) = run(
        domain.id,
        r#"<Sequence><CancelBackUp/><CancelWait/><SetBlackboard output_key="code" value="7"/></Sequence>"#,
    );
    assert_eq!(status, Status::Success);
    // No server of that name: Failure once `wait_for_server_timeout` is over.
    let (status, _) = run(
        domain.id,
        r#"<CancelSpin action_name="nobody_spins" wait_for_server_timeout="300"/>"#,
    );
    assert_eq!(status, Status::Failure);
}
