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

/// What `--groot`, `--groot-bind`, `--groot-linger` and `--groot-pace-ms` asked for.
pub struct GrootOptions {
    /// The request port; notifications go to the next one. 0 picks a free pair.
    pub port: u16,
    /// The address to listen on: loopback unless widened.
    pub bind: IpAddr,
    /// How long to keep serving once the run ended.
    pub linger: Duration,
    /// Wall time each tick waits, so that a client can follow.
    pub pace: Duration,
}

/// A monitor being served for one run.
pub struct Served {
    monitor: Groot2Monitor,
    server: Groot2Server,
    linger: Duration,
    pace: Duration,
}

impl Served {
    /// Serves a monitor of `blueprint`, whose main tree `tree_id` names.
    pub fn start(
        blueprint: &Blueprint<()>,
        registry: &Registry<()>,
        tree_id: &str,
        opts: &GrootOptions,
    ) -> Result<Served, GrootError> {
        let monitor = Groot2Monitor::new(blueprint, registry, tree_id);
        let server = monitor.serve_on(opts.bind, opts.port)?;
        Ok(Served {
            monitor,
            server,
            linger: opts.linger,
            pace: opts.pace,
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
