//! The route server: a [`RouteGraph`], ComputeRoute, ComputeAndTrackRoute and
//! ExtractRouteNodesAsGoals.
//!
//! A route graph is nodes (ids and positions) joined by directed edges; the route server
//! finds the cheapest route along them, an edge costing its length (Nav2's default
//! distance scorer). An edge that crosses a cell the global costmap holds blocked is left
//! out, as Nav2's costmap scorer leaves out an edge in collision. The route's path is the
//! edges' straight lines, a pose every cell (`path_density`), each facing along its edge.
//! Give a graph with [`Nav2Sim::with_route_graph`](super::Nav2Sim::with_route_graph).
//!
//! - **ComputeRoute**: a sync action. Ports `start`, `goal`, `start_id`, `goal_id`,
//!   `use_start` (default false), `use_poses` (default false); outputs `route`, `path`,
//!   `planning_time`, `error_code_id`, `error_msg`.
//!   - With `use_poses`: from the node nearest to `start` (when `use_start`; else to the
//!     robot) to the node nearest to `goal`. Else: from node `start_id` to node `goal_id`
//!     (INDETERMINANT_NODES_ON_GRAPH 403 when one is not on the graph).
//!   - Success writes the route, its path, `planning_time` 0 (seconds) and error code 0.
//!   - No graph: NO_VALID_GRAPH 402; no route: NO_VALID_ROUTE 405. A failure writes an
//!     empty route and path, as Nav2's node resets them.
//!   - Nav2's server is an action, Running while it plans; the simulated one answers within
//!     the tick, as the [planner](super::planner) does.
//! - **ComputeAndTrackRoute**: a stateful action, with the same inputs; outputs `route`,
//!   `path`, `last_node_id`, `next_node_id`, `current_edge_id`, `rerouted`,
//!   `execution_duration`, `error_code_id`, `error_msg`.
//!   - The tick from Idle computes the route as ComputeRoute does (failing the same way)
//!     and writes it: Running. The robot does not move by it: a FollowPath beside it
//!     follows `path`.
//!   - Later ticks track the robot along the route: a node counts as reached within one
//!     metre (Nav2's `radius_to_achieve_node`); the outputs say the last node reached, the
//!     next one and the edge between. When an edge ahead becomes blocked, the route is
//!     computed again from the robot (`rerouted` true); when none is left: NO_VALID_ROUTE.
//!   - Success when the last node is reached. A CancelComputeAndTrackRoute ends it with
//!     Success at its next tick (Nav2's `on_cancelled`). Halt ends the tracking.
//! - **ExtractRouteNodesAsGoals**: a sync action. Port `route`; output `goals`: the route's
//!   nodes as poses. Failure for an empty route, as Nav2's node.

use std::collections::{BinaryHeap, HashMap};
use std::time::Duration;

use neurotree_core::{Handle, StatefulAction, Status};

use super::codes::route as code;
use super::{ports, GoalState, Nav2Context, Nav2Sim};
use crate::{CostmapLayer, GridWorld};
use neurotree_nav2::robotics::{Path, Pose2D, Route, RouteEdge, RouteNode};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

/// Metres from a node at which the tracker counts it reached.
const RADIUS_TO_ACHIEVE_NODE: f64 = 1.0;

/// A route graph: see the [module documentation](self).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RouteGraph {
    nodes: Vec<RouteNode>,
    edges: Vec<RouteEdge>,
}

impl RouteGraph {
    /// A graph of `nodes` and no edges yet.
    pub fn new(nodes: Vec<RouteNode>) -> Self {
        Self {
            nodes,
            edges: Vec::new(),
        }
    }

    /// With an edge each way between nodes `a` and `b` (ids), numbered on from the edges
    /// already there (the first is 1).
    pub fn with_way(mut self, a: u16, b: u16) -> Self {
        for (start, end) in [(a, b), (b, a)] {
            let id = u16::try_from(self.edges.len() + 1).unwrap_or(u16::MAX);
            self.edges.push(RouteEdge { id, start, end });
        }
        self
    }

    /// The nodes.
    pub fn nodes(&self) -> &[RouteNode] {
        &self.nodes
    }

    /// The edges.
    pub fn edges(&self) -> &[RouteEdge] {
        &self.edges
    }

    /// Node `id`.
    pub fn node(&self, id: u16) -> Option<&RouteNode> {
        self.nodes.iter().find(|n| n.id == id)
    }

