//! Why a tree's state could not be saved or restored.

use alloc::string::String;

use crate::NodeId;

/// Why [`Tree::save_state`](crate::Tree::save_state) refused.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum SaveError {
    /// A stateful action or custom node that does not say what state it keeps.
    #[error("{path}: this {kind} keeps state that cannot be saved; implement its `save_state` and `restore_state` to save the tree")]
    Unsaveable {
        /// The node.
        node: NodeId,
        /// Its path in the tree.
        path: String,
        /// `stateful action` or `custom node`.
        kind: &'static str,
    },
    /// A running async action: its future cannot be frozen.
    #[error("{path}: this async action is running, and a running future cannot be saved; save between its runs, or halt the tree first")]
    AsyncRunning {
        /// The node.
        node: NodeId,
        /// Its path in the tree.
        path: String,
    },
    /// A halt that takes ticks is in progress.
    #[error(
        "{path}: a halt is in progress below this node; save once it is done (`Tree::tick_halt`)"
    )]
    Halting {
        /// The node.
        node: NodeId,
        /// Its path in the tree.
        path: String,
    },
    /// A blackboard value of a type without a codec.
    #[error("blackboard entry `{key}` holds a `{type_name}`, which the state codecs do not know; add it with `StateCodecs::with::<{type_name}>()`")]
    Value {
        /// The entry's key.
        key: String,
        /// The Rust type of its value.
        type_name: &'static str,
    },
}

crate::debug_shows_message!(enum SaveError {
    Unsaveable { node, path, kind },
    AsyncRunning { node, path },
    Halting { node, path },
    Value { key, type_name },
});

/// Why [`Tree::restore_state`](crate::Tree::restore_state) refused; the tree is left as it
/// was.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RestoreError {
    /// Not a saved state: other bytes, cut short, or altered.
    #[error("not a saved tree state: {0}")]
    Corrupt(String),
    /// The state of another tree.
    #[error("the state belongs to another tree (its structure hash is {found:016x}, this tree's is {expected:016x})")]
    OtherTree {
        /// This tree's structure hash.
        expected: u64,
        /// The one the state names.
        found: u64,
    },
    /// A node's object refused its saved state.
    #[error("{path}: its saved state was refused by its `restore_state`")]
    Node {
        /// The node.
        node: NodeId,
        /// Its path in the tree.
        path: String,
    },
    /// A blackboard value of a type without a codec here.
    #[error("blackboard entry `{key}` holds a `{type_name}`, which the state codecs do not know, or whose bytes it refused; add it with `StateCodecs::with`")]
    Value {
        /// The entry's key.
        key: String,
        /// The Rust type the state names.
        type_name: String,
    },
}

crate::debug_shows_message!(enum RestoreError {
    Corrupt(source),
    OtherTree { expected, found },
    Node { node, path },
    Value { key, type_name },
});
