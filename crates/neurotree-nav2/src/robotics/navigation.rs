//! Navigation: a [`MotionPlanner`] trait and the node that drives it to a goal.
//!
//! [`NavigationNode`] has the ports `goal`, `current_pose` (optional), `obstacles` (optional),
//! `goal_tolerance` (default 0.1) and `path` (optional).
//!
//! - First tick: already within `goal_tolerance` of `goal` → Success; else plan from
//!   `current_pose` (the planner's pose when the port is absent) to `goal` around
//!   `obstacles`; no plan → Failure; else start executing → Running.
//! - Later ticks:
//!   - the rest of the path blocked (or the planner reports it blocked) → plan again at once,
//!     from the planner's pose (no plan → stop, Failure);
//!   - execution failed → stop, Failure;
//!   - within `goal_tolerance` → Success (a motion still under way is stopped first);
//!   - execution finished elsewhere → Failure;
//!   - else Running.
//! - Halted while Running → the motion is stopped exactly once.
//!
//! The node keeps its state (the path, whether it is planning or executing) per tree
//! instance; the planner is reached through the user's context, like a
//! [sensor](super::sensor): an accessor `Fn(&mut C) -> &mut dyn MotionPlanner` finds it. A
//! planner owns the robot's motion, so the node never moves the robot itself: it plans, asks
//! the planner to execute (every tick, so a planner may also advance its motion then), and
//! watches.
//!
//! `path` is an optional output: each new plan is written to it, for loggers and for other
//! nodes.
//!
//! ```
//! use neurotree::robotics::{Pose2D, RoboticsBuilder};
//! use neurotree::sim::GridWorld;
//! use neurotree::{Blueprint, Status, Tree};
//! use std::time::Duration;
//!
//! // One row of five 1 m cells; beyond the edge is wall.
//! let mut world = GridWorld::parse("R....", 1.0).unwrap();
//! let blueprint = Blueprint::<GridWorld>::builder()
//!     .navigate("go", "goal", 0.1, |w: &mut GridWorld| w)
//!     .build_shared()
//!     .unwrap();
//! let mut tree = Tree::with_clock(blueprint, world.clock());
//! tree.blackboard_mut().set("goal", Pose2D::new(4.5, 0.5, 0.0)).unwrap();
//! let mut ticks = 0;
//! let status = loop {
//!     ticks += 1;
//!     match tree.tick_once(&mut world).unwrap() {
//!         Status::Running => world.step(Duration::from_millis(500)),
//!         done => break done,
//!     };
//! };
//! assert_eq!(status, Status::Success);
//! assert_eq!(world.robot(), Pose2D::new(4.5, 0.5, 0.0));
//! assert_eq!(ticks, 9); // 4 m at 1 m/s in 0.5 s steps, then the tick that sees it
//! ```

use std::fmt;
use std::sync::Arc;

use neurotree_core::{FromPortStr, Handle, PortError, StatefulAction, Status};

use super::Pose2D;
use neurotree_toolkit::registry::{PortSpec, Registry, RegistryError};

/// A route: poses from the start to the goal, in metres.
///
/// Port text is the poses separated by `;`, each `x,y,theta` (or `x,y`), as lists are in
/// BehaviorTree.CPP: `0.5,0.5,0;1.5,0.5,0`.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Path {
    /// The waypoints, start first.
    pub poses: Vec<Pose2D>,
}

impl Path {
    /// A path through `poses`.
    pub fn new(poses: Vec<Pose2D>) -> Self {
        Self { poses }
    }

    /// Number of waypoints.
    pub fn len(&self) -> usize {
        self.poses.len()
    }

    /// `true` without waypoints.
    pub fn is_empty(&self) -> bool {
        self.poses.is_empty()
    }

    /// The last waypoint.
    pub fn goal(&self) -> Option<Pose2D> {
        self.poses.last().copied()
    }

    /// Metres along the waypoints.
    pub fn length(&self) -> f64 {
        self.poses.windows(2).map(|w| w[0].distance(&w[1])).sum()
    }

    /// The index of the waypoint nearest to `pose` (the first of equals); `None` if empty.
    pub fn closest_index(&self, pose: &Pose2D) -> Option<usize> {
        let mut best: Option<(usize, f64)> = None;
        for (i, p) in self.poses.iter().enumerate() {
            let d = p.distance(pose);
            if best.is_none_or(|(_, b)| d < b) {
                best = Some((i, d));
            }
        }
        best.map(|(i, _)| i)
    }

