//! Why a blackboard access failed.

use alloc::string::String;

/// Why a blackboard access failed.
///
/// Each variant names the key or scope as the caller gave it, so that the message points at
/// the port or the line of code to fix.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BlackboardError {
    /// No entry under this key, in the scope asked or any scope it reaches.
    #[error(
        "no blackboard entry `{key}`: write it before reading it, or remap the key to an \
         entry of the parent scope"
    )]
    NotFound {
        /// The key as asked.
        key: String,
    },
    /// The entry holds a value of another type.
    #[error(
        "blackboard entry `{key}` holds a `{found}`, not a `{expected}`: an entry's type is \
         fixed by its first write, so use `{found}`, or unset the entry before writing \
         another type"
    )]
    WrongType {
        /// The key as asked.
        key: String,
        /// The type asked for (read) or given (write).
        expected: &'static str,
        /// The type the entry holds.
        found: &'static str,
    },
    /// The entry holds a number, `bool` or text that converts to the type asked for in
    /// general, but not this value: out of range, a fraction where an integer is wanted, or
    /// text that does not parse.
    #[error(
        "blackboard entry `{key}` holds the `{found}` {value}, which does not fit a \
         `{expected}`: read it as a type that holds it"
    )]
    NotConvertible {
        /// The key as asked.
        key: String,
        /// The value, printed.
        value: String,
        /// The type asked for.
        expected: &'static str,
        /// The type the entry holds.
        found: &'static str,
    },
    /// The scope does not exist in this blackboard.
    #[error(
        "blackboard scope {scope} does not exist: scopes are numbered in the order \
         `Blackboard::add_scope` created them, from 0 (the root)"
    )]
    NoSuchScope {
        /// The scope asked for.
        scope: u32,
    },
}

crate::debug_shows_message!(enum BlackboardError {
    NotFound { key },
    WrongType { key, expected, found },
    NotConvertible { key, value, expected, found },
    NoSuchScope { scope },
});
