//! ClearEntireCostmap: the costmaps' clearing service.
//!
//! Sync action with the port `service_name`: forgets the sensed obstacles of the global
//! costmap (a service name containing `global_costmap`) or the local one (`local_costmap`);
//! Success. Any other name: Failure.
//!
//! Nav2 names the costmap by the service that clears it
//! (`global_costmap/clear_entirely_global_costmap`); the walls of the map stay, and an
//! obstacle still in sensing range is learned again at the next step of the world.

use neurotree_core::{Handle, Status};

use super::{ports, Nav2Context};
use crate::CostmapLayer;
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

fn ports() -> Vec<PortSpec> {
    vec![
        PortSpec::input::<String>("service_name")
            .describe("Which costmap: `global_costmap/…` or `local_costmap/…`."),
        PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
        PortSpec::input::<Vec<String>>("plugins")
            .describe("Costmap layers to clear (unused: the grid world has one layer)."),
    ]
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_action("ClearEntireCostmap", ports(), clear::<C>)?;
    r.describe(
        "ClearEntireCostmap",
        "Forgets the obstacles the global or the local costmap learned.",
    );
    Ok(())
}

/// The costmap a clearing service name addresses.
pub(super) fn layer_of(service: &str) -> Option<CostmapLayer> {
    if service.contains("global_costmap") {
        Some(CostmapLayer::Global)
    } else if service.contains("local_costmap") {
        Some(CostmapLayer::Local)
    } else {
        None
    }
}

fn clear<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let service = ports::or(h, "service_name", String::new()).unwrap_or_default();
    let Some(layer) = layer_of(&service) else {
        let name = h.name().to_string();
        h.ctx_mut().nav2_mut().note(|| {
            format!("{name} failed: `{service}` names neither the global nor the local costmap")
        });
        return Status::Failure;
    };
    let name = h.name().to_string();
    let sim = h.ctx_mut().nav2_mut();
    sim.world.clear_costmap(layer);
    let which = match layer {
        CostmapLayer::Global => "global",
        CostmapLayer::Local => "local",
    };
    sim.note(|| format!("{name}: cleared the {which} costmap"));
    Status::Success
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;
    use crate::{Cell, GridWorld, TimedObstacle};
    use std::time::Duration;

    #[test]
    fn clears_the_costmap_its_service_names() {
        let world = GridWorld::parse("R..", 1.0)
            .unwrap()
            .with_timed_obstacle(TimedObstacle::new(Cell::new(2, 0), Duration::ZERO));
        let mut b = Bench::with_world(world, r#"<ClearEntireCostmap service_name="{service}"/>"#);
        let known = |b: &Bench, layer| b.sim.world.costmap(layer).is_marked(Cell::new(2, 0));
        assert!(known(&b, CostmapLayer::Global) && known(&b, CostmapLayer::Local));
        b.set(
            "service",
            "local_costmap/clear_entirely_local_costmap".to_string(),
        );
        assert_eq!(b.tick(), Status::Success);
        assert!(known(&b, CostmapLayer::Global) && !known(&b, CostmapLayer::Local));
        b.set(
            "service",
            "global_costmap/clear_entirely_global_costmap".to_string(),
        );
        assert_eq!(b.tick(), Status::Success);
        assert!(!known(&b, CostmapLayer::Global));
        b.set("service", "clear_everything".to_string());
        assert_eq!(b.tick(), Status::Failure);
    }
}
