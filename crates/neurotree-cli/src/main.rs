//! The `neurotree` command.
//!
//! - `neurotree demo`: Nav2's navigator drives a simulated robot; world and tree drawn live.
//! - `neurotree bench`: quick measurements of tick cost and of many agents per frame.
//! - `neurotree check`: validate BehaviorTree.CPP XML files against the node models.
//! - `neurotree run`: dry-run a BehaviorTree.CPP file with mock leaves, as JSON lines.
//! - `neurotree ros2`: Nav2's navigator and the simulated Nav2 servers as ROS 2 processes
//!   (feature `ros2`, on by default; Rust 1.88).
//! - `neurotree show`: draw a BehaviorTree.CPP file's tree as text, DOT, Mermaid or SVG.

mod bench;
mod check;
mod files;
mod groot;
mod registry;
#[cfg(feature = "ros2")]
mod ros2;
mod run;
mod show;

use std::io::{self, IsTerminal, Write};
use std::process::ExitCode;
use std::time::Duration;

use clap::{Args, Parser, Subcommand};
use neurotree_cli::demo;

/// Behavior trees for robots and game AI.
#[derive(Parser, Debug)]
#[command(name = "neurotree", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run Nav2's navigator tree on a simulated robot in a warehouse, drawing the world and
    /// the tree's statuses as it goes, then a summary.
    Demo(DemoArgs),
    /// Measure tick cost (tree1111) and a frame of many agents, in-process.
    Bench(BenchArgs),
    /// Validate BehaviorTree.CPP XML files: structure, node names, ports, literals.
    Check(CheckArgs),
    /// Tick a BehaviorTree.CPP file with mock leaves and print each tick as JSON.
    #[command(after_help = RUN_AFTER_HELP)]
    Run(RunArgs),
    /// Draw a BehaviorTree.CPP file's tree as text, Graphviz DOT, Mermaid or SVG, with the
    /// statuses of a `run --trace` if given one.
    Show(ShowArgs),
    /// Nav2's navigator and the simulated Nav2 servers as ROS 2 processes on 127.0.0.1.
    #[cfg(feature = "ros2")]
    #[command(subcommand)]
    Ros2(Ros2Command),
}

#[cfg(feature = "ros2")]
#[derive(Subcommand, Debug)]
enum Ros2Command {
    /// Serve the demo's warehouse as Nav2's planner, controller, behavior and costmap
    /// servers (compute_path_to_pose, follow_path, spin, backup, wait, clear_entirely_*).
    Sim {
        /// Picks the obstacle that steps onto the robot's path (as `neurotree demo`).
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// The DDS domain (ROS_DOMAIN_ID).
        #[arg(long, default_value_t = 0)]
        domain: u16,
        /// Simulated seconds per wall second.
        #[arg(long, default_value_t = 1.0, value_parser = parse_positive)]
        time_scale: f64,
        /// Stop after this many seconds [default: run until killed].
        #[arg(long, value_name = "SECS")]
        duration: Option<u64>,
    },
    /// Serve navigate_to_pose: for each goal, tick the tree at 10 Hz with its leaves
    /// calling Nav2's servers over ROS 2; feedback, result; a cancel halts the tree.
    Navigator {
        /// The tree to run [default: Nav2's navigate_to_pose_w_replanning_and_recovery.xml].
        #[arg(long, value_name = "FILE")]
        tree: Option<std::path::PathBuf>,
        /// The DDS domain (ROS_DOMAIN_ID).
        #[arg(long, default_value_t = 0)]
        domain: u16,
        /// Stop after this many seconds [default: run until killed].
        #[arg(long, value_name = "SECS")]
        duration: Option<u64>,
    },
    /// Start `ros2 sim` and `ros2 navigator` as processes, send the robot across the
    /// warehouse, print its progress and a summary, stop both.
    Demo {
        /// Picks the obstacle that steps onto the robot's path.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// The DDS domain (ROS_DOMAIN_ID).
        #[arg(long, default_value_t = 0)]
        domain: u16,
        /// Simulated seconds per wall second.
        #[arg(long, default_value_t = 4.0, value_parser = parse_positive)]
        time_scale: f64,
        /// Give up after this many seconds.
        #[arg(long, value_name = "SECS", default_value_t = 120)]
        timeout: u64,
    },
}

/// A number above zero.
#[cfg(feature = "ros2")]
fn parse_positive(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
        _ => Err(format!("`{text}` should be a number above 0")),
    }
}

/// What `neurotree run --help` says after the options.
const RUN_AFTER_HELP: &str = "\
Several files load together, as BehaviorTree.CPP's registerBehaviorTreeFromFile loads each:
`neurotree run main.xml subtrees.xml` runs a tree that uses the trees of another file. The
tree run is --tree, else the main_tree_to_execute of the first file, else the only tree,
else the only tree that no other tree uses (said on stderr).