    /// The part of the path from waypoint `start` on (empty if `start` is past the end).
    pub fn from_index(&self, start: usize) -> Path {
        Path::new(self.poses.get(start..).unwrap_or_default().to_vec())
    }
}

impl FromPortStr for Path {
    fn from_port_str(text: &str) -> Result<Self, ()> {
        if text.trim().is_empty() {
            return Ok(Path::default());
        }
        text.split(';')
            .map(|pose| {
                let fields: Vec<&str> = pose.split(',').collect();
                let [x, y, rest @ ..] = fields.as_slice() else {
                    return Err(());
                };
                let theta = match rest {
                    [] => "0",
                    [t] => t,
                    _ => return Err(()),
                };
                Pose2D::from_port_str(&format!("{x};{y};{theta}"))
            })
            .collect::<Result<Vec<_>, ()>>()
            .map(Path::new)
    }
}

/// Writes the form [`FromPortStr`] reads back.
impl fmt::Display for Path {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, p) in self.poses.iter().enumerate() {
            if i > 0 {
                f.write_str(";")?;
            }
            write!(f, "{},{},{}", p.x, p.y, p.theta)?;
        }
        Ok(())
    }
}

/// Something to keep clear of: a disc in the plane, in metres.
///
/// Port text is `x,y,radius`; a list of obstacles separates them with `;`.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Obstacle {
    /// Centre, metres along x.
    pub x: f64,
    /// Centre, metres along y.
    pub y: f64,
    /// Radius in metres.
    pub radius: f64,
}

impl Obstacle {
    /// A disc of `radius` around `(x, y)`.
    pub const fn new(x: f64, y: f64, radius: f64) -> Self {
        Self { x, y, radius }
    }

    /// `true` if the point `(x, y)` lies within the disc.
    pub fn covers(&self, x: f64, y: f64) -> bool {
        (self.x - x).hypot(self.y - y) <= self.radius
    }
}

impl FromPortStr for Obstacle {
    fn from_port_str(text: &str) -> Result<Self, ()> {
        let mut fields = text.split(',').map(|f| f.trim().parse::<f64>());
        let mut next = || fields.next().ok_or(())?.map_err(|_| ());
        let obstacle = Obstacle::new(next()?, next()?, next()?);
        if fields.next().is_some() || obstacle.radius < 0.0 {
            return Err(());
        }
        Ok(obstacle)
    }
}

/// Why planning or execution failed.
#[derive(Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum NavigationError {
    /// No collision-free route exists between the two poses.
    #[error("no path from {from} to {to}")]
    NoPath {
        /// Where the plan started.
        from: Pose2D,
        /// Where it was to end.
        to: Pose2D,
    },
    /// A pose lies outside the planner's map.
    #[error("{0} is outside the map")]
    OutsideMap(Pose2D),
    /// The motion ran into something; planning again may help.
    #[error("the path is blocked near {at}")]
    Blocked {
        /// Where the robot stopped.
        at: Pose2D,
    },
    /// The robot cannot move at all (no power, a fault, an emergency stop).
    #[error("the robot cannot move: {0}")]
    CannotMove(String),
}

neurotree_core::debug_shows_message!(enum NavigationError {
    NoPath { from, to },
    OutsideMap(source),
    Blocked { at },
    CannotMove(source),
});

/// How far the execution of a path has got.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress {
    /// Still moving along the path.
    Moving,
    /// The end of the path has been reached and the motion has ended.
    Finished,
}

/// Plans routes and moves the robot along them: the robot's motion planner, as the
/// navigation node sees it.
pub trait MotionPlanner {
    /// A collision-free path from `start` to `goal`, keeping clear of `obstacles` as well as
    /// of whatever the planner knows itself.
    fn plan_path(
        &mut self,
        start: Pose2D,
        goal: Pose2D,
        obstacles: &[Obstacle],
    ) -> Result<Path, NavigationError>;

    /// Starts or continues following `path`; called on every tick while navigating, so a
    /// planner that follows `path` already only reports its progress.
    fn execute_path(&mut self, path: &Path) -> Result<Progress, NavigationError>;

    /// `false` if the part of `path` still ahead of the robot is known to be blocked.
    fn is_path_clear(&self, path: &Path) -> bool;

