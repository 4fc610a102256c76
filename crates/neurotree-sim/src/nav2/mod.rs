//! ROS 2 Nav2's leaf nodes on the grid world, so that Nav2's navigator files run unchanged
//! on a simulated robot.
//!
//! Nav2's behavior trees (`navigate_to_pose_w_replanning_and_recovery.xml` and its kin) are
//! made of the [control nodes](neurotree_nav2) and of leaves that call Nav2's servers: the
//! planner, the controller, the costmaps, the recovery behaviors. Here each of those leaves
//! drives a [`GridWorld`] instead, with the ports `nav2_tree_nodes.xml` declares (names,
//! directions, defaults), so a Nav2 file loads as it is and also passes a check against
//! Nav2's own model. [`register_nav2_leaves`] adds them to a [`Registry`] whose context
//! gives access to a [`Nav2Sim`] (see [`Nav2Context`]).
//!
//! | node | in short |
//! |---|---|
//! | ComputePathToPose | the planner: A* on the global costmap |
//! | ComputePathThroughPoses | the planner, through several goals |
//! | RemovePassedGoals | forget the goals passed |
//! | FollowPath | the controller: follow the current path |
//! | CancelControl | stop following it |
//! | PlannerSelector, ControllerSelector, GoalCheckerSelector, ProgressCheckerSelector, PathHandlerSelector, SmootherSelector | pick the default plugin |
//! | IsGoalNearby | is the end of the path near? |
//! | TruncatePathLocal | the part of the path around the robot |
//! | ValidatePath | is the path still free? |
//! | TruncatePath | the path short of its last metres |
//! | IsWithinPathTrackingBounds | is the robot on its path? |
//! | PathExpiringTimer | has the path stayed the same for a while? |
//! | ClearEntireCostmap, ClearCostmapAroundRobot, ClearCostmapAroundPose, ClearCostmapExceptRegion | forget sensed obstacles, all or in (or out of) a square |
//! | WouldAPlannerRecoveryHelp, WouldAControllerRecoveryHelp, WouldARouteRecoveryHelp, WouldASmootherRecoveryHelp, AreErrorCodesPresent | is the error one of these codes? |
//! | Spin, Wait, BackUp, DriveOnHeading | the behaviors, as motions of the world |
//! | CancelSpin, CancelWait, CancelBackUp, CancelDriveOnHeading, CancelAssistedTeleop, CancelComputeAndTrackRoute, CancelFollowObject | cancel what a server does |
//! | GetCurrentPose, GetPoseFromPath, ConcatenatePaths, ArePosesNear, GoalReached | poses and paths |
//! | AppendGoalPoseToGoals, GetNextFewGoals | lists of goals |
//! | CheckPoseOccupancy, RemoveInCollisionGoals | the global costmap's cost at poses |
//! | SmoothPath | the smoother |
//! | IsStuck, DistanceTraveled, TimeExpired, CheckStopStatus, TransformAvailable, InitialPoseReceived | what the robot's motion says |
//! | IsBatteryLow, IsBatteryCharging | the world's battery and charger |
//! | ToggleCollisionMonitor, ReinitializeGlobalLocalization | switches of the system |
//! | DockRobot, UndockRobot | the docking server, on the [`Dock`]s given |
//! | NavigateToPose, NavigateThroughPoses | another navigator: plan, follow, replan when blocked |
//! | ComputeRoute, ComputeAndTrackRoute, ExtractRouteNodesAsGoals | the route server, on the [`RouteGraph`] given |
//! | FollowObject | follow the moving object ([`Nav2Sim::set_object`]) |
//!
//! Each node's ports, defaults, outcomes and error codes are told in its own module:
//! [`planner`], [`controller`], [`selectors`], [`path_checks`], [`costmaps`],
//! [`recovery_help`], [`tracking`], [`through_poses`], [`behaviors`], [`cancels`],
//! [`poses`], [`goal_lists`], [`occupancy`], [`smoother`], [`odometry`], [`battery`],
//! [`system`], [`docking`], [`navigate`], [`route`] and [`follow_object`]. Nav2's
//! GoalUpdated and GlobalUpdatedGoal, which read only the blackboard, are in
//! [`neurotree_nav2`] with the controls.
//!
//! # Not simulated
//!
//! One node of Nav2 has no meaning in the grid world: **AssistedTeleop**, which lets a
//! person drive the robot while it keeps clear of obstacles; the world has no person to
//! drive. [`NOT_SIMULATED`] lists it with the reason, and a tree that uses it does not load
//! in `neurotree demo` (the error names the node and says why).
//!
//! # The robot's state
//!
//! Nav2's DistanceController and SpeedController read the robot's pose (TF) and speed
//! (odometry); here they read the blackboard entries `robot_pose` and `robot_speed`, which
//! [`Nav2Sim::write_robot_state`] writes before each tick.
//!
//! Ports that only make sense on a ROS system (server names, timeouts, frames, plugin ids,
//! footprints) are declared, so that files using them load, and read nowhere.
//!
//! # Time
//!
//! The leaves command the world's motions and read their outcome; they never move time
//! themselves. Whoever runs the tree ticks it and then steps the world by the tick's
//! period ([`Nav2Sim::step`]), as Nav2's servers run beside the navigator: a motion
//! started in one tick has moved by one period at the next. The world's clock is the
//! tree's clock ([`GridWorld::clock`]), so Nav2's RateController and the behaviors' time
//! allowances run on simulated time, and every run is the same.
//!
//! # Counting
//!
//! [`Nav2Sim::replans`] counts the plans that replaced a different one, and a
//! [`RecoveryCounter`] attached to the tree counts the runs of each recovery branch, for a
//! summary of what the navigator went through. `neurotree demo` puts it all together (its
//! scenario is `neurotree_cli::demo::DemoRun`): a warehouse, the Nav2 navigator, frames, a summary.
//!
//! ```
//! use neurotree::robotics::Pose2D;
//! use neurotree::sim::nav2::{register_nav2_leaves, Nav2Sim};
//! use neurotree::sim::GridWorld;
//! use neurotree::{nav2, Registry, Status, Tree, XmlLoader};
//!
//! let mut registry = Registry::<Nav2Sim>::new();
//! nav2::register_controls(&mut registry).unwrap();
//! register_nav2_leaves(&mut registry).unwrap();
//! let mut loader = XmlLoader::new(&registry);
//! loader.load_str(r#"
//!     <root BTCPP_format="4">
//!       <BehaviorTree ID="Go">
//!         <PipelineSequence>
//!           <RateController hz="1.0">
//!             <ComputePathToPose goal="{goal}" path="{path}"/>
//!           </RateController>
//!           <FollowPath path="{path}"/>
//!         </PipelineSequence>
//!       </BehaviorTree>
//!     </root>"#, "go.xml").unwrap();
//!
//! let mut sim = Nav2Sim::new(GridWorld::parse("R....", 1.0).unwrap());
//! let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), sim.world.clock());
//! tree.blackboard_mut().set("goal", Pose2D::new(4.5, 0.5, 0.0)).unwrap();
//! let mut ticks = 1;
//! while tree.tick_once(&mut sim).unwrap() == Status::Running {
//!     sim.step();
//!     ticks += 1;
//! }
//! // 3.75 m at 1 m/s, in 0.1 s steps, and the tick that sees it within 0.25 m.
//! assert_eq!(ticks, 39);
//! assert!(sim.world.robot().distance(&Pose2D::new(4.5, 0.5, 0.0)) <= 0.25);
//! // Replanned every second from where the robot was: three times.
//! assert_eq!((sim.plans(), sim.replans()), (4, 3));
//! ```

