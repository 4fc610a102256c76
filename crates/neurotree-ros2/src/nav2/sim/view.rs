//! The navigator of Nav2's own trees: its checks on a view of the robot on the static map.

use neurotree_nav2::robotics::Pose2D;
use neurotree_sim::nav2::{register_nav2_checks, Nav2Sim};
use neurotree_sim::GridWorld;
use neurotree_toolkit::Registry;

use crate::nav2::NavigatorOptions;
use crate::nav2::{register_navigator_nodes, Navigator, NavigatorContext, NavigatorError};
use crate::RosNode;

/// The view follows the pose topic.
impl NavigatorContext for Nav2Sim {
    fn set_robot_pose(&mut self, pose: Pose2D) {
        // A pose off the map is the pose source's mistake; keep the last good one.
        let _ = self.world.set_robot(pose);
    }
}

impl Navigator<Nav2Sim> {
    /// A navigator on `ros` that runs the main tree of `xml` (named `file` in messages)
    /// with every node type of Nav2 main: [`register_navigator_nodes`] and the simulator's
    /// checks ([`register_nav2_checks`]) on a view of `map` (the static map, whose robot
    /// the pose topic moves).
    pub fn on_map(
        ros: &RosNode,
        xml: &str,
        file: &str,
        map: GridWorld,
        options: &NavigatorOptions,
    ) -> Result<Self, NavigatorError> {
        let mut registry = Registry::<Nav2Sim>::new();
        register_navigator_nodes(&mut registry, ros, options.release)?;
        register_nav2_checks(&mut registry)?;
        let start = map.robot();
        let mut navigator = Self::new(ros, &registry, xml, file, Nav2Sim::new(map), options)?;
        navigator.robot = start;
        Ok(navigator)
    }
}
