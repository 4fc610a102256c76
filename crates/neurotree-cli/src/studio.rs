//! `neurotree studio`: the browser studio on the files given, and `--studio PORT` for
//! `run` and `demo`, which serve their run to it (see the `neurotree-studio` crate).
//!
//! The studio serves the folder the command was started in: the page opens, saves and
//! replays files there only. The URL is printed on stderr on a line of its own,
//! `studio: http://127.0.0.1:PORT/` (with `?token=…` when `--bind` opens it beyond this
//! machine).

#[cfg(not(feature = "studio"))]
use std::io::{self, Write};
use std::net::IpAddr;
use std::path::PathBuf;
use std::time::Duration;

use crate::registry::Nav2Args;
#[cfg(not(feature = "studio"))]
use crate::Outcome;

/// What `neurotree studio` was asked to do.
#[derive(clap::Args, Debug)]
pub struct StudioArgs {
    /// Files to open at start: trees (.xml) in the editor, logs (.jsonl, .btlog, .db) and
    /// coverage (.json) in replay. They must be inside the current folder.
    pub files: Vec<PathBuf>,
    /// A file whose `TreeNodesModel` declares node types the files use (repeatable).
    #[arg(long = "model")]
    pub models: Vec<PathBuf>,
    #[command(flatten)]
    pub nav2: Nav2Args,
    /// The port to serve on; 0 picks a free one.
    #[arg(long, default_value_t = 8877)]
    pub port: u16,
    /// The address to listen on: 127.0.0.1 keeps the studio to this machine; any other
    /// (0.0.0.0 for every network) makes it ask for the token in the URL it prints.
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1")]
    pub bind: IpAddr,
}

/// A build without the studio keeps its flags, to refuse them with what to do, but does not
/// offer them in `--help`.
const NOT_IN_BUILD: bool = cfg!(not(feature = "studio"));

/// The flags of `run` and `demo` that serve their run to the studio.
#[derive(clap::Args, Debug, Clone)]
pub struct StudioFlags {
    /// Serve the run to the studio on PORT (0 picks a free one): open the URL printed on
    /// stderr to watch it, set breakpoints, pause, step and edit its blackboards.
    #[arg(long = "studio", id = "studio", value_name = "PORT", hide = NOT_IN_BUILD)]
    pub port: Option<u16>,
    /// Address the studio listens on (see `neurotree studio --bind`).
    #[arg(
        long = "studio-bind",
        id = "studio_bind",
        value_name = "ADDR",
        default_value = "127.0.0.1",
        requires = "studio",
        hide = NOT_IN_BUILD
    )]
    pub bind: IpAddr,
    /// Seconds to keep serving the studio once the run ended, so that a page still shows
    /// its last statuses.
    #[arg(long = "studio-linger", id = "studio_linger", value_name = "SECS", default_value = "5", value_parser = seconds, requires = "studio", hide = NOT_IN_BUILD)]
    pub linger: Duration,
    /// Ticks whose state the run keeps, so that a paused page can go back to them and fork
    /// the run there (0: none).
    #[arg(
        long = "rewind-window",
        id = "rewind_window",
        value_name = "N",
        default_value_t = 300,
        value_parser = clap::value_parser!(u32).range(0..=1_000_000),
        requires = "studio",
        hide = NOT_IN_BUILD
    )]
    pub rewind_window: u32,
}

/// A number of seconds, fractions allowed.
fn seconds(text: &str) -> Result<Duration, String> {
    text.parse::<f64>()
        .ok()
        .and_then(|s| Duration::try_from_secs_f64(s).ok())
        .ok_or_else(|| format!("`{text}` should be a number of seconds, 0 or more"))
}

#[cfg(feature = "studio")]
mod served;
#[cfg(feature = "studio")]
pub use served::{execute, run_demo, Served};

/// A build without the studio (`--no-default-features`): `studio` and `--studio` are
/// refused with what to do.
#[cfg(not(feature = "studio"))]
pub const NOT_BUILT: &str =
    "neurotree: this build has no studio; build it with `--features studio` (on by default)";

/// Refuses: this build has no studio.
#[cfg(not(feature = "studio"))]
pub fn execute(_: &StudioArgs, err: &mut impl Write) -> io::Result<Outcome> {
    writeln!(err, "{NOT_BUILT}")?;
    Ok(Outcome::Refused)
}

/// A build without the studio: no run is ever served.
#[cfg(not(feature = "studio"))]
pub enum Served {}

#[cfg(not(feature = "studio"))]
impl Served {
    /// Refuses when asked for (`--studio` given), else serves nothing.
    pub fn start(
        flags: &StudioFlags,
        _: &[PathBuf],
        _: Nav2Args,
        err: &mut impl Write,
    ) -> io::Result<Result<Option<Served>, ()>> {
        Ok(match flags.port {
            Some(_) => {
                writeln!(err, "{NOT_BUILT}")?;
                Err(())
            }
            None => Ok(None),
        })
    }

    /// Never called: no `Served` exists.
    pub fn force_hooks<C: 'static>(
        &self,
        _: Option<neurotree::xml::SharedHookWrapper<C>>,
    ) -> neurotree::xml::SharedHookWrapper<C> {
        match *self {}
    }

    /// Never called: no `Served` exists.
    pub fn forced(&mut self) -> Vec<serde_json::Value> {
        match *self {}
    }

    /// Never called: no `Served` exists.
    pub fn attach<C>(&mut self, _: &neurotree::Tree<C>, _: &str) -> Box<dyn neurotree::Observer> {
        match *self {}
    }

    /// Never called: no `Served` exists.
    #[cfg(feature = "ros2")]
    pub fn between_nav2_ticks<C>(&mut self, _: &mut neurotree::Tree<C>) -> Option<u64> {
        match *self {}
    }

    /// Never called: no `Served` exists.
    pub fn between_ticks_with<C, W>(
        &mut self,
        _: &mut neurotree::Tree<C>,
        _: &mut W,
    ) -> Option<u64> {
        match *self {}
    }

    /// Never called: no `Served` exists.
    pub fn reattach<C>(&mut self, _: &neurotree::Tree<C>, _: &str) {
        match *self {}
    }

    /// Never called: no `Served` exists.
    pub fn end<C>(&mut self, _: &mut neurotree::Tree<C>, _: neurotree::Status) {
        match *self {}
    }

    /// Never called: no `Served` exists.
    pub fn linger(self, _: &mut impl Write) -> io::Result<()> {
        match self {}
    }
}

/// Never called: no `Served` exists.
#[cfg(not(feature = "studio"))]
pub fn run_demo(
    served: Served,
    _: &neurotree_cli::demo::DemoOptions,
    _: &mut impl Write,
    _: &mut impl Write,
) -> io::Result<Option<neurotree_cli::demo::DemoSummary>> {
    match served {}
}