Ticks count passes of the root: with `--tick once`, a tick that passes again at once for a
node that asks to be woken (a Repeat, a Retry) counts each pass, and its line carries the
number of its last pass.

The last line is the summary: ticks, final status, per-node ticks and halts in `nodes`
(keyed by node name, nodes sharing a name summed) and in `paths` (keyed by the node's path
from the root, a list with one entry per node of that path, in tree order), and the root
blackboard.

Exit status:
  0  the root ended SUCCESS
  1  the files did not load (or a log could not be written)
  2  the root ended FAILURE or SKIPPED, or a tick failed with an error
  3  --max-ticks stopped the run while it was RUNNING";

#[derive(Args, Debug)]
struct RunArgs {
    /// The file to run, then any files with trees it uses (all loaded into one loader).
    #[arg(required = true, value_name = "FILE")]
    files: Vec<std::path::PathBuf>,
    /// The tree to run (default: main_tree_to_execute of the first file, else the only
    /// tree, else the only tree no other tree uses).
    #[arg(long)]
    tree: Option<String>,
    /// NAME=OUTCOMES: replace the leaves named NAME (else of type NAME) by a mock playing
    /// OUTCOMES, a comma list of SUCCESS, FAILURE, RUNNING, each optionally `*k`. Controls
    /// and decorators are not mocked: a NAME only they have is an error.
    #[arg(long = "mock", value_parser = key_value)]
    mocks: Vec<(String, String)>,
    /// Mock with SUCCESS every leaf without an implementation: unregistered, or known only
    /// from a `TreeNodesModel`. Mocks replace leaves only (Actions, Conditions).
    #[arg(long)]
    mock_unknown: bool,
    /// KEY=VALUE written to the root blackboard first (integer, else float, else
    /// true/false, else text).
    #[arg(long = "set", value_parser = key_value)]
    sets: Vec<(String, String)>,
    /// Stop after this many ticks; every pass of the root counts, including the passes
    /// `--tick once` makes at once for a node that asks to be woken.
    #[arg(long, default_value_t = 100)]
    max_ticks: u32,
    /// `once` re-ticks while a node asks to be woken; `exactly-once` does not.
    #[arg(long, default_value = "once", value_parser = ["once", "exactly-once"])]
    tick: String,
    /// Milliseconds the manual clock advances before every tick (at most a day: the clock
    /// must not run to its end).
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u64).range(0..=MAX_STEP_MS))]
    step_ms: u64,
    /// Also print every status change.
    #[arg(long)]
    trace: bool,
    /// Serve the run to Groot2 on PORT (requests; PORT+1 publishes), as BehaviorTree.CPP's
    /// Groot2Publisher does; 0 picks free ports and says which on stderr.
    #[arg(long, value_name = "PORT")]
    groot: Option<u16>,
    /// Address the Groot2 server listens on: 127.0.0.1 keeps it to this machine; 0.0.0.0
    /// opens it to every network the machine is on.
    #[arg(
        long,
        value_name = "ADDR",
        default_value = "127.0.0.1",
        requires = "groot"
    )]
    groot_bind: std::net::IpAddr,
    /// Seconds to keep serving Groot2 once the run ended.
    #[arg(long, value_name = "SECS", default_value = "5", value_parser = seconds, requires = "groot")]
    groot_linger: Duration,
    /// Milliseconds of wall time each tick waits while serving Groot2, so that a client
    /// sees the run unfold (the manual clock, and so the results, are the same).
    #[arg(long, value_name = "MS", default_value_t = 0, requires = "groot")]
    groot_pace_ms: u64,
    /// After each tick, draw the tree with the statuses of that tick on standard error.
    #[arg(long)]
    view: bool,
    #[command(flatten)]
    observe: run::ObserveArgs,
    #[command(flatten)]
    limits: LoadLimits,
}

/// The longest `--step-ms`: a day, in milliseconds.
const MAX_STEP_MS: u64 = 24 * 60 * 60 * 1000;

/// The bounds on what loading a file may build, shared by `run`, `check` and `show`.
#[derive(Args, Debug)]
struct LoadLimits {
    /// The most nodes a tree may have once its subtrees are expanded (each use of a
    /// subtree is a copy); a file past it is refused at the SubTree that crosses it.
    #[arg(long, value_name = "N", default_value_t = neurotree::xml::DEFAULT_MAX_NODES)]
    max_nodes: usize,
}

