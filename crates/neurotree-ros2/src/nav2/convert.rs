//! Between the tree's poses, paths, lists of goals and routes ([`Pose2D`], [`Path`],
//! `Vec<Pose2D>`, [`Route`], in the `map` frame) and their ROS 2 messages: the blackboard holds the same types as in the in-process
//! simulation, and only the leaves that talk ROS 2 see messages.

use neurotree_nav2::robotics::{Path, Pose2D, Route, RouteEdge, RouteNode};

use crate::msg::geometry_msgs::{Point, Pose, PoseStamped, Quaternion};
use crate::msg::std_msgs::Header;
use crate::msg::{nav2_msgs, nav_msgs};

/// The frame every pose of the navigator and the simulator is in.
pub const MAP_FRAME: &str = "map";

fn header() -> Header {
    Header {
        frame_id: MAP_FRAME.to_owned(),
        ..Header::default()
    }
}

/// `pose` as a stamped pose in the map frame (stamp zero: "the latest").
pub fn pose_stamped(pose: Pose2D) -> PoseStamped {
    PoseStamped {
        header: header(),
        pose: Pose {
            position: Point {
                x: pose.x,
                y: pose.y,
                z: 0.0,
            },
            orientation: Quaternion::from_yaw(pose.theta),
        },
    }
}

/// The plane pose of `pose`: x, y and the yaw.
pub fn pose_2d(pose: &PoseStamped) -> Pose2D {
    let p = &pose.pose;
    Pose2D::new(p.position.x, p.position.y, p.orientation.yaw())
}

/// `path` as a `nav_msgs/Path` in the map frame.
pub fn path_msg(path: &Path) -> nav_msgs::Path {
    nav_msgs::Path {
        header: header(),
        poses: path.poses.iter().copied().map(pose_stamped).collect(),
    }
}

/// The plane path of `path`.
pub fn path_2d(path: &nav_msgs::Path) -> Path {
    Path::new(path.poses.iter().map(pose_2d).collect())
}

/// Metres left along `path` for a robot at `robot`: to the nearest pose, then along the
/// rest; the straight line to `goal` when there is no path.
pub fn distance_remaining(path: Option<&Path>, robot: Pose2D, goal: Pose2D) -> f64 {
    let Some((path, from)) = path.and_then(|p| p.closest_index(&robot).map(|i| (p, i))) else {
        return robot.distance(&goal);
    };
    let rest: f64 = path.poses[from..]
        .windows(2)
        .map(|w| w[0].distance(&w[1]))
        .sum();
    robot.distance(&path.poses[from]) + rest
}

/// `goals` as a `nav_msgs/Goals` in the map frame.
pub fn goals_msg(goals: &[Pose2D]) -> nav_msgs::Goals {
    nav_msgs::Goals {
        header: header(),
        goals: goals.iter().copied().map(pose_stamped).collect(),
    }
}

/// The plane poses of `goals`.
pub fn goals_2d(goals: &nav_msgs::Goals) -> Vec<Pose2D> {
    goals.goals.iter().map(pose_2d).collect()
}

fn point(x: f64, y: f64) -> Point {
    Point { x, y, z: 0.0 }
}

/// `route` as a `nav2_msgs/Route`: each edge by the positions of its ends.
pub fn route_msg(route: &Route) -> nav2_msgs::Route {
    let at = |id: u16| {
        route
            .nodes
            .iter()
            .find(|n| n.id == id)
            .map_or(Point::default(), |n| point(n.x, n.y))
    };
    nav2_msgs::Route {
        header: header(),
        route_cost: route.cost as f32,
        nodes: route
            .nodes
            .iter()
            .map(|n| nav2_msgs::RouteNode {
                nodeid: n.id,
                position: point(n.x, n.y),
            })
            .collect(),
        edges: route
            .edges
            .iter()
            .map(|e| nav2_msgs::RouteEdge {
                edgeid: e.id,
                start: at(e.start),
                end: at(e.end),
            })
            .collect(),
    }
}

/// The route of `route`: the message names an edge's ends by position, so each end is
/// the route's node nearest to it.
pub fn route_2d(route: &nav2_msgs::Route) -> Route {
    let nodes: Vec<RouteNode> = route
        .nodes
        .iter()
        .map(|n| RouteNode::new(n.nodeid, n.position.x, n.position.y))
        .collect();
    let nearest = |p: &Point| {
        nodes
            .iter()
            .min_by(|a, b| {
                let d = |n: &RouteNode| (n.x - p.x).hypot(n.y - p.y);
                d(a).total_cmp(&d(b))
            })
            .map_or(0, |n| n.id)
    };
    Route {
        edges: route
            .edges
            .iter()
            .map(|e| RouteEdge {
                id: e.edgeid,
                start: nearest(&e.start),
                end: nearest(&e.end),
            })
            .collect(),
        nodes,
        cost: f64::from(route.route_cost),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poses_and_paths_go_through_their_messages_unchanged() {
        let pose = Pose2D::new(1.5, -2.0, 0.75);
        let back = pose_2d(&pose_stamped(pose));
        assert!((back.x - 1.5).abs() < 1e-12 && (back.y + 2.0).abs() < 1e-12);
        assert!((back.theta - 0.75).abs() < 1e-12);
        let path = Path::new(vec![Pose2D::new(0.0, 0.0, 0.0), Pose2D::new(1.0, 0.0, 0.0)]);
        let msg = path_msg(&path);
        assert_eq!(msg.header.frame_id, "map");
        assert_eq!(path_2d(&msg).len(), 2);
    }

    #[test]
    fn routes_and_goals_go_through_their_messages_unchanged() {
        let route = Route {
            nodes: vec![RouteNode::new(3, 0.5, 0.5), RouteNode::new(8, 4.5, 0.5)],
            edges: vec![RouteEdge {
                id: 5,
                start: 3,
                end: 8,
            }],
            cost: 4.0,
        };
        let msg = route_msg(&route);
        assert_eq!(msg.edges[0].end.x, 4.5);
        assert_eq!(route_2d(&msg), route);
        let goals = vec![Pose2D::new(1.0, 2.0, 0.0), Pose2D::new(3.0, 4.0, 0.0)];
        let back = goals_2d(&goals_msg(&goals));
        assert_eq!(back.len(), 2);
        assert!(back[1].distance(&goals[1]) < 1e-12);
    }

    #[test]
    fn the_distance_remaining_follows_the_path_from_the_nearest_pose() {
        let path = Path::new(vec![
            Pose2D::new(0.0, 0.0, 0.0),
            Pose2D::new(1.0, 0.0, 0.0),
            Pose2D::new(1.0, 2.0, 0.0),
        ]);
        let goal = Pose2D::new(1.0, 2.0, 0.0);
        let d = distance_remaining(Some(&path), Pose2D::new(0.9, 0.0, 0.0), goal);
        assert!((d - 2.1).abs() < 1e-12, "{d}");
        let straight = distance_remaining(None, Pose2D::new(1.0, 0.0, 0.0), goal);
        assert!((straight - 2.0).abs() < 1e-12);
    }
}
