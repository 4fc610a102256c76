//! `sensor_msgs`: the battery's state, as Nav2's battery conditions read it.

use serde::{Deserialize, Serialize};

use super::std_msgs::Header;
use crate::interface::messages;

/// `sensor_msgs/msg/BatteryState`: a battery's charge and whether it is charging.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BatteryState {
    /// Frame and time of the reading.
    pub header: Header,
    /// Volts; NaN when not measured.
    pub voltage: f32,
    /// Degrees Celsius; NaN when not measured.
    pub temperature: f32,
    /// Amperes, negative when discharging; NaN when not measured.
    pub current: f32,
    /// Ampere-hours; NaN when not measured.
    pub charge: f32,
    /// Ampere-hours; NaN when not measured.
    pub capacity: f32,
    /// Ampere-hours; NaN when not measured.
    pub design_capacity: f32,
    /// The charge left, from 0 to 1; NaN when not measured.
    pub percentage: f32,
    /// One of the `POWER_SUPPLY_STATUS_*` constants.
    pub power_supply_status: u8,
    /// One of ROS's `POWER_SUPPLY_HEALTH_*` constants (0: unknown).
    pub power_supply_health: u8,
    /// One of ROS's `POWER_SUPPLY_TECHNOLOGY_*` constants (0: unknown).
    pub power_supply_technology: u8,
    /// Whether a battery is there.
    pub present: bool,
    /// Volts of each cell.
    pub cell_voltage: Vec<f32>,
    /// Degrees Celsius of each cell.
    pub cell_temperature: Vec<f32>,
    /// Where the battery is.
    pub location: String,
    /// Its serial number.
    pub serial_number: String,
}

impl BatteryState {
    /// Unknown.
    pub const POWER_SUPPLY_STATUS_UNKNOWN: u8 = 0;
    /// Charging.
    pub const POWER_SUPPLY_STATUS_CHARGING: u8 = 1;
    /// Discharging.
    pub const POWER_SUPPLY_STATUS_DISCHARGING: u8 = 2;
    /// Connected, not charging.
    pub const POWER_SUPPLY_STATUS_NOT_CHARGING: u8 = 3;
    /// Full.
    pub const POWER_SUPPLY_STATUS_FULL: u8 = 4;
}

messages!("sensor_msgs": BatteryState);