#[derive(Args, Debug)]
struct ShowArgs {
    /// The file to draw, then any files with trees it uses (all loaded into one loader).
    #[arg(required = true, value_name = "FILE")]
    files: Vec<std::path::PathBuf>,
    /// The tree to draw (default: main_tree_to_execute of the first file, else the only
    /// tree, else the only tree no other tree uses).
    #[arg(long)]
    tree: Option<String>,
    /// ascii, unicode, dot, mermaid or svg (default: from the extension of --output, else
    /// unicode).
    #[arg(long, short = 'f')]
    format: Option<neurotree::render::Format>,
    /// Write the picture to this file instead of standard output.
    #[arg(long, short = 'o')]
    output: Option<std::path::PathBuf>,
    /// A file whose `TreeNodesModel` declares node types the file uses (repeatable); they
    /// are drawn with their type names, without an implementation.
    #[arg(long = "model")]
    models: Vec<std::path::PathBuf>,
    /// The JSON lines of `neurotree run --trace`: colour each node with the last status it
    /// reached; if the root failed, mark the path that failed with the reasons the trace
    /// gives (text: ` -- failed: REASON`; dot, mermaid, svg: red and wide, reasons in labels).
    #[arg(long)]
    trace: Option<std::path::PathBuf>,
    /// With --trace: the statuses of this tick instead (the last each node reached in it).
    #[arg(long, requires = "trace")]
    tick: Option<u32>,
    /// The JSON that `neurotree run --coverage-json FILE` wrote: mark each node covered,
    /// reached with outcomes not seen, or never reached.
    #[arg(long, value_name = "FILE", conflicts_with = "trace")]
    coverage: Option<std::path::PathBuf>,
    #[command(flatten)]
    limits: LoadLimits,
}

fn key_value(text: &str) -> Result<(String, String), String> {
    text.split_once('=')
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .ok_or_else(|| format!("`{text}` should be NAME=VALUE"))
}

/// A number of seconds, fractions allowed.
fn seconds(text: &str) -> Result<Duration, String> {
    text.parse::<f64>()
        .ok()
        .and_then(|s| Duration::try_from_secs_f64(s).ok())
        .ok_or_else(|| format!("`{text}` should be a number of seconds, 0 or more"))
}

#[derive(Args, Debug)]
struct CheckArgs {
    /// The files to check, each with the trees it uses from the others; every error is
    /// reported (up to 20 per file), and each valid file gets `FILE: ok (N trees)` on stdout.
    #[arg(required = true)]
    files: Vec<std::path::PathBuf>,
    /// A file whose `TreeNodesModel` declares node types the files use (repeatable).
    #[arg(long = "model")]
    models: Vec<std::path::PathBuf>,
    #[command(flatten)]
    limits: LoadLimits,
}

#[derive(Args, Debug)]
struct DemoArgs {
    /// A BehaviorTree.CPP file to run instead of Nav2's navigator; it may use Nav2's control
    /// nodes and the simulated Nav2 leaves (ComputePathToPose, FollowPath, Spin, ...).
    #[arg(long, value_name = "FILE")]
    tree: Option<std::path::PathBuf>,
    /// Where to send the robot, in metres from the map's lower left corner (1 m cells).
    #[arg(long, value_name = "X,Y", value_parser = parse_goal, default_value = "36.5,1.5")]
    goal: neurotree::robotics::Pose2D,
    /// Picks the obstacle that steps onto the robot's path, and whether it leaves again.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Simulated seconds per second of watching; 0 does not wait.
    #[arg(long, default_value_t = 3.0, value_parser = parse_speed)]
    speed: f64,
    /// Do not wait between frames (the same as --speed 0).
    #[arg(long)]
    fast: bool,
    /// Draw every Nth tick (and every tick in which more happens than routine planning)
    /// [default: 2 on a terminal, else 10: one frame per simulated second]
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    every: Option<u32>,
    /// Draw the tree with ascii characters instead of unicode box drawing.
    #[arg(long)]
    ascii: bool,
    /// Stop after this many ticks (of 100 ms) if the navigator has not finished.
    #[arg(long, default_value_t = 3000)]
    max_ticks: u32,
}