pub mod battery;
pub mod behaviors;
pub mod cancels;
pub mod codes;
pub mod controller;
pub mod costmaps;
pub mod docking;
mod failures;
pub mod follow_object;
pub mod goal_lists;
pub mod navigate;
pub mod occupancy;
pub mod odometry;
pub mod path_checks;
pub mod planner;
mod ports;
pub mod poses;
pub mod recovery_help;
pub mod route;
pub mod selectors;
pub mod smoother;
mod snapshot;
pub mod system;
#[cfg(test)]
mod testing;
pub mod through_poses;
pub mod tracking;

use std::time::Duration;

pub use controller::TrackingFeedback;
pub use docking::Dock;
pub use failures::FailureNotes;
pub use neurotree_nav2::{EventLog, RecoveryCounter};
pub use route::RouteGraph;
pub use snapshot::Nav2SimState;

use super::{GridWorld, MotionStatus};
use neurotree_core::{Blackboard, BlackboardError};
use neurotree_nav2::robotics::Pose2D;
use neurotree_nav2::{ROBOT_POSE, ROBOT_SPEED};
use neurotree_toolkit::{Registry, RegistryError};

/// How the simulated Nav2 servers behave.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nav2Params {
    /// The controller's speed along a path, in metres per second.
    pub speed: f64,
    /// The spin behavior's turn rate, in radians per second.
    pub spin_rate: f64,
    /// How close to a path's end counts as arrived, in metres (the goal checker's
    /// `xy_goal_tolerance`).
    pub goal_tolerance: f64,
    /// Simulated time per tick: how far [`Nav2Sim::step`] moves the world.
    pub period: Duration,
}

