//! What the world publishes each step besides the robot's pose: odometry and the battery.

use neurotree_sim::nav2::Nav2Sim;

use crate::msg::geometry_msgs::{Twist, Vector3};
use crate::msg::nav_msgs::Odometry;
use crate::msg::sensor_msgs::BatteryState;
use crate::msg::std_msgs::Header;
use crate::nav2::convert::pose_stamped;

/// The robot's odometry: its pose (in `odom`, which is the map here) and its speed and
/// turn rate over the last step (in `base_link`: straight ahead and about z), stamped
/// with the simulated time.
pub(super) fn odometry(sim: &Nav2Sim) -> Odometry {
    let now = sim.world.now();
    let mut odometry = Odometry {
        header: Header {
            stamp: crate::msg::builtin_interfaces::Time {
                sec: i32::try_from(now.as_secs()).unwrap_or(i32::MAX),
                nanosec: now.subsec_nanos(),
            },
            frame_id: "odom".to_owned(),
        },
        child_frame_id: "base_link".to_owned(),
        ..Odometry::default()
    };
    odometry.pose.pose = pose_stamped(sim.world.robot()).pose;
    odometry.twist.twist = Twist {
        linear: Vector3 {
            x: sim.robot_speed(),
            ..Vector3::default()
        },
        angular: Vector3 {
            z: sim.turn_rate(),
            ..Vector3::default()
        },
    };
    odometry
}

/// The world's battery as a `BatteryState`: its charge as a fraction, charging while the
/// robot stands on the charger with the battery not full (full there: FULL; elsewhere:
/// DISCHARGING); nothing else is measured (NaN).
pub(super) fn battery_state(sim: &Nav2Sim) -> BatteryState {
    let level = sim.world.battery().level();
    let status = match (sim.world.is_on_charger(), level < 100.0) {
        (true, true) => BatteryState::POWER_SUPPLY_STATUS_CHARGING,
        (true, false) => BatteryState::POWER_SUPPLY_STATUS_FULL,
        (false, _) => BatteryState::POWER_SUPPLY_STATUS_DISCHARGING,
    };
    BatteryState {
        voltage: f32::NAN,
        temperature: f32::NAN,
        current: f32::NAN,
        charge: f32::NAN,
        capacity: f32::NAN,
        design_capacity: f32::NAN,
        percentage: (level / 100.0) as f32,
        power_supply_status: status,
        present: true,
        ..BatteryState::default()
    }
}
