//! `neurotree demo`: the flags of the warehouse demo, and how they set up the run of
//! [`neurotree_cli::demo`], which paces and draws it.

use std::io::{self, IsTerminal, Write};
use std::path::PathBuf;
use std::time::Duration;

use neurotree::robotics::Pose2D;
use neurotree_cli::demo;

use crate::Outcome;

/// What `neurotree demo` was asked to do.
#[derive(clap::Args, Debug)]
pub struct DemoArgs {
    /// A BehaviorTree.CPP file to run instead of Nav2's navigator; it may use Nav2's control
    /// nodes and the simulated Nav2 leaves (ComputePathToPose, FollowPath, Spin, ...).
    #[arg(long, value_name = "FILE")]
    pub tree: Option<PathBuf>,
    /// Where to send the robot, in metres from the map's lower left corner (1 m cells).
    #[arg(long, value_name = "X,Y", value_parser = parse_goal, default_value = "36.5,1.5")]
    pub goal: Pose2D,
    /// Picks the obstacle that steps onto the robot's path, and whether it leaves again.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Simulated seconds per second of watching; 0 does not wait.
    #[arg(long, default_value_t = 3.0, value_parser = parse_speed)]
    pub speed: f64,
    /// Draw no frames before the last one, and do not wait.
    #[arg(long)]
    pub fast: bool,
    /// Draw every Nth tick (and every tick in which more happens than routine planning)
    /// [default: 2 on a terminal, else 10: one frame per simulated second]
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub every: Option<u32>,
    /// Draw the tree with ascii characters instead of unicode box drawing.
    #[arg(long)]
    pub ascii: bool,
    /// Stop after this many ticks (of 100 ms) if the navigator has not finished (exit 3).
    #[arg(long, default_value_t = 3000)]
    pub max_ticks: u32,
    /// Run for this many simulated seconds, for a tree that never ends by itself (Nav2's
    /// follow_point.xml): still running then, it succeeds if the robot is within the goal
    /// tolerance of the end of the path it follows.
    #[arg(long, value_name = "SECONDS", value_parser = parse_duration)]
    pub duration: Option<Duration>,
    /// The robot's heading at the start, in degrees counter-clockwise from east (0: facing
    /// the store; -90: facing south, as Nav2's odometry_calibration.xml needs to drive its
    /// square inside the warehouse).
    #[arg(
        long,
        value_name = "DEGREES",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pub heading: f64,
    /// Leave the seed's obstacle out: a tree without recoveries cannot get past one.
    #[arg(long)]
    pub no_obstacle: bool,
    #[command(flatten)]
    pub studio: crate::studio::StudioFlags,
    /// The battery's charge at the start, in percent; under 100 the robot, which starts on
    /// its dock, is charging (Nav2's docking example then undocks first).
    #[arg(long, value_name = "PERCENT", default_value_t = 100.0, value_parser = parse_battery)]
    pub battery: f64,
}

/// A charge in percent, 0 to 100.
fn parse_battery(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(level) if (0.0..=100.0).contains(&level) => Ok(level),
        _ => Err(format!("`{text}` should be a percentage from 0 to 100")),
    }
}

/// A number of seconds, more than 0.
fn parse_duration(text: &str) -> Result<Duration, String> {
    match text.trim().parse::<f64>() {
        Ok(seconds) if seconds > 0.0 && seconds.is_finite() => {
            Duration::try_from_secs_f64(seconds).map_err(|e| format!("`{text}`: {e}"))
        }
        _ => Err(format!("`{text}` should be a number of seconds above 0")),
    }
}

/// `X,Y` in metres.
fn parse_goal(text: &str) -> Result<Pose2D, String> {
    let numbers: Result<Vec<f64>, _> = text.split(',').map(|n| n.trim().parse::<f64>()).collect();
    match numbers.as_deref() {
        Ok([x, y]) if x.is_finite() && y.is_finite() => Ok(Pose2D::new(*x, *y, 0.0)),
        _ => Err(format!("`{text}` should be two numbers X,Y (metres)")),
    }
}

/// A speed: a number, zero or more.
fn parse_speed(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(speed) if speed >= 0.0 && speed.is_finite() => Ok(speed),
        _ => Err(format!("`{text}` should be a number of 0 or more")),
    }
}

/// Runs the demo, animated in place when standard output is a terminal, else one frame
/// after another. Done when the navigation succeeded; RunFailed when it failed (the summary
/// prints Nav2's error codes); Stopped when `--max-ticks` ended it unfinished; Refused when
/// the tree did not load.
pub fn execute(args: DemoArgs, out: &mut impl Write) -> io::Result<Outcome> {
    let animate_allowed = io::stdout().is_terminal();
    let opts = demo::DemoOptions {
        config: demo::DemoConfig {
            tree: args.tree,
            goal: args.goal,
            seed: args.seed,
            max_ticks: args.max_ticks,
            unicode: !args.ascii,
            obstacle: !args.no_obstacle,
            duration: args.duration,
            start_heading: args.heading.to_radians(),
            battery: args.battery,
            ..Default::default()
        },
        speed: (!args.fast && args.speed > 0.0).then_some(args.speed),
        every: args.every.unwrap_or(if animate_allowed { 2 } else { 10 }),
        frames_between: !args.fast,
        terminal: animate_allowed
            .then(terminal_size::terminal_size)
            .flatten()
            .map(|(w, h)| (usize::from(w.0), usize::from(h.0))),
    };
    let mut err = io::stderr();
    let files: Vec<std::path::PathBuf> = opts.config.tree.iter().cloned().collect();
    let nav2 = crate::registry::Nav2Args {
        nav2: Some(neurotree::nav2::Nav2Release::Main),
    };
    let summary = match crate::studio::Served::start(&args.studio, &files, nav2, &mut err)? {
        Err(()) => return Ok(Outcome::Refused),
        Ok(None) => demo::run(&opts, out, &mut err)?,
        Ok(Some(served)) => crate::studio::run_demo(served, &opts, out, &mut err)?,
    };
    Ok(match summary {
        None => Outcome::Refused,
        Some(summary) if summary.succeeded() => Outcome::Done,
        Some(summary)
            if summary.outcome == neurotree::Status::Running
                && summary.within_tolerance.is_none()
                && summary.error.is_none() =>
        {
            Outcome::Stopped
        }
        Some(_) => Outcome::RunFailed,
    })
}