impl Default for Nav2Params {
    /// 1 m/s, 1 rad/s, Nav2's goal tolerance of 0.25 m, a tick every 100 ms.
    fn default() -> Self {
        Self {
            speed: 1.0,
            spin_rate: 1.0,
            goal_tolerance: 0.25,
            period: Duration::from_millis(100),
        }
    }
}

/// The context the Nav2 leaves work on: the world, the servers' parameters, what they
/// counted, and (if asked) a log of what they did.
#[derive(Clone, Debug)]
pub struct Nav2Sim {
    /// The simulated robot and its surroundings.
    pub world: GridWorld,
    /// How the simulated servers behave.
    pub params: Nav2Params,
    plans: u32,
    replans: u32,
    /// The robot's speed over the last step, in metres per second.
    speed: f64,
    /// The speed over the step before, for the deceleration IsStuck watches.
    previous_speed: f64,
    /// The robot's turn rate over the last step, in radians per second.
    turn_rate: f64,
    /// The docks the docking server knows ([`Nav2Sim::with_dock`]).
    docks: Vec<Dock>,
    /// The route server's graph ([`Nav2Sim::with_route_graph`]).
    route_graph: Option<RouteGraph>,
    /// Where the object FollowObject follows is ([`Nav2Sim::set_object`]).
    object: Option<Pose2D>,
    /// The goals of the long-running servers a cancel node can cancel.
    pub(super) goals: ServerGoals,
    /// The type of the dock the robot last docked at, until it undocks.
    pub(super) current_dock_type: Option<String>,
    collision_monitor: bool,
    relocalizations: u32,
    log: Option<EventLog>,
}

/// Where the goal of a Nav2 server that a cancel node addresses stands.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) enum GoalState {
    /// No goal under way.
    #[default]
    Idle,
    /// A node's goal is under way.
    Active,
    /// A cancel node cancelled it; its node sees that at its next tick.
    Cancelled,
}

/// The goals of the servers whose work is not a motion of the world: route tracking and
/// following an object.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct ServerGoals {
    pub(super) route_tracking: GoalState,
    pub(super) following: GoalState,
}

impl Nav2Sim {
    /// The servers of Nav2 on `world`, with the default [`Nav2Params`].
    pub fn new(world: GridWorld) -> Self {
        Self {
            world,
            params: Nav2Params::default(),
            plans: 0,
            replans: 0,
            speed: 0.0,
            previous_speed: 0.0,
            turn_rate: 0.0,
            docks: Vec::new(),
            route_graph: None,
            object: None,
            goals: ServerGoals::default(),
            current_dock_type: None,
            collision_monitor: true,
            relocalizations: 0,
            log: None,
        }
    }

    /// With a dock the docking server knows (DockRobot, UndockRobot).
    pub fn with_dock(mut self, dock: Dock) -> Self {
        self.docks.push(dock);
        self
    }

    /// The docks the docking server knows.
    pub fn docks(&self) -> &[Dock] {
        &self.docks
    }

    /// With a route graph for the route server (ComputeRoute, ComputeAndTrackRoute).
    pub fn with_route_graph(mut self, graph: RouteGraph) -> Self {
        self.route_graph = Some(graph);
        self
    }

    /// The route server's graph, if it has one.
    pub fn route_graph(&self) -> Option<&RouteGraph> {
        self.route_graph.as_ref()
    }

