//! [`SimServers`]: the grid world served as the Nav2 servers a navigator calls.
//!
//! | server | name | what it does on the world |
//! |---|---|---|
//! | planner | actions `compute_path_to_pose`, `compute_path_through_poses` | A* on the global costmap (the sim's ComputePathToPose, ComputePathThroughPoses) |
//! | smoother | action `smooth_path` | the sim's SmoothPath |
//! | controller | action `follow_path` | follows the path, fails when blocked (the sim's FollowPath) |
//! | behaviors | actions `spin`, `backup`, `drive_on_heading`, `wait` | turn, drive back, drive on, stand still (the sim's Spin, BackUp, DriveOnHeading, Wait) |
//! | costmaps | services `global_costmap/clear_entirely_global_costmap`, `local_costmap/clear_entirely_local_costmap` | forget the sensed obstacles |
//! | costmaps | services `clear_around_`, `clear_except_` and `clear_around_pose_` of each costmap (`local_costmap/clear_around_local_costmap`, ...) | forget them in, or outside, a square (the sim's ClearCostmapAroundRobot, ClearCostmapExceptRegion, ClearCostmapAroundPose) |
//! | costmaps | services `global_costmap/get_cost_global_costmap`, `local_costmap/get_cost_local_costmap` (`nav2_msgs/srv/GetCosts`) | the cost at each pose: 254 on a wall or sensed obstacle, 0 on a free cell; off the map 255 and `success` false (the sim's CheckPoseOccupancy, RemoveInCollisionGoals) |
//! | route server | actions `compute_route`, `compute_and_track_route` | the cheapest route on the world's [`RouteGraph`](neurotree_sim::nav2::RouteGraph), and the robot tracked along it with feedback (the sim's ComputeRoute, ComputeAndTrackRoute) |
//! | docking server | actions `dock_robot`, `undock_robot` | dock at one of the world's [`Dock`](neurotree_sim::nav2::Dock)s, back off it (the sim's DockRobot, UndockRobot) |
//! | navigator | action `navigate_through_poses` | plan and follow through the poses (the sim's NavigateThroughPoses) |
//! | following server | action `follow_object` | follow the world's object ([`Nav2Sim::set_object`]), a metre behind (the sim's FollowObject); a pose on [`OBJECT_POSE_TOPIC`] moves the object (a goal naming another `pose_topic` follows it all the same) |
//! | behaviors | action `assisted_teleop` | no one drives: the robot stands still until the time allowance runs out (TIMEOUT 731) or a message on [`PREEMPT_TELEOP_TOPIC`] ends it with success |
//! | collision monitor | service `collision_monitor/toggle` (`nav2_msgs/srv/Toggle`) | turns the world's collision monitor on or off |
//! | localization | service `reinitialize_global_localization` (`std_srvs/srv/Empty`) | counted: the simulated robot knows where it is |
//! | pose | topic [`ROBOT_POSE_TOPIC`] | the robot's pose, each step |
//! | odometry | topic [`ODOM_TOPIC`](super::ODOM_TOPIC) | `nav_msgs/Odometry`: the robot's pose, its speed and turn rate over the last step, stamped with the simulated time, each step |
//! | battery | topic [`BATTERY_TOPIC`](super::BATTERY_TOPIC) | the world's battery (`sensor_msgs/BatteryState`: percentage, charging on the charger), each step |
//!
//! Each goal runs the in-process leaf of `neurotree_sim::nav2` of the same name, alone in a
//! tree of its own, over the one [`Nav2Sim`]: the servers behave as the simulated leaves do
//! (the same error codes, tolerances and time allowances). The world steps on its own
//! clock: every `period / time_scale` of wall time, it moves on by one period
//! ([`Nav2Params::period`](neurotree_sim::nav2::Nav2Params)), from the first goal on
//! ([`SimOptions::start_on_first_goal`]). The controller, the behaviors, the docking
//! server, the navigator through poses and the following server command the one robot: a
//! goal for one of them aborts the goal another one is running. A cancel request halts the goal's tree, which stops the robot.

mod actions;
mod clearings;
mod layouts;
mod roster;
mod served;
mod services;
mod stats;
mod teleop;
mod topics;
mod view;

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use neurotree_nav2::Nav2Release;
use neurotree_sim::nav2::{register_nav2_leaves, Nav2Sim};
use neurotree_sim::CostmapLayer;
use neurotree_toolkit::Registry;
use ros2_client::service::Server;
use ros2_client::{Publisher, Subscription};