/// `X,Y` in metres.
fn parse_goal(text: &str) -> Result<neurotree::robotics::Pose2D, String> {
    let numbers: Result<Vec<f64>, _> = text.split(',').map(|n| n.trim().parse::<f64>()).collect();
    match numbers.as_deref() {
        Ok([x, y]) if x.is_finite() && y.is_finite() => {
            Ok(neurotree::robotics::Pose2D::new(*x, *y, 0.0))
        }
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

#[derive(Args, Debug)]
struct BenchArgs {
    /// One JSON object per benchmark, one per line.
    #[arg(long)]
    json: bool,
    /// Measure for a fifth of the usual time.
    #[arg(long)]
    quick: bool,
    /// Instances in the many-agents benchmark.
    #[arg(long, default_value_t = 100_000, hide = true)]
    agents: usize,
}

/// How a command ended, which [`main`] turns into the exit status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// It did what was asked; a run ended SUCCESS (0).
    Done,
    /// It could not: a file did not load or was invalid, an output could not be written (1).
    Refused,
    /// A run ended FAILURE or SKIPPED, or a tick failed with an error (2).
    RunFailed,
    /// `--max-ticks` stopped a run that was still RUNNING (3).
    Stopped,
}

impl From<bool> for Outcome {
    /// `true` for a command that did what was asked.
    fn from(done: bool) -> Self {
        if done {
            Outcome::Done
        } else {
            Outcome::Refused
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let stdout = io::stdout();
    let animate_allowed = stdout.is_terminal();
    let mut out = stdout.lock();
    let result = match cli.command {
        Command::Demo(args) => {
            let opts = demo::DemoOptions {
                config: demo::DemoConfig {
                    tree: args.tree,
                    goal: args.goal,
                    seed: args.seed,
                    max_ticks: args.max_ticks,
                    unicode: !args.ascii,
                    ..Default::default()
                },
                speed: (!args.fast && args.speed > 0.0).then_some(args.speed),
                every: args.every.unwrap_or(if animate_allowed { 2 } else { 10 }),
                terminal: animate_allowed
                    .then(terminal_size::terminal_size)
                    .flatten()
                    .map(|(w, h)| (usize::from(w.0), usize::from(h.0))),
            };
            demo::run(&opts, &mut out, &mut io::stderr()).map(Outcome::from)
        }
        #[cfg(feature = "ros2")]
        Command::Ros2(command) => match command {
            Ros2Command::Sim {
                seed,
                domain,
                time_scale,
                duration,
            } => ros2::sim(
                seed,
                domain,
                time_scale,
                duration.map(Duration::from_secs),
                &mut out,
            ),
            Ros2Command::Navigator {
                tree,
                domain,
                duration,
            } => ros2::navigator(tree, domain, duration.map(Duration::from_secs), &mut out),
            Ros2Command::Demo {
                seed,
                domain,
                time_scale,
                timeout,
            } => {
                let options = ros2::DemoOptions {
                    seed,
                    domain,
                    time_scale,
                    goal: neurotree_cli::demo::DEFAULT_GOAL,
                    timeout: Duration::from_secs(timeout),
                };
                ros2::demo(&options, &mut out)
            }
        },
        Command::Bench(args) => {
            let opts = bench::BenchOptions {
                quick: args.quick,
                agents: args.agents,
            };
            // A benchmark that ran has nothing to fail on.
            bench::run(&opts, args.json, &mut out).map(|()| Outcome::Done)
        }
        Command::Run(args) => {
            let opts = run::RunOptions {
                tree: args.tree,
                mocks: args.mocks,
                mock_unknown: args.mock_unknown,
                sets: args.sets,
                max_ticks: args.max_ticks,
                exactly_once: args.tick == "exactly-once",
                step: Duration::from_millis(args.step_ms),
                trace: args.trace,
                groot: args.groot.map(|port| groot::GrootOptions {
                    port,
                    bind: args.groot_bind,
                    linger: args.groot_linger,
                    pace: Duration::from_millis(args.groot_pace_ms),
                }),
                view: args.view,
                observe: args.observe,
                max_nodes: args.limits.max_nodes,
            };
            run::run(&args.files, &opts, &mut out, &mut io::stderr())
        }
        Command::Show(args) => {
            let opts = show::ShowOptions {
                tree: args.tree,
                format: args.format,
                output: args.output,
                models: args.models,
                trace: args.trace,
                tick: args.tick,
                coverage: args.coverage,
                max_nodes: args.limits.max_nodes,
            };
            show::run(&args.files, &opts, &mut out, &mut io::stderr()).map(Outcome::from)
        }
        Command::Check(args) => {
            let opts = check::CheckOptions {
                models: args.models,
                max_nodes: args.limits.max_nodes,
            };
            check::run(&args.files, &opts, &mut out, &mut io::stderr()).map(Outcome::from)
        }
    };
    match result {
        Ok(Outcome::Done) => ExitCode::SUCCESS,
        // The command has already said why (a load error, an invalid file).
        Ok(Outcome::Refused) => ExitCode::FAILURE,
        Ok(Outcome::RunFailed) => ExitCode::from(2),
        Ok(Outcome::Stopped) => ExitCode::from(3),
        // The reader went away (`neurotree demo | head`): nothing left to tell.
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(e) => {
            let _ = out.flush();
            eprintln!("neurotree: {e}");
            ExitCode::FAILURE
        }
    }
}
