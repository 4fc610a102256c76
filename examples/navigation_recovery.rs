//! Navigation with recovery: escalating recoveries, loaded from BehaviorTree.CPP XML.
//!
//! A rover drives to a goal. When the drive fails, it tries ever stronger recoveries, each
//! followed by a new attempt, as in Colledanchise & Ögren's *Behavior Trees in Robotics and
//! AI*:
//!
//! 1. normal navigation;
//! 2. clear the costmap, wait for the sensors to refill it, and retry;
//! 3. back up, and retry;
//! 4. signal a human and wait for help (within a time limit), and retry.
//!
//! The tree is the XML below, as Groot2 or a Nav2 user would write it. The rover's leaves
//! are registered in a [`Registry`] with their ports, and [`XmlLoader`] checks the file
//! against them before anything runs.
//!
//! The world is scripted: the first `blocked_attempts` drives get stuck after two steps,
//! and a human, once called, arrives after `help_after` and clears the way. Each scenario
//! therefore reaches a different level of the escalation. Time is a [`ManualClock`]
//! advanced by [`TICK`] per tick, so the waits (Sleep, Timeout) are exact and every run is
//! the same.
//!
//! Run it with `cargo run -p neurotree --example navigation_recovery [SCENARIO]`, where
//! SCENARIO is `normal`, `clear-costmap`, `back-up`, `ask-for-help` or `no-help` (all of
//! them without an argument).

use std::fmt;
use std::sync::Arc;
use std::time::Duration;

use neurotree::render::LastTickStatuses;
use neurotree::robotics::Pose2D;
use neurotree::{
    BlackboardError, Handle, LoadError, ManualClock, NodeStatus, PortSpec, Registry, RegistryError,
    StatefulAction, Status, TickError, Tree, XmlLoader,
};

/// The tree: a Fallback over the four levels of the escalation.
pub const NAVIGATION_XML: &str = r#"
<root BTCPP_format="4" main_tree_to_execute="NavigateWithRecovery">
  <BehaviorTree ID="NavigateWithRecovery">
    <Fallback name="navigate_with_recovery">
      <NavigateToGoal name="navigate" goal="{goal}"/>
      <Sequence name="clear_costmap_and_retry">
        <ClearCostmap/>
        <Sleep name="let_the_costmap_refill" msec="1000"/>
        <NavigateToGoal name="navigate_after_clearing" goal="{goal}"/>
      </Sequence>
      <Sequence name="back_up_and_retry">
        <BackUp distance="0.5"/>
        <NavigateToGoal name="navigate_after_backing_up" goal="{goal}"/>
      </Sequence>
      <Sequence name="ask_for_help">
        <SignalHuman message="stuck on the way to the goal"/>
        <Timeout name="help_deadline" msec="5000">
          <WaitForHelp/>
        </Timeout>
        <NavigateToGoal name="navigate_after_help" goal="{goal}"/>
      </Sequence>
    </Fallback>
  </BehaviorTree>
</root>
"#;

/// Where the rover is sent.
pub const GOAL: Pose2D = Pose2D::new(4.0, 0.0, 0.0);
/// Metres driven per tick towards the goal.
pub const DRIVE_STEP: f64 = 0.5;
/// Metres backed up per tick.
pub const BACKUP_STEP: f64 = 0.25;
/// A blocked drive notices it is stuck after this many steps.
pub const STEPS_BEFORE_STUCK: u32 = 2;
/// Simulated time between two ticks.
pub const TICK: Duration = Duration::from_millis(250);
/// A run stops after this many ticks whatever happens.
pub const MAX_TICKS: u32 = 100;

/// What the world does during a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// How many drives, from the first, get stuck.
    pub blocked_attempts: u32,
    /// How long a human takes to arrive once called; `None`: nobody comes.
    pub help_after: Option<Duration>,
}

