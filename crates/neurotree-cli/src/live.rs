//! What `neurotree run` does with a tree that lives on: its state saved after a tick
//! (`--save-state OUT --stop-after N`), a run resumed from such a state (`--resume FILE`),
//! a state kept every K ticks (`--keep-states K --states-dir DIR`), the files reloaded when
//! they change on disk (`--watch`), and ticks paced in wall time (`--pace-ms MS`).
//!
//! A state file holds everything the run had that the command line does not give again:
//! the tree's state (each mock's place in its outcomes included), the run's tick count, its
//! clock, and the per-node counts its summary reports. The command line gives the tree,
//! the mocks and the options, as it did for the run that saved it.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use neurotree::Tree;
use serde::{Deserialize, Serialize};

/// The options of `neurotree run` for trees that live on.
#[derive(clap::Args, Debug, Default)]
pub struct LiveArgs {
    /// Write the run's state to OUT when it stops (at --stop-after, or at its end), for
    /// `--resume`.
    #[arg(long, value_name = "OUT")]
    pub save_state: Option<PathBuf>,
    /// Stop after tick N (every pass of the root counts, as for --max-ticks).
    #[arg(long, value_name = "N")]
    pub stop_after: Option<u32>,
    /// Go on from a state --save-state or --keep-states wrote, with the same files, mocks
    /// and options: the ticks printed are those the uninterrupted run would have printed
    /// after it, numbered on from it. The state holds the blackboard: a --set given with
    /// --resume changes it after the restore, and another --mock plays from the saved place
    /// in its outcomes: a fork of the run.
    #[arg(long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
    /// Keep the run's state every K ticks, as DIR/tick-N.state (with --states-dir).
    #[arg(long, value_name = "K", requires = "states_dir", value_parser = clap::value_parser!(u32).range(1..))]
    pub keep_states: Option<u32>,
    /// Where --keep-states writes its files (made if missing).
    #[arg(long, value_name = "DIR", requires = "keep_states")]
    pub states_dir: Option<PathBuf>,
    /// Reload the files between two ticks when one changes on disk, keeping the state of
    /// every unchanged node; prints `{"reload":{"kept":K,"restarted":R,"halted":H}}`. A
    /// file that no longer loads is reported and the running tree goes on.
    #[arg(long)]
    pub watch: bool,
    /// Wall-clock milliseconds to wait before each tick, so that a run can be followed by
    /// eye or edited while it runs.
    #[arg(long = "pace-ms", value_name = "MS", default_value_t = 0, value_parser = clap::value_parser!(u64).range(0..=60_000))]
    pub pace: u64,
}

/// A run's saved state: the layout of a state file.
#[derive(Serialize, Deserialize)]
pub struct SavedRun {
    /// The first bytes of every state file.
    magic: [u8; 8],
    /// Passes of the root so far.
    pub ticks: u32,
    /// The status the last tick printed.
    pub status: String,
    /// The run's clock, in nanoseconds.
    pub clock_nanos: u64,
    /// Each node's ticks so far, by node id.
    pub node_ticks: Vec<u32>,
    /// Each node's halts so far, by node id.
    pub node_halts: Vec<u32>,
    /// The tree's state ([`Tree::save_state`]).
    pub tree: Vec<u8>,
}

const MAGIC: [u8; 8] = *b"NTRUN\0\0\x01";

impl SavedRun {
    /// The state of a run after `ticks` ticks.
    pub fn new(
        tree: &Tree<()>,
        ticks: u32,
        status: &str,
        counts: (&[u32], &[u32]),
    ) -> Result<Self, String> {
        let state = tree
            .save_state()
            .map_err(|e| format!("the run's state cannot be saved: {e}"))?;
        Ok(SavedRun {
            magic: MAGIC,
            ticks,
            status: status.to_string(),
            clock_nanos: u64::try_from(tree.now().as_nanos()).unwrap_or(u64::MAX),
            node_ticks: counts.0.to_vec(),
            node_halts: counts.1.to_vec(),
            tree: state,
        })
    }

