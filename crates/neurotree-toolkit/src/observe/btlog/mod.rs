//! BehaviorTree.CPP's `.btlog` files (its `FileLogger2`), which Groot2 replays: the
//! writer here, the reader in `read`.

mod read;

pub use read::{read_btlog, read_btlog_file, Btlog, BtlogReadError, BtlogRecord};

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use neurotree_core::{Observer, StatusChange, Tree};

use super::{lock, micros, status_code, Sink};
use crate::xml::{write_xml, SaveOptions};
use crate::Registry;

/// The first bytes of every `.btlog` file.
pub const BTLOG_MAGIC: &[u8; 18] = b"BTCPP4-FileLogger2";

/// The protocol byte after the magic: the record layout [`BtlogWriter`] describes.
pub const BTLOG_PROTOCOL: u8 = 1;

/// Bytes per record: 6 of offset, 2 of uid, 1 of status.
const RECORD_LEN: usize = 9;

/// The largest offset 48 bits hold (some 8.9 years); later ones are written as this.
const MAX_OFFSET_US: u64 = (1 << 48) - 1;

/// Why a `.btlog` could not be started.
#[derive(thiserror::Error)]
#[non_exhaustive]
pub enum BtlogError {
    /// Creating the file or writing the header failed.
    #[error("writing the .btlog header: {0}")]
    Io(#[from] io::Error),
    /// Uids are `u16` and start at 1, so a tree may have at most 65,535 nodes.
    #[error("the tree has {nodes} nodes, more than the 65535 a .btlog can name")]
    TooManyNodes {
        /// The tree's node count.
        nodes: usize,
    },
    /// The XML length is an `i32`.
    #[error("the tree XML is {bytes} bytes, more than a .btlog can hold")]
    XmlTooLong {
        /// The XML's length.
        bytes: usize,
    },
}

neurotree_core::debug_shows_message!(enum BtlogError {
    Io(source),
    TooManyNodes { nodes },
    XmlTooLong { bytes },
});

/// Writes a `.btlog`, BehaviorTree.CPP's `FileLogger2` format, that Groot2 replays and
/// [`read_btlog`] reads back.
///
/// The header is written when the writer is made; then every status change of the tree it
/// is attached to adds a record. A handle: clones share the writer. Call
/// [`flush`](Self::flush) at the end to learn whether every write succeeded.
///
/// The layout, all integers little-endian:
///
/// | bytes | what |
/// |---|---|
/// | 18 | the magic `BTCPP4-FileLogger2` (no terminator) |
/// | 1 | the protocol, 1 |
/// | 4 | `i32`: length N of the tree XML |
/// | N | the tree XML, with a `_uid` on every node and a `TreeNodesModel` |
/// | 8 | `i64`: the first timestamp, microseconds since the Unix epoch |
/// | 9 each | one record per status change, to the end of the file |
///
/// A record is a 48-bit offset in microseconds from the first timestamp, the node's `u16`
/// uid, and its new status as a byte in BehaviorTree.CPP's numbering (IDLE 0, RUNNING 1,
/// SUCCESS 2, FAILURE 3, SKIPPED 4).
///
/// As in BehaviorTree.CPP:
/// - uids count nodes from 1 in depth-first creation order, subtrees' nodes in place after
///   their SubTree node, which is NeuroTree's pre-order: a node's uid is its
///   [`NodeId`](crate::NodeId) plus one (the XML says so with its `_uid` attributes);
/// - every change is recorded, those to Idle included, and only changes: there is no
///   opening record of all-Idle statuses, and a Skipped node (which stays Idle) writes
///   nothing;
/// - the file is a plain stream of records: BehaviorTree.CPP hands them to a writer thread
///   that writes them in batches, which changes nothing in the file. Here they go to the
///   writer given, so give a file a `BufWriter` ([`create`](Self::create) does).
///
/// Offsets are taken on the tree's clock from the moment the writer was made, so a run on a
/// [`ManualClock`](crate::ManualClock) writes the same records every time; the first
/// timestamp is the wall-clock time then (or the one given to
/// [`with_start`](Self::with_start)).
///
/// ```
/// use neurotree::observe::{read_btlog, BtlogWriter};
/// use neurotree::{Blueprint, ManualClock, NodeStatus, Registry, Tree};
///
/// let blueprint = Blueprint::<()>::builder().always_success("done").build_shared().unwrap();
/// let mut tree = Tree::with_clock(blueprint, ManualClock::new());
/// let log = BtlogWriter::new(Vec::new(), &tree, &Registry::new()).unwrap();
/// tree.set_observer(log.clone());
/// tree.tick_once(&mut ()).unwrap();
///
/// let bytes = log.with_writer(|out| out.clone());
/// let read = read_btlog(&bytes[..]).unwrap();
/// assert!(read.xml.contains(r#"_uid="1""#));
/// let statuses: Vec<NodeStatus> = read.records.iter().map(|r| r.status).collect();
/// assert_eq!(statuses, [NodeStatus::Success, NodeStatus::Idle]);
/// ```
pub struct BtlogWriter<W> {
    state: Arc<Mutex<Records<W>>>,
}

struct Records<W> {
    sink: Sink<W>,
    /// The tree's clock when the writer was made: offset zero.
    origin: Duration,
    nodes: usize,
}

impl<W> Clone for BtlogWriter<W> {
    fn clone(&self) -> Self {
        Self {
            state: Arc::clone(&self.state),
        }
    }
}

impl BtlogWriter<BufWriter<File>> {
    /// Creates (or truncates) the file at `path` and writes the header for `tree`, whose
    /// registered types `registry` describes. Groot2 opens only files named `*.btlog`.
    pub fn create<C: 'static>(
        path: impl AsRef<Path>,
        tree: &Tree<C>,
        registry: &Registry<C>,
    ) -> Result<Self, BtlogError> {
        let file = File::create(path)?;
        Self::new(BufWriter::new(file), tree, registry)
    }
}