    /// The node nearest to `pose` (the first of equals).
    pub fn nearest(&self, pose: &Pose2D) -> Option<&RouteNode> {
        self.nodes
            .iter()
            .min_by(|a, b| a.pose().distance(pose).total_cmp(&b.pose().distance(pose)))
    }

    /// The cheapest route from node `from` to node `to` over the edges `usable` allows.
    fn route(&self, from: u16, to: u16, usable: impl Fn(&RouteEdge) -> bool) -> Option<Route> {
        #[derive(PartialEq)]
        struct Entry(f64, u16);
        impl Eq for Entry {}
        impl PartialOrd for Entry {
            fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
                Some(self.cmp(other))
            }
        }
        impl Ord for Entry {
            fn cmp(&self, other: &Self) -> std::cmp::Ordering {
                // The cheapest first; then the smaller id, for one answer among equals.
                other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
            }
        }
        let length = |e: &RouteEdge| match (self.node(e.start), self.node(e.end)) {
            (Some(a), Some(b)) => Some(a.pose().distance(&b.pose())),
            _ => None,
        };
        let mut best: HashMap<u16, (f64, Option<RouteEdge>)> = HashMap::new();
        best.insert(from, (0.0, None));
        let mut open = BinaryHeap::from([Entry(0.0, from)]);
        while let Some(Entry(cost, at)) = open.pop() {
            if at == to {
                break;
            }
            if best.get(&at).is_some_and(|(c, _)| *c < cost) {
                continue;
            }
            for edge in self.edges.iter().filter(|e| e.start == at && usable(e)) {
                let Some(len) = length(edge) else { continue };
                let next = cost + len;
                if !best.get(&edge.end).is_some_and(|(c, _)| next >= *c) {
                    best.insert(edge.end, (next, Some(*edge)));
                    open.push(Entry(next, edge.end));
                }
            }
        }
        let (cost, _) = *best.get(&to)?;
        let mut edges = Vec::new();
        let mut at = to;
        while let Some((_, Some(edge))) = best.get(&at) {
            edges.push(*edge);
            at = edge.start;
        }
        edges.reverse();
        let mut nodes = vec![*self.node(from)?];
        for edge in &edges {
            nodes.push(*self.node(edge.end)?);
        }
        Some(Route { nodes, edges, cost })
    }
}

/// The dense path along a route's nodes: a pose every `step` metres on each edge, facing
/// along it, and the last node.
fn path_along(route: &Route, step: f64) -> Path {
    let mut poses = Vec::new();
    for pair in route.nodes.windows(2) {
        let (a, b) = (pair[0].pose(), pair[1].pose());
        let heading = (b.y - a.y).atan2(b.x - a.x);
        let length = a.distance(&b);
        let count = (length / step).ceil().max(1.0) as usize;
        for i in 0..count {
            let t = i as f64 / count as f64;
            poses.push(Pose2D::new(
                a.x + t * (b.x - a.x),
                a.y + t * (b.y - a.y),
                heading,
            ));
        }
    }
    if let Some(last) = route.nodes.last() {
        let heading = poses.last().map_or(0.0, |p: &Pose2D| p.theta);
        poses.push(Pose2D::new(last.x, last.y, heading));
    }
    Path::new(poses)
}

/// `true` when the straight line of `edge` crosses no cell the global costmap blocks.
fn edge_free(world: &GridWorld, graph: &RouteGraph, edge: &RouteEdge) -> bool {
    let step = world.map().resolution() / 4.0;
    let route = match (graph.node(edge.start), graph.node(edge.end)) {
        (Some(a), Some(b)) => Route {
            nodes: vec![*a, *b],
            edges: vec![*edge],
            cost: 0.0,
        },
        _ => return false,
    };
    let costmap = world.costmap(CostmapLayer::Global);
    path_along(&route, step).poses.iter().all(|p| {
        world
            .map()
            .cell_at(p)
            .is_some_and(|c| !costmap.is_blocked(c))
    })
}

/// What a route request asks: from which node to which.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
enum Ends {
    Poses { start: Option<Pose2D>, goal: Pose2D },
    Ids { start: u16, goal: u16 },
}

