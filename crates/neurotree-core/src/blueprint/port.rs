//! Ports: the named inputs and outputs of a node, bound to text or to a blackboard entry.
//!
//! A BehaviorTree.CPP file gives a node its parameters as attributes:
//! `<MoveTo goal="{target}" speed="0.5"/>`. Each attribute is a [`Port`]: `speed` is bound
//! to the literal text `0.5`, converted to the type the node asks for when it reads it;
//! `goal` is bound to the blackboard entry `target`, read or written through the node's
//! scope (so a SubTree's remapping applies, and `{@key}` reaches the root). Leaves read them
//! through [`Handle::input`](crate::Handle::input) and
//! [`Handle::output`](crate::Handle::output).

use alloc::string::String;
use alloc::vec::Vec;
use core::str::FromStr;

use crate::blackboard::BlackboardError;

/// What a port is bound to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PortValue {
    /// Text, converted to the reader's type on each read.
    Literal(String),
    /// A blackboard entry, by key as seen from the node's scope (`@key`: the root's).
    Entry(String),
}

/// One port of a node and its binding.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Port {
    /// The port's name (the XML attribute).
    pub name: String,
    /// What it is bound to.
    pub value: PortValue,
}

impl Port {
    /// A port bound to literal text.
    pub fn literal(name: &str, text: &str) -> Self {
        Self {
            name: String::from(name),
            value: PortValue::Literal(String::from(text)),
        }
    }

    /// A port bound to a blackboard entry.
    pub fn entry(name: &str, key: &str) -> Self {
        Self {
            name: String::from(name),
            value: PortValue::Entry(String::from(key)),
        }
    }
}

/// Why a port could not be read or written.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PortError {
    /// The node has no port of this name.
    #[error("no port `{port}` on this node")]
    NoSuchPort {
        /// The port asked for.
        port: String,
    },
    /// The text does not convert to the type asked for.
    #[error("port `{port}`: cannot read `{text}` as {type_name}")]
    Convert {
        /// The port.
        port: String,
        /// The text that failed.
        text: String,
        /// The type asked for.
        type_name: &'static str,
    },
    /// An output port bound to a literal has nowhere to write.
    #[error("port `{port}` is bound to a literal; bind it to an entry (`{{key}}`) to write it")]
    NotAnEntry {
        /// The port.
        port: String,
    },
    /// The bound entry could not be read or written.
    #[error("port `{port}`: {source}")]
    Blackboard {
        /// The port.
        port: String,
        /// What the blackboard said.
        source: BlackboardError,
    },
}

/// Conversion from the text of a port (an XML attribute, or a text blackboard entry).
///
/// Implemented for the integers, floats, `bool` (`true`/`false` in any case, `1`/`0`),
/// `String` and `Vec<T>` (`;`-separated). Implement it for your own types to read them from
/// ports.
pub trait FromPortStr: Sized {
    /// Converts `text`, or says why not (the message names no port; the caller adds it).
    fn from_port_str(text: &str) -> Result<Self, ()>;
}

macro_rules! from_port_str_by_parse {
    ($($t:ty),*) => {$(
        impl FromPortStr for $t {
            fn from_port_str(text: &str) -> Result<Self, ()> {
                <$t>::from_str(text.trim()).map_err(|_| ())
            }
        }
    )*};
}

from_port_str_by_parse!(i8, i16, i32, i64, i128, isize, u8, u16, u32, u64, u128, usize, f32, f64);

impl FromPortStr for bool {
    fn from_port_str(text: &str) -> Result<Self, ()> {
        match text.trim() {
            "1" => Ok(true),
            "0" => Ok(false),
            t if t.eq_ignore_ascii_case("true") => Ok(true),
            t if t.eq_ignore_ascii_case("false") => Ok(false),
            _ => Err(()),
        }
    }
}

impl FromPortStr for String {
    fn from_port_str(text: &str) -> Result<Self, ()> {
        Ok(String::from(text))
    }
}

impl<T: FromPortStr> FromPortStr for Vec<T> {
    fn from_port_str(text: &str) -> Result<Self, ()> {
        if text.trim().is_empty() {
            return Ok(Vec::new());
        }
        text.split(';').map(T::from_port_str).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;

    #[test]
    fn numbers_bools_strings_and_lists() {
        assert_eq!(i32::from_port_str(" 42 "), Ok(42));
        assert_eq!(u8::from_port_str("-1"), Err(()));
        assert_eq!(f64::from_port_str("0.5"), Ok(0.5));
        for (text, b) in [("true", true), ("TRUE", true), ("True", true), ("1", true)] {
            assert_eq!(bool::from_port_str(text), Ok(b), "{text}");
        }
        assert_eq!(bool::from_port_str("0"), Ok(false));
        assert_eq!(bool::from_port_str("yes"), Err(()));
        assert_eq!(String::from_port_str("a b"), Ok(String::from("a b")));
        assert_eq!(Vec::<i32>::from_port_str("1;2;3"), Ok(vec![1, 2, 3]));
        assert_eq!(Vec::<i32>::from_port_str(""), Ok(vec![]));
        assert_eq!(Vec::<i32>::from_port_str("1;x"), Err(()));
    }
}