impl<W: Write> BtlogWriter<W> {
    /// Writes the header for `tree` to `out`, with the wall-clock time now as the first
    /// timestamp.
    pub fn new<C: 'static>(
        out: W,
        tree: &Tree<C>,
        registry: &Registry<C>,
    ) -> Result<Self, BtlogError> {
        Self::with_start(out, tree, registry, SystemTime::now())
    }

    /// Writes the header for `tree` to `out`, with `start` as the first timestamp (for
    /// files that must come out the same on every run).
    pub fn with_start<C: 'static>(
        mut out: W,
        tree: &Tree<C>,
        registry: &Registry<C>,
        start: SystemTime,
    ) -> Result<Self, BtlogError> {
        let blueprint = tree.blueprint();
        if blueprint.len() > usize::from(u16::MAX) {
            return Err(BtlogError::TooManyNodes {
                nodes: blueprint.len(),
            });
        }
        let opts = SaveOptions {
            uids: true,
            builtin_models: true,
            ..SaveOptions::default()
        };
        let xml = write_xml(blueprint, registry, &opts);
        let len =
            i32::try_from(xml.len()).map_err(|_| BtlogError::XmlTooLong { bytes: xml.len() })?;
        out.write_all(BTLOG_MAGIC)?;
        out.write_all(&[BTLOG_PROTOCOL])?;
        out.write_all(&len.to_le_bytes())?;
        out.write_all(xml.as_bytes())?;
        out.write_all(&unix_micros(start).to_le_bytes())?;
        Ok(Self {
            state: Arc::new(Mutex::new(Records {
                sink: Sink::new(out),
                origin: tree.now(),
                nodes: blueprint.len(),
            })),
        })
    }

    /// Flushes the writer, or returns the first error writing met (writing stops at it).
    pub fn flush(&self) -> io::Result<()> {
        lock(&self.state).sink.flush()
    }

    /// Runs `f` on the writer, e.g. to read what a `Vec<u8>` collected.
    pub fn with_writer<R>(&self, f: impl FnOnce(&mut W) -> R) -> R {
        f(&mut lock(&self.state).sink.out)
    }
}

impl<W: Write + Send> Observer for BtlogWriter<W> {
    fn on_status_change(&mut self, change: StatusChange) {
        let mut state = lock(&self.state);
        if change.node.index() >= state.nodes {
            return;
        }
        let offset = micros(change.at.saturating_sub(state.origin)).min(MAX_OFFSET_US);
        // At most 65,535 nodes (checked when made), so the uid fits.
        let uid = (change.node.0 + 1) as u16;
        let mut record = [0u8; RECORD_LEN];
        record[..6].copy_from_slice(&offset.to_le_bytes()[..6]);
        record[6..8].copy_from_slice(&uid.to_le_bytes());
        record[8] = status_code(change.to);
        state.sink.write_all(&record);
    }
}

/// Microseconds since the Unix epoch (negative before it).
fn unix_micros(t: SystemTime) -> i64 {
    match t.duration_since(UNIX_EPOCH) {
        Ok(after) => i64::try_from(after.as_micros()).unwrap_or(i64::MAX),
        Err(before) => i64::try_from(before.duration().as_micros()).map_or(i64::MIN, |us| -us),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timestamps_before_the_epoch_are_negative() {
        let t = UNIX_EPOCH - Duration::from_micros(1_500);
        assert_eq!(unix_micros(t), -1_500);
        assert_eq!(unix_micros(UNIX_EPOCH + Duration::from_secs(2)), 2_000_000);
    }
}
