//! The other services: the costmaps' costs, the collision monitor's switch, the
//! localization's reinitialization.

use neurotree_sim::nav2::Nav2Sim;
use neurotree_sim::CostmapLayer;
use ros2_client::service::Server;

use super::stats::SimStatsHandle;
use crate::msg::nav2_msgs::{GetCostsRequest, GetCostsResponse, ToggleRequest, ToggleResponse};
use crate::msg::std_srvs::{EmptyRequest, EmptyResponse};
use crate::nav2::convert::pose_2d;
use crate::Ros2Error;

fn serve_failed(name: &str) -> impl Fn(ros2_client::ReadError) -> Ros2Error + '_ {
    move |e| Ros2Error::Serve {
        kind: "service server",
        name: name.to_owned(),
        message: format!("{e:?}"),
    }
}

/// Answers the costmaps' cost requests, as Nav2's costmap does: a pose off the map costs
/// 255 (unknown) and makes the answer unsuccessful.
pub(super) fn serve_costs(
    servers: &[(CostmapLayer, Server<GetCostsRequest, GetCostsResponse>)],
    sim: &Nav2Sim,
    stats: &SimStatsHandle,
) -> Result<(), Ros2Error> {
    for (layer, server) in servers {
        while let Some((id, request)) = server
            .receive_request()
            .map_err(serve_failed("costmap costs"))?
        {
            let costs: Vec<Option<f64>> = request
                .poses
                .iter()
                .map(|pose| sim.cost(*layer, &pose_2d(pose)))
                .collect();
            let response = GetCostsResponse {
                success: costs.iter().all(Option::is_some),
                costs: costs.iter().map(|c| c.unwrap_or(255.0) as f32).collect(),
            };
            stats.lock().cost_requests += 1;
            // A client gone since it asked does not need the answer.
            let _ = server.send_response(id, response);
        }
    }
    Ok(())
}

/// Answers the collision monitor's `toggle` and the localization's
/// `reinitialize_global_localization`.
pub(super) fn serve_switches(
    toggle: &Server<ToggleRequest, ToggleResponse>,
    relocalize: &Server<EmptyRequest, EmptyResponse>,
    sim: &mut Nav2Sim,
    stats: &SimStatsHandle,
) -> Result<(), Ros2Error> {
    while let Some((id, request)) = toggle
        .receive_request()
        .map_err(serve_failed("collision monitor"))?
    {
        sim.set_collision_monitor(request.enable);
        let state = if request.enable { "on" } else { "off" };
        let response = ToggleResponse {
            success: true,
            message: format!("the collision monitor is {state}"),
        };
        stats.lock().collision_monitor = request.enable;
        let _ = toggle.send_response(id, response);
    }
    while let Some((id, _)) = relocalize
        .receive_request()
        .map_err(serve_failed("localization"))?
    {
        sim.count_relocalization();
        stats.lock().relocalizations += 1;
        let _ = relocalize.send_response(id, EmptyResponse::default());
    }
    Ok(())
}
