//! Nav2's region-clearing services over ROS 2: ClearCostmapAroundRobot,
//! ClearCostmapExceptRegion and ClearCostmapAroundPose as clients of the costmaps'
//! `clear_around_`, `clear_except_` and `clear_around_pose_` services, served by
//! [`SimServers`].

use crate::common;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

use common::{free_domain, node, tick_until_done};
use neurotree_ros2::nav2::{register_nav2_ros_leaves, SimOptions, SimServers, SimStats};
use neurotree_sim::nav2::Nav2Sim;
use neurotree_sim::{Cell, GridWorld, TimedObstacle};
use neurotree_toolkit::{Registry, Status, Tree, XmlLoader};

/// A room; the robot at (1.5, 2.5), an obstacle next to it and one at the far end, both
/// sensed at the start and remembered (no goal starts the world's clock).
fn room() -> GridWorld {
    GridWorld::parse(
        "
        #########
        #.......#
        #R......#
        #.......#
        #########",
        1.0,
    )
    .unwrap()
    .with_sensing_radius(10.0)
    .with_timed_obstacle(TimedObstacle::new(Cell::new(2, 2), Duration::ZERO))
    .with_timed_obstacle(TimedObstacle::new(Cell::new(6, 2), Duration::ZERO))
}

/// Runs the tree body `xml` against the simulator; the tree's status and what the servers
/// counted once they served it.
fn run(xml: &str, served: u32) -> (Status, SimStats) {
    let domain = free_domain();
    let stop = Arc::new(AtomicBool::new(false));
    let stopped = Arc::clone(&stop);
    let (tx, rx) = mpsc::channel();
    let id = domain.id;
    let thread = std::thread::spawn(move || {
        let ros = node("nav2_sim", id);
        let mut servers =
            SimServers::new(&ros, Nav2Sim::new(room()), SimOptions::default()).unwrap();
        tx.send(servers.stats()).unwrap();
        servers.run(&stopped).unwrap();
    });
    let stats = rx.recv_timeout(common::HANG).unwrap();
    let ros = node("bt_navigator", domain.id);
    let mut registry = Registry::<()>::new();
    register_nav2_ros_leaves(&mut registry, &ros).unwrap();
    let mut loader = XmlLoader::new(&registry);
    let file =
        format!(r#"<root BTCPP_format="4"><BehaviorTree ID="T">{xml}</BehaviorTree></root>"#);
    loader.load_str(&file, "clear.xml").unwrap();
    let mut tree = Tree::new(Arc::new(loader.build_main().unwrap()));
    let status = tick_until_done(&mut tree, &mut (), common::HANG);
    // The servers record after each step: wait for the step that served the last request.
    let until = Instant::now() + common::HANG;
    while stats.get().clears < served && Instant::now() < until {
        std::thread::sleep(Duration::from_millis(20));
    }
    let seen = common::after_steps(&stats, 3);
    stop.store(true, Ordering::SeqCst);
    let _ = thread.join();
    (status, seen)
}

pub(crate) fn each_region_clearing_forgets_nav2s_square_of_the_costmap_it_names() {
    let (status, seen) = run(
        r#"<Sequence>
             <ClearCostmapAroundRobot service_name="local_costmap/clear_around_local_costmap" reset_distance="3.0"/>
             <ClearCostmapExceptRegion service_name="global_costmap/clear_except_global_costmap" reset_distance="3.0"/>
           </Sequence>"#,
        2,
    );
    assert_eq!(status, Status::Success);
    assert_eq!(seen.clears, 2, "{seen:?}");
    // Around the robot, in the local costmap: the near obstacle; away from it, in the
    // global one: the far obstacle.
    assert_eq!(
        (seen.global_obstacles, seen.local_obstacles),
        (1, 1),
        "{seen:?}"
    );
    let (status, seen) = run(
        r#"<ClearCostmapAroundPose service_name="global_costmap/clear_around_pose_global_costmap" pose="6.5;2.5" reset_distance="3.0"/>"#,
        1,
    );
    assert_eq!(status, Status::Success);
    assert_eq!(
        (seen.global_obstacles, seen.local_obstacles),
        (1, 2),
        "{seen:?}"
    );
}

pub(crate) fn a_service_no_costmap_serves_fails_the_node() {
    let (status, seen) = run(
        r#"<ClearCostmapAroundRobot service_name="elsewhere/clear_around" wait_for_server_timeout="300"/>"#,
        0,
    );
    assert_eq!(status, Status::Failure);
    assert_eq!(
        (seen.clears, seen.global_obstacles, seen.local_obstacles),
        (0, 2, 2)
    );
}
