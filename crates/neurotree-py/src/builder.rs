//! `neurotree.Builder`: a tree built in code, as the Rust builder builds one — the engine's
//! built-in nodes by their BehaviorTree.CPP names, and Python leaves given as functions and
//! classes, with no XML and no registry.
//!
//! The Python subclass (`neurotree/__init__.py`) adds `with b.node(...)`, which opens a
//! control or decorator here and closes it at the end of the block.

use std::sync::Arc;

use neurotree::nodes::built_ins;
use neurotree::{Blueprint, Builder, Clock, ManualClock, NodeKind, Port, PortBinding, Tree};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyString};

use crate::leaf::{PyAction, PyCondition, PyCoroutine, PyStateful};
use crate::ports::{self, PortTuple};
use crate::tree::{Ctx, PyTree};

/// Builds a tree node by node: `open` a control or decorator, add its children, `close` it.
#[pyclass(module = "neurotree", name = "Builder", subclass)]
pub struct PyBuilder {
    /// `None` once built.
    inner: Option<Builder<Ctx>>,
}

/// How a keyword argument binds a port: `"{key}"` is a blackboard entry, anything else a
/// literal written as BehaviorTree.CPP's XML writes it.
fn bindings(ports: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<Port>> {
    let mut out = Vec::new();
    for (name, value) in ports.into_iter().flat_map(|d| d.iter()) {
        let name: String = name.extract()?;
        let text = if let Ok(b) = value.downcast::<PyBool>() {
            if b.is_true() { "true" } else { "false" }.to_owned()
        } else if let Ok(s) = value.downcast::<PyString>() {
            s.to_cow()?.into_owned()
        } else {
            value.str()?.to_cow()?.into_owned()
        };
        let entry = text
            .strip_prefix('{')
            .and_then(|t| t.strip_suffix('}'))
            .filter(|key| !key.is_empty() && *key != "=");
        out.push(match entry {
            Some(key) => Port::entry(&name, key),
            None => Port::literal(&name, &text),
        });
    }
    Ok(out)
}

impl PyBuilder {
    fn take(&mut self) -> PyResult<Builder<Ctx>> {
        self.inner.take().ok_or_else(|| {
            PyRuntimeError::new_err("this Builder has built its tree; make a new one")
        })
    }

    /// Opens the built-in `type_name` with `ports`.
    fn open_built_in(
        &mut self,
        type_name: &str,
        name: Option<&str>,
        ports: Vec<Port>,
    ) -> PyResult<()> {
        let Some(decl) = built_ins().find(|d| d.name == type_name) else {
            let known: Vec<&str> = built_ins().map(|d| d.name).collect();
            return Err(PyValueError::new_err(format!(
                "`{type_name}` is no built-in node; the built-ins are {}",
                known.join(", ")
            )));
        };
        let binding = |port: &str| match ports.iter().find(|p| p.name == port) {
            Some(Port {
                value: neurotree::PortValue::Literal(text),
                ..
            }) => PortBinding::Literal(text.clone()),
            Some(_) => PortBinding::Entry,
            None => PortBinding::Missing,
        };
        let kind = match NodeKind::<Ctx>::from_declared(decl, &binding) {
            Some(Ok(kind)) => kind,
            Some(Err(e)) => return Err(PyValueError::new_err(format!("{type_name}: {e}"))),
            None => {
                return Err(PyValueError::new_err(format!(
                    "`{type_name}` is made by the registry, not the engine; load it from XML"
                )))
            }
        };
        let reads_entries = ports
            .iter()
            .any(|p| matches!(p.value, neurotree::PortValue::Entry(_)));
        let mut b = self.take()?.open(kind, name.unwrap_or(type_name));
        if reads_entries {
            b = b.ports(ports);
        }
        self.inner = Some(b);
        Ok(())
    }

    /// Adds the leaf `kind` named `name` with `ports` bound.
    fn add_leaf(&mut self, kind: NodeKind<Ctx>, name: &str, ports: Vec<Port>) -> PyResult<()> {
        let b = self.take()?.open(kind, name).ports(ports).close();
        self.inner = Some(b);
        Ok(())
    }
}

#[pymethods]
impl PyBuilder {
    /// An empty tree.
    #[new]
    fn new() -> Self {
        PyBuilder {
            inner: Some(Blueprint::builder()),
        }
    }

    /// Opens the built-in control or decorator `type_name` (`"Sequence"`, `"Repeat"`, ...),
    /// its ports given as keyword arguments; the nodes added until `close()` are its children.
    #[pyo3(signature = (type_name, name = None, **ports))]
    fn open(
        &mut self,
        type_name: &str,
        name: Option<&str>,
        ports: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        self.open_built_in(type_name, name, bindings(ports)?)
    }

    /// Closes the node opened last.
    fn close(&mut self) -> PyResult<()> {
        let b = self.take()?.close();
        self.inner = Some(b);
        Ok(())
    }

    /// Adds the built-in leaf `type_name` (`"AlwaysSuccess"`, `"Sleep"`, ...).
    #[pyo3(signature = (type_name, name = None, **ports))]
    fn leaf(
        &mut self,
        type_name: &str,
        name: Option<&str>,
        ports: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        self.open_built_in(type_name, name, bindings(ports)?)?;
        self.close()
    }

    /// Adds condition `name`: `func(node, robot) -> bool`, with ports declared by `ports`
    /// (as `Registry.condition` takes them) and bound by `bind`.
    fn add_condition(
        &mut self,
        name: &str,
        func: PyObject,
        ports: Vec<PortTuple>,
        bind: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        let (_, kinds) = ports::read(ports)?;
        let condition = PyCondition { func, kinds };
        self.add_leaf(
            NodeKind::Condition(Arc::new(condition)),
            name,
            bindings(bind)?,
        )
    }

    /// Adds action `name`: `func(node, robot) -> Status`.
    fn add_action(
        &mut self,
        name: &str,
        func: PyObject,
        ports: Vec<PortTuple>,
        bind: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        let (_, kinds) = ports::read(ports)?;
        let action = PyAction { func, kinds };
        self.add_leaf(NodeKind::Action(Arc::new(action)), name, bindings(bind)?)
    }

    /// Adds action `name`: an `async def (node, robot) -> Status`.
    fn add_async_action(
        &mut self,
        name: &str,
        func: PyObject,
        ports: Vec<PortTuple>,
        bind: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        let (_, kinds) = ports::read(ports)?;
        let make = PyCoroutine::maker(func, kinds);
        let kind = NodeKind::Stateful(Box::new(
            move || -> Box<dyn neurotree::StatefulAction<Ctx>> { Box::new(make()) },
        ));
        self.add_leaf(kind, name, bindings(bind)?)
    }

    /// Adds action `name`: an instance of `cls` (a `StatefulAction` subclass) per tree.
    fn add_stateful_action(
        &mut self,
        name: &str,
        cls: PyObject,
        ports: Vec<PortTuple>,
        bind: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        let (_, kinds) = ports::read(ports)?;
        let make = PyStateful::maker(cls, kinds);
        let kind = NodeKind::Stateful(Box::new(
            move || -> Box<dyn neurotree::StatefulAction<Ctx>> { Box::new(make()) },
        ));
        self.add_leaf(kind, name, bindings(bind)?)
    }

    /// Checks the tree and returns it, ready to tick on `clock` (a new `ManualClock` if none).
    #[pyo3(signature = (clock = None))]
    fn build(&mut self, py: Python<'_>, clock: Option<&Bound<'_, PyAny>>) -> PyResult<PyTree> {
        let clock: Arc<dyn Clock> = match clock {
            Some(c) => crate::clock::shared(c)?,
            None => Arc::new(ManualClock::new()),
        };
        let blueprint = self
            .take()?
            .build()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        PyTree::new(
            py,
            Tree::with_shared_clock(Arc::new(blueprint), clock),
            None,
        )
    }
}