    /// Puts the object FollowObject follows at `pose` (`None`: it is not seen). Whoever
    /// runs the world moves it, as a detector would publish its pose on `dynamic_pose`.
    pub fn set_object(&mut self, pose: Option<Pose2D>) {
        self.object = pose;
    }

    /// Where the followed object is, if it is seen.
    pub fn object(&self) -> Option<Pose2D> {
        self.object
    }

    /// Whether the collision monitor is on (ToggleCollisionMonitor switches it; on at the
    /// start).
    pub fn collision_monitor(&self) -> bool {
        self.collision_monitor
    }

    /// Turns the collision monitor on or off, as its `toggle` service does.
    pub fn set_collision_monitor(&mut self, on: bool) {
        self.collision_monitor = on;
    }

    /// How many times ReinitializeGlobalLocalization was called.
    pub fn relocalizations(&self) -> u32 {
        self.relocalizations
    }

    /// Counts a call of the localization's `reinitialize_global_localization`.
    pub fn count_relocalization(&mut self) {
        self.relocalizations += 1;
    }

    /// The robot's turn rate over the last [`step`](Self::step), in radians per second.
    pub fn turn_rate(&self) -> f64 {
        self.turn_rate
    }

    /// The change of speed over the last step, in metres per second squared: negative
    /// when the robot slowed down.
    pub fn acceleration(&self) -> f64 {
        let seconds = self.params.period.as_secs_f64();
        if seconds > 0.0 {
            (self.speed - self.previous_speed) / seconds
        } else {
            0.0
        }
    }

    /// With `params` instead of the defaults.
    pub fn with_params(mut self, params: Nav2Params) -> Self {
        self.params = params;
        self
    }

    /// Writing what the leaves do to `log` (one line per plan, clearing or behavior
    /// done; their failures are told by a [`FailureNotes`] on the tree), for a live view. Off by default, so that a long run does not grow a log
    /// nobody reads.
    pub fn with_log(mut self, log: EventLog) -> Self {
        self.log = Some(log);
        self
    }

    /// Moves the world on by one period ([`Nav2Params::period`]); see [`GridWorld::step`].
    pub fn step(&mut self) -> MotionStatus {
        let before = self.world.distance_travelled();
        let heading = self.world.robot().theta;
        let status = self.world.step(self.params.period);
        let seconds = self.params.period.as_secs_f64();
        self.previous_speed = self.speed;
        let turned = angle_between(heading, self.world.robot().theta);
        (self.speed, self.turn_rate) = if seconds > 0.0 {
            (
                (self.world.distance_travelled() - before) / seconds,
                turned / seconds,
            )
        } else {
            (0.0, 0.0)
        };
        status
    }

    /// The robot's speed over the last [`step`](Self::step), in metres per second: what
    /// Nav2's odometry smoother would report (0 before the first step).
    pub fn robot_speed(&self) -> f64 {
        self.speed
    }

    /// Writes the robot's state where Nav2's controls read it, as TF and odometry give it
    /// to them in Nav2: the pose to `robot_pose` ([`ROBOT_POSE`], read by
    /// DistanceController) and the speed to `robot_speed` ([`ROBOT_SPEED`], read by
    /// SpeedController). Whoever runs the tree calls it before each tick.
    pub fn write_robot_state(&self, blackboard: &mut Blackboard) -> Result<(), BlackboardError> {
        blackboard.set(ROBOT_POSE, self.world.robot())?;
        blackboard.set(ROBOT_SPEED, self.speed)
    }

    /// Paths ComputePathToPose produced.
    pub fn plans(&self) -> u32 {
        self.plans
    }

    /// Paths ComputePathToPose produced that replaced a different path: every plan after
    /// the first one, except those identical to the path they replaced.
    pub fn replans(&self) -> u32 {
        self.replans
    }

    /// Records a plan; `replaced` says it differs from the path it replaced.
    pub(super) fn count_plan(&mut self, replaced: bool) {
        if self.plans > 0 && replaced {
            self.replans += 1;
        }
        self.plans += 1;
    }

    /// The log the leaves write to, if it is on: for a [`FailureNotes`] to write to as well.
    pub fn log(&self) -> Option<&EventLog> {
        self.log.as_ref()
    }