/// A failure: code, reason, message.
type Failed = (u16, &'static str, String);

fn read_ends<C>(h: &Handle<'_, C>) -> Result<Ends, Failed> {
    let bad = |e: neurotree_core::PortError| (code::UNKNOWN, "bad input", e.to_string());
    if ports::or(h, "use_poses", false).map_err(bad)? {
        let goal = ports::or(h, "goal", Pose2D::default()).map_err(bad)?;
        let start = if ports::or(h, "use_start", false).map_err(bad)? {
            Some(ports::or(h, "start", Pose2D::default()).map_err(bad)?)
        } else {
            None
        };
        Ok(Ends::Poses { start, goal })
    } else {
        Ok(Ends::Ids {
            start: ports::or(h, "start_id", 0_u16).map_err(bad)?,
            goal: ports::or(h, "goal_id", 0_u16).map_err(bad)?,
        })
    }
}

/// The route `ends` asks for, from `robot` when a start pose is wanted and not given.
fn compute(sim: &Nav2Sim, ends: Ends) -> Result<(Route, Path), Failed> {
    let Some(graph) = sim.route_graph() else {
        return Err((
            code::NO_VALID_GRAPH,
            "no valid graph",
            "the route server has no graph".into(),
        ));
    };
    let (from, to) = match ends {
        Ends::Poses { start, goal } => {
            let start = start.unwrap_or_else(|| sim.world.robot());
            match (graph.nearest(&start), graph.nearest(&goal)) {
                (Some(a), Some(b)) => (a.id, b.id),
                _ => {
                    return Err((
                        code::NO_VALID_GRAPH,
                        "no valid graph",
                        "the graph has no nodes".into(),
                    ))
                }
            }
        }
        Ends::Ids { start, goal } => {
            for id in [start, goal] {
                if graph.node(id).is_none() {
                    return Err((
                        code::INDETERMINANT_NODES_ON_GRAPH,
                        "node not on the graph",
                        format!("node {id} is not on the graph"),
                    ));
                }
            }
            (start, goal)
        }
    };
    let route = graph
        .route(from, to, |e| edge_free(&sim.world, graph, e))
        .ok_or((
            code::NO_VALID_ROUTE,
            "no valid route",
            format!("no route from node {from} to node {to}"),
        ))?;
    let path = path_along(&route, sim.world.map().resolution());
    Ok((route, path))
}

/// The inputs both route nodes take.
fn route_inputs() -> Vec<PortSpec> {
    vec![
        PortSpec::input::<Pose2D>("start").describe("Start pose, with `use_start`."),
        PortSpec::input::<Pose2D>("goal").describe("Goal pose, with `use_poses`."),
        PortSpec::input::<u16>("start_id").describe("Start node, without `use_poses`."),
        PortSpec::input::<u16>("goal_id").describe("Goal node, without `use_poses`."),
        PortSpec::input::<bool>("use_start")
            .default_value("false")
            .describe("Start from `start` rather than the robot."),
        PortSpec::input::<bool>("use_poses")
            .default_value("false")
            .describe("Route between poses rather than node ids."),
        PortSpec::input::<String>("server_name").describe("Action server name (unused)."),
        PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
    ]
}

fn route_output() -> PortSpec {
    PortSpec::output::<Route>("route").describe("The route; empty after a failure.")
}

fn path_output() -> PortSpec {
    PortSpec::output::<Path>("path").describe("The route's path; empty after a failure.")
}

fn error_outputs() -> [PortSpec; 2] {
    [
        PortSpec::output::<u16>("error_code_id").describe("0, or the route server's error code."),
        PortSpec::output::<String>("error_msg").describe("Why it failed; empty on success."),
    ]
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    // In the order of Nav2's model.
    let mut compute_ports = route_inputs();
    compute_ports.extend([
        route_output(),
        path_output(),
        PortSpec::output::<f64>("planning_time").describe("Seconds routing took."),
    ]);
    compute_ports.extend(error_outputs());
    r.register_action("ComputeRoute", compute_ports, compute_route::<C>)?;
    r.describe(
        "ComputeRoute",
        "Finds the cheapest route on the route graph.",
    );
    let mut track_ports = route_inputs();
    track_ports.extend([
        PortSpec::output::<f64>("execution_duration").describe("Seconds tracked so far."),
        PortSpec::output::<u16>("last_node_id").describe("The last node reached."),
        PortSpec::output::<u16>("next_node_id").describe("The next node."),
        PortSpec::output::<u16>("current_edge_id").describe("The edge being driven."),
        route_output(),
        path_output(),
        PortSpec::output::<bool>("rerouted").describe("Whether the route was computed again."),
    ]);
    track_ports.extend(error_outputs());
    r.register_stateful("ComputeAndTrackRoute", track_ports, TrackRoute::default)?;
    r.describe(
        "ComputeAndTrackRoute",
        "Finds a route on the route graph and tracks the robot along it.",
    );
    register_extract_route_nodes(r)
}

/// ExtractRouteNodesAsGoals alone: it reads only the blackboard, so a navigator whose route
/// server is served elsewhere has it too.
pub(super) fn register_extract_route_nodes<C: Nav2Context>(
    r: &mut Registry<C>,
) -> Result<(), RegistryError> {
    r.register_action(
        "ExtractRouteNodesAsGoals",
        vec![
            PortSpec::input::<Route>("route").describe("The route."),
            PortSpec::output::<Vec<Pose2D>>("goals").describe("The route's nodes as poses."),
        ],
        extract_route_nodes::<C>,
    )?;
    r.describe(
        "ExtractRouteNodesAsGoals",
        "Writes a route's nodes as goals.",
    );
    Ok(())
}

fn reset<C>(h: &mut Handle<'_, C>) {
    ports::emit(h, "path", Path::default());
    ports::emit(h, "route", Route::default());
}

/// ComputeRoute: see the [module documentation](self).
fn compute_route<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let computed = read_ends(h).and_then(|ends| compute(h.ctx().nav2(), ends));
    match computed {
        Ok((route, path)) => {
            let (nodes, cost) = (route.nodes.len(), route.cost);
            h.ctx_mut()
                .nav2_mut()
                .note(|| format!("ComputeRoute: a route of {nodes} nodes, {cost:.1} m"));
            ports::emit(h, "route", route);
            ports::emit(h, "path", path);
            ports::emit(h, "planning_time", 0.0_f64);
            ports::succeed(h)
        }
        Err((code, why, message)) => {
            reset(h);
            ports::emit(h, "planning_time", 0.0_f64);
            ports::fail(h, code, why, message)
        }
    }
}

