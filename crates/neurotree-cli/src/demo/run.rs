//! The demo: Nav2's navigator, unchanged, driving the simulated robot across a warehouse.
//!
//! A [`DemoRun`] loads the tree (Nav2's `navigate_to_pose_w_replanning_and_recovery.xml`
//! by default, or any BehaviorTree.CPP file that uses these nodes), builds the
//! [`Scenario`] of a seed, and then ticks: each [`tick`](DemoRun::tick) steps the world by
//! one period, ticks the tree once, and records what happened for a
//! [`frame`](DemoRun::frame). When the tree completes, [`summary`](DemoRun::summary) says
//! how it went. Nothing reads the wall clock, so a run is the same every time; pacing the
//! frames is the caller's business.

use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use neurotree::{BlackboardError, Status, Tree};

use super::frame::{Layout, Parts};
use super::scenario::{dock, route_graph, Scenario, DEFAULT_GOAL, PLACING_LOCATION};
use super::world::{plan_ahead, DemoWorld};
use neurotree::fault::{build_with_faults, FaultBuildError, FaultHit, FaultLog, NodeFault};
use neurotree::render::LastTickStatuses;
use neurotree::robotics::Pose2D;
use neurotree::sim::nav2::{
    register_nav2_leaves, EventLog, FailureNotes, Nav2Params, Nav2Sim, RecoveryCounter,
    NOT_SIMULATED,
};
use neurotree::sim::{Battery, MapError, LEGEND};
use neurotree::{nav2, LoadError, Registry, RegistryError, XmlLoader};

/// Nav2's NavigateToPose navigator with replanning and recovery, as Nav2 ships it: the
/// tree the demo runs unless given another.
pub const NAVIGATE_TO_POSE_XML: &str =
    include_str!("../../trees/navigate_to_pose_w_replanning_and_recovery.xml");

/// The name [`NAVIGATE_TO_POSE_XML`] goes by in messages: its place in the repository.
const NAVIGATE_TO_POSE_FILE: &str = "corpus/nav2/navigate_to_pose_w_replanning_and_recovery.xml";

/// What to run.
#[derive(Clone, Debug, PartialEq)]
pub struct DemoConfig {
    /// A BehaviorTree.CPP file to run instead of Nav2's navigator.
    pub tree: Option<PathBuf>,
    /// Where the robot is sent, in metres (1 m cells, origin at the lower left corner).
    pub goal: Pose2D,
    /// Picks the obstacle: see [`Scenario::new`].
    pub seed: u64,
    /// Ticks after which the run stops, unfinished.
    pub max_ticks: u32,
    /// Draw the tree with unicode box lines and marks rather than ASCII.
    pub unicode: bool,
    /// How the simulated servers behave.
    pub params: Nav2Params,
    /// The robot's heading at the start, in radians counter-clockwise from +x (east).
    pub start_heading: f64,
    /// Put the seed's obstacle on the robot's path (a tree without recoveries cannot get
    /// past one that stays).
    pub obstacle: bool,
    /// Simulated time after which a tree that is still running is judged by where the
    /// robot is ([`DemoSummary::within_tolerance`]): for a tree that never ends by itself,
    /// such as Nav2's `follow_point.xml`.
    pub duration: Option<Duration>,
    /// The battery's charge at the start, in percent: under 100, a robot on the charger is
    /// charging (Nav2's docking example then undocks first).
    pub battery: f64,
    /// Nodes that misbehave on a given call ([`neurotree::fault`]).
    pub faults: Vec<NodeFault>,
    /// The battery falls to this level (percent) at this simulated time, if it is higher.
    pub battery_drop: Option<(Duration, f64)>,
}

impl Default for DemoConfig {
    /// Nav2's navigator, the far corner of the store, seed 0 with its obstacle, at most 3000
    /// ticks (five simulated minutes), no duration, unicode.
    fn default() -> Self {
        Self {
            tree: None,
            goal: DEFAULT_GOAL,
            seed: 0,
            max_ticks: 3000,
            unicode: true,
            params: Nav2Params::default(),
            obstacle: true,
            duration: None,
            start_heading: 0.0,
            battery: 100.0,
            faults: Vec::new(),
            battery_drop: None,
        }
    }
}