    /// Adds a line to the log, if it is on; `line` is only called then.
    pub(super) fn note(&mut self, line: impl FnOnce() -> String) {
        if let Some(log) = &self.log {
            log.push(line());
        }
    }
}

/// The signed smallest turn from heading `from` to heading `to`, in radians.
pub(super) fn angle_between(from: f64, to: f64) -> f64 {
    let d = (to - from).rem_euclid(std::f64::consts::TAU);
    if d > std::f64::consts::PI {
        d - std::f64::consts::TAU
    } else {
        d
    }
}

/// Gives the Nav2 leaves their [`Nav2Sim`]: implemented by `Nav2Sim` itself, and by any
/// context that holds one (a game or a test harness with more in it).
pub trait Nav2Context: 'static {
    /// The simulation, to read.
    fn nav2(&self) -> &Nav2Sim;
    /// The simulation, to command.
    fn nav2_mut(&mut self) -> &mut Nav2Sim;
}

impl Nav2Context for Nav2Sim {
    fn nav2(&self) -> &Nav2Sim {
        self
    }
    fn nav2_mut(&mut self) -> &mut Nav2Sim {
        self
    }
}

/// Registers every Nav2 leaf the simulator implements ([`LEAVES`]: all of Nav2's
/// conditions and actions but GoalUpdated and GlobalUpdatedGoal, which
/// [`nav2::register_controls`](neurotree_nav2::register_controls) registers with the controls,
/// and those in [`NOT_SIMULATED`]), under its Nav2 name with the ports of
/// `nav2_tree_nodes.xml`. Fails if one of the names is taken.
pub fn register_nav2_leaves<C: Nav2Context>(
    registry: &mut Registry<C>,
) -> Result<(), RegistryError> {
    neurotree_nav2::register_values(registry);
    planner::register(registry)?;
    controller::register(registry)?;
    selectors::register(registry)?;
    path_checks::register(registry)?;
    costmaps::register(registry)?;
    recovery_help::register(registry)?;
    tracking::register(registry)?;
    through_poses::register(registry)?;
    behaviors::register(registry)?;
    poses::register(registry)?;
    goal_lists::register(registry)?;
    occupancy::register(registry)?;
    smoother::register(registry)?;
    cancels::register(registry)?;
    odometry::register(registry)?;
    battery::register(registry)?;
    system::register(registry)?;
    docking::register(registry)?;
    navigate::register(registry)?;
    route::register(registry)?;
    follow_object::register(registry)
}

/// Registers the Nav2 leaves that call no server in Nav2 either, or only to read what the
/// navigator's own view answers (the map, the robot's pose, the clock): the six selectors,
/// IsGoalNearby, TruncatePathLocal, ValidatePath, the five error-code conditions
/// (WouldAPlannerRecoveryHelp, …, AreErrorCodesPresent), AppendGoalPoseToGoals,
/// GetNextFewGoals, GetCurrentPose, GetPoseFromPath, ConcatenatePaths, ArePosesNear,
/// GoalReached, TruncatePath, IsWithinPathTrackingBounds, PathExpiringTimer,
/// RemovePassedGoals, ExtractRouteNodesAsGoals, DistanceTraveled, TimeExpired,
/// TransformAvailable and InitialPoseReceived. A navigator
/// whose planner, controller, behaviors and costmaps are served elsewhere (over ROS 2)
/// registers these and its own clients for the rest. Fails if one of the names is taken.
pub fn register_nav2_checks<C: Nav2Context>(
    registry: &mut Registry<C>,
) -> Result<(), RegistryError> {
    neurotree_nav2::register_values(registry);
    selectors::register(registry)?;
    path_checks::register(registry)?;
    recovery_help::register(registry)?;
    goal_lists::register(registry)?;
    poses::register(registry)?;
    tracking::register(registry)?;
    through_poses::register_remove_passed_goals(registry)?;
    route::register_extract_route_nodes(registry)?;
    odometry::register_pose_and_clock(registry)
}