    /// Where the robot is.
    fn current_pose(&self) -> Pose2D;

    /// Stops the motion at once.
    fn stop_execution(&mut self);
}

/// Finds the planner in the context.
type PlannerAccess<C> = dyn Send + Sync + Fn(&mut C) -> &mut dyn MotionPlanner;

/// What the node is doing between ticks.
#[derive(Clone, Debug, PartialEq)]
enum Phase {
    Idle,
    Executing { path: Path, goal: Pose2D },
}

/// The navigation node: see the [module documentation](self) for its semantics and ports.
pub struct NavigationNode<C> {
    access: Arc<PlannerAccess<C>>,
    phase: Phase,
}

impl<C> NavigationNode<C> {
    /// A factory of nodes (one per tree instance) driving the planner `access` finds, for
    /// [`Builder::stateful`](neurotree_core::Builder::stateful).
    pub fn factory<F>(access: F) -> impl Fn() -> Self + Send + Sync + 'static
    where
        C: 'static,
        F: Fn(&mut C) -> &mut dyn MotionPlanner,
        F: Send + Sync + 'static,
    {
        let access: Arc<PlannerAccess<C>> = Arc::new(access);
        move || NavigationNode {
            access: Arc::clone(&access),
            phase: Phase::Idle,
        }
    }

    /// The ports the node reads and writes, for [`Registry`] declarations.
    pub fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<Pose2D>("goal").describe("where to go: x;y;theta in metres"),
            PortSpec::input::<Pose2D>("current_pose")
                .describe("where the first plan starts; the planner's own pose when absent"),
            PortSpec::input::<Vec<Obstacle>>("obstacles")
                .describe("extra obstacles to plan around: x,y,radius;..."),
            PortSpec::input::<f64>("goal_tolerance")
                .default_value("0.1")
                .describe("metres from the goal that count as arrived"),
            PortSpec::output::<Path>("path").describe("receives each new plan"),
        ]
    }

    fn planner<'h>(&self, h: &'h mut Handle<'_, C>) -> &'h mut dyn MotionPlanner {
        (self.access)(h.ctx_mut())
    }

    /// Plans from `start` (the robot's pose if `None`) to `goal` and starts the motion.
    /// `moving` says a motion is under way, to be stopped if this fails.
    fn plan_and_start(
        &mut self,
        h: &mut Handle<'_, C>,
        start: Option<Pose2D>,
        goal: Pose2D,
        moving: bool,
    ) -> Status {
        let planned = optional::<Vec<Obstacle>, C>(h, "obstacles").and_then(|obstacles| {
            let planner = self.planner(h);
            let start = start.unwrap_or_else(|| planner.current_pose());
            planner
                .plan_path(start, goal, &obstacles.unwrap_or_default())
                .map_err(|_| ())
        });
        let written = planned.and_then(|path| match h.output("path", path.clone()) {
            Ok(()) | Err(PortError::NoSuchPort { .. }) => Ok(path),
            Err(_) => Err(()),
        });
        let started = written.and_then(|path| match self.planner(h).execute_path(&path) {
            Ok(_) => Ok(path),
            Err(_) => Err(()),
        });
        match started {
            Ok(path) => {
                self.phase = Phase::Executing { path, goal };
                Status::Running
            }
            Err(()) => {
                if moving {
                    self.planner(h).stop_execution();
                }
                Status::Failure
            }
        }
    }
}

/// `goal_tolerance`, 0.1 m when the node has no such port.
fn tolerance<C>(h: &Handle<'_, C>) -> Result<f64, ()> {
    match h.input::<f64>("goal_tolerance") {
        Ok(t) => Ok(t),
        Err(PortError::NoSuchPort { .. }) => Ok(0.1),
        Err(_) => Err(()),
    }
}

