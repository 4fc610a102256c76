//! The battery: IsBatteryLow and IsBatteryCharging.
//!
//! Nav2 reads a `sensor_msgs/BatteryState` topic (`battery_topic`); here the world's
//! [`Battery`](crate::Battery) and charger answer, at every tick, as a battery message
//! would on each loop of the navigator.
//!
//! - **IsBatteryLow**: a condition. Ports `min_battery`, `battery_topic` (default
//!   `/battery_status`, unused), `is_voltage` (default false). Success when the battery's
//!   percentage, as a fraction (`BatteryState.percentage`: 0.2 is 20 %), is at most
//!   `min_battery` (0 when absent, as Nav2's member starts); else Failure. The simulated
//!   battery reports no voltage (NaN, as `BatteryState` says for an unmeasured one), so with
//!   `is_voltage` true it is never low.
//! - **IsBatteryCharging**: a condition. Port `battery_topic` (unused). Success when the
//!   robot stands on the charger with the battery not full (`POWER_SUPPLY_STATUS_CHARGING`);
//!   off the charger, moving, or full: Failure.

use neurotree_core::Handle;

use super::{ports, Nav2Context};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

fn topic() -> PortSpec {
    PortSpec::input::<String>("battery_topic")
        .default_value("/battery_status")
        .describe("Battery topic (unused: the world's battery answers).")
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_condition(
        "IsBatteryLow",
        vec![
            PortSpec::input::<f64>("min_battery")
                .describe("The fraction (or voltage) at or under which the battery is low."),
            topic(),
            PortSpec::input::<bool>("is_voltage")
                .default_value("false")
                .describe("Compare the voltage rather than the percentage."),
        ],
        is_battery_low::<C>,
    )?;
    r.describe(
        "IsBatteryLow",
        "Succeeds when the battery's charge is at most `min_battery`.",
    );
    r.register_condition("IsBatteryCharging", vec![topic()], |h: &Handle<'_, C>| {
        is_charging(h.ctx().nav2())
    })?;
    r.describe(
        "IsBatteryCharging",
        "Succeeds while the robot charges on the charger.",
    );
    Ok(())
}

/// `true` while the robot stands on the charger with the battery not full.
pub(super) fn is_charging(sim: &super::Nav2Sim) -> bool {
    sim.world.is_on_charger() && sim.world.battery().level() < 100.0
}

/// IsBatteryLow: see the [module documentation](self).
fn is_battery_low<C: Nav2Context>(h: &Handle<'_, C>) -> bool {
    let read = ports::or(h, "min_battery", 0.0_f64)
        .and_then(|min| Ok((min, ports::or(h, "is_voltage", false)?)));
    let Ok((min, is_voltage)) = read else {
        return false;
    };
    let reading = if is_voltage {
        f64::NAN
    } else {
        h.ctx().nav2().world.battery().level() / 100.0
    };
    reading <= min
}

#[cfg(test)]
mod tests {
    use crate::nav2::testing::Bench;
    use crate::{Battery, GridWorld};
    use neurotree_core::Status::{Failure as F, Success as S};
    use neurotree_nav2::robotics::Pose2D;

    #[test]
    fn the_battery_is_low_at_or_under_the_fraction() {
        for (level, expected) in [(19.0, S), (20.0, S), (21.0, F)] {
            let world = GridWorld::parse("R", 1.0)
                .unwrap()
                .with_battery(Battery::at(level));
            let mut b = Bench::with_world(world, r#"<IsBatteryLow min_battery="0.2"/>"#);
            assert_eq!(b.tick(), expected, "{level}");
        }
        let world = GridWorld::parse("R", 1.0)
            .unwrap()
            .with_battery(Battery::at(0.0));
        let mut b = Bench::with_world(
            world,
            r#"<IsBatteryLow min_battery="0.2" is_voltage="true"/>"#,
        );
        assert_eq!(b.tick(), F, "no voltage");
    }

    #[test]
    fn the_battery_charges_on_the_charger_standing_still_until_full() {
        let world = GridWorld::parse("R.C", 1.0)
            .unwrap()
            .with_battery(Battery::at(90.0));
        let mut b = Bench::with_world(world, r#"<IsBatteryCharging/>"#);
        assert_eq!(b.tick(), F, "off the charger");
        b.sim.world.set_robot(Pose2D::new(2.5, 0.5, 0.0)).unwrap();
        assert_eq!(b.tick(), S);
        // 5 % a second: full after two seconds.
        for _ in 0..20 {
            b.sim.step();
        }
        assert_eq!(b.sim.world.battery().level(), 100.0);
        assert_eq!(b.tick(), F, "full");
    }
}
