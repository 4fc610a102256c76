//! Port declarations: what a node type reads and writes, and how a literal is checked.

use std::fmt;

use neurotree_core::{FromPortStr, PortDecl};

/// Which way a port carries data (declared in the core, with the built-in nodes' ports).
pub use neurotree_core::PortDirection;

/// A declared port: name, direction, type, default and description.
#[derive(Clone)]
pub struct PortSpec {
    /// The attribute name.
    pub name: String,
    /// Which way it carries data.
    pub direction: PortDirection,
    /// The Rust type it converts to.
    pub type_name: &'static str,
    /// Text used when the attribute is absent.
    pub default: Option<String>,
    /// What it is for.
    pub description: String,
    /// `true` if a literal converts to the port's type.
    pub(crate) check: Option<fn(&str) -> bool>,
}

impl PortSpec {
    /// An input port of type `T`.
    pub fn input<T: FromPortStr + 'static>(name: &str) -> Self {
        Self::new::<T>(name, PortDirection::Input)
    }

    /// An output port of type `T`.
    pub fn output<T: 'static>(name: &str) -> Self {
        Self {
            name: name.to_string(),
            direction: PortDirection::Output,
            type_name: std::any::type_name::<T>(),
            default: None,
            description: String::new(),
            check: None,
        }
    }

    /// A port read and written, of type `T`.
    pub fn inout<T: FromPortStr + 'static>(name: &str) -> Self {
        Self::new::<T>(name, PortDirection::InOut)
    }

    fn new<T: FromPortStr + 'static>(name: &str, direction: PortDirection) -> Self {
        Self {
            name: name.to_string(),
            direction,
            type_name: std::any::type_name::<T>(),
            default: None,
            description: String::new(),
            check: Some(|text| T::from_port_str(text).is_ok()),
        }
    }

    /// With a default value (as text).
    pub fn default_value(mut self, text: &str) -> Self {
        self.default = Some(text.to_string());
        self
    }

    /// With a description.
    pub fn describe(mut self, text: &str) -> Self {
        self.description = text.to_string();
        self
    }

    /// `true` if `text` converts to the port's type (always for types without a check).
    pub fn accepts(&self, text: &str) -> bool {
        self.check.map_or(true, |check| check(text))
    }
}

impl From<&PortDecl> for PortSpec {
    /// A built-in node's declared port, its literals checked as the declared type converts.
    fn from(p: &PortDecl) -> Self {
        Self {
            name: p.name.to_string(),
            direction: p.direction,
            type_name: p.type_name,
            default: p.default.map(str::to_string),
            description: p.description.to_string(),
            // What a node writes is not read from a literal.
            check: match p.direction {
                PortDirection::Output => None,
                _ => literal_check(p.type_name),
            },
        }
    }
}

/// How a literal of a declared type is checked; `None` for text, read as the node needs it.
/// The types are those of [`PORT_TYPES`](neurotree_core::nodes::PORT_TYPES).
pub(crate) fn literal_check(type_name: &str) -> Option<fn(&str) -> bool> {
    fn converts<T: FromPortStr>(text: &str) -> bool {
        T::from_port_str(text).is_ok()
    }
    match type_name {
        "i32" => Some(converts::<i32>),
        "u64" => Some(converts::<u64>),
        "bool" => Some(converts::<bool>),
        "f64" => Some(converts::<f64>),
        _ => None,
    }
}

impl fmt::Debug for PortSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("PortSpec")
            .field("name", &self.name)
            .field("direction", &self.direction)
            .field("type_name", &self.type_name)
            .field("default", &self.default)
            .finish()
    }
}
