//! The `neurotree` command.
//!
//! - `neurotree demo`: a simulated robot patrols a corridor; its tree is drawn every tick.
//! - `neurotree bench`: quick measurements of tick cost and of many agents per frame.
//! - `neurotree check`: validate BehaviorTree.CPP XML files against the node models.
//! - `neurotree run`: dry-run a BehaviorTree.CPP file with mock leaves, as JSON lines.
//! - `neurotree show`: draw a BehaviorTree.CPP file's tree as text, DOT, Mermaid or SVG.

mod bench;
mod check;
mod demo;
mod registry;
mod run;
mod show;

use std::io::{self, IsTerminal, Write};
use std::process::ExitCode;
use std::time::Duration;

use clap::{Args, Parser, Subcommand};

/// Behavior trees for robots and game AI.
#[derive(Parser, Debug)]
#[command(name = "neurotree", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run a simulated robot on a corridor and draw its tree with the statuses of each tick.
    Demo(DemoArgs),
    /// Measure tick cost (tree1111) and a frame of many agents, in-process.
    Bench(BenchArgs),
    /// Validate BehaviorTree.CPP XML files: structure, node names, ports, literals.
    Check(CheckArgs),
    /// Tick a BehaviorTree.CPP file with mock leaves and print each tick as JSON.
    Run(RunArgs),
    /// Draw a BehaviorTree.CPP file's tree as text, Graphviz DOT, Mermaid or SVG, with the
    /// statuses of a `run --trace` if given one.
    Show(ShowArgs),
}

#[derive(Args, Debug)]
struct RunArgs {
    /// The file to run.
    file: std::path::PathBuf,
    /// The tree to run (default: main_tree_to_execute, or the only tree).
    #[arg(long)]
    tree: Option<String>,
    /// NAME=OUTCOMES: replace nodes named NAME (else of type NAME) by a mock playing
    /// OUTCOMES, a comma list of SUCCESS, FAILURE, RUNNING, each optionally `*k`.
    #[arg(long = "mock", value_parser = key_value)]
    mocks: Vec<(String, String)>,
    /// Mock every unregistered leaf with SUCCESS.
    #[arg(long)]
    mock_unknown: bool,
    /// KEY=VALUE written to the root blackboard first (integer, else float, else
    /// true/false, else text).
    #[arg(long = "set", value_parser = key_value)]
    sets: Vec<(String, String)>,
    /// Stop after this many ticks.
    #[arg(long, default_value_t = 100)]
    max_ticks: u32,
    /// `once` re-ticks while a node asks to be woken; `exactly-once` does not.
    #[arg(long, default_value = "once", value_parser = ["once", "exactly-once"])]
    tick: String,
    /// Milliseconds the manual clock advances before every tick.
    #[arg(long, default_value_t = 100)]
    step_ms: u64,
    /// Also print every status change.
    #[arg(long)]
    trace: bool,
    /// After each tick, draw the tree with the statuses of that tick on standard error.
    #[arg(long)]
    view: bool,
}

#[derive(Args, Debug)]
struct ShowArgs {
    /// The file to draw.
    file: std::path::PathBuf,
    /// The tree to draw (default: main_tree_to_execute, or the only tree).
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
    /// reached.
    #[arg(long)]
    trace: Option<std::path::PathBuf>,
    /// With --trace: the statuses of this tick instead (the last each node reached in it).
    #[arg(long, requires = "trace")]
    tick: Option<u32>,
}

fn key_value(text: &str) -> Result<(String, String), String> {
    text.split_once('=')
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .ok_or_else(|| format!("`{text}` should be NAME=VALUE"))
}

#[derive(Args, Debug)]
struct CheckArgs {
    /// The files to check.
    #[arg(required = true)]
    files: Vec<std::path::PathBuf>,
    /// A file whose `TreeNodesModel` declares node types the files use (repeatable).
    #[arg(long = "model")]
    models: Vec<std::path::PathBuf>,
}

#[derive(Args, Debug)]
struct DemoArgs {
    /// Stop after this many ticks if the patrol has not ended.
    #[arg(long, default_value_t = 200)]
    ticks: u32,
    /// Milliseconds between frames when animating.
    #[arg(long, default_value_t = 150)]
    speed_ms: u64,
    /// Print every frame one after the other, without redrawing or pausing (the default
    /// when the output is not a terminal).
    #[arg(long)]
    no_animation: bool,
    /// Draw the tree with ascii characters instead of unicode box drawing.
    #[arg(long)]
    ascii: bool,
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

fn main() -> ExitCode {
    let cli = Cli::parse();
    let stdout = io::stdout();
    let animate_allowed = stdout.is_terminal();
    let mut out = stdout.lock();
    let result = match cli.command {
        Command::Demo(args) => {
            let opts = demo::DemoOptions {
                max_ticks: args.ticks,
                frame_pause: Duration::from_millis(args.speed_ms),
                animate: animate_allowed && !args.no_animation,
                unicode: !args.ascii,
            };
            demo::run(&opts, &mut out).map(|_| ())
        }
        Command::Bench(args) => {
            let opts = bench::BenchOptions {
                quick: args.quick,
                agents: args.agents,
            };
            bench::run(&opts, args.json, &mut out)
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
                view: args.view,
            };
            return match run::run(&args.file, &opts, &mut out, &mut io::stderr()) {
                Ok(true) => ExitCode::SUCCESS,
                Ok(false) => ExitCode::FAILURE,
                Err(e) if e.kind() == io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
                Err(e) => {
                    eprintln!("neurotree: {e}");
                    ExitCode::FAILURE
                }
            };
        }
        Command::Show(args) => {
            let opts = show::ShowOptions {
                tree: args.tree,
                format: args.format,
                output: args.output,
                models: args.models,
                trace: args.trace,
                tick: args.tick,
            };
            return match show::run(&args.file, &opts, &mut out, &mut io::stderr()) {
                Ok(true) => ExitCode::SUCCESS,
                Ok(false) => ExitCode::FAILURE,
                Err(e) if e.kind() == io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
                Err(e) => {
                    eprintln!("neurotree: {e}");
                    ExitCode::FAILURE
                }
            };
        }
        Command::Check(args) => {
            return match check::run(&args.files, &args.models, &mut io::stderr()) {
                Ok(true) => ExitCode::SUCCESS,
                Ok(false) => ExitCode::FAILURE,
                Err(e) => {
                    eprintln!("neurotree: {e}");
                    ExitCode::FAILURE
                }
            };
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // The reader went away (`neurotree demo | head`): nothing left to tell.
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(e) => {
            let _ = out.flush();
            eprintln!("neurotree: {e}");
            ExitCode::FAILURE
        }
    }
}
