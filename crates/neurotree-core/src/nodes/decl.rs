//! What a built-in node is, as data: its BehaviorTree.CPP name, family, number of children,
//! ports and [semantics](super::semantics).
//!
//! Each built-in node's module declares its node(s) as a `pub const` [`NodeDecl`] next to
//! its tick, and [`BUILT_INS`](super::BUILT_INS) lists them. Everything that describes a
//! built-in from the outside is read from these declarations: the registry of the
//! `neurotree` toolkit (names, families, ports and the checks of their literals), its
//! `TreeNodesModel` export, the ports its XML writer writes and the node catalog of the
//! README. The tick itself does not look at them: it goes through the [`NodeKind`] enum.
//!
//! [`NodeKind`]: crate::NodeKind

use super::semantics::Semantics;
use crate::{Arity, Category};

/// Which way a port carries data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PortDirection {
    /// Read by the node.
    Input,
    /// Written by the node.
    Output,
    /// Both.
    InOut,
}

impl PortDirection {
    /// The element name BehaviorTree.CPP's `TreeNodesModel` uses.
    pub const fn model_tag(self) -> &'static str {
        match self {
            PortDirection::Input => "input_port",
            PortDirection::Output => "output_port",
            PortDirection::InOut => "inout_port",
        }
    }
}

/// A port of a built-in node, as BehaviorTree.CPP 4.10's `providedPorts()` declares it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PortDecl {
    /// The attribute name.
    pub name: &'static str,
    /// Which way it carries data.
    pub direction: PortDirection,
    /// The Rust type a literal converts to: `"i32"`, `"u64"`, `"bool"`, `"f64"` or
    /// `"String"` (text, read as the node needs it).
    pub type_name: &'static str,
    /// The text used when the attribute is absent; `None`: the port must be given.
    pub default: Option<&'static str>,
    /// What it is for, in a sentence.
    pub description: &'static str,
}

impl PortDecl {
    /// An input port with no default.
    pub const fn input(
        name: &'static str,
        type_name: &'static str,
        description: &'static str,
    ) -> Self {
        Self {
            name,
            direction: PortDirection::Input,
            type_name,
            default: None,
            description,
        }
    }

    /// An output port.
    pub const fn output(
        name: &'static str,
        type_name: &'static str,
        description: &'static str,
    ) -> Self {
        Self {
            direction: PortDirection::Output,
            ..Self::input(name, type_name, description)
        }
    }

    /// The same port, with `text` used when the attribute is absent.
    pub const fn or(self, text: &'static str) -> Self {
        Self {
            default: Some(text),
            ..self
        }
    }
}

/// A built-in node: what the registry, the model export, the loader's checks, the XML writer
/// and the catalog know of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NodeDecl {
    /// The BehaviorTree.CPP name, as XML writes it.
    pub name: &'static str,
    /// Its family.
    pub category: Category,
    /// How many children it takes.
    pub arity: Arity,
    /// Its ports, in BehaviorTree.CPP's order.
    pub ports: &'static [PortDecl],
    /// What it does, in one line (the catalog's "in short").
    pub summary: &'static str,
    /// What it can return and how it ticks its children.
    pub semantics: Semantics,
}

impl NodeDecl {
    /// The port named `name`.
    pub fn port(&self, name: &str) -> Option<&'static PortDecl> {
        self.ports.iter().find(|p| p.name == name)
    }
}

/// The port types a declaration may name: those the toolkit knows how to check.
pub const PORT_TYPES: [&str; 5] = ["i32", "u64", "bool", "f64", "String"];