/// Why a demo could not start.
#[derive(Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DemoError {
    /// The tree did not load; the message reads `file:line:col: error: …`.
    #[error(transparent)]
    Load(#[from] LoadError),
    /// The warehouse map did not parse (a bug in this module).
    #[error("the demo's map: {0}")]
    Map(#[from] MapError),
    /// A node type of the demo was registered twice (a bug in this module).
    #[error("registering the demo's nodes: {0}")]
    Registry(#[from] RegistryError),
    /// Nav2's model of its node types did not load (a bug in this module).
    #[error("Nav2's model: {0}")]
    Model(String),
    /// The tree's root blackboard would not take the goal.
    #[error("cannot give the tree its goal: {0}")]
    Goal(#[from] BlackboardError),
    /// A fault names no node of the tree, or several.
    #[error("{0}")]
    Fault(String),
}

neurotree::debug_shows_message!(
    enum DemoError {
        Load(source),
        Map(source),
        Registry(source),
        Model(source),
        Goal(source),
        Fault(source),
    }
);

/// A load error that names a Nav2 type known only by its model, told as what it is for the
/// demo: a node of Nav2 that the simulated robot does not implement. Other errors pass.
fn not_simulated(mut error: LoadError) -> LoadError {
    let name = error
        .message
        .strip_prefix('`')
        .and_then(|rest| rest.split_once("` is only described by a model"))
        .map(|(name, _)| name.to_string());
    if let Some(name) = name {
        let why = NOT_SIMULATED
            .iter()
            .find(|(n, _)| *n == name)
            .map_or(String::new(), |(_, why)| format!(": {why}"));
        error.message = format!(
            "`{name}` is a Nav2 node the demo's simulated robot does not implement{why} \
             (the simulated ones are listed in neurotree::sim::nav2::LEAVES)"
        );
    }
    error
}

/// How a run went.
#[derive(Clone, Debug, PartialEq)]
pub struct DemoSummary {
    /// The tree's last status: Running if it was stopped unfinished.
    pub outcome: Status,
    /// Ticks of the tree.
    pub ticks: u32,
    /// Simulated time at the last tick.
    pub time: Duration,
    /// Metres the robot drove.
    pub distance: f64,
    /// Plans that replaced a different one ([`Nav2Sim::replans`]).
    pub replans: u32,
    /// Runs of the recovery branches, all together ([`RecoveryCounter`]).
    pub recoveries: u32,
    /// Runs of each recovery branch that ran, in tree order.
    pub recovery_runs: Vec<(String, u32)>,
    /// Where the robot ended, and where it was sent.
    pub pose: Pose2D,
    /// Where it was sent.
    pub goal: Pose2D,
    /// The error a tick ended with, if one did.
    pub error: Option<String>,
    /// Nav2's error codes the tree holds when it ends: each root entry named
    /// `…_error_code` that is not 0, with its `…_error_msg` (empty if none), in name order.
    pub error_codes: Vec<(String, u16, String)>,
    /// When the run was stopped by its duration: whether the robot was within the goal
    /// tolerance of the end of the path it was following (it kept up with its goal).
    pub within_tolerance: Option<bool>,
}

impl DemoSummary {
    /// Whether the navigation succeeded: the tree ended with Success, or it was still
    /// running at the end of its duration with the robot within its tolerance.
    pub fn succeeded(&self) -> bool {
        self.error.is_none()
            && (self.outcome == Status::Success
                || (self.outcome == Status::Running && self.within_tolerance == Some(true)))
    }
}

impl fmt::Display for DemoSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "Summary")?;
        writeln!(f, "  outcome     {}", self.outcome)?;
        writeln!(f, "  ticks       {}", self.ticks)?;
        writeln!(f, "  time        {:.1} s", self.time.as_secs_f64())?;
        writeln!(f, "  distance    {:.2} m", self.distance)?;
        writeln!(f, "  replans     {}", self.replans)?;
        write!(f, "  recoveries  {}", self.recoveries)?;
        if self.recoveries > 0 {
            let runs: Vec<String> = self
                .recovery_runs
                .iter()
                .filter(|(_, n)| *n > 0)
                .map(|(label, n)| format!("{label} {n}"))
                .collect();
            write!(f, " ({})", runs.join(", "))?;
        }
        writeln!(f)?;
        writeln!(
            f,
            "  robot       ({:.2}, {:.2}), {:.2} m from the goal ({:.2}, {:.2})",
            self.pose.x,
            self.pose.y,
            self.pose.distance(&self.goal),
            self.goal.x,
            self.goal.y
        )?;
        if let Some(within) = self.within_tolerance {
            let verdict = if within { "within" } else { "outside" };
            writeln!(f, "  duration    over, the robot {verdict} its tolerance")?;
        }
        for (entry, code, message) in &self.error_codes {
            write!(f, "  error code  {code} ({entry})")?;
            if !message.is_empty() {
                write!(f, ": {message}")?;
            }
            writeln!(f)?;
        }
        if let Some(error) = &self.error {
            writeln!(f, "  error       {error}")?;
        }
        let verdict = if self.succeeded() {
            "navigation succeeded"
        } else if self.outcome == Status::Running && self.within_tolerance.is_none() {
            "navigation stopped unfinished"
        } else {
            "navigation failed"
        };
        writeln!(f, "{verdict}")
    }
}

