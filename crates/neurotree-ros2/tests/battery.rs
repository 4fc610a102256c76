//! Nav2's battery conditions over ROS 2: IsBatteryLow and IsBatteryCharging subscribed to
//! `/battery_status`, where [`SimServers`] publishes the world's battery.

use crate::common;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

use common::{free_domain, node};
use neurotree_nav2::robotics::Pose2D;
use neurotree_ros2::nav2::{register_nav2_ros_leaves, SimOptions, SimServers};
use neurotree_sim::nav2::Nav2Sim;
use neurotree_sim::{Battery, GridWorld};
use neurotree_toolkit::{Registry, Status, Tree, XmlLoader};

/// Ticks the tree body `xml` every 20 ms against the simulator serving `world`, until it
/// succeeds or 5 s have passed; the statuses seen, each once, in order.
fn statuses(world: GridWorld, xml: &str) -> Vec<Status> {
    let domain = free_domain();
    let stop = Arc::new(AtomicBool::new(false));
    let stopped = Arc::clone(&stop);
    let (tx, rx) = mpsc::channel();
    let id = domain.id;
    let thread = std::thread::spawn(move || {
        let ros = node("nav2_sim", id);
        let mut servers =
            SimServers::new(&ros, Nav2Sim::new(world), SimOptions::default()).unwrap();
        tx.send(()).unwrap();
        servers.run(&stopped).unwrap();
    });
    rx.recv_timeout(common::HANG).unwrap();
    let ros = node("bt_navigator", domain.id);
    let mut registry = Registry::<()>::new();
    register_nav2_ros_leaves(&mut registry, &ros).unwrap();
    let mut loader = XmlLoader::new(&registry);
    let file =
        format!(r#"<root BTCPP_format="4"><BehaviorTree ID="T">{xml}</BehaviorTree></root>"#);
    loader.load_str(&file, "battery.xml").unwrap();
    let mut tree = Tree::new(Arc::new(loader.build_main().unwrap()));
    let mut seen: Vec<Status> = Vec::new();
    let until = Instant::now() + Duration::from_secs(5);
    while Instant::now() < until {
        let status = tree.tick_once(&mut ()).unwrap();
        if seen.last() != Some(&status) {
            seen.push(status);
        }
        if status == Status::Success {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    stop.store(true, Ordering::SeqCst);
    let _ = thread.join();
    seen
}

pub(crate) fn on_the_charger_with_a_quarter_left_the_battery_is_charging_and_low() {
    let mut world = GridWorld::parse("#CR#", 1.0)
        .unwrap()
        .with_battery(Battery::at(25.0));
    world.set_robot(Pose2D::new(1.5, 0.5, 0.0)).unwrap();
    // Failure until the first message comes, then Success.
    let seen = statuses(
        world,
        r#"<Sequence><IsBatteryCharging/><IsBatteryLow min_battery="0.3"/></Sequence>"#,
    );
    assert_eq!(seen, [Status::Failure, Status::Success]);
}

pub(crate) fn off_the_charger_the_battery_is_not_charging_nor_low_above_the_minimum() {
    let world = GridWorld::parse("#CR#", 1.0)
        .unwrap()
        .with_battery(Battery::at(25.0));
    // Succeeds once both answer as expected: not charging, not at or under 20 %.
    let seen = statuses(
        world,
        r#"<Sequence>
             <Inverter><IsBatteryCharging/></Inverter>
             <Inverter><IsBatteryLow min_battery="0.2"/></Inverter>
             <IsBatteryLow min_battery="0.3" battery_topic="/battery_status"/>
           </Sequence>"#,
    );
    assert_eq!(seen, [Status::Failure, Status::Success]);
}