/// ExtractRouteNodesAsGoals: see the [module documentation](self).
fn extract_route_nodes<C: Nav2Context>(h: &mut Handle<'_, C>) -> Status {
    let Ok(route) = ports::or(h, "route", Route::default()) else {
        return Status::Failure;
    };
    if route.is_empty() {
        return Status::Failure;
    }
    let goals: Vec<Pose2D> = route.nodes.iter().map(RouteNode::pose).collect();
    ports::emit(h, "goals", goals);
    Status::Success
}

/// ComputeAndTrackRoute: see the [module documentation](self).
#[derive(Default)]
struct TrackRoute {
    ends: Option<Ends>,
    route: Route,
    /// Index in the route's nodes of the next node to reach.
    next: usize,
    started: Duration,
}

impl TrackRoute {
    fn take<C: Nav2Context>(&mut self, h: &mut Handle<'_, C>, route: Route, path: Path) {
        self.route = route.clone();
        self.next = 0;
        ports::emit(h, "route", route);
        ports::emit(h, "path", path);
    }

    fn feedback<C>(&self, h: &mut Handle<'_, C>) {
        let id = |i: usize| self.route.nodes.get(i).map_or(0, |n| n.id);
        let last = self.next.checked_sub(1).map_or(0, id);
        ports::emit(h, "last_node_id", last);
        ports::emit(h, "next_node_id", id(self.next));
        let edge = self
            .next
            .checked_sub(1)
            .and_then(|i| self.route.edges.get(i))
            .map_or(0, |e| e.id);
        ports::emit(h, "current_edge_id", edge);
        let elapsed = h.now().saturating_sub(self.started).as_secs_f64();
        ports::emit(h, "execution_duration", elapsed);
    }

    fn end<C: Nav2Context>(&mut self, h: &mut Handle<'_, C>) {
        h.ctx_mut().nav2_mut().goals.route_tracking = GoalState::Idle;
    }
}

