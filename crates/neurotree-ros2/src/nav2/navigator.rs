//! [`Navigator`]: Nav2's BT navigator, the `navigate_to_pose` action server that runs a
//! behavior tree for each goal, over the program's own context and registry.
//!
//! | event | what the navigator does |
//! |---|---|
//! | goal | accepts it, writes the pose to the blackboard entry `goal`, resets `compute_path_error_code` and `follow_path_error_code` to 0, and ticks the tree every period |
//! | goal while one runs | the new goal preempts the old one (Aborted); the tree keeps running and sees the new `goal` (GoalUpdated) |
//! | each period | gives the robot's pose from the pose topic to the context ([`NavigatorContext::set_robot_pose`]) and to the blackboard entry `robot_pose` (where Nav2's DistanceController reads it), ticks, publishes feedback: the robot's pose, navigation time, metres left along `{path}`, the recoveries of this goal |
//! | tree Success | the goal Succeeded, error code 0 |
//! | tree Failure, or a tick error | the goal Aborted, error code UNKNOWN (9000) and the reason |
//! | cancel | halts the tree (every Running action node cancels its own goal on its server), the goal Canceled |
//!
//! The tree loads from the program's [`Registry`]: Nav2's control nodes and ROS 2 clients
//! ([`register_navigator_nodes`]) beside the robot's own leaves, which reach the robot
//! through the context `C` the navigator ticks the tree with. Recoveries are counted by a
//! [`RecoveryCounter`]: each run of a recovery branch of the tree. With the `sim` feature,
//! `Navigator::on_map` is the navigator of Nav2's own trees: its checks (selectors,
//! IsGoalNearby, TruncatePathLocal, ValidatePath, WouldA…RecoveryHelp) run on a view of
//! the robot on the static map, placed where the pose topic says (Nav2 reads it from TF,
//! which the bridge does not speak).
//!
//! No tick waits on the network: [`Navigator::spin_once`] polls and ticks once, and
//! [`Navigator::run`] calls it at a fixed rate (10 Hz by default).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use neurotree_nav2::robotics::{Path, Pose2D};
use neurotree_nav2::{Nav2Release, RecoveryCounter, ROBOT_POSE};
use neurotree_toolkit::{LoadError, Registry, RegistryError, Status, Tree, XmlLoader};
use ros2_client::action::GoalStatusEnum;
use ros2_client::Subscription;

use super::convert::{distance_remaining, pose_2d, pose_stamped};
use super::goal_server::{GoalServer, Request};
use super::register_nav2_ros_leaves_for;
use crate::msg::geometry_msgs::PoseStamped;
use crate::msg::nav2_msgs::{NavigateToPose, NavigateToPoseFeedback, NavigateToPoseResult};
use crate::{Ros2Error, RosNode};

/// The topic the robot's pose comes on, in the map frame (the simulator publishes it).
pub const ROBOT_POSE_TOPIC: &str = "robot_pose";

/// The blackboard entries of Nav2's error codes, reset for each goal (Nav2's
/// `error_code_names`).
const ERROR_CODES: [&str; 2] = ["compute_path_error_code", "follow_path_error_code"];

