//! Blackboard values between Python and Rust.
//!
//! Python's `None`, `bool`, `int` (as `i64`), `float` (as `f64`) and `str` are stored as those
//! Rust types, so that built-in nodes and Rust leaves read them as they read any entry; a
//! `list` or a `dict` is stored as a `serde_json::Value`. Reading goes the other way, and an
//! entry of any other Rust type comes back as the toolkit's JSON view of it
//! (`blackboard_json::entry_json`): every integer width, and the registered value types as
//! dicts.
//!
//! Writing to an entry that keeps a type of its own converts the value to it through the
//! type's JSON codec (the blackboard's `set_json_in`): an `int` written to an `f64` entry is
//! stored as a float, a dict written to a `Pose2D` entry (a type registered with
//! `Registry::register_value`, as Nav2's are) as a `Pose2D`; a value that does not fit is
//! refused with the entry's type named. Reading goes through the same codecs.

use std::time::Duration;

use neurotree::blackboard_json::entry_json;
use neurotree::{Blackboard, BlackboardError, ScopeId};
use pyo3::exceptions::{PyOverflowError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde_json::{Map, Number, Value};

/// A Python value as it is stored on a blackboard.
pub(crate) enum Stored {
    /// `None`.
    Null,
    Bool(bool),
    Int(i64),
    Float(f64),
    Text(String),
    /// A `list` or a `dict`.
    Json(Value),
}

impl Stored {
    /// Reads `value`, refusing what has no blackboard form.
    pub(crate) fn from_py(value: &Bound<'_, PyAny>) -> PyResult<Stored> {
        if value.is_none() {
            Ok(Stored::Null)
        } else if let Ok(b) = value.downcast::<PyBool>() {
            Ok(Stored::Bool(b.is_true()))
        } else if let Ok(i) = value.downcast::<PyInt>() {
            i.extract::<i64>()
                .map(Stored::Int)
                .map_err(|_| PyOverflowError::new_err(format!("{i} does not fit a 64-bit integer")))
        } else if let Ok(f) = value.downcast::<PyFloat>() {
            Ok(Stored::Float(f.value()))
        } else if let Ok(s) = value.downcast::<PyString>() {
            Ok(Stored::Text(s.to_cow()?.into_owned()))
        } else {
            json_of(value).map(Stored::Json)
        }
    }

    /// Writes the value to `key` as seen from `scope`.
    pub(crate) fn write(
        self,
        bb: &mut Blackboard,
        scope: ScopeId,
        key: &str,
        stamp: Duration,
    ) -> PyResult<()> {
        let json = self.json();
        let written = match self {
            Stored::Null => bb.set_untyped_in(scope, key, Value::Null, stamp),
            Stored::Bool(v) => bb.set_untyped_in(scope, key, v, stamp),
            Stored::Int(v) => bb.set_untyped_in(scope, key, v, stamp),
            Stored::Float(v) => bb.set_untyped_in(scope, key, v, stamp),
            Stored::Text(v) => bb.set_untyped_in(scope, key, v, stamp),
            Stored::Json(v) => bb.set_untyped_in(scope, key, v, stamp),
        };
        match written {
            Ok(()) => Ok(()),
            // The entry keeps a type of its own (an `f64`, a `u32`, a registered type such as
            // Nav2's `Pose2D`): the value becomes one through the type's JSON codec.
            Err(BlackboardError::WrongType { .. }) => bb
                .set_json_in(scope, key, json, stamp)
                .map_err(|e| PyTypeError::new_err(e.to_string())),
            Err(other) => Err(PyValueError::new_err(other.to_string())),
        }
    }

    /// The value as JSON.
    fn json(&self) -> Value {
        match self {
            Stored::Null => Value::Null,
            Stored::Bool(v) => Value::Bool(*v),
            Stored::Int(v) => Value::Number((*v).into()),
            Stored::Float(v) => Number::from_f64(*v).map_or(Value::Null, Value::Number),
            Stored::Text(v) => Value::String(v.clone()),
            Stored::Json(v) => v.clone(),
        }
    }
}

/// The entry `key` resolves to from `scope`, as a Python value; `None` for an entry declared
/// and never written.
pub(crate) fn read(py: Python<'_>, bb: &Blackboard, scope: ScopeId, key: &str) -> PyObject {
    let Some(any) = bb.get_any_in(scope, key) else {
        return py.None();
    };
    // The types Python writes, without the trip through JSON.
    if let Some(v) = any.downcast_ref::<i64>() {
        return v
            .into_pyobject(py)
            .map_or_else(|_| py.None(), |o| o.into_any().unbind());
    }
    if let Some(v) = any.downcast_ref::<f64>() {
        return PyFloat::new(py, *v).into_any().unbind();
    }
    if let Some(v) = any.downcast_ref::<bool>() {
        return PyBool::new(py, *v).to_owned().into_any().unbind();
    }
    if let Some(v) = any.downcast_ref::<String>() {
        return PyString::new(py, v).into_any().unbind();
    }
    if let Some(v) = any.downcast_ref::<Value>() {
        return py_of(py, v);
    }
    py_of(py, &entry_json(bb, scope, key))
}

/// A JSON value as Python's `None`, `bool`, `int`, `float`, `str`, `list` or `dict`.
pub(crate) fn py_of(py: Python<'_>, value: &Value) -> PyObject {
    match value {
        Value::Null => py.None(),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any().unbind(),
        Value::Number(n) => match (n.as_i64(), n.as_u64()) {
            (Some(i), _) => i
                .into_pyobject(py)
                .map_or_else(|_| py.None(), |o| o.into_any().unbind()),
            (None, Some(u)) => u
                .into_pyobject(py)
                .map_or_else(|_| py.None(), |o| o.into_any().unbind()),
            _ => PyFloat::new(py, n.as_f64().unwrap_or(f64::NAN))
                .into_any()
                .unbind(),
        },
        Value::String(s) => PyString::new(py, s).into_any().unbind(),
        Value::Array(items) => {
            let items: Vec<PyObject> = items.iter().map(|v| py_of(py, v)).collect();
            PyList::new(py, items).map_or_else(|_| py.None(), |l| l.into_any().unbind())
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, v) in map {
                // A fresh dict with a text key: nothing here can fail.
                let _ = dict.set_item(k, py_of(py, v));
            }
            dict.into_any().unbind()
        }
    }
}