/// A demo under way: Nav2's navigator (or another tree) on the [`Scenario`] of a seed.
///
/// Each [`tick`](Self::tick) steps the world by one period (from the second tick on) and
/// ticks the tree once; [`frame`](Self::frame) draws the last tick, [`notes`](Self::notes)
/// say what happened in it, and [`summary`](Self::summary) how the run went. Nothing reads
/// the wall clock: the same configuration gives the same run, frame for frame.
///
/// ```
/// use neurotree_cli::demo::{DemoConfig, DemoRun};
/// use neurotree::Status;
///
/// let mut run = DemoRun::new(&DemoConfig::default()).unwrap();
/// let summary = run.run_to_end();
/// assert_eq!(summary.outcome, Status::Success);
/// assert_eq!((summary.replans, summary.recoveries), (38, 4));
/// ```
pub struct DemoRun {
    sim: Nav2Sim,
    tree: Tree<Nav2Sim>,
    seen: LastTickStatuses,
    recoveries: RecoveryCounter,
    scenario: Scenario,
    log: EventLog,
    tree_file: String,
    /// The goal has no path from the start, hence no obstacle.
    unreachable: bool,
    unicode: bool,
    max_ticks: u32,
    duration: Option<Duration>,
    ticks: u32,
    status: Status,
    error: Option<String>,
    /// What happened in the last tick.
    notes: Vec<String>,
    /// Plans made in the last tick.
    plans_in_tick: u32,
    /// What the loader warned of (an old Nav2 name, say), `file:line:col: warning: …`.
    warnings: Vec<String>,
    /// Where the configured faults landed.
    faults: FaultLog,
    battery_drop: Option<(Duration, f64)>,
}

impl DemoRun {
    /// Loads the tree and sets the scene.
    pub fn new(config: &DemoConfig) -> Result<Self, DemoError> {
        Self::with_hooks(config, None)
    }