/// Why a navigator could not start or go on.
#[derive(thiserror::Error)]
#[non_exhaustive]
pub enum NavigatorError {
    /// A ROS 2 endpoint could not be made or used.
    #[error(transparent)]
    Ros(#[from] Ros2Error),
    /// The tree did not load; the message reads `file:line:col: error: …`.
    #[error(transparent)]
    Load(#[from] LoadError),
    /// A node type was registered twice: the program's leaf has the name of one of Nav2's.
    #[error("registering the navigator's nodes: {0}")]
    Registry(#[from] RegistryError),
}

neurotree_toolkit::debug_shows_message!(
    enum NavigatorError {
        Ros(source),
        Load(source),
        Registry(source),
    }
);

/// How a [`Navigator`] runs.
#[derive(Clone, Debug)]
pub struct NavigatorOptions {
    /// The action it serves.
    pub action_name: String,
    /// The topic of the robot's pose.
    pub pose_topic: String,
    /// Time between ticks.
    pub period: Duration,
    /// The Nav2 release whose goal layouts the tree's clients send (see
    /// [`register_nav2_ros_leaves_for`](super::register_nav2_ros_leaves_for)).
    pub release: Nav2Release,
}

impl Default for NavigatorOptions {
    /// `navigate_to_pose`, [`ROBOT_POSE_TOPIC`], 10 Hz, Nav2 main's goals.
    fn default() -> Self {
        Self {
            action_name: "navigate_to_pose".to_owned(),
            pose_topic: ROBOT_POSE_TOPIC.to_owned(),
            period: Duration::from_millis(100),
            release: Nav2Release::default(),
        }
    }
}

/// The goal being navigated to.
struct Navigation {
    goal: Pose2D,
    started: Instant,
    recoveries_before: u32,
}

/// How the navigator's goals went, for a summary.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NavigatorStats {
    /// Goals accepted.
    pub goals: u32,
    /// Goals that succeeded.
    pub succeeded: u32,
    /// Goals that aborted.
    pub aborted: u32,
    /// Goals cancelled.
    pub canceled: u32,
}

/// Registers what every Nav2 navigator tree needs beside the robot's own leaves: Nav2's
/// control nodes ([`neurotree_nav2::register_controls`]) and its leaves that call servers,
/// services and topics, as ROS 2 clients on `ros` speaking `release`'s layouts
/// ([`register_nav2_ros_leaves_for`]). Fails if one of the names is taken.
pub fn register_navigator_nodes<C: 'static>(
    registry: &mut Registry<C>,
    ros: &RosNode,
    release: Nav2Release,
) -> Result<(), RegistryError> {
    neurotree_nav2::register_controls(registry)?;
    register_nav2_ros_leaves_for(registry, ros, release)
}

/// What a [`Navigator`] tells the program's context between ticks.
///
/// ```
/// use neurotree_ros2::nav2::NavigatorContext;
/// use neurotree_nav2::robotics::Pose2D;
///
/// /// A robot whose leaves want to know where it is.
/// #[derive(Default)]
/// struct Robot {
///     at: Pose2D,
/// }
///
/// impl NavigatorContext for Robot {
///     fn set_robot_pose(&mut self, pose: Pose2D) {
///         self.at = pose;
///     }
/// }
/// ```
pub trait NavigatorContext: 'static {
    /// The robot's pose in the map frame, as it came on the pose topic, before the tick
    /// that follows. The default ignores it: the navigator also writes it to the
    /// blackboard entry `robot_pose`.
    fn set_robot_pose(&mut self, pose: Pose2D) {
        let _ = pose;
    }
}

/// A context with nothing in it, for trees made of Nav2's nodes alone.
impl NavigatorContext for () {}

/// Nav2's BT navigator over ROS 2, ticking its tree with the program's context `C`; see
/// the [module](crate::nav2).
pub struct Navigator<C: NavigatorContext> {
    goals: GoalServer<NavigateToPose>,
    poses: Subscription<PoseStamped>,
    tree: Tree<C>,
    context: C,
    /// Where the robot is, from the pose topic.
    pub(super) robot: Pose2D,
    recoveries: RecoveryCounter,
    navigation: Option<Navigation>,
    period: Duration,
    stats: NavigatorStats,
}

impl<C: NavigatorContext> Navigator<C> {
    /// A navigator on `ros` that runs the main tree of `xml` (named `file` in messages),
    /// loaded with `registry`, over `context`. The registry usually holds
    /// [`register_navigator_nodes`] and the robot's own leaves.
    pub fn new(
        ros: &RosNode,
        registry: &Registry<C>,
        xml: &str,
        file: &str,
        context: C,
        options: &NavigatorOptions,
    ) -> Result<Self, NavigatorError> {
        let mut loader = XmlLoader::new(registry);
        loader.load_str(xml, file)?;
        let blueprint = Arc::new(loader.build_main()?);
        let recoveries = RecoveryCounter::new(&blueprint);
        // One tree for every goal: its ROS clients are made, and discover their servers,
        // once.
        let mut tree = Tree::new(blueprint);
        tree.set_observer(recoveries.clone());
        Ok(Self {
            goals: GoalServer::new(ros, &options.action_name)?,
            poses: ros.subscription(&options.pose_topic)?,
            tree,
            context,
            robot: Pose2D::default(),
            recoveries,
            navigation: None,
            period: options.period,
            stats: NavigatorStats::default(),
        })
    }

    /// The context the tree runs with.
    pub fn context(&self) -> &C {
        &self.context
    }

    /// The context the tree runs with, to change between ticks.
    pub fn context_mut(&mut self) -> &mut C {
        &mut self.context
    }

    /// Where the robot is: the last pose of the pose topic (the origin before the first,
    /// unless the constructor knew better).
    pub fn robot_pose(&self) -> Pose2D {
        self.robot
    }

    /// Time between ticks.
    pub fn period(&self) -> Duration {
        self.period
    }

    /// How the goals went so far.
    pub fn stats(&self) -> NavigatorStats {
        self.stats
    }

    /// Recovery runs so far, all goals together.
    pub fn recoveries(&self) -> u32 {
        self.recoveries.total()
    }

    /// The navigator's tree, for what watches it from outside (the studio).
    pub fn tree_mut(&mut self) -> &mut Tree<C> {
        &mut self.tree
    }

    /// Adds `observer` beside the navigator's own: it sees every tick from now on.
    pub fn add_observer(&mut self, observer: Box<dyn neurotree_toolkit::Observer>) {
        let mut all: Vec<Box<dyn neurotree_toolkit::Observer>> = Vec::new();
        all.extend(self.tree.take_observer());
        all.push(observer);
        self.tree.set_observer(all);
    }

