//! A route on a route graph, as Nav2's route server returns it (`nav2_msgs/msg/Route`): the
//! graph's nodes passed, in order, and the edges between them.

use neurotree_core::FromPortStr;

use super::Pose2D;

/// A node of a route graph: its id and its position, in metres.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RouteNode {
    /// The node's id in its graph.
    pub id: u16,
    /// Metres along x.
    pub x: f64,
    /// Metres along y.
    pub y: f64,
}

impl RouteNode {
    /// Node `id` at `(x, y)`.
    pub const fn new(id: u16, x: f64, y: f64) -> Self {
        Self { id, x, y }
    }

    /// The node's position as a pose facing +x (Nav2's route nodes have no heading).
    pub fn pose(&self) -> Pose2D {
        Pose2D::new(self.x, self.y, 0.0)
    }
}

/// A directed edge of a route graph, from node `start` to node `end` (ids).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct RouteEdge {
    /// The edge's id in its graph.
    pub id: u16,
    /// The id of the node it leaves.
    pub start: u16,
    /// The id of the node it reaches.
    pub end: u16,
}

/// A route: the nodes from the start node to the goal node, the edges taken between them,
/// and the route's cost (its length in metres, as Nav2's default edge scorer counts it).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Route {
    /// The nodes, start first.
    pub nodes: Vec<RouteNode>,
    /// The edges, one fewer than the nodes.
    pub edges: Vec<RouteEdge>,
    /// The route's cost.
    pub cost: f64,
}

impl Route {
    /// `true` without nodes: what Nav2's nodes write after a failure.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }
}

/// A route has no text form but the empty one: it is written by ComputeRoute and read back
/// from the blackboard, never typed into a file.
impl FromPortStr for Route {
    fn from_port_str(text: &str) -> Result<Self, ()> {
        if text.trim().is_empty() {
            Ok(Route::default())
        } else {
            Err(())
        }
    }
}
