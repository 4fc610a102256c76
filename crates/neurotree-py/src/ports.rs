//! A Python leaf's ports: `{"goal": str, "steps": nt.Output(int)}` as the registry's
//! `PortSpec`s, and the Python type of each, which `Node.input` and `Node.output` convert to.
//!
//! The Python side (`neurotree/__init__.py`) turns the declaration into tuples
//! `(name, direction, type, default, description)`, with `type` one of `int`, `float`,
//! `bool`, `str`, `list`, `dict` and `any`; this module reads those.

use neurotree::{PortDirection, PortSpec};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The Python type a port is declared as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Int,
    Float,
    Bool,
    Str,
    List,
    Dict,
    /// Declared without a type (`object`): read and written as whatever it holds.
    Any,
}

impl Kind {
    fn parse(name: &str) -> Option<Kind> {
        Some(match name {
            "int" => Kind::Int,
            "float" => Kind::Float,
            "bool" => Kind::Bool,
            "str" => Kind::Str,
            "list" => Kind::List,
            "dict" => Kind::Dict,
            "any" => Kind::Any,
            _ => return None,
        })
    }

    /// As Python spells the type.
    pub(crate) fn python_name(self) -> &'static str {
        match self {
            Kind::Int => "int",
            Kind::Float => "float",
            Kind::Bool => "bool",
            Kind::Str => "str",
            Kind::List => "list",
            Kind::Dict => "dict",
            Kind::Any => "object",
        }
    }

    /// The port's declaration: typed ports are checked as Rust ports of the same type are
    /// (a literal that does not convert is a load error); lists, dicts and untyped ports
    /// take any entry.
    fn spec(self, name: &str, direction: PortDirection) -> PortSpec {
        use PortDirection::{InOut, Input, Output};
        macro_rules! typed {
            ($t:ty) => {
                match direction {
                    Input => PortSpec::input::<$t>(name),
                    Output => PortSpec::output::<$t>(name),
                    InOut => PortSpec::inout::<$t>(name),
                }
            };
        }
        match self {
            Kind::Int => typed!(i64),
            Kind::Float => typed!(f64),
            Kind::Bool => typed!(bool),
            Kind::Str => typed!(String),
            Kind::List | Kind::Dict | Kind::Any => PortSpec::untyped(name, direction),
        }
    }
}

/// The Python types of a node type's ports, by name.
#[derive(Debug, Default)]
pub(crate) struct PortKinds(Vec<(String, Kind)>);

impl PortKinds {
    /// The type of port `name`.
    pub(crate) fn get(&self, name: &str) -> Option<Kind> {
        self.0.iter().find(|(n, _)| n == name).map(|(_, k)| *k)
    }
}

/// One declared port, as the Python side passes it.
pub(crate) type PortTuple = (String, String, String, Option<String>, String);

/// The registry's declarations and the Python types of `ports`.
pub(crate) fn read(ports: Vec<PortTuple>) -> PyResult<(Vec<PortSpec>, PortKinds)> {
    let mut specs = Vec::with_capacity(ports.len());
    let mut kinds = Vec::with_capacity(ports.len());
    for (name, direction, kind_name, default, description) in ports {
        let direction = match direction.as_str() {
            "input" => PortDirection::Input,
            "output" => PortDirection::Output,
            "inout" => PortDirection::InOut,
            other => {
                return Err(PyValueError::new_err(format!(
                    "port `{name}`: direction `{other}` is none of input, output, inout"
                )))
            }
        };
        let kind = Kind::parse(&kind_name).ok_or_else(|| {
            PyValueError::new_err(format!(
                "port `{name}`: a port is int, float, bool, str, list, dict or object, not {kind_name}"
            ))
        })?;
        let mut spec = kind.spec(&name, direction).describe(&description);
        if let Some(default) = default {
            spec = spec.default_value(&default);
        }
        specs.push(spec);
        kinds.push((name, kind));
    }
    Ok((specs, PortKinds(kinds)))
}