    /// `true` while a goal runs.
    pub fn is_navigating(&self) -> bool {
        self.navigation.is_some()
    }

    /// One period's work: reads the robot's pose and the clients' requests, ticks the tree
    /// once if a goal runs, sends feedback or the result.
    pub fn spin_once(&mut self) -> Result<(), NavigatorError> {
        let mut latest = None;
        while let Ok(Some((pose, _))) = self.poses.take() {
            latest = Some(pose);
        }
        if let Some(pose) = latest {
            self.robot = pose_2d(&pose);
            self.context.set_robot_pose(self.robot);
        }
        for request in self.goals.poll()? {
            match request {
                Request::Goal(goal) => self.start(pose_2d(&goal.pose), &goal.behavior_tree),
                Request::Cancel => {
                    self.tree.halt(&mut self.context);
                    self.end(GoalStatusEnum::Canceled, 0, String::new());
                }
            }
        }
        if self.navigation.is_some() {
            // Set before each tick, as TF is there for Nav2's nodes; an entry the tree
            // writes as something else is the tree's to report.
            let _ = self.tree.blackboard_mut().set(ROBOT_POSE, self.robot);
            match self.tree.tick_once(&mut self.context) {
                Ok(Status::Running) => self.send_feedback(),
                Ok(Status::Success) => self.end(GoalStatusEnum::Succeeded, 0, String::new()),
                Ok(status) => self.end(
                    GoalStatusEnum::Aborted,
                    NavigateToPoseResult::UNKNOWN,
                    format!("the navigator's tree ended {status}"),
                ),
                Err(e) => {
                    self.tree.halt(&mut self.context);
                    self.end(
                        GoalStatusEnum::Aborted,
                        NavigateToPoseResult::UNKNOWN,
                        format!("the navigator's tree failed: {e}"),
                    );
                }
            }
        }
        Ok(())
    }

    /// Calls [`spin_once`](Self::spin_once) every period until `stop` is raised.
    pub fn run(&mut self, stop: &AtomicBool) -> Result<(), NavigatorError> {
        let mut next = Instant::now();
        while !stop.load(Ordering::SeqCst) {
            self.spin_once()?;
            next += self.period;
            let now = Instant::now();
            if next > now {
                std::thread::sleep(next - now);
            } else {
                // Late: start again from now rather than catch up with a burst.
                next = now;
            }
        }
        self.tree.halt(&mut self.context);
        Ok(())
    }

    fn start(&mut self, goal: Pose2D, behavior_tree: &str) {
        self.stats.goals += 1;
        if !behavior_tree.is_empty() {
            self.tree.halt(&mut self.context);
            self.navigation = Some(Navigation {
                goal,
                started: Instant::now(),
                recoveries_before: self.recoveries.total(),
            });
            self.end(
                GoalStatusEnum::Aborted,
                NavigateToPoseResult::FAILED_TO_LOAD_BEHAVIOR_TREE,
                format!("this navigator runs one tree; cannot load `{behavior_tree}`"),
            );
            return;
        }
        let blackboard = self.tree.blackboard_mut();
        // The entries are the navigator's: set_ fails only on a type clash with a tree
        // that writes them as something else, and then the tree reports it.
        let _ = blackboard.set("goal", goal);
        if self.navigation.is_none() {
            for code in ERROR_CODES {
                let _ = blackboard.set(code, 0_u16);
            }
        }
        let recoveries_before = match &self.navigation {
            // Preempted: the recoveries go on counting for the navigation.
            Some(navigation) => navigation.recoveries_before,
            None => self.recoveries.total(),
        };
        self.navigation = Some(Navigation {
            goal,
            started: Instant::now(),
            recoveries_before,
        });
    }

    fn send_feedback(&self) {
        let Some(navigation) = &self.navigation else {
            return;
        };
        let robot = self.robot;
        let path = self.tree.blackboard().get::<Path>("path").ok();
        let remaining = distance_remaining(path.as_ref(), robot, navigation.goal);
        let recoveries = self.recoveries.total() - navigation.recoveries_before;
        self.goals.feedback(NavigateToPoseFeedback {
            current_pose: pose_stamped(robot),
            navigation_time: navigation.started.elapsed().into(),
            estimated_time_remaining: Duration::ZERO.into(),
            number_of_recoveries: i16::try_from(recoveries).unwrap_or(i16::MAX),
            distance_remaining: remaining as f32,
        });
    }

    fn end(&mut self, status: GoalStatusEnum, error_code: u16, error_msg: String) {
        if self.navigation.take().is_none() {
            return;
        }
        match status {
            GoalStatusEnum::Succeeded => self.stats.succeeded += 1,
            GoalStatusEnum::Canceled => self.stats.canceled += 1,
            _ => self.stats.aborted += 1,
        }
        let result = NavigateToPoseResult {
            error_code,
            error_msg,
        };
        self.goals.finish(status, result);
    }
}
