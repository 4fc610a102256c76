//! Why a blueprint could not be built.

use alloc::string::String;

use super::Arity;

/// A blueprint that failed validation, with the path of the node at fault.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[error("{path}: {kind}")]
pub struct BuildError {
    /// Names from the root to the node at fault, joined by `/` (empty when no node is at fault).
    pub path: String,
    /// What is wrong.
    pub kind: BuildErrorKind,
}

crate::debug_shows_message!(struct BuildError { path, kind });

/// What made a blueprint invalid.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BuildErrorKind {
    /// The builder was given no node.
    #[error("the tree is empty: add a root node")]
    Empty,
    /// A second node was added at the top level.
    #[error("a tree has one root; wrap these nodes in a Sequence or another control node")]
    SecondRoot,
    /// A node has the wrong number of children.
    #[error("{type_name} takes {expected}, found {found}")]
    ChildCount {
        /// The node's type.
        type_name: String,
        /// What it accepts.
        expected: Arity,
        /// What it was given.
        found: u32,
    },
    /// A Parallel threshold exceeds the number of children.
    #[error(
        "{type_name}: {which} threshold {value} needs at least {value} children, found {children}"
    )]
    Threshold {
        /// `Parallel` or `ParallelAll`.
        type_name: String,
        /// `success`, `failure` or `max_failures`.
        which: &'static str,
        /// The resolved threshold.
        value: i64,
        /// The number of children.
        children: u32,
    },
    /// The tree is deeper than the limit.
    #[error("the tree is deeper than the limit of {limit} levels; flatten it or raise the limit with Builder::max_depth")]
    TooDeep {
        /// The limit in force.
        limit: u32,
    },
    /// `close` was called with no open node.
    #[error("close() without a matching open()")]
    UnbalancedClose,
    /// `build` was called with nodes still open.
    #[error("{open} node(s) still open: call close() for each open()")]
    Unclosed {
        /// How many are open.
        open: usize,
    },
    /// The tree has more nodes than ids can index.
    #[error("the tree has more than {max} nodes")]
    TooManyNodes {
        /// The most nodes a blueprint holds.
        max: u32,
    },
    /// The nodes' names and type ids together are longer than a blueprint holds.
    #[error("the names of the nodes take more than {max} bytes together; shorten them")]
    NamesTooLong {
        /// The most bytes of names a blueprint holds.
        max: usize,
    },
    /// A node's configuration was refused by the code that added it (a script that does
    /// not parse): see [`Builder::reject`](crate::Builder::reject).
    #[error("{message}")]
    Rejected {
        /// What is wrong, and what to do.
        message: String,
    },
}