impl<C: Nav2Context> StatefulAction<C> for TrackRoute {
    /// The request, the route, the next node and when tracking began; the server's goal
    /// is the world's, saved with it.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(
            self.ends,
            &self.route,
            self.next,
            self.started,
        )))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(ends, route, next, started)| {
                (self.ends, self.route, self.next, self.started) = (ends, route, next, started);
            })
            .is_some()
    }

    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.started = h.now();
        let computed = read_ends(h).and_then(|ends| Ok((ends, compute(h.ctx().nav2(), ends)?)));
        match computed {
            Ok((ends, (route, path))) => {
                self.ends = Some(ends);
                self.take(h, route, path);
                ports::emit(h, "rerouted", false);
                self.feedback(h);
                h.ctx_mut().nav2_mut().goals.route_tracking = GoalState::Active;
                Status::Running
            }
            Err((code, why, message)) => {
                reset(h);
                ports::fail(h, code, why, message)
            }
        }
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        if h.ctx().nav2().goals.route_tracking == GoalState::Cancelled {
            self.end(h);
            return ports::succeed(h);
        }
        let robot = h.ctx().nav2().world.robot();
        while self
            .route
            .nodes
            .get(self.next)
            .is_some_and(|n| n.pose().distance(&robot) <= RADIUS_TO_ACHIEVE_NODE)
        {
            self.next += 1;
        }
        self.feedback(h);
        if self.next >= self.route.nodes.len() {
            self.end(h);
            return ports::succeed(h);
        }
        // An edge still ahead that became blocked: route again from the robot.
        let sim = h.ctx().nav2();
        let blocked = sim.route_graph().is_some_and(|graph| {
            let ahead = self.next.saturating_sub(1);
            self.route.edges[ahead.min(self.route.edges.len())..]
                .iter()
                .any(|e| !edge_free(&sim.world, graph, e))
        });
        if blocked {
            let ends = match self.ends {
                Some(Ends::Poses { goal, .. }) => Ends::Poses { start: None, goal },
                Some(Ends::Ids { .. }) | None => {
                    let start = sim
                        .route_graph()
                        .and_then(|g| g.nearest(&robot))
                        .map_or(0, |n| n.id);
                    let goal = match self.ends {
                        Some(Ends::Ids { goal, .. }) => goal,
                        _ => self.route.nodes.last().map_or(0, |n| n.id),
                    };
                    Ends::Ids { start, goal }
                }
            };
            match compute(sim, ends) {
                Ok((route, path)) => {
                    self.take(h, route, path);
                    ports::emit(h, "rerouted", true);
                }
                Err((code, why, message)) => {
                    self.end(h);
                    reset(h);
                    return ports::fail(h, code, why, message);
                }
            }
        }
        Status::Running
    }

    fn on_halted(&mut self, h: &mut Handle<'_, C>) {
        self.end(h);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;
    use crate::{Cell, TimedObstacle};
    use Status::{Failure as F, Running as R, Success as S};

    /// Two ways from the west end to the east end of a room with a pillar: over the top
    /// (nodes 1, 2, 3, 4) or along the bottom (1, 5, 4), which is shorter.
    const ROOM: &str = "
        .......
        .......
        ...#...
        R......";

    fn graph() -> RouteGraph {
        RouteGraph::new(vec![
            RouteNode::new(1, 0.5, 0.5),
            RouteNode::new(2, 0.5, 3.5),
            RouteNode::new(3, 6.5, 3.5),
            RouteNode::new(4, 6.5, 0.5),
            RouteNode::new(5, 3.5, 0.5),
        ])
        .with_way(1, 2)
        .with_way(2, 3)
        .with_way(3, 4)
        .with_way(1, 5)
        .with_way(5, 4)
    }

    fn bench(xml: &str) -> Bench {
        let mut b = Bench::new(ROOM, xml);
        b.sim.route_graph = Some(graph());
        b
    }

    fn ids(route: &Route) -> Vec<u16> {
        route.nodes.iter().map(|n| n.id).collect()
    }

    #[test]
    fn the_cheapest_route_between_nodes_and_its_dense_path() {
        let mut b = bench(
            r#"<ComputeRoute start_id="1" goal_id="4" route="{route}" path="{path}" error_code_id="{code}"/>"#,
        );
        assert_eq!(b.tick(), S);
        let route: Route = b.get("route");
        assert_eq!(ids(&route), [1, 5, 4]);
        assert_eq!(route.edges.iter().map(|e| e.id).collect::<Vec<_>>(), [7, 9]);
        assert_eq!(route.cost, 6.0);
        let path: Path = b.get("path");
        // A pose a metre, from node 1 to node 4.
        assert_eq!(path.len(), 7);
        assert_eq!(path.poses[3], Pose2D::new(3.5, 0.5, 0.0));
        assert_eq!(b.get::<u16>("code"), 0);
    }

    #[test]
    fn a_blocked_edge_is_routed_round_and_unknown_nodes_fail() {
        let world = GridWorld::parse(ROOM, 1.0)
            .unwrap()
            .with_timed_obstacle(TimedObstacle::new(Cell::new(2, 0), Duration::ZERO));
        let mut b = Bench::with_world(
            world,
            r#"<ComputeRoute start_id="{from}" goal_id="4" route="{route}" path="{path}" error_code_id="{code}"/>"#,
        );
        b.sim.route_graph = Some(graph());
        b.set("from", 1_u16);
        assert_eq!(b.tick(), S);
        assert_eq!(ids(&b.get::<Route>("route")), [1, 2, 3, 4]);
        b.set("from", 9_u16);
        assert_eq!(b.tick(), F);
        assert_eq!(b.get::<u16>("code"), code::INDETERMINANT_NODES_ON_GRAPH);
        assert!(b.get::<Route>("route").is_empty());
        assert!(b.get::<Path>("path").is_empty());
    }

    #[test]
    fn poses_route_from_the_nearest_nodes_and_no_graph_fails() {
        let mut b = bench(
            r#"<ComputeRoute goal="{goal}" use_poses="true" route="{route}" error_code_id="{code}"/>"#,
        );
        // From node 1, under the robot, to node 2, the nearest to the goal.
        b.set_goal(Pose2D::new(1.0, 3.0, 0.0));
        assert_eq!(b.tick(), S);
        assert_eq!(ids(&b.get::<Route>("route")), [1, 2]);
        b.sim.route_graph = None;
        assert_eq!(b.tick(), F);
        assert_eq!(b.get::<u16>("code"), code::NO_VALID_GRAPH);
    }

    #[test]
    fn route_nodes_become_goals() {
        let mut b = bench(
            r#"<Sequence>
                 <ComputeRoute start_id="1" goal_id="4" route="{route}"/>
                 <ExtractRouteNodesAsGoals route="{route}" goals="{goals}"/>
               </Sequence>"#,
        );
        assert_eq!(b.tick(), S);
        let goals: Vec<Pose2D> = b.get("goals");
        assert_eq!(
            goals,
            [(0.5, 0.5), (3.5, 0.5), (6.5, 0.5)].map(|(x, y)| Pose2D::new(x, y, 0.0))
        );
        let mut b = bench(r#"<ExtractRouteNodesAsGoals route="{route}" goals="{goals}"/>"#);
        b.set("route", Route::default());
        assert_eq!(b.tick(), F);
    }

    #[test]
    fn tracking_follows_the_robot_node_by_node_to_the_end() {
        let mut b = bench(
            r#"<Parallel success_count="2" failure_count="1">
                 <ComputeAndTrackRoute start_id="1" goal_id="4" path="{path}" next_node_id="{next}" last_node_id="{last}"/>
                 <FollowPath path="{path}"/>
               </Parallel>"#,
        );
        assert_eq!(b.tick(), R);
        assert_eq!((b.get::<u16>("last"), b.get::<u16>("next")), (0, 1));
        b.sim.step();
        assert_eq!(b.tick(), R);
        // Node 1 is under the robot: reached.
        assert_eq!((b.get::<u16>("last"), b.get::<u16>("next")), (1, 5));
        let run = b.run(200);
        // The tracking ends a metre from node 4; FollowPath 0.25 m from it, 5.75 m along the
        // route's 6 m: after 58 steps of 0.1 m (one before these ticks, 57 between them).
        assert_eq!(run.len(), 58);
        assert_eq!(run.last(), Some(&S));
        assert_eq!(b.get::<u16>("last"), 4);
        assert_eq!(b.sim.goals.route_tracking, GoalState::Idle);
    }

    #[test]
    fn a_cancel_ends_the_tracking_with_success() {
        let mut b = bench(r#"<ComputeAndTrackRoute start_id="1" goal_id="4"/>"#);
        assert_eq!(b.tick(), R);
        assert_eq!(b.sim.goals.route_tracking, GoalState::Active);
        b.sim.goals.route_tracking = GoalState::Cancelled;
        assert_eq!(b.tick(), S);
        assert_eq!(b.sim.goals.route_tracking, GoalState::Idle);
    }
}
