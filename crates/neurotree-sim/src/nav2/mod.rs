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
//! | PlannerSelector | pick the default planner |
//! | ControllerSelector | pick the default controller |
//! | GoalCheckerSelector | pick the default goal checker |
//! | ProgressCheckerSelector | pick the default progress checker |
//! | PathHandlerSelector | pick the default path handler |
//! | IsGoalNearby | is the end of the path near? |
//! | TruncatePathLocal | the part of the path around the robot |
//! | ValidatePath | is the path still free? |
//! | TruncatePath | the path short of its last metres |
//! | IsWithinPathTrackingBounds | is the robot on its path? |
//! | PathExpiringTimer | has the path stayed the same for a while? |
//! | ClearEntireCostmap | forget the sensed obstacles of a costmap |
//! | WouldAPlannerRecoveryHelp | can a recovery fix the planner's error? |
//! | WouldAControllerRecoveryHelp | can a recovery fix the controller's error? |
//! | Spin | turn on the spot |
//! | Wait | stand still |
//! | BackUp | drive backwards |
//! | DriveOnHeading | drive straight on |
//!
//! Each node's ports, defaults, outcomes and error codes are told in its own module:
//! [`planner`], [`controller`], [`selectors`], [`path_checks`], [`costmaps`],
//! [`recovery_help`], [`tracking`] (TruncatePath, IsWithinPathTrackingBounds, PathExpiringTimer), [`through_poses`] (ComputePathThroughPoses, RemovePassedGoals) and [`behaviors`] (Spin, Wait, BackUp, DriveOnHeading).
//!
//! # Not simulated
//!
//! Nav2's other leaves have no implementation here, and a tree that uses one does not load
//! in `neurotree demo` (the error names the node). Some would need what the grid world does
//! not have: a route graph (ComputeRoute, ExtractRouteNodesAsGoals, WouldARouteRecoveryHelp),
//! a docking server (DockRobot, UndockRobot) and the NavigateToPose action of another
//! navigator; others are not written yet, such as the battery checks (IsBatteryLow,
//! IsBatteryCharging), which the world's battery and charger could answer.
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

pub mod behaviors;
pub mod codes;
pub mod controller;
pub mod costmaps;
mod failures;
pub mod path_checks;
pub mod planner;
mod ports;
mod recoveries;
pub mod recovery_help;
pub mod selectors;
#[cfg(test)]
mod testing;
pub mod through_poses;
pub mod tracking;

use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

pub use controller::TrackingFeedback;
pub use failures::FailureNotes;
pub use recoveries::RecoveryCounter;

use super::{GridWorld, MotionStatus};
use neurotree_core::{Blackboard, BlackboardError};
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
#[derive(Debug)]
pub struct Nav2Sim {
    /// The simulated robot and its surroundings.
    pub world: GridWorld,
    /// How the simulated servers behave.
    pub params: Nav2Params,
    plans: u32,
    replans: u32,
    /// The robot's speed over the last step, in metres per second.
    speed: f64,
    log: Option<EventLog>,
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
            log: None,
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
        let status = self.world.step(self.params.period);
        let seconds = self.params.period.as_secs_f64();
        self.speed = if seconds > 0.0 {
            (self.world.distance_travelled() - before) / seconds
        } else {
            0.0
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

/// Lines of what happened, in order, written by the leaves ([`Nav2Sim::with_log`]), by
/// a [`RecoveryCounter`] ([`RecoveryCounter::with_log`]) and by a [`FailureNotes`], and
/// read by a view. Clones share
/// the lines.
#[derive(Clone, Debug, Default)]
pub struct EventLog {
    lines: Arc<Mutex<Vec<String>>>,
}

impl EventLog {
    /// An empty log.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a line.
    pub fn push(&self, line: String) {
        self.lock().push(line);
    }

    /// The lines written since the last call.
    pub fn take(&self) -> Vec<String> {
        std::mem::take(&mut *self.lock())
    }

    fn lock(&self) -> MutexGuard<'_, Vec<String>> {
        // Whole lines only: still readable if a writer panicked.
        self.lines.lock().unwrap_or_else(|e| e.into_inner())
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

/// Registers every Nav2 leaf that `navigate_to_pose_w_replanning_and_recovery.xml` uses, under
/// its Nav2 name with the ports of `nav2_tree_nodes.xml`: ComputePathToPose, FollowPath,
/// CancelControl, ComputePathThroughPoses, RemovePassedGoals, the
/// five selectors, IsGoalNearby, TruncatePathLocal, ValidatePath, ClearEntireCostmap,
/// WouldAPlannerRecoveryHelp, WouldAControllerRecoveryHelp, TruncatePath,
/// IsWithinPathTrackingBounds, PathExpiringTimer, Spin, Wait, BackUp and DriveOnHeading. The control
/// nodes come from [`nav2::register_controls`](neurotree_nav2::register_controls). Fails if one
/// of the names is taken.
pub fn register_nav2_leaves<C: Nav2Context>(
    registry: &mut Registry<C>,
) -> Result<(), RegistryError> {
    planner::register(registry)?;
    controller::register(registry)?;
    selectors::register(registry)?;
    path_checks::register(registry)?;
    costmaps::register(registry)?;
    recovery_help::register(registry)?;
    tracking::register(registry)?;
    through_poses::register(registry)?;
    behaviors::register(registry)
}

/// Registers the Nav2 leaves that call no server in Nav2 either, or only to read what the
/// navigator's own view answers: the five selectors, IsGoalNearby, TruncatePathLocal,
/// ValidatePath, WouldAPlannerRecoveryHelp and WouldAControllerRecoveryHelp. A navigator
/// whose planner, controller, behaviors and costmaps are served elsewhere (over ROS 2)
/// registers these and its own clients for the rest. Fails if one of the names is taken.
pub fn register_nav2_checks<C: Nav2Context>(
    registry: &mut Registry<C>,
) -> Result<(), RegistryError> {
    selectors::register(registry)?;
    path_checks::register(registry)?;
    recovery_help::register(registry)
}

/// The names [`register_nav2_leaves`] registers, in its order.
pub const LEAVES: [&str; 23] = [
    "ComputePathToPose",
    "FollowPath",
    "CancelControl",
    "ComputePathThroughPoses",
    "RemovePassedGoals",
    "ProgressCheckerSelector",
    "GoalCheckerSelector",
    "PathHandlerSelector",
    "ControllerSelector",
    "PlannerSelector",
    "IsGoalNearby",
    "TruncatePathLocal",
    "ValidatePath",
    "ClearEntireCostmap",
    "WouldAPlannerRecoveryHelp",
    "WouldAControllerRecoveryHelp",
    "TruncatePath",
    "IsWithinPathTrackingBounds",
    "PathExpiringTimer",
    "Spin",
    "Wait",
    "BackUp",
    "DriveOnHeading",
];

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_nav2::robotics::Pose2D;

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