    /// [`new`](Self::new), the tree's nodes also given the hooks of `hooks` (which wrap
    /// the configured faults' hooks).
    pub fn with_hooks(
        config: &DemoConfig,
        hooks: Option<neurotree::xml::SharedHookWrapper<Nav2Sim>>,
    ) -> Result<Self, DemoError> {
        let mut registry = Registry::<Nav2Sim>::new();
        nav2::register_controls(&mut registry)?;
        register_nav2_leaves(&mut registry)?;
        // Nav2's other types, by their ports: they load, and building one says it has no
        // simulated implementation.
        registry
            .add_model_str(nav2::NAV2_TREE_NODES_MODEL, "nav2_tree_nodes.xml")
            .map_err(|e| DemoError::Model(e.to_string()))?;
        // Files written for older releases load, with a warning, as on `check --nav2`.
        for (old, new) in nav2::RENAMED {
            registry.add_renamed(old, new, "renamed in Nav2 after Kilted");
        }
        let faults = FaultLog::default();
        let mut warnings = Vec::new();
        let mut tree_file = String::new();
        let blueprint = build_with_faults(&config.faults, &faults, |wrap| {
            let mut loader = XmlLoader::new(&registry)
                .unknown_type_advice("the demo runs Nav2's node types, simulated");
            let wrap = match (wrap, &hooks) {
                (wrap, Some(hooks)) => Some(neurotree::fault::chain(wrap, Arc::clone(hooks))),
                (wrap, None) => wrap,
            };
            if let Some(wrap) = wrap {
                loader = loader.wrap_hooks(wrap);
            }
            tree_file = match &config.tree {
                Some(path) => {
                    loader.load_file(path)?;
                    path.display().to_string()
                }
                None => {
                    loader.load_str(NAVIGATE_TO_POSE_XML, NAVIGATE_TO_POSE_FILE)?;
                    NAVIGATE_TO_POSE_FILE.to_string()
                }
            };
            let built = loader.build_main().map_err(not_simulated)?;
            warnings = loader.warnings().iter().map(ToString::to_string).collect();
            Ok::<_, LoadError>(built)
        })
        .map_err(|e| match e {
            FaultBuildError::Load(e) => DemoError::Load(e),
            FaultBuildError::Fault(e) => DemoError::Fault(e),
        })?;
        let blueprint = Arc::new(blueprint);
        let mut scenario = Scenario::new(config.seed, config.goal, &config.params)?;
        let unreachable = scenario.obstacle.is_none();
        if !config.obstacle {
            scenario.obstacle = None;
        }
        let log = EventLog::new();
        let mut world = scenario.world()?.with_battery(Battery::at(config.battery));
        let start = world.robot();
        world.set_robot(Pose2D::new(start.x, start.y, config.start_heading))?;
        let sim = Nav2Sim::new(world)
            .with_params(config.params)
            .with_log(log.clone())
            .with_dock(dock())
            .with_route_graph(route_graph());
        let mut tree = Tree::with_clock(Arc::clone(&blueprint), sim.world.clock());
        neurotree::runtime::attach(&mut tree);
        tree.blackboard_mut().set("goal", config.goal)?;
        // The through-poses navigator's goals: the one goal.
        tree.blackboard_mut().set("goals", vec![config.goal])?;
        // What Nav2's docking example asks of its user: where to pick and place, and the
        // dock to return to.
        tree.blackboard_mut().set("picking_location", config.goal)?;
        tree.blackboard_mut()
            .set("placing_location", PLACING_LOCATION)?;
        tree.blackboard_mut().set("dock_id", dock().id)?;
        tree.blackboard_mut().set("dock_type", dock().dock_type)?;
        let seen = LastTickStatuses::new();
        let recoveries = RecoveryCounter::new(&blueprint).with_log(log.clone());
        // Failures are told as the nodes give their reasons, in the order they come.
        let failures = FailureNotes::new(&blueprint, log.clone());
        tree.set_observer((seen.clone(), (recoveries.clone(), failures)));
        Ok(Self {
            sim,
            tree,
            seen,
            recoveries,
            scenario,
            log,
            tree_file,
            unreachable,
            unicode: config.unicode,
            max_ticks: config.max_ticks,
            duration: config.duration,
            ticks: 0,
            status: Status::Running,
            error: None,
            notes: Vec::new(),
            plans_in_tick: 0,
            warnings,
            faults,
            battery_drop: config.battery_drop,
        })
    }

    /// What the loader warned of, one line each: an old Nav2 name that loads as its new one.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// `true` once the tree has completed, the tick limit is reached, or the duration is
    /// over.
    pub fn is_over(&self) -> bool {
        self.status != Status::Running || self.ticks >= self.max_ticks || self.duration_over()
    }

    /// `true` once the simulated time reached the duration, if there is one.
    fn duration_over(&self) -> bool {
        self.ticks > 0 && self.duration.is_some_and(|d| self.sim.world.now() >= d)
    }

    /// Ticks the tree once (after stepping the world by one period, from the second tick
    /// on); returns its status. Does nothing once the run [is over](Self::is_over).
    pub fn tick(&mut self) -> Status {
        self.tick_timed().0
    }