    /// Writes the state to `path`, through a file beside it renamed into place, so that a
    /// reader never sees half a state.
    pub fn write(&self, path: &Path) -> Result<(), String> {
        let bytes = neurotree::state::encode(self);
        let partial = path.with_extension("partial");
        fs::write(&partial, &bytes)
            .and_then(|()| fs::rename(&partial, path))
            .map_err(|e| format!("{}: error: cannot write the state: {e}", path.display()))
    }

    /// The state in `path`, checked against the tree it is to go on with: refused with
    /// `FILE: error: …` when it is no state file or belongs to another tree.
    pub fn read(path: &Path, tree: &mut Tree<()>) -> Result<Self, String> {
        let shown = path.display();
        let bytes = fs::read(path).map_err(|e| format!("{shown}: error: cannot read it: {e}"))?;
        let run: SavedRun = match neurotree::state::decode(&bytes) {
            Some(run @ SavedRun { magic: MAGIC, .. }) => run,
            _ => {
                return Err(format!(
                    "{shown}: error: not a state file of `neurotree run --save-state`"
                ))
            }
        };
        let n = tree.blueprint().len();
        if run.node_ticks.len() != n || run.node_halts.len() != n {
            return Err(format!(
                "{shown}: error: the state belongs to another tree (it has {} nodes, this tree {n}); resume with the files and options of the run that saved it",
                run.node_ticks.len()
            ));
        }
        tree.restore_state(&run.tree).map_err(|e| {
            format!(
                "{shown}: error: {e}; resume with the files and options of the run that saved it"
            )
        })?;
        Ok(run)
    }

    /// The run's clock when saved.
    pub fn clock(&self) -> Duration {
        Duration::from_nanos(self.clock_nanos)
    }
}

/// The path `--keep-states` writes the state after tick `tick` to.
pub fn kept_state_path(dir: &Path, tick: u32) -> PathBuf {
    dir.join(format!("tick-{tick}.state"))
}

/// What a file on disk looked like: enough to see that it changed, whether it was written
/// in place or replaced by a new file renamed over it.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Stamp {
    modified: Option<SystemTime>,
    len: u64,
    #[cfg(unix)]
    inode: u64,
}

fn stamp(path: &Path) -> Option<Stamp> {
    let meta = fs::metadata(path).ok()?;
    Some(Stamp {
        modified: meta.modified().ok(),
        len: meta.len(),
        #[cfg(unix)]
        inode: std::os::unix::fs::MetadataExt::ino(&meta),
    })
}

/// The files of a run, looked at between ticks.
///
/// Polled, not notified: a run looks once per tick, which costs a `stat` per file, sees a
/// rename over the file as well as a write in place, and keeps the run's output
/// deterministic (a change is taken at the next tick boundary, never in between).
pub struct Watcher {
    files: Vec<(PathBuf, Option<Stamp>)>,
}

impl Watcher {
    /// Watches `files` as they are now.
    pub fn new(files: &[PathBuf]) -> Self {
        Watcher {
            files: files.iter().map(|f| (f.clone(), stamp(f))).collect(),
        }
    }

    /// `true` if a file changed since the last look (a file being replaced, missing for a
    /// moment, is taken when it is back).
    pub fn changed(&mut self) -> bool {
        let mut changed = false;
        for (path, seen) in &mut self.files {
            let now = stamp(path);
            if now.is_some() && now != *seen {
                *seen = now;
                changed = true;
            }
        }
        changed
    }
}

/// Waits the pace between two ticks.
pub fn pace(args: &LiveArgs) {
    if args.pace > 0 {
        std::thread::sleep(Duration::from_millis(args.pace));
    }
}

/// Makes `--states-dir` if it is missing.
pub fn make_states_dir(args: &LiveArgs) -> io::Result<()> {
    match &args.states_dir {
        Some(dir) => fs::create_dir_all(dir),
        None => Ok(()),
    }
}