/// A Python value as JSON: `None`, `bool`, `int`, `float`, `str`, and lists, tuples and dicts
/// (with text keys) of them.
pub(crate) fn json_of(value: &Bound<'_, PyAny>) -> PyResult<Value> {
    if value.is_none() {
        return Ok(Value::Null);
    }
    if let Ok(b) = value.downcast::<PyBool>() {
        return Ok(Value::Bool(b.is_true()));
    }
    if let Ok(i) = value.downcast::<PyInt>() {
        if let Ok(v) = i.extract::<i64>() {
            return Ok(Value::Number(v.into()));
        }
        return i
            .extract::<u64>()
            .map(|v| Value::Number(v.into()))
            .map_err(|_| PyOverflowError::new_err(format!("{i} does not fit a 64-bit integer")));
    }
    if let Ok(f) = value.downcast::<PyFloat>() {
        return Number::from_f64(f.value())
            .map(Value::Number)
            .ok_or_else(|| PyValueError::new_err(format!("{} has no JSON form", f.value())));
    }
    if let Ok(s) = value.downcast::<PyString>() {
        return Ok(Value::String(s.to_cow()?.into_owned()));
    }
    if let Ok(list) = value.downcast::<PyList>() {
        return list
            .iter()
            .map(|v| json_of(&v))
            .collect::<PyResult<_>>()
            .map(Value::Array);
    }
    if let Ok(tuple) = value.downcast::<PyTuple>() {
        return tuple
            .iter()
            .map(|v| json_of(&v))
            .collect::<PyResult<_>>()
            .map(Value::Array);
    }
    if let Ok(dict) = value.downcast::<PyDict>() {
        let mut map = Map::new();
        for (k, v) in dict.iter() {
            let Ok(k) = k.downcast::<PyString>() else {
                return Err(PyTypeError::new_err(format!(
                    "a blackboard dict's keys must be str, not {}",
                    k.get_type().name()?
                )));
            };
            map.insert(k.to_cow()?.into_owned(), json_of(&v)?);
        }
        return Ok(Value::Object(map));
    }
    Err(PyTypeError::new_err(format!(
        "a blackboard holds None, bool, int, float, str, list and dict, not {}",
        value.get_type().name()?
    )))
}