/// The names [`register_nav2_leaves`] registers.
pub const LEAVES: [&str; 65] = [
    "ComputePathToPose",
    "FollowPath",
    "CancelControl",
    "ProgressCheckerSelector",
    "GoalCheckerSelector",
    "PathHandlerSelector",
    "ControllerSelector",
    "PlannerSelector",
    "SmootherSelector",
    "IsGoalNearby",
    "TruncatePathLocal",
    "ValidatePath",
    "ClearEntireCostmap",
    "ClearCostmapAroundRobot",
    "ClearCostmapAroundPose",
    "ClearCostmapExceptRegion",
    "WouldAPlannerRecoveryHelp",
    "WouldAControllerRecoveryHelp",
    "WouldARouteRecoveryHelp",
    "WouldASmootherRecoveryHelp",
    "AreErrorCodesPresent",
    "TruncatePath",
    "IsWithinPathTrackingBounds",
    "PathExpiringTimer",
    "ComputePathThroughPoses",
    "RemovePassedGoals",
    "Spin",
    "Wait",
    "BackUp",
    "DriveOnHeading",
    "GetCurrentPose",
    "GetPoseFromPath",
    "ConcatenatePaths",
    "ArePosesNear",
    "GoalReached",
    "AppendGoalPoseToGoals",
    "GetNextFewGoals",
    "CheckPoseOccupancy",
    "RemoveInCollisionGoals",
    "SmoothPath",
    "CancelSpin",
    "CancelBackUp",
    "CancelDriveOnHeading",
    "CancelWait",
    "CancelAssistedTeleop",
    "CancelComputeAndTrackRoute",
    "CancelFollowObject",
    "IsStuck",
    "DistanceTraveled",
    "TimeExpired",
    "CheckStopStatus",
    "TransformAvailable",
    "InitialPoseReceived",
    "IsBatteryLow",
    "IsBatteryCharging",
    "ToggleCollisionMonitor",
    "ReinitializeGlobalLocalization",
    "DockRobot",
    "UndockRobot",
    "NavigateToPose",
    "NavigateThroughPoses",
    "ComputeRoute",
    "ComputeAndTrackRoute",
    "ExtractRouteNodesAsGoals",
    "FollowObject",
];

/// Nav2's nodes that have no meaning in the grid world, with the reason.
pub const NOT_SIMULATED: [(&str, &str); 1] = [(
    "AssistedTeleop",
    "it lets a person drive the robot, and the simulated world has no person to drive",
)];

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_nav2::robotics::Pose2D;

    #[test]
    fn every_leaf_listed_is_registered_and_with_the_controls_and_the_exceptions_makes_nav2s_81() {
        let mut registry = Registry::<Nav2Sim>::new();
        register_nav2_leaves(&mut registry).unwrap();
        let mut names: Vec<&str> = LEAVES.to_vec();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), LEAVES.len());
        for name in LEAVES {
            assert!(registry.get(name).is_some(), "{name}");
        }
        neurotree_nav2::register_controls(&mut registry).unwrap();
        let model = neurotree_nav2::NAV2_TREE_NODES_MODEL;
        let mut nav2: Vec<&str> = model
            .split("ID=\"")
            .skip(1)
            .filter_map(|rest| rest.split('"').next())
            .collect();
        nav2.sort_unstable();
        assert_eq!(nav2.len(), 81);
        let missing: Vec<&str> = nav2
            .into_iter()
            .filter(|name| registry.get(name).is_none())
            .collect();
        assert_eq!(missing, NOT_SIMULATED.map(|(name, _)| name));
    }

    #[test]
    fn the_robot_state_is_written_where_nav2s_controls_read_it() {
        let mut sim = Nav2Sim::new(GridWorld::parse("R....", 1.0).unwrap());
        let mut blackboard = Blackboard::default();
        sim.write_robot_state(&mut blackboard).unwrap();
        assert_eq!(blackboard.get::<f64>(ROBOT_SPEED).unwrap(), 0.0);
        let goal = Pose2D::new(4.5, 0.5, 0.0);
        let path = sim.world.plan(sim.world.robot(), goal).unwrap();
        sim.world.follow(path, 1.0);
        sim.step();
        sim.step();
        sim.write_robot_state(&mut blackboard).unwrap();
        // 1 m/s, in 100 ms steps.
        assert!((blackboard.get::<f64>(ROBOT_SPEED).unwrap() - 1.0).abs() < 1e-9);
        let pose: Pose2D = blackboard.get(ROBOT_POSE).unwrap();
        assert_eq!(pose, sim.world.robot());
        assert!((pose.x - 0.7).abs() < 1e-9, "{pose:?}");
    }
}