/// The scenarios `main` knows by name: one per level of the escalation, and one where the
/// last level fails too.
pub fn scenarios() -> [(&'static str, Scenario); 5] {
    let help = Some(Duration::from_secs(2));
    let blocked = |n| Scenario {
        blocked_attempts: n,
        help_after: help,
    };
    [
        ("normal", blocked(0)),
        ("clear-costmap", blocked(1)),
        ("back-up", blocked(2)),
        ("ask-for-help", blocked(3)),
        (
            "no-help",
            Scenario {
                blocked_attempts: 3,
                help_after: None,
            },
        ),
    ]
}

/// A level of the escalation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Recovery {
    /// Normal navigation sufficed.
    Normal,
    /// The costmap was cleared.
    ClearCostmap,
    /// The rover backed up.
    BackUp,
    /// A human was called.
    AskForHelp,
}

/// What a run produced.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The root's status on the last tick.
    pub status: Status,
    /// Ticks made.
    pub ticks: u32,
    /// The highest level of the escalation that ran.
    pub level: Recovery,
    /// Drives started.
    pub attempts: u32,
    /// Times the costmap was cleared.
    pub costmap_clears: u32,
    /// Back-ups made.
    pub backups: u32,
    /// Calls for help.
    pub help_calls: u32,
    /// The actions halted while running, in order.
    pub halted: Vec<String>,
    /// Where the rover ended.
    pub pose: Pose2D,
    /// The time of the last tick.
    pub elapsed: Duration,
}

/// The rover and its scripted surroundings: the context `C` the leaves receive.
#[derive(Debug)]
pub struct Rover {
    pose: Pose2D,
    blocked_attempts: u32,
    help_after: Option<Duration>,
    /// When a human was called, if one was.
    help_called_at: Option<Duration>,
    helper_present: bool,
    attempts: u32,
    level: Recovery,
    costmap_clears: u32,
    backups: u32,
    help_calls: u32,
    halted: Vec<String>,
    /// What happened during the current tick, for the log.
    events: Vec<String>,
}

impl Rover {
    fn new(scenario: &Scenario) -> Self {
        Self {
            pose: Pose2D::new(0.0, 0.0, 0.0),
            blocked_attempts: scenario.blocked_attempts,
            help_after: scenario.help_after,
            help_called_at: None,
            helper_present: false,
            attempts: 0,
            level: Recovery::Normal,
            costmap_clears: 0,
            backups: 0,
            help_calls: 0,
            halted: Vec::new(),
            events: Vec::new(),
        }
    }

    /// The world's script, before the tick at `now`: a called human arrives in time and
    /// clears the way.
    fn update(&mut self, now: Duration) {
        let arrival = self.help_called_at.zip(self.help_after).map(|(c, a)| c + a);
        if !self.helper_present && arrival.is_some_and(|at| now >= at) {
            self.helper_present = true;
            self.blocked_attempts = 0;
            self.note("a human arrives and clears the way");
        }
    }

    fn recovered(&mut self, level: Recovery) {
        self.level = self.level.max(level);
        match level {
            Recovery::Normal => {}
            Recovery::ClearCostmap => self.costmap_clears += 1,
            Recovery::BackUp => self.backups += 1,
            Recovery::AskForHelp => self.help_calls += 1,
        }
    }

    fn note(&mut self, event: impl Into<String>) {
        self.events.push(event.into());
    }
}

/// Drives [`DRIVE_STEP`] per tick straight to the `goal` port; a drive the script blocks
/// fails after [`STEPS_BEFORE_STUCK`] steps.
#[derive(Default)]
struct NavigateToGoal {
    goal: Pose2D,
    blocked: bool,
    steps: u32,
}

