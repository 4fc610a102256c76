//! Nav2's battery conditions over ROS 2: IsBatteryLow and IsBatteryCharging, each
//! subscribed to `battery_topic` (`/battery_status`, `sensor_msgs/msg/BatteryState`).
//!
//! As Nav2's `is_battery_low_condition.cpp` and `is_battery_charging_condition.cpp`, each
//! keeps what the last message said and answers from it at every tick (Failure until a
//! message came):
//!
//! - **IsBatteryLow** (ports `min_battery`, `is_voltage`): Success when the message's
//!   `percentage` (with `is_voltage`, its `voltage`) was at most `min_battery`.
//! - **IsBatteryCharging**: Success when its `power_supply_status` was CHARGING.
//!
//! [`SimServers`](super::SimServers) publishes the world's battery on [`BATTERY_TOPIC`].

use neurotree_toolkit::{Category, Handle, PortSpec, Registry, RegistryError, Status};

use crate::msg::sensor_msgs::BatteryState;
use crate::nodes::subscriber::SubscriberSpec;
use crate::{RosNode, RosTopicSubNode};

/// Where Nav2's battery conditions listen unless told otherwise.
pub const BATTERY_TOPIC: &str = "/battery_status";

fn topic_port() -> PortSpec {
    PortSpec::input::<String>("battery_topic")
        .default_value(BATTERY_TOPIC)
        .describe("The battery's topic.")
}

/// Registers IsBatteryLow and IsBatteryCharging as subscribers on `ros`. Fails if one of
/// the names is taken.
pub fn register_battery_conditions<C: 'static>(
    registry: &mut Registry<C>,
    ros: &RosNode,
) -> Result<(), RegistryError> {
    let node = ros.clone();
    let mut low_ports = <BatteryLow as SubscriberSpec<C>>::ports();
    low_ports.push(topic_port());
    registry.register_stateful_as("IsBatteryLow", Category::Condition, low_ports, move || {
        RosTopicSubNode::new(node.clone(), BATTERY_TOPIC, BatteryLow::default())
            .with_name_port("battery_topic")
    })?;
    registry.describe(
        "IsBatteryLow",
        "Succeeds when the last battery message said at most `min_battery` was left.",
    );
    let node = ros.clone();
    registry.register_stateful_as(
        "IsBatteryCharging",
        Category::Condition,
        vec![topic_port()],
        move || {
            RosTopicSubNode::new(node.clone(), BATTERY_TOPIC, BatteryCharging::default())
                .with_name_port("battery_topic")
        },
    )?;
    registry.describe(
        "IsBatteryCharging",
        "Succeeds when the last battery message said the battery was charging.",
    );
    Ok(())
}

/// IsBatteryLow: see the [module documentation](self).
#[derive(Default)]
struct BatteryLow {
    low: bool,
}

impl<C> SubscriberSpec<C> for BatteryLow {
    type Message = BatteryState;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<f64>("min_battery")
                .describe("The fraction (or voltage) at or under which the battery is low."),
            PortSpec::input::<bool>("is_voltage")
                .default_value("false")
                .describe("Compare the voltage rather than the percentage."),
        ]
    }

    fn on_tick(&mut self, h: &mut Handle<'_, C>, latest: Option<&BatteryState>) -> Status {
        if let Some(message) = latest {
            // Nav2's members start at 0 and false when the ports are not given.
            let min = h.input::<f64>("min_battery").unwrap_or(0.0);
            let is_voltage = h.input::<bool>("is_voltage").unwrap_or(false);
            let reading = if is_voltage {
                message.voltage
            } else {
                message.percentage
            };
            self.low = f64::from(reading) <= min;
        }
        if self.low {
            Status::Success
        } else {
            Status::Failure
        }
    }
}

/// IsBatteryCharging: see the [module documentation](self).
#[derive(Default)]
struct BatteryCharging {
    charging: bool,
}

impl<C> SubscriberSpec<C> for BatteryCharging {
    type Message = BatteryState;

    fn on_tick(&mut self, _h: &mut Handle<'_, C>, latest: Option<&BatteryState>) -> Status {
        if let Some(message) = latest {
            self.charging =
                message.power_supply_status == BatteryState::POWER_SUPPLY_STATUS_CHARGING;
        }
        if self.charging {
            Status::Success
        } else {
            Status::Failure
        }
    }
}