    /// [`tick`](Self::tick), and how long the tree's own tick took (its leaves' calls into
    /// the simulated servers included; the world's step and the robot's state written
    /// before it not): what `neurotree bench` reports as the navigator's tick times.
    pub fn tick_timed(&mut self) -> (Status, Duration) {
        if self.is_over() {
            return (self.status, Duration::ZERO);
        }
        if self.ticks > 0 {
            let before = self.present_obstacles();
            self.sim.step();
            self.note_obstacles(&before);
        }
        if let Some((at, level)) = self.battery_drop {
            let world = &mut self.sim.world;
            if world.now() >= at {
                self.battery_drop = None;
                if world.battery().level() > level {
                    self.log.push(format!("the battery falls to {level:.0} %"));
                    world.set_battery_level(level);
                }
            }
        }
        self.ticks += 1;
        let plans = self.sim.plans();
        // Nav2's controls read the robot's pose and speed (TF and odometry in Nav2).
        if let Err(error) = self.sim.write_robot_state(self.tree.blackboard_mut()) {
            self.log.push(format!("the robot's state: {error}"));
        }
        let started = Instant::now();
        let ticked = self.tree.tick_once(&mut self.sim);
        let took = started.elapsed();
        self.status = match ticked {
            Ok(status) => status,
            Err(error) => {
                self.log.push(format!("the tick failed: {error}"));
                self.error = Some(error.to_string());
                Status::Failure
            }
        };
        self.notes = self.log.take();
        self.plans_in_tick = self.sim.plans() - plans;
        (self.status, took)
    }

    /// Adds `observer` beside the demo's own: it sees every tick from now on.
    pub fn add_observer(&mut self, observer: Box<dyn neurotree::Observer>) {
        let mut all: Vec<Box<dyn neurotree::Observer>> = Vec::new();
        all.extend(self.tree.take_observer());
        all.push(observer);
        self.tree.set_observer(all);
    }

    /// The tree's blueprint.
    pub fn blueprint(&self) -> &Arc<neurotree::Blueprint<Nav2Sim>> {
        self.tree.blueprint()
    }

    /// The navigator's tree, for what watches it from outside (the studio).
    pub fn tree_mut(&mut self) -> &mut Tree<Nav2Sim> {
        &mut self.tree
    }

    /// The tree, and the world and counters around it, for a watcher that keeps both after
    /// each tick and restores both to go back to a tick (the studio).
    pub fn watched(&mut self) -> (&mut Tree<Nav2Sim>, DemoWorld<'_>) {
        let world = DemoWorld {
            sim: &mut self.sim,
            ticks: &mut self.ticks,
            status: &mut self.status,
            error: &mut self.error,
            notes: &mut self.notes,
            plans_in_tick: &mut self.plans_in_tick,
            recoveries: &self.recoveries,
            scenario: &self.scenario,
        };
        (&mut self.tree, world)
    }

    /// Where the configured faults landed so far, in order.
    pub fn fault_hits(&self) -> Vec<FaultHit> {
        self.faults.hits()
    }

    /// The file the tree was loaded from (the built-in navigator's name if none was given).
    pub fn tree_file(&self) -> &str {
        &self.tree_file
    }

    /// Runs to the end without drawing; the summary.
    pub fn run_to_end(&mut self) -> DemoSummary {
        while !self.is_over() {
            self.tick();
        }
        self.summary()
    }

    /// Ticks so far.
    pub fn ticks(&self) -> u32 {
        self.ticks
    }

    /// The simulation: the world and the counters.
    pub fn sim(&self) -> &Nav2Sim {
        &self.sim
    }

    /// The scenario being run.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// What happened in the last tick, one line each: obstacles coming and going, plans,
    /// failures, recoveries.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// `true` if more happened in the last tick than the navigator's routine planning: an
    /// obstacle came or went, a node failed, a recovery ran, a behavior ended, or the run
    /// ended. A view that skips frames still shows these.
    pub fn is_eventful(&self) -> bool {
        // Each plan writes one note; any other note is news.
        self.notes.len() > self.plans_in_tick as usize || self.is_over()
    }

    fn present_obstacles(&self) -> Vec<bool> {
        let world = &self.sim.world;
        world
            .timed_obstacles()
            .iter()
            .map(|o| o.is_present(world.now()))
            .collect()
    }

    fn note_obstacles(&self, before: &[bool]) {
        let now = self.present_obstacles();
        for ((obstacle, was), is) in self.sim.world.timed_obstacles().iter().zip(before).zip(now) {
            match (was, is) {
                (false, true) => self
                    .log
                    .push(format!("an obstacle appears in cell {}", obstacle.cell)),
                (true, false) => self
                    .log
                    .push(format!("the obstacle in cell {} is gone", obstacle.cell)),
                _ => {}
            }
        }
    }