/// Reads an optional input port: `Ok(None)` if the node has no such port or its entry was
/// never written, `Err` if it is there but unreadable.
fn optional<T, C>(h: &Handle<'_, C>, port: &str) -> Result<Option<T>, ()>
where
    T: FromPortStr + std::any::Any + Clone,
{
    match h.input::<T>(port) {
        Ok(v) => Ok(Some(v)),
        Err(PortError::NoSuchPort { .. })
        | Err(PortError::Blackboard {
            source: neurotree_core::BlackboardError::NotFound { .. },
            ..
        }) => Ok(None),
        Err(_) => Err(()),
    }
}

impl<C> StatefulAction<C> for NavigationNode<C> {
    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.phase = Phase::Idle;
        let (Ok(goal), Ok(tolerance)) = (h.input::<Pose2D>("goal"), tolerance(h)) else {
            return Status::Failure;
        };
        let Ok(start) = optional::<Pose2D, C>(h, "current_pose") else {
            return Status::Failure;
        };
        let here = start.unwrap_or_else(|| self.planner(h).current_pose());
        if here.distance(&goal) <= tolerance {
            return Status::Success;
        }
        self.plan_and_start(h, start, goal, false)
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        // Taken out so the path is not cloned every tick; put back while still Running.
        let Phase::Executing { path, goal } = std::mem::replace(&mut self.phase, Phase::Idle)
        else {
            // Only reachable if a tick left the node Running without a path, which none
            // does; failing is the safe answer.
            return Status::Failure;
        };
        let Ok(tolerance) = tolerance(h) else {
            self.planner(h).stop_execution();
            return Status::Failure;
        };
        let planner = self.planner(h);
        let progress = if planner.is_path_clear(&path) {
            planner.execute_path(&path)
        } else {
            Err(NavigationError::Blocked {
                at: planner.current_pose(),
            })
        };
        match progress {
            // The robot has moved since the first plan: replans start where it is.
            Err(NavigationError::Blocked { .. }) => self.plan_and_start(h, None, goal, true),
            Err(_) => {
                planner.stop_execution();
                Status::Failure
            }
            Ok(progress) if planner.current_pose().distance(&goal) <= tolerance => {
                if progress == Progress::Moving {
                    planner.stop_execution();
                }
                Status::Success
            }
            Ok(Progress::Finished) => Status::Failure,
            Ok(Progress::Moving) => {
                self.phase = Phase::Executing { path, goal };
                Status::Running
            }
        }
    }

    fn on_halted(&mut self, h: &mut Handle<'_, C>) {
        self.phase = Phase::Idle;
        self.planner(h).stop_execution();
    }
}

