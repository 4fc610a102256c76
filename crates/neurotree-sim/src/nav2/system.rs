//! Switches of the navigation system: ToggleCollisionMonitor and
//! ReinitializeGlobalLocalization.
//!
//! - **ToggleCollisionMonitor**: a sync action. Port `enable` (default true), `service_name`,
//!   `server_timeout`. Turns the collision monitor on or off
//!   ([`Nav2Sim::collision_monitor`](super::Nav2Sim::collision_monitor)): Success. The
//!   world never lets the robot into an occupied cell whichever it is, so the switch is
//!   recorded for whoever runs the world and changes no motion.
//! - **ReinitializeGlobalLocalization**: a sync action. Ports `service_name`,
//!   `server_timeout`. Nav2 asks AMCL to spread its particles over the map; the simulated
//!   robot knows its pose exactly, so the call is counted
//!   ([`Nav2Sim::relocalizations`](super::Nav2Sim::relocalizations)) and succeeds.

use neurotree_core::{Handle, Status};

use super::{ports, Nav2Context};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

fn service_ports() -> [PortSpec; 2] {
    [
        PortSpec::input::<String>("service_name").describe("Service name (unused)."),
        PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
    ]
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    let mut toggle = vec![PortSpec::input::<bool>("enable")
        .default_value("true")
        .describe("Turn the collision monitor on (true) or off.")];
    toggle.extend(service_ports());
    r.register_action(
        "ToggleCollisionMonitor",
        toggle,
        toggle_collision_monitor::<C>,
    )?;
    r.describe(
        "ToggleCollisionMonitor",
        "Turns the collision monitor on or off.",
    );
    r.register_action(
        "ReinitializeGlobalLocalization",
        service_ports().to_vec(),
        |h: &mut Handle<'_, C>| {
            h.ctx_mut().nav2_mut().count_relocalization();
            Status::Success
        },
    )?;
    r.describe(
        "ReinitializeGlobalLocalization",
        "Asks the localization to start over (the simulated robot knows its pose).",
    );
    Ok(())
}

/// ToggleCollisionMonitor: see the [module documentation](self).
fn toggle_collision_monitor<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let Ok(enable) = ports::or(h, "enable", true) else {
        return Status::Failure;
    };
    h.ctx_mut().nav2_mut().set_collision_monitor(enable);
    Status::Success
}

#[cfg(test)]
mod tests {
    use crate::nav2::testing::Bench;
    use neurotree_core::Status;

    #[test]
    fn the_collision_monitor_toggles_and_relocalization_is_counted() {
        let mut b = Bench::new(
            "R",
            r#"<Sequence>
                 <ToggleCollisionMonitor enable="false"/>
                 <ReinitializeGlobalLocalization/>
               </Sequence>"#,
        );
        assert!(b.sim.collision_monitor());
        assert_eq!(b.tick(), Status::Success);
        assert!(!b.sim.collision_monitor());
        assert_eq!(b.sim.relocalizations(), 1);
        let mut b = Bench::new("R", r#"<ToggleCollisionMonitor/>"#);
        b.sim.set_collision_monitor(false);
        assert_eq!(b.tick(), Status::Success);
        assert!(b.sim.collision_monitor());
    }
}
