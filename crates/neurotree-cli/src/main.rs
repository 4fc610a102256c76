//! The `neurotree` command.
//!
//! - `neurotree demo`: Nav2's navigator drives a simulated robot; world and tree drawn live.
//! - `neurotree bench`: quick measurements of tick cost, of many agents per frame, and of a
//!   crowd of them on every core.
//! - `neurotree campaign`: a tree through many worlds and faults on every core, each result
//!   a row of a SQLite file; reports, replays, merges shards.
//! - `neurotree check`: validate BehaviorTree.CPP XML files against the node models.
//! - `neurotree lint`: `check`, then static analysis: data flow, reachability, liveness.
//! - `neurotree run`: dry-run a BehaviorTree.CPP file with mock leaves, as JSON lines.
//! - `neurotree ros2`: Nav2's navigator and the simulated Nav2 servers as ROS 2 processes
//!   (feature `ros2`, on by default; Rust 1.88).
//! - `neurotree test`: run scenario files (mocks, inputs, expectations per tick) as tests.
//! - `neurotree show`: draw a BehaviorTree.CPP file's tree as text, DOT, Mermaid or SVG.
//! - `neurotree studio`: see, edit, watch and replay trees in the browser (feature `studio`).
//! - `neurotree mcp`: a Model Context Protocol server, so an assistant can use the commands.
//! - `neurotree models`: write the TreeNodesModel of Nav2's node types.
//!
//! Each command's flags and what it does are in its own module, so that a command reads in
//! one file; here the command line is only parsed and handed over, and the outcome turned
//! into the exit status.

#![forbid(unsafe_code)]

mod bench;
mod campaign_command;
mod check;
mod demo_command;
mod files;
mod groot;
mod lint;
mod live;
mod mcp;
mod models;
mod registry;
#[cfg(feature = "ros2")]
mod ros2;
mod run;
mod show;
mod studio;
mod test;
mod testbench;

use std::io::{self, Write};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

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
    Demo(demo_command::DemoArgs),
    /// Measure tick cost (tree1111), a frame of many agents, and a crowd on every core, in-process.
    Bench(bench::BenchArgs),
    /// Run a tree through the worlds and faults of a campaign file on every core, each
    /// result a row of a SQLite file; report on it, replay a variant, merge shards.
    #[command(subcommand)]
    Campaign(campaign_command::CampaignCommand),
    /// Validate BehaviorTree.CPP XML files: structure, node names, ports, literals.
    Check(check::CheckArgs),
    /// Check BehaviorTree.CPP XML files, then find what they do wrong without running them:
    /// blackboard data flow, unreachable children, loops that never end.
    Lint(lint::LintArgs),
    /// Tick a BehaviorTree.CPP file with mock leaves and print each tick as JSON.
    Run(Box<run::RunArgs>),
    /// Run scenario files: a tree with mocks, inputs and expectations per tick; reports as
    /// `cargo test` does.
    Test(test::TestArgs),
    /// Draw a BehaviorTree.CPP file's tree as text, Graphviz DOT, Mermaid or SVG, with the
    /// statuses of a `run --trace` if given one.
    Show(show::ShowArgs),
    /// See, edit, watch and replay behavior trees in the browser: serves a page on
    /// 127.0.0.1 and prints its URL on stderr.
    #[command(hide = cfg!(not(feature = "studio")))]
    Studio(studio::StudioArgs),
    /// Serve the Model Context Protocol on stdin/stdout: tools to check, lint, draw and run
    /// trees, for an assistant.
    Mcp(mcp::McpArgs),
    /// Write the TreeNodesModel of Nav2's node types (--nav2), for Groot2 and the studio.
    Models(models::ModelsArgs),
    /// Nav2's navigator and the simulated Nav2 servers as ROS 2 processes on 127.0.0.1.
    #[cfg(feature = "ros2")]
    #[command(subcommand)]
    Ros2(ros2::Ros2Command),
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
    let mut out = stdout.lock();
    let result = match cli.command {
        Command::Demo(args) => demo_command::execute(args, &mut out),
        #[cfg(feature = "ros2")]
        Command::Ros2(command) => ros2::execute(command, &mut out),
        Command::Bench(args) => bench::execute(&args, &mut out),
        Command::Campaign(command) => {
            campaign_command::execute(command, &mut out, &mut io::stderr())
        }
        Command::Run(args) => run::execute(&args, &mut out, &mut io::stderr()),
        Command::Test(args) => test::execute(&args, &mut out, &mut io::stderr()),
        Command::Show(args) => show::execute(&args, &mut out, &mut io::stderr()),
        Command::Check(args) => check::execute(&args, &mut out, &mut io::stderr()),
        Command::Lint(args) => lint::execute(&args, &mut out, &mut io::stderr()),
        Command::Studio(args) => studio::execute(&args, &mut io::stderr()),
        Command::Mcp(args) => mcp::execute(&args, &mut io::stderr()),
        Command::Models(args) => models::execute(&args, &mut out, &mut io::stderr()),
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

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    /// Every command's flags, flattened from several modules, fit together (clap checks
    /// this only when a command is used).
    #[test]
    fn the_command_line_is_consistent() {
        super::Cli::command().debug_assert();
    }

    /// The flags of `command`'s `--help`.
    fn offered(command: &[&str]) -> Vec<String> {
        let mut cli = super::Cli::command();
        let mut help = Vec::new();
        let mut cmd = &mut cli;
        for name in command {
            cmd = cmd.find_subcommand_mut(name).expect("a command");
        }
        cmd.write_long_help(&mut help).expect("help written");
        let help = String::from_utf8(help).expect("UTF-8 help");
        help.split_whitespace()
            .filter(|w| w.starts_with("--"))
            .map(|w| w.trim_end_matches([',', '.']).to_owned())
            .collect()
    }

    /// A build offers in `--help` the flags and commands it has, and no other.
    #[test]
    fn help_offers_what_this_build_has() {
        let has = |command: &[&str], flag: &str| offered(command).iter().any(|f| f == flag);
        for (command, flag) in [
            (&["demo"][..], "--studio"),
            (&["run"], "--studio"),
            (&["run"], "--studio-linger"),
            (&["run"], "--rewind-window"),
        ] {
            assert_eq!(
                has(command, flag),
                cfg!(feature = "studio"),
                "{command:?} {flag}"
            );
        }
        for flag in [
            "--groot",
            "--groot-bind",
            "--groot-linger",
            "--groot-pace-ms",
        ] {
            assert_eq!(has(&["run"], flag), cfg!(feature = "groot"), "run {flag}");
        }
        assert_eq!(has(&["run"], "--sqlite"), cfg!(feature = "sqlite"));
        let mut help = Vec::new();
        super::Cli::command().write_long_help(&mut help).unwrap();
        let help = String::from_utf8(help).unwrap();
        let commands: Vec<&str> = help
            .lines()
            .filter_map(|l| l.split_whitespace().next())
            .collect();
        assert_eq!(commands.contains(&"studio"), cfg!(feature = "studio"));
        assert_eq!(commands.contains(&"ros2"), cfg!(feature = "ros2"));
        assert!(commands.contains(&"demo") && has(&["run"], "--btlog"));
    }
}