use self::clearings::ServeClearings;
use self::roster::{clearing_servers, motion_servers, planning_servers};
use self::served::Serving;
use self::services::{serve_costs, serve_switches};
use self::topics::{battery_state, odometry};
use super::convert::{pose_2d, pose_stamped};
use super::navigator::{NavigatorError, ROBOT_POSE_TOPIC};
use super::GET_COST_GLOBAL_COSTMAP;
use crate::msg::geometry_msgs::PoseStamped;
use crate::msg::nav2_msgs::{
    GetCosts, GetCostsRequest, GetCostsResponse, Toggle, ToggleRequest, ToggleResponse,
};
use crate::msg::nav_msgs::Odometry;
use crate::msg::sensor_msgs::BatteryState;
use crate::msg::std_srvs::{self, EmptyRequest, EmptyResponse};
use crate::{Ros2Error, RosNode};

pub use self::stats::{ServerCounts, SimStats, SimStatsHandle};
pub use self::teleop::PREEMPT_TELEOP_TOPIC;

/// The global costmap's clearing service.
pub const CLEAR_GLOBAL_COSTMAP: &str = "global_costmap/clear_entirely_global_costmap";
/// The local costmap's clearing service.
pub const CLEAR_LOCAL_COSTMAP: &str = "local_costmap/clear_entirely_local_costmap";
/// The local costmap's cost service (the global one's is
/// [`GET_COST_GLOBAL_COSTMAP`](super::GET_COST_GLOBAL_COSTMAP)).
pub const GET_COST_LOCAL_COSTMAP: &str = "local_costmap/get_cost_local_costmap";

/// Where the object FollowObject follows is published (FollowObject's default
/// `pose_topic`): each pose moves the world's object there.
pub const OBJECT_POSE_TOPIC: &str = "dynamic_pose";

/// How the servers run.
#[derive(Clone, Copy, Debug)]
pub struct SimOptions {
    /// Simulated seconds per wall second: 2.0 runs the world twice as fast as real time.
    pub time_scale: f64,
    /// Hold the world's clock until the first goal arrives, so that its timed obstacles
    /// are timed from the start of the navigation, however long the navigator took to
    /// come up.
    pub start_on_first_goal: bool,
    /// The Nav2 release whose goal and clearing layouts the servers read (see
    /// [`register_nav2_ros_leaves_for`](super::register_nav2_ros_leaves_for)).
    pub release: Nav2Release,
}

impl Default for SimOptions {
    /// Real time, from the first goal, Nav2 main's goals.
    fn default() -> Self {
        Self {
            time_scale: 1.0,
            start_on_first_goal: true,
            release: Nav2Release::default(),
        }
    }
}

/// The grid world as Nav2's servers; see the [module](crate::nav2).
pub struct SimServers {
    sim: Nav2Sim,
    /// The planner, the smoother and the route server: they plan, and move nothing.
    planning: Vec<Box<dyn Serving>>,
    /// The controller, the behaviors, the docking server, the navigator through poses,
    /// the following server and assisted teleoperation: the servers that move the robot.
    motions: Vec<Box<dyn Serving>>,
    /// Both costmaps' clearing services.
    clearings: Vec<Box<dyn ServeClearings>>,
    costs: [(CostmapLayer, Server<GetCostsRequest, GetCostsResponse>); 2],
    toggle: Server<ToggleRequest, ToggleResponse>,
    relocalize: Server<EmptyRequest, EmptyResponse>,
    poses: Publisher<PoseStamped>,
    battery: Publisher<BatteryState>,
    odometry: Publisher<Odometry>,
    object: Subscription<PoseStamped>,
    stats: SimStatsHandle,
    wall_period: Duration,
    clock_running: bool,
}

