//! SmoothPath: the smoother server.
//!
//! A sync action. Ports `unsmoothed_path`, `max_smoothing_duration` (default 3.0),
//! `check_for_collisions` (default false), `smoother_id`; outputs `smoothed_path`,
//! `smoothing_duration`, `was_completed`, `error_code_id`, `error_msg`.
//!
//! - An empty or absent path: Failure INVALID_PATH 505, as Nav2's server refuses it.
//! - Otherwise the path without its repeated poses (where two paths were joined end to
//!   start): the grid planner's paths run from cell centre to cell centre in straight
//!   lines and have nothing else to smooth. With `check_for_collisions`, a pose on a cell
//!   the global costmap holds blocked fails with SMOOTHED_PATH_IN_COLLISION 503.
//! - Success writes the path, `smoothing_duration` 0 (seconds: the simulated smoother
//!   takes no time), `was_completed` true and error code 0.
//!
//! Any `smoother_id` is accepted: the simulation has one smoother.

use neurotree_core::{Handle, Status};

use super::codes::smooth_path as code;
use super::{ports, Nav2Context};
use crate::CostmapLayer;
use neurotree_nav2::robotics::Path;
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_action(
        "SmoothPath",
        vec![
            PortSpec::input::<Path>("unsmoothed_path").describe("The path to smooth."),
            PortSpec::input::<f64>("max_smoothing_duration")
                .default_value("3.0")
                .describe("Seconds the smoother may take (it takes none)."),
            PortSpec::input::<bool>("check_for_collisions")
                .default_value("false")
                .describe("Fail when the smoothed path crosses a blocked cell."),
            PortSpec::input::<String>("smoother_id")
                .describe("Smoother plugin to use; the simulation has one and accepts any id."),
            PortSpec::input::<String>("server_name").describe("Action server name (unused)."),
            PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
            PortSpec::output::<Path>("smoothed_path").describe("The smoothed path."),
            PortSpec::output::<f64>("smoothing_duration").describe("Seconds smoothing took."),
            PortSpec::output::<bool>("was_completed").describe("Smoothing finished in time."),
            PortSpec::output::<u16>("error_code_id").describe("0, or the smoother's error code."),
            PortSpec::output::<String>("error_msg").describe("Why it failed; empty on success."),
        ],
        smooth_path::<C>,
    )?;
    r.describe("SmoothPath", "Smooths a path: drops its repeated poses.");
    Ok(())
}

/// SmoothPath: see the [module documentation](self).
fn smooth_path<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let read = ports::or(h, "unsmoothed_path", Path::default())
        .and_then(|path| Ok((path, ports::or(h, "check_for_collisions", false)?)));
    let (mut path, check) = match read {
        Ok(read) => read,
        Err(e) => return ports::fail(h, code::UNKNOWN, "bad input", e.to_string()),
    };
    if path.is_empty() {
        return ports::fail(
            h,
            code::INVALID_PATH,
            "invalid path",
            "the path is empty".into(),
        );
    }
    path.poses.dedup();
    if check {
        let world = &h.ctx().nav2().world;
        let costmap = world.costmap(CostmapLayer::Global);
        let hit = path
            .poses
            .iter()
            .find(|p| world.map().cell_at(p).is_none_or(|c| costmap.is_blocked(c)))
            .copied();
        if let Some(p) = hit {
            let message = format!("the smoothed path collides at ({:.2}, {:.2})", p.x, p.y);
            return ports::fail(h, code::SMOOTHED_PATH_IN_COLLISION, "in collision", message);
        }
    }
    ports::emit(h, "smoothed_path", path);
    ports::emit(h, "smoothing_duration", 0.0_f64);
    ports::emit(h, "was_completed", true);
    ports::succeed(h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;
    use neurotree_nav2::robotics::Pose2D;
    use Status::{Failure as F, Success as S};

    fn path(xs: &[f64]) -> Path {
        Path::new(xs.iter().map(|&x| Pose2D::new(x, 0.5, 0.0)).collect())
    }

    #[test]
    fn smoothing_drops_repeated_poses_and_refuses_an_empty_path() {
        let mut b = Bench::new(
            "R.#..",
            r#"<SmoothPath unsmoothed_path="{in}" smoothed_path="{out}" check_for_collisions="{check}" error_code_id="{code}" was_completed="{done}"/>"#,
        );
        b.set("check", false);
        b.set("in", path(&[0.5, 1.5, 1.5, 2.5]));
        assert_eq!(b.tick(), S);
        assert_eq!(b.get::<Path>("out"), path(&[0.5, 1.5, 2.5]));
        assert!(b.get::<bool>("done"));
        assert_eq!(b.get::<u16>("code"), 0);
        b.set("check", true);
        assert_eq!(b.tick(), F);
        assert_eq!(b.get::<u16>("code"), code::SMOOTHED_PATH_IN_COLLISION);
        b.set("in", Path::default());
        assert_eq!(b.tick(), F);
        assert_eq!(b.get::<u16>("code"), code::INVALID_PATH);
        assert_eq!(b.reason().as_deref(), Some("invalid path (error 505)"));
    }
}