impl StatefulAction<Rover> for NavigateToGoal {
    fn on_start(&mut self, h: &mut Handle<'_, Rover>) -> Status {
        match h.input::<Pose2D>("goal") {
            Ok(goal) => self.goal = goal,
            Err(e) => {
                h.ctx_mut().note(format!("no goal: {e}"));
                return Status::Failure;
            }
        }
        let rover = h.ctx_mut();
        rover.attempts += 1;
        self.blocked = rover.blocked_attempts > 0;
        if self.blocked {
            rover.blocked_attempts -= 1;
        }
        self.steps = 0;
        let attempt = rover.attempts;
        rover.note(format!("drive {attempt} starts"));
        self.on_running(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, Rover>) -> Status {
        let rover = h.ctx_mut();
        if self.blocked && self.steps == STEPS_BEFORE_STUCK {
            rover.note("stuck: the drive fails");
            return Status::Failure;
        }
        rover.pose = step_towards(rover.pose, self.goal, DRIVE_STEP);
        self.steps += 1;
        if rover.pose == self.goal {
            rover.note("goal reached");
            Status::Success
        } else {
            Status::Running
        }
    }

    fn on_halted(&mut self, h: &mut Handle<'_, Rover>) {
        record_halt(h);
    }
}

/// `from` moved `step` metres straight towards `to`, stopping on it.
fn step_towards(from: Pose2D, to: Pose2D, step: f64) -> Pose2D {
    let distance = from.distance(&to);
    if distance <= step {
        return to;
    }
    let k = step / distance;
    Pose2D::new(
        from.x + k * (to.x - from.x),
        from.y + k * (to.y - from.y),
        from.theta,
    )
}

/// Backs up `distance` metres, [`BACKUP_STEP`] per tick.
#[derive(Default)]
struct BackUp {
    target: Pose2D,
}

impl StatefulAction<Rover> for BackUp {
    fn on_start(&mut self, h: &mut Handle<'_, Rover>) -> Status {
        let distance: f64 = match h.input("distance") {
            Ok(d) => d,
            Err(e) => {
                h.ctx_mut().note(format!("cannot back up: {e}"));
                return Status::Failure;
            }
        };
        let rover = h.ctx_mut();
        rover.recovered(Recovery::BackUp);
        let p = rover.pose;
        self.target = Pose2D::new(
            p.x - distance * p.theta.cos(),
            p.y - distance * p.theta.sin(),
            p.theta,
        );
        rover.note(format!("backing up {distance} m"));
        self.on_running(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, Rover>) -> Status {
        let rover = h.ctx_mut();
        rover.pose = step_towards(rover.pose, self.target, BACKUP_STEP);
        if rover.pose == self.target {
            Status::Success
        } else {
            Status::Running
        }
    }

    fn on_halted(&mut self, h: &mut Handle<'_, Rover>) {
        record_halt(h);
    }
}

/// Running until the called human is there.
struct WaitForHelp;

impl StatefulAction<Rover> for WaitForHelp {
    fn on_start(&mut self, h: &mut Handle<'_, Rover>) -> Status {
        h.ctx_mut().note("waiting for help");
        self.on_running(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, Rover>) -> Status {
        if h.ctx().helper_present {
            Status::Success
        } else {
            Status::Running
        }
    }

    fn on_halted(&mut self, h: &mut Handle<'_, Rover>) {
        record_halt(h);
    }
}

fn record_halt(h: &mut Handle<'_, Rover>) {
    let name = h.name().to_string();
    let rover = h.ctx_mut();
    rover.note(format!("{name} halted"));
    rover.halted.push(name);
}

/// The rover's node types, with the ports the XML may bind.
pub fn registry() -> Result<Registry<Rover>, RegistryError> {
    let mut r = Registry::new();
    r.register_stateful(
        "NavigateToGoal",
        vec![PortSpec::input::<Pose2D>("goal").describe("where to drive: x;y;theta")],
        NavigateToGoal::default,
    )?;
    r.register_action("ClearCostmap", vec![], |h| {
        let rover = h.ctx_mut();
        rover.recovered(Recovery::ClearCostmap);
        rover.note("costmap cleared");
        Status::Success
    })?;
    r.register_stateful(
        "BackUp",
        vec![PortSpec::input::<f64>("distance")
            .default_value("0.3")
            .describe("metres")],
        BackUp::default,
    )?;
    r.register_action(
        "SignalHuman",
        vec![PortSpec::input::<String>("message")],
        |h| {
            let message = h.input::<String>("message").unwrap_or_default();
            let now = h.now();
            let rover = h.ctx_mut();
            rover.recovered(Recovery::AskForHelp);
            rover.help_called_at = Some(now);
            rover.note(format!("calling for help: {message}"));
            Status::Success
        },
    )?;
    r.register_stateful("WaitForHelp", vec![], || WaitForHelp)?;
    Ok(r)
}

/// Why a run could not be made.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The rover's node types could not be registered.
    #[error(transparent)]
    Registry(#[from] RegistryError),
    /// The XML did not load.
    #[error(transparent)]
    Load(#[from] LoadError),
    /// The goal could not be written to the blackboard.
    #[error(transparent)]
    Blackboard(#[from] BlackboardError),
    /// A tick failed.
    #[error(transparent)]
    Tick(#[from] TickError),
}

/// Runs `scenario` until the tree completes, passing each line of a readable log to `log`.
pub fn run(scenario: &Scenario, mut log: impl FnMut(&str)) -> Result<Outcome, RunError> {
    let registry = registry()?;
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(NAVIGATION_XML, "navigation_recovery.xml")?;
    let blueprint = Arc::new(loader.build_main()?);
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(Arc::clone(&blueprint), clock.clone());
    tree.blackboard_mut().set("goal", GOAL)?;
    let seen = LastTickStatuses::new();
    tree.set_observer(seen.clone());
    let mut rover = Rover::new(scenario);

    let mut status = Status::Running;
    let mut ticks = 0;
    let mut drawn_running = Vec::new();
    while ticks < MAX_TICKS {
        rover.update(tree.now());
        ticks += 1;
        status = tree.tick_once(&mut rover)?;
        log(&format!(
            "tick {ticks:>3}  t = {:>4.2} s  rover at x = {:>4.2} m  -> {status}",
            tree.now().as_secs_f64(),
            rover.pose.x,
        ));
        for event in rover.events.drain(..) {
            log(&format!("          {event}"));
        }
        let done = status != Status::Running;
        // Draw the tree when other nodes are running than at the last drawing, and at the end.
        let running = running_nodes(&seen);
        if done || running != drawn_running {
            log(&seen.render(&blueprint, true));
            drawn_running = running;
        }
        if done {
            break;
        }
        clock.advance(TICK);
    }

    Ok(Outcome {
        status,
        ticks,
        level: rover.level,
        attempts: rover.attempts,
        costmap_clears: rover.costmap_clears,
        backups: rover.backups,
        help_calls: rover.help_calls,
        halted: rover.halted,
        pose: rover.pose,
        elapsed: tree.now(),
    })
}

/// Which nodes were Running at the end of the last tick.
fn running_nodes(seen: &LastTickStatuses) -> Vec<bool> {
    let statuses = seen.statuses();
    statuses.iter().map(|s| *s == NodeStatus::Running).collect()
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} after {} ticks ({:?})",
            self.status, self.ticks, self.elapsed
        )?;
        writeln!(f, "  level      {:?}", self.level)?;
        writeln!(f, "  drives     {}", self.attempts)?;
        writeln!(f, "  clearings  {}", self.costmap_clears)?;
        writeln!(f, "  back-ups   {}", self.backups)?;
        writeln!(f, "  help calls {}", self.help_calls)?;
        writeln!(f, "  halted     {:?}", self.halted)?;
        write!(f, "  ended at   x = {} m", self.pose.x)
    }
}

fn main() -> Result<(), RunError> {
    let wanted = std::env::args().nth(1);
    let all = scenarios();
    if let Some(name) = &wanted
        && !all.iter().any(|(n, _)| n == name)
    {
        let names: Vec<&str> = all.iter().map(|(n, _)| *n).collect();
        eprintln!(
            "unknown scenario `{name}`; try one of: {}",
            names.join(", ")
        );
        std::process::exit(2);
    }
    for (name, scenario) in &all {
        if wanted.as_deref().is_some_and(|w| w != *name) {
            continue;
        }
        println!("=== {name}: {scenario:?}\n");
        let outcome = run(scenario, |line| println!("{line}"))?;
        println!("{outcome}\n");
    }
    Ok(())
}
