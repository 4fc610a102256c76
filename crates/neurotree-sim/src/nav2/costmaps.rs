//! The costmaps' clearing services: ClearEntireCostmap, ClearCostmapAroundRobot,
//! ClearCostmapAroundPose and ClearCostmapExceptRegion.
//!
//! Sync actions with the port `service_name`, which names the costmap: the global one (a
//! name containing `global_costmap`) or the local one (`local_costmap`); any other name:
//! Failure.
//!
//! - **ClearEntireCostmap**: forgets every sensed obstacle of the costmap. Success.
//! - **ClearCostmapAroundRobot** (port `reset_distance`, default 1.0): forgets those in the
//!   square of side `reset_distance` centred on the robot. Success.
//! - **ClearCostmapAroundPose** (ports `pose`, `reset_distance`): the same around `pose`.
//! - **ClearCostmapExceptRegion** (port `reset_distance`): forgets those outside that square
//!   around the robot. Success.
//!
//! The square is Nav2's (`clear_costmap_service.cpp`, `CostmapLayer::clearArea`): its
//! corners are turned into cell indices by truncation, and a cell is inside when its
//! indices lie strictly between the corners' (so a `reset_distance` under two cells clears
//! nothing around a robot at a cell's centre, as in Nav2).
//!
//! Nav2 names the costmap by the service that clears it
//! (`global_costmap/clear_entirely_global_costmap`); the walls of the map stay, and an
//! obstacle still in sensing range is learned again at the next step of the world.

use neurotree_core::{Handle, Status};

use super::{ports, Nav2Context};
use crate::{Cell, CostmapLayer};
use neurotree_nav2::robotics::Pose2D;
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

fn region_ports() -> Vec<PortSpec> {
    let mut ports = vec![PortSpec::input::<f64>("reset_distance")
        .default_value("1.0")
        .describe("Side of the square, in metres.")];
    ports.extend(self::ports());
    ports
}

/// Which part of a costmap a clearing node forgets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Region {
    AroundRobot,
    AroundPose,
    ExceptAroundRobot,
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_action("ClearEntireCostmap", ports(), clear::<C>)?;
    r.describe(
        "ClearEntireCostmap",
        "Forgets the obstacles the global or the local costmap learned.",
    );
    r.register_action("ClearCostmapAroundRobot", region_ports(), |h| {
        clear_region(h, Region::AroundRobot)
    })?;
    r.describe(
        "ClearCostmapAroundRobot",
        "Forgets the obstacles a costmap learned in a square around the robot.",
    );
    let mut pose_ports = vec![PortSpec::input::<Pose2D>("pose").describe("The square's centre.")];
    pose_ports.extend(region_ports());
    r.register_action("ClearCostmapAroundPose", pose_ports, |h| {
        clear_region(h, Region::AroundPose)
    })?;
    r.describe(
        "ClearCostmapAroundPose",
        "Forgets the obstacles a costmap learned in a square around `pose`.",
    );
    r.register_action("ClearCostmapExceptRegion", region_ports(), |h| {
        clear_region(h, Region::ExceptAroundRobot)
    })?;
    r.describe(
        "ClearCostmapExceptRegion",
        "Forgets the obstacles a costmap learned outside a square around the robot.",
    );
    Ok(())
}

/// Forgets the sensed obstacles of `layer` inside Nav2's square of side `distance` centred
/// on `centre` (outside it when `invert`), as the clearing services do (see the
/// [module documentation](self)); returns how many cells were forgotten. The ROS 2
/// simulator serves Nav2's clearing services with it.
pub fn clear_square(
    sim: &mut super::Nav2Sim,
    layer: CostmapLayer,
    centre: Pose2D,
    distance: f64,
    invert: bool,
) -> usize {
    let resolution = sim.world.map().resolution();
    // Nav2's worldToMapNoBounds: truncation, from an origin at 0.
    let index = |metres: f64| (metres / resolution) as i32;
    let (x0, y0) = (
        index(centre.x - distance / 2.0),
        index(centre.y - distance / 2.0),
    );
    let (x1, y1) = (
        index(centre.x - distance / 2.0 + distance),
        index(centre.y - distance / 2.0 + distance),
    );
    let inside = move |c: Cell| c.x > x0 && c.x < x1 && c.y > y0 && c.y < y1;
    sim.world
        .clear_costmap_where(layer, move |c| inside(c) != invert)
}

