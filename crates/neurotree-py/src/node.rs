//! `neurotree.Node`: what a Python leaf is handed on each call — its ports, its blackboard
//! scope, the clock, its name and path.
//!
//! The engine gives a leaf a `Handle` that lives for one call. A tree keeps one `Node` object
//! and points it at the handle of the leaf being called, and at nothing between calls, so a
//! leaf costs no Python allocation, and a `Node` kept past its call raises instead of reading
//! freed memory.

use std::ptr;
use std::sync::atomic::{AtomicBool, AtomicPtr, Ordering};

use neurotree::{Handle, PortValue, Reason};
use pyo3::exceptions::{PyRuntimeError, PyTypeError};
use pyo3::prelude::*;

use crate::errors::node_error;
use crate::ports::{Kind, PortKinds};
use crate::tree::Ctx;
use crate::value::{self, Stored};

/// The node a Python leaf is called for (valid during the call only).
#[pyclass(module = "neurotree", frozen)]
pub struct Node {
    /// The `Handle<'_, Ctx>` of the call under way, or null.
    handle: AtomicPtr<()>,
    /// The port types of the leaf's node type, or null.
    kinds: AtomicPtr<PortKinds>,
    /// `false` for a condition, which reads and never writes.
    writable: AtomicBool,
}

/// While alive, the node points at one call's handle.
pub(crate) struct Entered<'n> {
    node: &'n Node,
}

impl Drop for Entered<'_> {
    fn drop(&mut self) {
        self.node.handle.store(ptr::null_mut(), Ordering::Release);
        self.node.kinds.store(ptr::null_mut(), Ordering::Release);
    }
}

impl Node {
    /// A node pointing at nothing.
    pub(crate) fn detached() -> Self {
        Node {
            handle: AtomicPtr::new(ptr::null_mut()),
            kinds: AtomicPtr::new(ptr::null_mut()),
            writable: AtomicBool::new(false),
        }
    }

    /// Points the node at `h` for a condition's call: its ports are read only.
    pub(crate) fn enter_read<'n>(&'n self, h: &Handle<'_, Ctx>, kinds: &PortKinds) -> Entered<'n> {
        self.point(h as *const Handle<'_, Ctx> as *mut (), kinds, false)
    }

    /// Points the node at `h` for an action's call.
    pub(crate) fn enter<'n>(&'n self, h: &mut Handle<'_, Ctx>, kinds: &PortKinds) -> Entered<'n> {
        self.point(h as *mut Handle<'_, Ctx> as *mut (), kinds, true)
    }

    fn point(&self, handle: *mut (), kinds: &PortKinds, writable: bool) -> Entered<'_> {
        self.handle.store(handle, Ordering::Release);
        self.kinds.store(
            kinds as *const PortKinds as *mut PortKinds,
            Ordering::Release,
        );
        self.writable.store(writable, Ordering::Release);
        Entered { node: self }
    }

    /// The handle of the call under way.
    fn handle(&self) -> PyResult<&Handle<'static, Ctx>> {
        let h = self.handle.load(Ordering::Acquire) as *const Handle<'static, Ctx>;
        // Not null only while `Entered` lives, which is during the leaf's call, when the
        // handle it was made from is alive and used by nothing else; the GIL, held by the
        // caller, keeps other threads out.
        unsafe { h.as_ref() }.ok_or_else(|| {
            PyRuntimeError::new_err(
                "this Node was used outside its leaf's call; use the node a leaf is given while it runs",
            )
        })
    }

    /// The handle of the call under way, to write through.
    // The `&mut` is the one the engine lent the leaf's call (`enter`), reached through the
    // pointer, not through `self`; each method takes it once and lets it go before it returns.
    #[allow(clippy::mut_from_ref)]
    fn handle_mut(&self) -> PyResult<&mut Handle<'static, Ctx>> {
        let h = self.handle.load(Ordering::Acquire) as *mut Handle<'static, Ctx>;
        if !h.is_null() && !self.writable.load(Ordering::Acquire) {
            let name = self.handle()?.name();
            return Err(PyTypeError::new_err(format!(
                "{name} is a condition: it reads ports and the blackboard and writes neither; register an action to write"
            )));
        }
        // As in `handle`, and the call is an action's, which was given its handle `&mut`.
        unsafe { h.as_mut() }.ok_or_else(|| {
            PyRuntimeError::new_err(
                "this Node was used outside its leaf's call; use the node a leaf is given while it runs",
            )
        })
    }

    fn kind(&self, h: &Handle<'static, Ctx>, port: &str) -> PyResult<Kind> {
        // Set with the handle, to the leaf type's kinds, which outlive the call.
        let kinds = unsafe { self.kinds.load(Ordering::Acquire).as_ref() };
        kinds.and_then(|k| k.get(port)).ok_or_else(|| {
            node_error(
                h,
                format!("has no port `{port}`; declare it in the node type's ports"),
            )
        })
    }
}

#[pymethods]
impl Node {
    /// The node's name (its `name` attribute, or its type).
    #[getter]
    fn name(&self) -> PyResult<String> {
        Ok(self.handle()?.name().to_owned())
    }

    /// The node's path in the tree (`patrol/MoveTo`, from the root node).
    #[getter]
    fn path(&self) -> PyResult<String> {
        let h = self.handle()?;
        Ok(crate::errors::path_of(h))
    }

