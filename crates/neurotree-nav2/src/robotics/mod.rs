//! Robotics building blocks: poses, sensor nodes and navigation.
//!
//! - [`sensor`]: the [`SensorReader`] trait and the sensor node (read, check quality,
//!   publish on the blackboard);
//! - [`navigation`]: the [`MotionPlanner`] trait and the navigation node (plan, follow,
//!   replan when blocked, stop when halted), with [`Path`] and [`Obstacle`];
//! - [`route`]: a [`Route`] on a route graph, as Nav2's route server gives it;
//! - [`TrackingFeedback`]: how the robot tracks its path, as Nav2's controller reports it.
//!
//! Everything here is plain data and traits, so the same nodes drive a real robot or the
//! simulated one of `neurotree::sim`. Nodes reach the robot through the user's context:
//! each takes an accessor that finds its sensor or planner in it. They are added to a tree
//! with the [`RoboticsBuilder`] methods, or registered for XML with [`register_sensor`] and
//! [`register_navigation`].

pub mod navigation;
pub mod route;
pub mod sensor;
mod tracking;

use core::fmt;

use neurotree_core::{Builder, FromPortStr, NodeKind, Port};

pub use navigation::{
    register_navigation, MotionPlanner, NavigationError, NavigationNode, Obstacle, Path, Progress,
};
pub use route::{Route, RouteEdge, RouteNode};
pub use sensor::{register_sensor, SensorData, SensorError, SensorNode, SensorReader, SensorValue};
pub use tracking::TrackingFeedback;

/// Adds the robotics nodes to a [`Builder`], with their ports bound.
///
/// Further ports (a navigation node's `obstacles`, `current_pose` or `path`) can be bound with
/// [`Builder::ports`] right after.
pub trait RoboticsBuilder<C>: Sized {
    /// A [sensor node](sensor) that writes each reading of quality `min_quality` or better to
    /// the entry `key`.
    fn sensor<F>(self, name: &str, key: &str, min_quality: f64, access: F) -> Self
    where
        F: Fn(&mut C) -> &mut dyn SensorReader,
        F: Send + Sync + 'static;

    /// A [navigation node](navigation) that drives to the pose in the entry `goal_key` and
    /// succeeds within `tolerance` metres of it.
    fn navigate<F>(self, name: &str, goal_key: &str, tolerance: f64, access: F) -> Self
    where
        F: Fn(&mut C) -> &mut dyn MotionPlanner,
        F: Send + Sync + 'static;
}

impl<C: 'static> RoboticsBuilder<C> for Builder<C> {
    fn sensor<F>(self, name: &str, key: &str, min_quality: f64, access: F) -> Self
    where
        F: Fn(&mut C) -> &mut dyn SensorReader,
        F: Send + Sync + 'static,
    {
        let node = SensorNode::new(access);
        self.leaf(NodeKind::Action(std::sync::Arc::new(node)), name)
            .ports([
                Port::entry("output", key),
                Port::literal("min_quality", &min_quality.to_string()),
            ])
    }

    fn navigate<F>(self, name: &str, goal_key: &str, tolerance: f64, access: F) -> Self
    where
        F: Fn(&mut C) -> &mut dyn MotionPlanner,
        F: Send + Sync + 'static,
    {
        self.stateful(name, NavigationNode::factory(access)).ports([
            Port::entry("goal", goal_key),
            Port::literal("goal_tolerance", &tolerance.to_string()),
        ])
    }
}

/// A position and heading in the plane: metres and radians, as Nav2's 2D poses are.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Pose2D {
    /// Metres along x.
    pub x: f64,
    /// Metres along y.
    pub y: f64,
    /// Heading in radians, counter-clockwise from +x.
    pub theta: f64,
}

impl Pose2D {
    /// A pose at `(x, y)` facing `theta`.
    pub const fn new(x: f64, y: f64, theta: f64) -> Self {
        Pose2D { x, y, theta }
    }

    /// Straight-line distance between the two positions, ignoring heading.
    pub fn distance(&self, other: &Pose2D) -> f64 {
        (self.x - other.x).hypot(self.y - other.y)
    }
}

/// Port text is `x;y` or `x;y;theta`, the `;`-separated form BT.CPP uses for compound values.
impl FromPortStr for Pose2D {
    fn from_port_str(text: &str) -> Result<Self, ()> {
        let mut parts = text.split(';').map(|p| p.trim().parse::<f64>());
        let x = parts.next().ok_or(())?.map_err(|_| ())?;
        let y = parts.next().ok_or(())?.map_err(|_| ())?;
        let theta = match parts.next() {
            Some(t) => t.map_err(|_| ())?,
            None => 0.0,
        };
        if parts.next().is_some() {
            return Err(());
        }
        Ok(Pose2D { x, y, theta })
    }
}

/// Writes the form [`FromPortStr`] reads back.
impl fmt::Display for Pose2D {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{};{};{}", self.x, self.y, self.theta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pose_reads_two_or_three_fields_and_round_trips() {
        assert_eq!(
            Pose2D::from_port_str("1.5; -2"),
            Ok(Pose2D::new(1.5, -2.0, 0.0))
        );
        let p = Pose2D::new(3.0, 4.0, 0.5);
        assert_eq!(Pose2D::from_port_str(&p.to_string()), Ok(p));
        assert_eq!(Pose2D::from_port_str("1"), Err(()));
        assert_eq!(Pose2D::from_port_str("1;2;3;4"), Err(()));
        assert_eq!(Pose2D::from_port_str("a;2"), Err(()));
        assert_eq!(Pose2D::new(0.0, 0.0, 0.0).distance(&p), 5.0);
    }
}
