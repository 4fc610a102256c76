//! Saving a running tree and resuming it later or elsewhere, and going back in a run.
//!
//! A [`Tree`](crate::Tree) instance holds little: a status byte per node, a state slot for
//! the nodes that need one (a cursor, a counter, the moment a wait began), the per-instance
//! objects of stateful leaves and custom nodes, and its blackboard. All of it can be saved
//! to bytes ([`Tree::save_state`](crate::Tree::save_state)) and restored into a fresh
//! instance of the same blueprint ([`Tree::restore_state`](crate::Tree::restore_state)),
//! in this process or another; the restored tree then runs tick for tick as the original
//! would have, given the same context.
//!
//! - **What must opt in.** The state of your own objects: a [`StatefulAction`] or
//!   [`CustomNode`] says what it keeps through `save_state` / `restore_state` (with
//!   [`encode`] and [`decode`] for any `serde` value); one that does not makes saving fail
//!   with an error naming the node. Blackboard values are saved through [`StateCodecs`]:
//!   numbers, `bool`, `char`, `String` and `Duration` are known; add your own types with
//!   [`StateCodecs::with`]. A value of another type makes saving fail, naming its key.
//! - **What cannot be saved.** A running async action's future cannot be frozen: saving
//!   a tree in which one runs is refused ([`SaveError::AsyncRunning`]); save between its
//!   runs, or halt the tree first. A halt in progress ([`slow_halt`]) is refused the same
//!   way. The record of the last tick's failure reasons is not saved: a restored tree has
//!   none until its next tick.
//! - **Time.** Nodes that wait (Delay, Timeout, Cooldown, Sleep) keep the time elapsed
//!   since they began: restored on a clock that reads another time, they wait what was
//!   left. Give the restored tree a clock set to [`SavedInfo::clock`] to resume exactly.
//! - **Which tree.** A state names its blueprint by [`Blueprint::structure_hash`]; restoring
//!   into another tree is refused ([`RestoreError::OtherTree`]), and so are bytes that are
//!   not a saved state, cut short or tampered with ([`RestoreError::Corrupt`]): nothing
//!   panics, and a refused restore leaves the tree as it was.
//!
//! [`Snapshots`] keeps a state every K ticks, so that any earlier tick can be restored and
//! the run continued from there, differently if you like: rewind and fork.
//!
//! [`StatefulAction`]: crate::StatefulAction
//! [`CustomNode`]: crate::CustomNode
//! [`slow_halt`]: crate::tree::slow_halt
//! [`Blueprint::structure_hash`]: crate::Blueprint::structure_hash

mod codecs;
mod error;
mod snapshots;

use alloc::string::String;
use alloc::vec::Vec;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

pub use codecs::StateCodecs;
pub use error::{RestoreError, SaveError};
pub use snapshots::Snapshots;

/// Any `serde` value as bytes, in the format saved states use (postcard): what a
/// `save_state` of your own object returns.
pub fn encode<T: Serialize + ?Sized>(value: &T) -> Vec<u8> {
    // Writing to a growing vector fails only for a value whose `Serialize` fails.
    postcard::to_allocvec(value).unwrap_or_default()
}

/// The value [`encode`] made of it; `None` if the bytes are not one.
pub fn decode<T: DeserializeOwned>(bytes: &[u8]) -> Option<T> {
    postcard::from_bytes(bytes).ok()
}

/// What a saved state says of itself, read without restoring it ([`SavedInfo::read`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SavedInfo {
    /// The [structure hash](crate::Blueprint::structure_hash) of the tree it belongs to.
    pub blueprint: u64,
    /// The tree's clock when it was saved.
    pub clock: core::time::Duration,
    /// Its number of nodes.
    pub nodes: usize,
}

impl SavedInfo {
    /// Reads the heading of a saved state.
    pub fn read(bytes: &[u8]) -> Result<SavedInfo, RestoreError> {
        let saved = SavedTree::read(bytes)?;
        Ok(SavedInfo {
            blueprint: saved.blueprint,
            clock: core::time::Duration::from_nanos(saved.clock_nanos),
            nodes: saved.statuses.len(),
        })
    }
}

/// The first bytes of every saved state.
const MAGIC: [u8; 8] = *b"NTSTATE\0";
/// The layout's version: a state of another is refused.
const VERSION: u32 = 1;

/// A saved tree: the layout of the bytes.
#[derive(Serialize, Deserialize)]
pub(crate) struct SavedTree {
    pub(crate) magic: [u8; 8],
    pub(crate) version: u32,
    /// The blueprint's structure hash.
    pub(crate) blueprint: u64,
    /// The clock when saved, in nanoseconds.
    pub(crate) clock_nanos: u64,
    /// Every node's status (`NodeStatus as u8`), by node id.
    pub(crate) statuses: Vec<u8>,
    /// Per node that keeps state, in node order, its slots as one `u64`, in the form it had
    /// when slots were 64 bits (see `Tick::saved_aux`), so that states saved then read now.
    pub(crate) aux: Vec<u64>,
    /// The per-instance objects, in slot order.
    pub(crate) objects: Vec<SavedObject>,
    /// The blackboard's entries, in scope then key order.
    pub(crate) entries: Vec<SavedEntry>,
    /// The blackboard's latest stamp, in nanoseconds.
    pub(crate) last_stamp_nanos: u64,
    /// What the root returned on the last tick.
    pub(crate) last_root: u8,
}

impl SavedTree {
    /// A new state with its heading.
    pub(crate) fn new(blueprint: u64, clock_nanos: u64) -> Self {
        Self {
            magic: MAGIC,
            version: VERSION,
            blueprint,
            clock_nanos,
            statuses: Vec::new(),
            aux: Vec::new(),
            objects: Vec::new(),
            entries: Vec::new(),
            last_stamp_nanos: 0,
            last_root: 0,
        }
    }

    /// The state in `bytes`, its heading checked.
    pub(crate) fn read(bytes: &[u8]) -> Result<Self, RestoreError> {
        if bytes.len() < MAGIC.len() || bytes[..MAGIC.len()] != MAGIC {
            return Err(RestoreError::Corrupt(String::from(
                "it does not begin as a saved tree state does",
            )));
        }
        let (saved, rest): (SavedTree, &[u8]) = postcard::take_from_bytes(bytes)
            .map_err(|e| RestoreError::Corrupt(alloc::format!("it cannot be read ({e})")))?;
        if !rest.is_empty() {
            return Err(RestoreError::Corrupt(alloc::format!(
                "{} bytes follow the state",
                rest.len()
            )));
        }
        if saved.version != VERSION {
            return Err(RestoreError::Corrupt(alloc::format!(
                "it is of layout version {}, this library reads version {VERSION}",
                saved.version
            )));
        }
        Ok(saved)
    }
}

/// A per-instance object's saved state.
#[derive(Serialize, Deserialize)]
pub(crate) enum SavedObject {
    /// An async action between runs: nothing to keep.
    Idle,
    /// What the object's `save_state` returned.
    State(Vec<u8>),
}

/// A blackboard entry's saved state.
#[derive(Serialize, Deserialize)]
pub(crate) struct SavedEntry {
    pub(crate) scope: u32,
    pub(crate) key: String,
    /// The Rust type of the value (`None`: declared, not written yet).
    pub(crate) type_name: Option<String>,
    pub(crate) sequence: u64,
    pub(crate) stamp_nanos: u64,
    pub(crate) untyped: bool,
    /// The value, as its codec encoded it.
    pub(crate) value: Vec<u8>,
}
