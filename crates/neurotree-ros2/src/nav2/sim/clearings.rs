//! The costmaps' clearing services, in a release's layout, on the world's costmaps.

use neurotree_sim::nav2::costmaps::clear_square;
use neurotree_sim::nav2::Nav2Sim;
use neurotree_sim::CostmapLayer;
use ros2_client::service::Server;

use super::stats::SimStatsHandle;
use crate::nav2::clearing::ClearLayout;
use crate::nav2::convert::pose_2d;
use crate::{Ros2Error, RosNode, RosService};

/// One clearing service of one costmap, in a release's layout.
type ClearServer<S> = Server<<S as RosService>::Request, <S as RosService>::Response>;

/// What a clearing request asks of a costmap.
#[derive(Clone, Copy)]
enum Clearing {
    Entire,
    AroundRobot,
    ExceptRegion,
    AroundPose,
}

/// Takes `server`'s requests and clears `layer` as each asks, counting each in `stats`. A
/// request in another release's layout cannot be read: it is dropped, and its client times
/// out.
fn serve_clearing<S: ClearLayout>(
    server: &ClearServer<S>,
    clearing: Clearing,
    layer: CostmapLayer,
    sim: &mut Nav2Sim,
    stats: &SimStatsHandle,
) -> Result<(), Ros2Error> {
    let mut undecodable = 0;
    loop {
        let (id, request) = match server.receive_request() {
            Ok(Some(request)) => request,
            Ok(None) => return Ok(()),
            Err(ros2_client::ReadError::Deserialization { .. }) if undecodable < 64 => {
                undecodable += 1;
                continue;
            }
            Err(e) => {
                return Err(Ros2Error::Serve {
                    kind: "service server",
                    name: format!("{layer:?} costmap clearing"),
                    message: format!("{e:?}"),
                })
            }
        };
        let side = S::reset_distance(&request);
        let robot = sim.world.robot();
        match clearing {
            Clearing::Entire => sim.world.clear_costmap(layer),
            Clearing::AroundRobot => {
                clear_square(sim, layer, robot, side, false);
            }
            Clearing::ExceptRegion => {
                clear_square(sim, layer, robot, side, true);
            }
            Clearing::AroundPose => {
                let centre = S::pose(&request).map_or(robot, pose_2d);
                clear_square(sim, layer, centre, side, false);
            }
        }
        stats.lock().clears += 1;
        // A client gone since it asked does not need the answer: responses are best effort.
        let _ = server.send_response(id, S::response(true));
    }
}

/// The clearing services of a costmap.
pub(super) trait ServeClearings {
    /// Answers the requests that came, counting each in `stats` before its answer goes
    /// out (a client that has its answer may read the count at once).
    fn serve(&self, sim: &mut Nav2Sim, stats: &SimStatsHandle) -> Result<(), Ros2Error>;
}

/// The four clearing services of one costmap, in the layouts `E`, `A`, `X` and `P`,
/// named as Nav2's costmaps name them (`local_costmap/clear_around_local_costmap`, ...).
pub(super) struct Clearings<E: ClearLayout, A: ClearLayout, X: ClearLayout, P: ClearLayout> {
    layer: CostmapLayer,
    entire: ClearServer<E>,
    around: ClearServer<A>,
    except: ClearServer<X>,
    around_pose: ClearServer<P>,
}

impl<E: ClearLayout, A: ClearLayout, X: ClearLayout, P: ClearLayout> Clearings<E, A, X, P> {
    /// Both costmaps' services.
    pub(super) fn both(ros: &RosNode) -> Result<Vec<Box<dyn ServeClearings>>, Ros2Error>
    where
        Self: 'static,
    {
        let mut both: Vec<Box<dyn ServeClearings>> = Vec::new();
        for (costmap, layer) in [
            ("global_costmap", CostmapLayer::Global),
            ("local_costmap", CostmapLayer::Local),
        ] {
            both.push(Box::new(Self {
                layer,
                entire: ros.service_server::<E>(&format!("{costmap}/clear_entirely_{costmap}"))?,
                around: ros.service_server::<A>(&format!("{costmap}/clear_around_{costmap}"))?,
                except: ros.service_server::<X>(&format!("{costmap}/clear_except_{costmap}"))?,
                around_pose: ros
                    .service_server::<P>(&format!("{costmap}/clear_around_pose_{costmap}"))?,
            }));
        }
        Ok(both)
    }
}

impl<E: ClearLayout, A: ClearLayout, X: ClearLayout, P: ClearLayout> ServeClearings
    for Clearings<E, A, X, P>
{
    fn serve(&self, sim: &mut Nav2Sim, stats: &SimStatsHandle) -> Result<(), Ros2Error> {
        let layer = self.layer;
        serve_clearing::<E>(&self.entire, Clearing::Entire, layer, sim, stats)?;
        serve_clearing::<A>(&self.around, Clearing::AroundRobot, layer, sim, stats)?;
        serve_clearing::<X>(&self.except, Clearing::ExceptRegion, layer, sim, stats)?;
        serve_clearing::<P>(&self.around_pose, Clearing::AroundPose, layer, sim, stats)
    }
}