/// Registers a navigation node type for XML under `name`, driving the planner `access`
/// finds: `<Navigate goal="{goal}" goal_tolerance="0.25" obstacles="{seen}"/>`.
pub fn register_navigation<C, F>(
    registry: &mut Registry<C>,
    name: &str,
    access: F,
) -> Result<(), RegistryError>
where
    C: 'static,
    F: Fn(&mut C) -> &mut dyn MotionPlanner,
    F: Send + Sync + 'static,
{
    registry.register_stateful(
        name,
        NavigationNode::<C>::ports(),
        NavigationNode::factory(access),
    )?;
    registry.describe(
        name,
        "Plans a path to goal and follows it, planning again when it is blocked; halting it stops the robot.",
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robotics::RoboticsBuilder;
    use neurotree_toolkit::{Blueprint, ManualClock, Port, Tree, XmlLoader};

    /// A robot on a line: each `execute_path` moves it 1 m along x towards the path's end.
    #[derive(Default)]
    struct Line {
        x: f64,
        /// Planning fails while set.
        no_path: bool,
        /// The path ahead reads as blocked while set.
        blocked: bool,
        /// Each new plan ends this far short of the goal (to test a finish off the goal).
        short_by: f64,
        plans: Vec<(f64, f64, usize)>,
        executes: u32,
        stops: u32,
    }

    impl MotionPlanner for Line {
        fn plan_path(
            &mut self,
            start: Pose2D,
            goal: Pose2D,
            obstacles: &[Obstacle],
        ) -> Result<Path, NavigationError> {
            self.plans.push((start.x, goal.x, obstacles.len()));
            if self.no_path {
                return Err(NavigationError::NoPath {
                    from: start,
                    to: goal,
                });
            }
            self.blocked = false;
            let end = Pose2D::new(goal.x - self.short_by, 0.0, 0.0);
            Ok(Path::new(vec![start, end]))
        }
        fn execute_path(&mut self, path: &Path) -> Result<Progress, NavigationError> {
            self.executes += 1;
            let end = path.goal().map_or(self.x, |p| p.x);
            self.x = if end > self.x {
                (self.x + 1.0).min(end)
            } else {
                (self.x - 1.0).max(end)
            };
            Ok(if self.x == end {
                Progress::Finished
            } else {
                Progress::Moving
            })
        }
        fn is_path_clear(&self, _path: &Path) -> bool {
            !self.blocked
        }
        fn current_pose(&self) -> Pose2D {
            Pose2D::new(self.x, 0.0, 0.0)
        }
        fn stop_execution(&mut self) {
            self.stops += 1;
        }
    }

    fn tree(tolerance: f64) -> Tree<Line> {
        let bp = Blueprint::<Line>::builder()
            .navigate("go", "goal", tolerance, |l: &mut Line| l)
            .ports([
                Port::entry("obstacles", "seen"),
                Port::entry("path", "plan"),
            ])
            .build_shared()
            .unwrap();
        let mut t = Tree::with_clock(bp, ManualClock::new());
        t.blackboard_mut()
            .set("goal", Pose2D::new(4.0, 0.0, 0.0))
            .unwrap();
        t
    }

    fn ticks(t: &mut Tree<Line>, line: &mut Line, n: usize) -> Vec<Status> {
        (0..n).map(|_| t.tick_once(line).unwrap()).collect()
    }

    use Status::{Failure as F, Running as R, Success as S};

    #[test]
    fn plans_once_executes_and_succeeds_at_the_goal() {
        let mut t = tree(0.1);
        let mut line = Line::default();
        // Plan and first step, two more steps, then the step that reaches the goal.
        assert_eq!(ticks(&mut t, &mut line, 4), [R, R, R, S]);
        assert_eq!(line.x, 4.0);
        assert_eq!(line.plans, [(0.0, 4.0, 0)]);
        assert_eq!(line.executes, 4);
        assert_eq!(line.stops, 0);
        let plan: Path = t.blackboard().get("plan").unwrap();
        assert_eq!(plan.poses.len(), 2);
        assert_eq!(plan.length(), 4.0);
    }

    #[test]
    fn already_at_the_goal_succeeds_without_planning() {
        let mut t = tree(0.5);
        let mut line = Line {
            x: 3.6,
            ..Line::default()
        };
        assert_eq!(t.tick_once(&mut line), Ok(S));
        assert!(line.plans.is_empty());
        assert_eq!(line.executes, 0);
    }

    #[test]
    fn no_path_fails_on_the_first_tick_without_stopping() {
        let mut t = tree(0.1);
        let mut line = Line {
            no_path: true,
            ..Line::default()
        };
        assert_eq!(t.tick_once(&mut line), Ok(F));
        assert_eq!(line.plans.len(), 1);
        assert_eq!((line.executes, line.stops), (0, 0));
    }

    #[test]
    fn a_blocked_path_is_planned_again_from_where_the_robot_is() {
        let mut t = tree(0.1);
        let mut line = Line::default();
        t.blackboard_mut()
            .set("seen", vec![Obstacle::new(2.0, 1.0, 0.5)])
            .unwrap();
        assert_eq!(ticks(&mut t, &mut line, 2), [R, R]);
        line.blocked = true;
        // The blocked tick plans again and starts the new path: still Running.
        assert_eq!(t.tick_once(&mut line), Ok(R));
        assert_eq!(line.plans, [(0.0, 4.0, 1), (2.0, 4.0, 1)]);
        assert_eq!(line.x, 3.0);
        assert_eq!(t.tick_once(&mut line), Ok(S));
        assert_eq!(line.stops, 0);
    }

    #[test]
    fn a_failed_replan_stops_the_motion_and_fails() {
        let mut t = tree(0.1);
        let mut line = Line::default();
        assert_eq!(t.tick_once(&mut line), Ok(R));
        line.blocked = true;
        line.no_path = true;
        assert_eq!(t.tick_once(&mut line), Ok(F));
        assert_eq!(line.plans.len(), 2);
        assert_eq!(line.stops, 1);
    }

    #[test]
    fn halt_stops_the_motion_exactly_once() {
        let mut t = tree(0.1);
        let mut line = Line::default();
        assert_eq!(ticks(&mut t, &mut line, 2), [R, R]);
        t.halt(&mut line);
        assert_eq!(line.stops, 1);
        // Halting an idle tree stops nothing more.
        t.halt(&mut line);
        assert_eq!(line.stops, 1);
        // The next tick starts afresh from where the robot stopped.
        assert_eq!(t.tick_once(&mut line), Ok(R));
        assert_eq!(line.plans, [(0.0, 4.0, 0), (2.0, 4.0, 0)]);
    }

    #[test]
    fn within_tolerance_while_moving_stops_and_succeeds() {
        let mut t = tree(1.5);
        let mut line = Line::default();
        assert_eq!(ticks(&mut t, &mut line, 3), [R, R, S]);
        assert_eq!(line.x, 3.0);
        assert_eq!(line.stops, 1);
    }

    #[test]
    fn a_path_that_ends_off_the_goal_fails() {
        let mut t = tree(0.1);
        let mut line = Line {
            short_by: 1.0,
            ..Line::default()
        };
        assert_eq!(ticks(&mut t, &mut line, 3), [R, R, F]);
        assert_eq!(line.x, 3.0);
        assert_eq!(line.stops, 0);
    }

    #[test]
    fn a_missing_goal_or_unreadable_obstacles_fail() {
        let mut t = tree(0.1);
        t.blackboard_mut().unset("goal");
        let mut line = Line::default();
        assert_eq!(t.tick_once(&mut line), Ok(F));
        let mut t = tree(0.1);
        t.blackboard_mut().set("seen", 7_u8).unwrap();
        assert_eq!(t.tick_once(&mut line), Ok(F));
        assert!(line.plans.is_empty());
    }

    #[test]
    fn registered_for_xml_with_its_ports() {
        let mut registry = Registry::<Line>::new();
        register_navigation(&mut registry, "Navigate", |l: &mut Line| l).unwrap();
        let nav = registry.get("Navigate").unwrap();
        let names: Vec<&str> = nav.ports.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "goal",
                "current_pose",
                "obstacles",
                "goal_tolerance",
                "path"
            ]
        );
        let mut loader = XmlLoader::new(&registry);
        loader
            .load_str(
                r#"<root BTCPP_format="4">
                     <BehaviorTree ID="Main">
                       <Navigate goal="3;0;0" current_pose="1;0" obstacles="2,1,0.5;2,-1,0.5"
                                 goal_tolerance="0.25" path="{plan}"/>
                     </BehaviorTree>
                   </root>"#,
                "nav.xml",
            )
            .unwrap();
        let mut t = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
        let mut line = Line::default();
        assert_eq!(ticks(&mut t, &mut line, 3), [R, R, S]);
        // The first plan starts at `current_pose`; the line robot's own pose is 0.
        assert_eq!(line.plans, [(1.0, 3.0, 2)]);
        let plan: Path = t.blackboard().get("plan").unwrap();
        assert_eq!(plan.to_string(), "1,0,0;3,0,0");
    }

    #[test]
    fn paths_and_obstacles_read_from_port_text() {
        let path = Path::from_port_str("0.5,0.5,0; 1.5,0.5").unwrap();
        assert_eq!(
            path.poses,
            [Pose2D::new(0.5, 0.5, 0.0), Pose2D::new(1.5, 0.5, 0.0)]
        );
        assert_eq!(Path::from_port_str(&path.to_string()), Ok(path.clone()));
        assert_eq!(Path::from_port_str(""), Ok(Path::default()));
        assert_eq!(Path::from_port_str("1"), Err(()));
        assert_eq!(Path::from_port_str("1,2,3,4"), Err(()));
        assert_eq!(
            Vec::<Obstacle>::from_port_str("1,2,0.5;3,4,1"),
            Ok(vec![
                Obstacle::new(1.0, 2.0, 0.5),
                Obstacle::new(3.0, 4.0, 1.0)
            ])
        );
        assert_eq!(Obstacle::from_port_str("1,2"), Err(()));
        assert_eq!(Obstacle::from_port_str("1,2,-1"), Err(()));
        assert!(Obstacle::new(0.0, 0.0, 1.0).covers(0.0, -1.0));
        assert!(!Obstacle::new(0.0, 0.0, 1.0).covers(0.8, 0.8));
    }

    #[test]
    fn path_geometry() {
        let path = Path::new(vec![
            Pose2D::new(0.0, 0.0, 0.0),
            Pose2D::new(3.0, 4.0, 0.0),
            Pose2D::new(3.0, 5.0, 0.0),
        ]);
        assert_eq!(path.length(), 6.0);
        assert_eq!(path.closest_index(&Pose2D::new(2.9, 4.2, 0.0)), Some(1));
        assert_eq!(path.from_index(1).poses.len(), 2);
        assert!(path.from_index(7).is_empty());
        assert_eq!(Path::default().closest_index(&Pose2D::default()), None);
    }
}