impl SimServers {
    /// Serves `sim` on `ros`.
    pub fn new(ros: &RosNode, sim: Nav2Sim, options: SimOptions) -> Result<Self, NavigatorError> {
        let mut registry = Registry::<Nav2Sim>::new();
        register_nav2_leaves(&mut registry)?;
        let scale = if options.time_scale.is_finite() && options.time_scale > 0.0 {
            options.time_scale
        } else {
            1.0
        };
        let wall_period = sim.params.period.div_f64(scale);
        let planning = planning_servers(ros, &registry, options.release)?;
        let motions = motion_servers(ros, &registry, options.release)?;
        let clearings = clearing_servers(ros, options.release)?;
        let stats = SimStatsHandle::default();
        stats.lock().collision_monitor = sim.collision_monitor();
        let servers = Self {
            planning,
            motions,
            clearings,
            costs: [
                (
                    CostmapLayer::Global,
                    ros.service_server::<GetCosts>(GET_COST_GLOBAL_COSTMAP)?,
                ),
                (
                    CostmapLayer::Local,
                    ros.service_server::<GetCosts>(GET_COST_LOCAL_COSTMAP)?,
                ),
            ],
            toggle: ros.service_server::<Toggle>(super::TOGGLE_COLLISION_MONITOR)?,
            relocalize: ros
                .service_server::<std_srvs::Empty>(super::REINITIALIZE_GLOBAL_LOCALIZATION)?,
            poses: ros.publisher(ROBOT_POSE_TOPIC)?,
            battery: ros.publisher(super::BATTERY_TOPIC)?,
            odometry: ros.publisher(super::ODOM_TOPIC)?,
            object: ros.subscription(OBJECT_POSE_TOPIC)?,
            stats,
            wall_period,
            clock_running: !options.start_on_first_goal,
            sim,
        };
        servers.record();
        Ok(servers)
    }

    /// The counts, shared: read them while [`run`](Self::run) goes on in another thread.
    pub fn stats(&self) -> SimStatsHandle {
        self.stats.clone()
    }

    /// The simulation.
    pub fn sim(&self) -> &Nav2Sim {
        &self.sim
    }

    /// Wall time between steps.
    pub fn wall_period(&self) -> Duration {
        self.wall_period
    }

    /// One step: answers the requests, ticks the running goals, steps the world and
    /// publishes the robot's pose.
    pub fn spin_once(&mut self) -> Result<(), Ros2Error> {
        let sim = &mut self.sim;
        let stats = &self.stats;
        let mut seen = None;
        // A pose lost is replaced by the next one the detector sends.
        while let Ok(Some((pose, _))) = self.object.take() {
            seen = Some(pose_2d(&pose));
        }
        if seen.is_some() {
            sim.set_object(seen);
        }
        let mut planned = false;
        for server in &mut self.planning {
            planned |= server.poll(sim, stats)?;
        }
        // The servers that move the robot share it: the newest goal has it.
        let mut moved = Vec::with_capacity(self.motions.len());
        for motion in &mut self.motions {
            moved.push(motion.poll(sim, stats)?);
        }
        self.clock_running |= planned || moved.contains(&true);
        if let Some(newest) = moved.iter().rposition(|m| *m) {
            for (i, motion) in self.motions.iter_mut().enumerate() {
                if i != newest && motion.is_running() {
                    motion.preempt(sim, stats);
                }
            }
        }
        for clearings in &self.clearings {
            clearings.serve(sim, stats)?;
        }
        serve_costs(&self.costs, sim, stats)?;
        serve_switches(&self.toggle, &self.relocalize, sim, stats)?;
        for server in &mut self.planning {
            server.tick(sim, stats);
        }
        for motion in &mut self.motions {
            motion.tick(sim, stats);
        }
        if self.clock_running {
            sim.step();
        }
        // Best effort: the next step publishes again.
        let _ = self.poses.publish(pose_stamped(sim.world.robot()));
        let _ = self.battery.publish(battery_state(sim));
        let _ = self.odometry.publish(odometry(sim));
        self.record();
        Ok(())
    }

    /// Calls [`spin_once`](Self::spin_once) every wall period until `stop` is raised.
    pub fn run(&mut self, stop: &AtomicBool) -> Result<(), Ros2Error> {
        let mut next = Instant::now();
        while !stop.load(Ordering::SeqCst) {
            self.spin_once()?;
            next += self.wall_period;
            let now = Instant::now();
            if next > now {
                std::thread::sleep(next - now);
            } else {
                next = now;
            }
        }
        Ok(())
    }

    fn record(&self) {
        let mut stats = self.stats.lock();
        stats.robot = self.sim.world.robot();
        stats.time = self.sim.world.now();
        stats.distance = self.sim.world.distance_travelled();
        stats.steps += 1;
        stats.global_obstacles = self
            .sim
            .world
            .costmap(CostmapLayer::Global)
            .marked()
            .count();
        stats.local_obstacles = self.sim.world.costmap(CostmapLayer::Local).marked().count();
    }
}
