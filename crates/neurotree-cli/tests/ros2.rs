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
    let output = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(["ros2", "demo", "--domain", &domain.to_string()])
        .args(["--timeout", "45"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);

    assert!(output.status.success(), "{stdout}");
    assert!(stdout.contains("  outcome     SUCCESS"), "{stdout}");
    let recoveries: u32 = stdout
        .lines()
        .find_map(|l| l.strip_prefix("  recoveries  "))
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("no recoveries line: {stdout}"));
    assert!(recoveries >= 1, "{stdout}");
    assert!(
        stdout.contains("FollowPath failed: blocked (error 106)"),
        "the simulator reported the obstacle: {stdout}"
    );
}
