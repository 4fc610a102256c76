//! `neurotree run --groot PORT`: the run served to Groot2 (and other clients of its
//! protocol) while it goes on, and for a while after it ended.
//!
//! A dry run on the manual clock takes no time, so a client that connects once the run has
//! ended still finds its last statuses and blackboard during the linger time; with a pace,
//! each tick also waits that long in wall time, and a client watches the run unfold. The
//! manual clock, and so every result, is the same either way.

#[cfg(not(feature = "groot"))]
use std::io::{self, Write};
use std::net::IpAddr;
use std::time::Duration;

/// A build without Groot2 support keeps its flags, to refuse them with what to do, but does
/// not offer them in `--help`.
const NOT_IN_BUILD: bool = cfg!(not(feature = "groot"));

/// The flags of `neurotree run` that serve the run to Groot2.
#[derive(clap::Args, Debug)]
pub struct GrootArgs {
    /// Serve the run to Groot2 on PORT (requests; PORT+1 publishes), as BehaviorTree.CPP's
    /// Groot2Publisher does; 0 picks free ports and says which on stderr.
    #[arg(long = "groot", id = "groot", value_name = "PORT", hide = NOT_IN_BUILD)]
    pub port: Option<u16>,
    /// Address the Groot2 server listens on: 127.0.0.1 keeps it to this machine; 0.0.0.0
    /// opens it to every network the machine is on.
    #[arg(
        long = "groot-bind",
        value_name = "ADDR",
        default_value = "127.0.0.1",
        requires = "groot",
        hide = NOT_IN_BUILD
    )]
    pub bind: IpAddr,
    /// Seconds to keep serving Groot2 once the run ended.
    #[arg(long = "groot-linger", value_name = "SECS", default_value = "5", value_parser = seconds, requires = "groot", hide = NOT_IN_BUILD)]
    pub linger: Duration,
    /// Milliseconds of wall time each tick waits while serving Groot2, so that a client
    /// sees the run unfold (the manual clock, and so the results, are the same).
    #[arg(
        long = "groot-pace-ms",
        value_name = "MS",
        default_value_t = 0,
        requires = "groot",
        hide = NOT_IN_BUILD
    )]
    pub pace_ms: u64,
}

/// A number of seconds, fractions allowed.
fn seconds(text: &str) -> Result<Duration, String> {
    text.parse::<f64>()
        .ok()
        .and_then(|s| Duration::try_from_secs_f64(s).ok())
        .ok_or_else(|| format!("`{text}` should be a number of seconds, 0 or more"))
}

#[cfg(feature = "groot")]
mod served;
#[cfg(feature = "groot")]
pub use served::Served;

/// A build without Groot2 support (`--no-default-features`): `--groot` is refused.
#[cfg(not(feature = "groot"))]
pub enum Served {}

#[cfg(not(feature = "groot"))]
impl Served {
    /// Refuses: this build has no Groot2 server.
    pub fn start(
        _: &neurotree::Blueprint<()>,
        _: &neurotree::Registry<()>,
        _: &str,
        _: u16,
        _: &GrootArgs,
    ) -> Result<Served, String> {
        Err("neurotree: this build has no Groot2 monitor; build it with `--features groot`".into())
    }

    /// Never called: no `Served` exists.
    pub fn announce(&self, _: &mut impl Write) -> io::Result<()> {
        match *self {}
    }

    /// Never called: no `Served` exists.
    pub fn monitor(&self) -> Vec<Box<dyn neurotree::Observer>> {
        match *self {}
    }

    /// Never called: no `Served` exists.
    pub fn publish(&self, _: &neurotree::Tree<()>) {
        match *self {}
    }

    /// Never called: no `Served` exists.
    pub fn after_tick(&self, _: &neurotree::Tree<()>) {
        match *self {}
    }

    /// Never called: no `Served` exists.
    pub fn linger(self, _: &mut impl Write) -> io::Result<()> {
        match self {}
    }
}
