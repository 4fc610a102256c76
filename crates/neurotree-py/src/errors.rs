//! `neurotree.LoadError` and `neurotree.NodeError` (classes of `neurotree/__init__.py`), and
//! how a Python leaf's exception leaves the tree.
//!
//! A leaf that raises ends the tick at once, as an exception ends Python code: the error is
//! kept on the ticking thread and the leaf unwinds (`resume_unwind`, which prints nothing)
//! into the tree's catch of a node's panic, which halts every Running node once and leaves
//! the tree ready for the next tick. The tick's caller then raises `NodeError` naming the
//! node, with the leaf's exception as its `__cause__`.

use std::cell::RefCell;

use neurotree::{Handle, LoadError, LoadErrors, TickError};
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::sync::GILOnceCell;
use pyo3::types::PyType;

use crate::tree::Ctx;

static LOAD_ERROR: GILOnceCell<Py<PyType>> = GILOnceCell::new();
static NODE_ERROR: GILOnceCell<Py<PyType>> = GILOnceCell::new();

thread_local! {
    /// The exception a leaf or an observer raised in the tick under way on this thread.
    static RAISED: RefCell<Option<PyErr>> = const { RefCell::new(None) };
}

/// Keeps the exception classes.
pub(crate) fn bind(py: Python<'_>, load: &Bound<'_, PyType>, node: &Bound<'_, PyType>) {
    let _ = LOAD_ERROR.set(py, load.clone().unbind());
    let _ = NODE_ERROR.set(py, node.clone().unbind());
}

/// An instance of the bound class `cell`, made with `args`, as an error.
fn make<'py>(
    py: Python<'py>,
    cell: &GILOnceCell<Py<PyType>>,
    args: impl pyo3::call::PyCallArgs<'py>,
) -> PyErr {
    let Some(class) = cell.get(py) else {
        return PyException::new_err(
            "neurotree is not initialised: import neurotree, not neurotree._native",
        );
    };
    match class.bind(py).call1(args) {
        Ok(instance) => PyErr::from_value(instance),
        Err(e) => e,
    }
}

/// `NodeError(message, path)`.
pub(crate) fn node_error_at(py: Python<'_>, path: &str, message: &str) -> PyErr {
    make(py, &NODE_ERROR, (format!("{path}: {message}"), path))
}

/// A `NodeError` for the node `h` is called for: `message` follows its path.
pub(crate) fn node_error(h: &Handle<'_, Ctx>, message: impl AsRef<str>) -> PyErr {
    Python::with_gil(|py| node_error_at(py, &path_of(h), message.as_ref()))
}

/// The path of the node `h` is called for.
pub(crate) fn path_of(h: &Handle<'_, Ctx>) -> String {
    h.ctx().paths[h.node().index()].clone()
}

/// `LoadError(message, kind, file, line, column)`, the message as `neurotree check` prints it.
pub(crate) fn load_error(py: Python<'_>, e: &LoadError) -> PyErr {
    let kind = format!("{:?}", e.kind());
    make(
        py,
        &LOAD_ERROR,
        (e.to_string(), kind, e.file.clone(), e.line, e.col),
    )
}

/// A `LoadError` of the first of `errors`, whose `errors` lists every one of them (each a
/// `LoadError`), as `neurotree check` lists them.
pub(crate) fn load_errors(py: Python<'_>, errors: &LoadErrors) -> PyErr {
    if errors.len() == 1 {
        // Its `errors` is itself.
        return load_error(py, errors.first());
    }
    let all: Vec<Py<PyAny>> = errors
        .iter()
        .map(|e| load_error(py, e).into_value(py).into_any())
        .collect();
    let first = errors.first();
    let kind = format!("{:?}", first.kind());
    make(
        py,
        &LOAD_ERROR,
        (
            first.to_string(),
            kind,
            first.file.clone(),
            first.line,
            first.col,
            all,
        ),
    )
}

/// Ends the tick from inside a leaf or an observer, keeping `error` for the tick's caller.
pub(crate) fn raise_in_tree(error: PyErr, summary: String) -> ! {
    RAISED.with(|r| {
        let mut r = r.borrow_mut();
        // The first exception of a tick is the one the caller sees.
        if r.is_none() {
            *r = Some(error);
        }
    });
    std::panic::resume_unwind(Box::new(summary))
}

/// Keeps `error` for the caller of the call under way on this thread, without ending it:
/// for user code whose failure the engine can only see as "nothing" (a `save_state` that
/// raised), or that runs where nothing may unwind.
pub(crate) fn keep_raised(error: PyErr) {
    RAISED.with(|r| {
        let mut r = r.borrow_mut();
        if r.is_none() {
            *r = Some(error);
        }
    });
}

/// Takes the exception kept by the call under way on this thread, if any.
pub(crate) fn take_raised() -> Option<PyErr> {
    RAISED.with(|r| r.borrow_mut().take())
}

static TREE_BUSY: GILOnceCell<Py<PyType>> = GILOnceCell::new();

/// Keeps the class of `TreeBusy`.
pub(crate) fn bind_busy(py: Python<'_>, busy: &Bound<'_, PyType>) {
    let _ = TREE_BUSY.set(py, busy.clone().unbind());
}

/// `TreeBusy(message)`.
pub(crate) fn tree_busy(py: Python<'_>, message: &str) -> PyErr {
    make(py, &TREE_BUSY, (message.to_owned(),))
}

/// Forgets an exception kept by a tick that did not report it.
pub(crate) fn forget_raised() {
    RAISED.with(|r| r.borrow_mut().take());
}

/// The Python exception for a tick's error: a leaf's own `KeyboardInterrupt` or `SystemExit`
/// as it was, anything else as a `NodeError` naming the node, with the leaf's exception (if
/// one was raised) as its `__cause__`.
pub(crate) fn tick_error(py: Python<'_>, e: TickError) -> PyErr {
    let raised = RAISED.with(|r| r.borrow_mut().take());
    let path = match &e {
        TickError::LeafRunning { path, .. }
        | TickError::ReturnedIdle { path, .. }
        | TickError::TooManyPasses { path, .. }
        | TickError::Panicked { path, .. }
        | TickError::Node { path, .. } => path.clone(),
        _ => String::new(),
    };
    match raised {
        Some(cause) if !cause.is_instance_of::<PyException>(py) => cause,
        // The node's own NodeError (a bad return, a port read wrongly): already says it all.
        Some(cause) if names_node(py, &cause, &path) => cause,
        Some(cause) => {
            let message = match &e {
                TickError::Panicked { message, .. } => format!("{path}: {message}"),
                other => other.to_string(),
            };
            let error = make(py, &NODE_ERROR, (message, path));
            error.set_cause(py, Some(cause));
            error
        }
        None => make(py, &NODE_ERROR, (e.to_string(), path)),
    }
}

/// `true` if `error` is a `NodeError` about the node at `path`.
fn names_node(py: Python<'_>, error: &PyErr, path: &str) -> bool {
    let Some(class) = NODE_ERROR.get(py) else {
        return false;
    };
    error.get_type(py).is(class.bind(py))
        && error
            .value(py)
            .getattr("path")
            .and_then(|p| p.extract::<String>())
            .is_ok_and(|p| p == path)
}
