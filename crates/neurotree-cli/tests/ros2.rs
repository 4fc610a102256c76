//! `neurotree ros2 demo`: the simulator and the navigator as processes on 127.0.0.1, a goal
//! across the warehouse, an obstacle that forces a recovery, the robot arriving.

#![cfg(feature = "ros2")]

use std::net::UdpSocket;
use std::process::Command;

/// A DDS domain no other test process uses, held while the socket lives: the UDP port of
/// the domain's participant 0 (7410 + 250 × domain), as in neurotree-ros2's tests.
fn free_domain() -> (u16, UdpSocket) {
    let start = (std::process::id() * 7) % 132;
    for i in 0..132 {
        let id = 100 + ((start + i) % 132) as u16;
        if let Ok(claim) = UdpSocket::bind(("0.0.0.0", 7410 + 250 * id)) {
            return (id, claim);
        }
    }
    panic!("no free DDS domain between 100 and 231");
}

#[test]
fn the_ros2_demo_reaches_the_goal_after_a_recovery() {
    let (domain, _claim) = free_domain();
    // The navigator replans while the robot drives. On a loaded machine a new path around
    // the obstacle (the costmaps learn it when the robot bumps into it) can reach FollowPath
    // before the controller's "blocked" abort does, or the robot, timed against a slower
    // simulator, passes before the obstacle stands: it then arrives with no recovery, as
    // Nav2 would. So a run without a recovery is tried again, up to three times; every run
    // must arrive, and one with a recovery must have met the obstacle.
    let mut last = String::new();
    for _ in 0..3 {
        let output = Command::new(env!("CARGO_BIN_EXE_neurotree"))
            .args(["ros2", "demo", "--domain", &domain.to_string()])
            .args(["--timeout", "45"])
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
        assert!(output.status.success(), "{stdout}");
        assert!(stdout.contains("  outcome     SUCCESS"), "{stdout}");
        let recoveries: u32 = stdout
            .lines()
            .find_map(|l| l.strip_prefix("  recoveries  "))
            .and_then(|n| n.trim().parse().ok())
            .unwrap_or_else(|| panic!("no recoveries line: {stdout}"));
        if recoveries >= 1 {
            assert!(
                stdout.contains("FollowPath failed: blocked (error 106)"),
                "the simulator reported the obstacle: {stdout}"
            );
            return;
        }
        last = stdout;
    }
    panic!("three runs arrived without a recovery; the last:\n{last}");
}

/// A child process killed when the value is dropped, however the test ends.
struct Killed(std::process::Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn ros2_sim_serves_the_demos_dock_and_jazzys_goals_with_nav2_jazzy() {
    use neurotree::nav2::Nav2Release;
    use neurotree::{Registry, Status, Tree, XmlLoader};
    use neurotree_ros2::{RosNode, RosOptions};
    use std::sync::Arc;
    use std::time::{Duration, Instant};

    let (domain, _claim) = free_domain();
    let _sim = Killed(
        Command::new(env!("CARGO_BIN_EXE_neurotree"))
            .args(["ros2", "sim", "--domain", &domain.to_string()])
            .args(["--time-scale", "4", "--duration", "60", "--nav2=jazzy"])
            .stdout(std::process::Stdio::null())
            .spawn()
            .unwrap(),
    );
    let ros = RosNode::new("client", &RosOptions::loopback(domain)).unwrap();
    let mut registry = Registry::<()>::new();
    neurotree_ros2::nav2::register_nav2_ros_leaves_for(&mut registry, &ros, Nav2Release::Jazzy)
        .unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            r#"<root BTCPP_format="4"><BehaviorTree ID="T"><Sequence>
                 <Spin spin_dist="0.5" wait_for_server_timeout="10000" error_code_id="{code}"/>
                 <DockRobot dock_id="warehouse_dock" success="{ok}" error_code_id="{code}"/>
               </Sequence></BehaviorTree></root>"#,
            "dock.xml",
        )
        .unwrap();
    let mut tree = Tree::new(Arc::new(loader.build_main().unwrap()));
    let until = Instant::now() + Duration::from_secs(45);
    let status = loop {
        let status = tree.tick_once(&mut ()).unwrap();
        if status != Status::Running || Instant::now() > until {
            break status;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let code = tree.blackboard().get::<u16>("code");
    assert_eq!(status, Status::Success, "{code:?}");
    assert!(tree.blackboard().get::<bool>("ok").unwrap());
}
