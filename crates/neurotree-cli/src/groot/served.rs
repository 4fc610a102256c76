//! The Groot2 monitor a run serves.

use std::io::{self, Write};
use std::time::Duration;

use neurotree::groot::{Groot2Monitor, Groot2Server, GrootError};
use neurotree::{Blueprint, Registry, Tree};

use super::GrootArgs;

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