/// ClearCostmapAroundRobot, ClearCostmapAroundPose, ClearCostmapExceptRegion: see the
/// [module documentation](self).
fn clear_region<C: Nav2Context>(h: &mut Handle<'_, C>, region: Region) -> Status {
    let read = (|| {
        let service = ports::or(h, "service_name", String::new())?;
        let distance: f64 = ports::or(h, "reset_distance", 1.0)?;
        let centre = match region {
            Region::AroundPose => Some(ports::or(h, "pose", Pose2D::default())?),
            Region::AroundRobot | Region::ExceptAroundRobot => None,
        };
        Ok::<_, neurotree_core::PortError>((service, distance, centre))
    })();
    let Ok((service, distance, centre)) = read else {
        return Status::Failure;
    };
    let Some(layer) = layer_of(&service) else {
        return Status::Failure;
    };
    let name = h.name().to_string();
    let sim = h.ctx_mut().nav2_mut();
    let centre = centre.unwrap_or_else(|| sim.world.robot());
    let invert = region == Region::ExceptAroundRobot;
    let forgotten = clear_square(sim, layer, centre, distance, invert);
    sim.note(|| format!("{name}: forgot {forgotten} obstacle cells"));
    Status::Success
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

    #[test]
    fn region_clearing_forgets_inside_or_outside_nav2s_square() {
        let cells = [Cell::new(1, 2), Cell::new(3, 2), Cell::new(4, 2)];
        let mut world = GridWorld::parse(
            "
            .....
            .....
            ..R..
            .....
            .....",
            1.0,
        )
        .unwrap()
        .with_sensing_radius(10.0);
        for cell in cells {
            world = world.with_timed_obstacle(TimedObstacle::new(cell, Duration::ZERO));
        }
        let marked = |b: &Bench| {
            b.sim
                .world
                .costmap(CostmapLayer::Local)
                .marked()
                .collect::<Vec<_>>()
        };
        let local = r#"service_name="local_costmap/clear_around_local_costmap""#;
        // Around (2.5, 2.5) with 3 m: corners at indices 1 and 4, so only x 2..=3 clear.
        let mut b = Bench::with_world(
            world,
            &format!(r#"<ClearCostmapAroundRobot reset_distance="3.0" {local}/>"#),
        );
        assert_eq!(b.tick(), Status::Success);
        assert_eq!(marked(&b), [Cell::new(1, 2), Cell::new(4, 2)]);
        assert!(b
            .sim
            .world
            .costmap(CostmapLayer::Global)
            .is_marked(Cell::new(3, 2)));
        let mut world = GridWorld::parse(".....\n.....\n..R..", 1.0).unwrap();
        for cell in [Cell::new(0, 0), Cell::new(2, 1), Cell::new(4, 2)] {
            world = world.with_timed_obstacle(TimedObstacle::new(cell, Duration::ZERO));
        }
        let mut b = Bench::with_world(
            world.with_sensing_radius(10.0),
            &format!(r#"<ClearCostmapExceptRegion reset_distance="3.0" {local}/>"#),
        );
        assert_eq!(b.tick(), Status::Success);
        assert_eq!(marked(&b), [Cell::new(2, 1)]);
        let mut b = Bench::new(
            "R....",
            r#"<ClearCostmapAroundPose pose="1;1" service_name="elsewhere"/>"#,
        );
        assert_eq!(b.tick(), Status::Failure);
    }
}