    /// What the demo is about, to show before the first frame: the tree, the goal, the
    /// obstacle, the legend.
    pub fn intro(&self) -> String {
        let goal = self.scenario.goal;
        let (success, failure) = if self.unicode {
            ("[✓]", "[✗]")
        } else {
            ("[S]", "[F]")
        };
        let obstacle = match self.scenario.obstacle {
            Some(o) => {
                let stays = match o.vanishes {
                    Some(gone) => format!("until {:.1} s", gone.as_secs_f64()),
                    None => "for good".to_string(),
                };
                format!(
                    "an obstacle steps into cell {} at {:.1} s, {stays}",
                    o.cell,
                    o.appears.as_secs_f64()
                )
            }
            None if self.unreachable => "no obstacle (the goal cannot be reached)".to_string(),
            None => "no obstacle".to_string(),
        };
        format!(
            "NeuroTree demo: Nav2's navigator drives a simulated robot\n\
             tree      {}\n\
             goal      ({:.2}, {:.2}) m\n\
             seed      {}: {obstacle}\n\
             map       {LEGEND}\n\
             statuses  [R] running  {success} success  {failure} failure  [ ] idle\n",
            self.tree_file, goal.x, goal.y, self.scenario.seed,
        )
    }

    /// The frame of the last tick: the tick, the time, the outcome so far, the world
    /// with the current plan and the goal, the tree with the statuses of the tick, and
    /// what happened.
    pub fn frame(&self, layout: Layout) -> String {
        let world = &self.sim.world;
        let robot = world.robot();
        let plan = self.plan_ahead();
        let rendered = world.render_with(&plan, Some(self.scenario.goal));
        // The world's own status line is wider than the map; the head says it shorter.
        let map = rendered.split_once('\n').map_or("", |(_, map)| map);
        let recoveries = self.recoveries.total();
        // Each line no wider than the map, for the side-by-side layout.
        let head = [
            format!(
                "tick {:<4}  t = {:5.1} s   {}",
                self.ticks,
                world.now().as_secs_f64(),
                self.status
            ),
            format!(
                "robot ({:.2}, {:.2})  heading {}°",
                robot.x,
                robot.y,
                // + 0.0 turns -0 into 0, which prints without a sign.
                robot.theta.to_degrees().round() + 0.0,
            ),
            format!("motion {}", world.motion_status()),
            format!(
                "{:.1} m   {} replans   {} recover{}",
                world.distance_travelled(),
                self.sim.replans(),
                recoveries,
                if recoveries == 1 { "y" } else { "ies" }
            ),
        ];
        let tree = self.seen.render(self.tree.blueprint(), self.unicode);
        Parts {
            head: &head,
            map,
            tree: &tree,
            notes: &self.notes,
        }
        .compose(layout)
    }

    /// The latest plan from the pose nearest the robot on.
    fn plan_ahead(&self) -> Vec<Pose2D> {
        plan_ahead(&self.tree, &self.sim.world)
    }

    /// How the run went so far.
    pub fn summary(&self) -> DemoSummary {
        let world = &self.sim.world;
        DemoSummary {
            outcome: self.status,
            ticks: self.ticks,
            time: world.now(),
            distance: world.distance_travelled(),
            replans: self.sim.replans(),
            recoveries: self.recoveries.total(),
            recovery_runs: self.recoveries.branches(),
            pose: world.robot(),
            goal: self.scenario.goal,
            error: self.error.clone(),
            error_codes: self.error_codes(),
            within_tolerance: (self.status == Status::Running && self.duration_over())
                .then(|| self.within_tolerance()),
        }
    }

    /// The root's nonzero `…_error_code` entries with their messages, in name order.
    fn error_codes(&self) -> Vec<(String, u16, String)> {
        let blackboard = self.tree.blackboard();
        let mut codes: Vec<(String, u16, String)> = blackboard
            .keys()
            .filter_map(|key| {
                let stem = key.strip_suffix("_error_code")?;
                let code = blackboard.get::<u16>(key).ok().filter(|c| *c != 0)?;
                let message = blackboard
                    .get::<String>(&format!("{stem}_error_msg"))
                    .unwrap_or_default();
                Some((key.to_string(), code, message))
            })
            .collect();
        codes.sort();
        codes
    }

    /// Whether the robot is within the goal tolerance of the end of the path it follows
    /// (or of the goal, when it follows none).
    fn within_tolerance(&self) -> bool {
        let world = &self.sim.world;
        let target = world
            .followed_path()
            .and_then(|path| path.poses.last().copied())
            .unwrap_or(self.scenario.goal);
        world.robot().distance(&target) <= self.sim.params.goal_tolerance
    }
}