    /// The tree's clock, in seconds.
    #[getter]
    fn now(&self) -> PyResult<f64> {
        Ok(self.handle()?.now().as_secs_f64())
    }

    /// Reads input port `port` as the type its node type declares.
    fn input(&self, py: Python<'_>, port: &str) -> PyResult<PyObject> {
        let h = self.handle()?;
        let kind = self.kind(h, port)?;
        let read = match kind {
            Kind::Int => h
                .input::<i64>(port)
                .map(|v| v.into_pyobject(py).map(|o| o.into_any().unbind())),
            Kind::Float => h
                .input::<f64>(port)
                .map(|v| v.into_pyobject(py).map(|o| o.into_any().unbind())),
            Kind::Bool => h.input::<bool>(port).map(|v| {
                v.into_pyobject(py)
                    .map(|o| o.to_owned().into_any().unbind())
            }),
            Kind::Str => h
                .input::<String>(port)
                .map(|v| v.into_pyobject(py).map(|o| o.into_any().unbind())),
            Kind::List | Kind::Dict | Kind::Any => return read_json_port(py, h, port, kind),
        };
        match read {
            Ok(v) => Ok(v?),
            Err(e) => Err(node_error(h, e.to_string())),
        }
    }

    /// Writes output port `port`, which must be of its declared type.
    fn output(&self, port: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let h = self.handle_mut()?;
        let kind = self.kind(h, port)?;
        let stored =
            Stored::from_py(value).map_err(|e| node_error(h, format!("port `{port}`: {e}")))?;
        let written = match (kind, stored) {
            (Kind::Int, Stored::Int(v)) => h.output(port, v),
            (Kind::Float, Stored::Float(v)) => h.output(port, v),
            (Kind::Float, Stored::Int(v)) => h.output(port, v as f64),
            (Kind::Bool, Stored::Bool(v)) => h.output(port, v),
            (Kind::Str, Stored::Text(v)) => h.output(port, v),
            (Kind::List | Kind::Dict | Kind::Any, stored) => {
                return write_untyped_port(h, port, stored)
            }
            (kind, _) => {
                return Err(node_error(
                    h,
                    format!(
                        "port `{port}` is declared {}, and was given {}",
                        kind.python_name(),
                        value.get_type().name()?
                    ),
                ))
            }
        };
        written.map_err(|e| node_error(h, format!("port `{port}`: {e}")))
    }

    /// The blackboard entry `key` in the node's scope, or `None`.
    fn get(&self, py: Python<'_>, key: &str) -> PyResult<PyObject> {
        let h = self.handle()?;
        Ok(value::read(py, h.blackboard(), h.scope(), key))
    }

    /// Writes the blackboard entry `key` in the node's scope.
    fn set(&self, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let h = self.handle_mut()?;
        let (scope, now) = (h.scope(), h.now());
        Stored::from_py(value)?.write(h.blackboard_mut(), scope, key, now)
    }

    /// Returns `Status.FAILURE`, giving `reason` (and `code`) for `Tree.last_failure()`.
    #[pyo3(signature = (reason, code = 0))]
    fn fail(&self, py: Python<'_>, reason: String, code: u32) -> PyResult<PyObject> {
        let h = self.handle_mut()?;
        let status = h.fail_because(Reason::owned(code, reason));
        Ok(crate::status::to_py(py, status.into()))
    }

    fn __repr__(&self) -> String {
        match self.handle() {
            Ok(h) => format!("<neurotree.Node {}>", crate::errors::path_of(h)),
            Err(_) => "<neurotree.Node (outside its call)>".to_owned(),
        }
    }
}

/// Reads a port declared `list`, `dict` or of no type: a literal as JSON (`json:` prefix
/// optional) for the first two and as text otherwise; an entry as what it holds.
fn read_json_port(
    py: Python<'_>,
    h: &Handle<'static, Ctx>,
    port: &str,
    kind: Kind,
) -> PyResult<PyObject> {
    let Some(binding) = h.ports().iter().find(|p| p.name == port) else {
        return Ok(py.None());
    };
    match &binding.value {
        PortValue::Literal(text) if kind == Kind::Any => {
            Ok(text.into_pyobject(py)?.into_any().unbind())
        }
        PortValue::Literal(text) => {
            let json = text.strip_prefix("json:").unwrap_or(text);
            serde_json::from_str(json)
                .map(|v| value::py_of(py, &v))
                .map_err(|e| {
                    node_error(
                        h,
                        format!(
                            "port `{port}`: `{text}` is no JSON {}: {e}",
                            kind.python_name()
                        ),
                    )
                })
        }
        PortValue::Entry(key) => Ok(value::read(py, h.blackboard(), h.scope(), key)),
    }
}

/// Writes a port declared `list`, `dict` or of no type: the entry it is bound to.
fn write_untyped_port(h: &mut Handle<'static, Ctx>, port: &str, stored: Stored) -> PyResult<()> {
    let Some(binding) = h.ports().iter().find(|p| p.name == port) else {
        return Err(node_error(h, format!("has no port `{port}`")));
    };
    let PortValue::Entry(key) = &binding.value else {
        return Err(node_error(
            h,
            format!("port `{port}` is given a literal, not a blackboard entry (`{{key}}`), so it cannot be written"),
        ));
    };
    let (scope, now) = (h.scope(), h.now());
    let key = key.to_string();
    stored.write(h.blackboard_mut(), scope, &key, now)
}
