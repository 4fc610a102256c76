//! `neurotree run --groot PORT`: the run served to Groot2 (and other clients of its
//! protocol) while it goes on, and for a while after it ended.
//!
//! A dry run on the manual clock takes no time, so a client that connects once the run has
//! ended still finds its last statuses and blackboard during the linger time; with a pace,
//! each tick also waits that long in wall time, and a client watches the run unfold. The
//! manual clock, and so every result, is the same either way.

use std::io::{self, Write};
use std::net::IpAddr;
use std::time::Duration;

use neurotree::groot::{Groot2Monitor, Groot2Server, GrootError};
use neurotree::{Blueprint, Registry, Tree};

/// The flags of `neurotree run` that serve the run to Groot2.
#[derive(clap::Args, Debug)]
pub struct GrootArgs {
    /// Serve the run to Groot2 on PORT (requests; PORT+1 publishes), as BehaviorTree.CPP's
    /// Groot2Publisher does; 0 picks free ports and says which on stderr.
    #[arg(long = "groot", id = "groot", value_name = "PORT")]
    pub port: Option<u16>,
    /// Address the Groot2 server listens on: 127.0.0.1 keeps it to this machine; 0.0.0.0
    /// opens it to every network the machine is on.
    #[arg(
        long = "groot-bind",
        value_name = "ADDR",
        default_value = "127.0.0.1",
        requires = "groot"
    )]
    pub bind: IpAddr,
    /// Seconds to keep serving Groot2 once the run ended.
    #[arg(long = "groot-linger", value_name = "SECS", default_value = "5", value_parser = seconds, requires = "groot")]
    pub linger: Duration,
    /// Milliseconds of wall time each tick waits while serving Groot2, so that a client
    /// sees the run unfold (the manual clock, and so the results, are the same).
    #[arg(
        long = "groot-pace-ms",
        value_name = "MS",
        default_value_t = 0,
        requires = "groot"
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

/// A monitor being served for one run.
pub struct Served {
    monitor: Groot2Monitor,
    server: Groot2Server,
    linger: Duration,
    pace: Duration,
}

impl Served {
    /// Serves a monitor of `blueprint`, whose main tree `tree_id` names, on `port` (the
    /// one `--groot` gave) as `opts` says.
    pub fn start(
        blueprint: &Blueprint<()>,
        registry: &Registry<()>,
        tree_id: &str,
        port: u16,
        opts: &GrootArgs,
    ) -> Result<Served, GrootError> {
        let monitor = Groot2Monitor::new(blueprint, registry, tree_id);
        let server = monitor.serve_on(opts.bind, port)?;
        Ok(Served {
            monitor,
            server,
            linger: opts.linger,
            pace: Duration::from_millis(opts.pace_ms),
        })
    }

    /// Tells on `err` where clients connect (the port chosen, when asked for any).
    pub fn announce(&self, err: &mut impl Write) -> io::Result<()> {
        let address = self.server.local_addr();
        writeln!(
            err,
            "neurotree: Groot2 monitor on tcp://{address} (publisher on port {})",
            u32::from(address.port()) + 1
        )
    }

    /// The observer to attach to the tree.
    pub fn monitor(&self) -> Groot2Monitor {
        self.monitor.clone()
    }

    /// Shows clients the blackboard as it now is.
    pub fn publish(&self, tree: &Tree<()>) {
        self.monitor.publish_blackboard(tree);
    }

    /// After a tick: the blackboard as it now is, then the pause, if any.
    pub fn after_tick(&self, tree: &Tree<()>) {
        self.publish(tree);
        if !self.pace.is_zero() {
            std::thread::sleep(self.pace);
        }
    }

    /// Keeps serving for the linger time, then stops.
    pub fn linger(self, err: &mut impl Write) -> io::Result<()> {
        if !self.linger.is_zero() {
            writeln!(
                err,
                "neurotree: the run ended; serving Groot2 for {} s more",
                self.linger.as_secs_f64()
            )?;
            std::thread::sleep(self.linger);
        }
        self.server.stop();
        Ok(())
    }
}
