//! Leaves written in Python: conditions and actions (functions), stateful actions (a class
//! whose instance lives as long as its tree) and `async def` actions (a coroutine per run,
//! advanced once per tick, closed on halt).
//!
//! Every call takes the GIL for itself, points the tree's `Node` at the call's handle, and
//! calls `f(node, robot)`. A return value that is no status, and any exception, end the tick
//! (see [`crate::errors`]).

use std::sync::Arc;

use neurotree::{Action, Condition, Handle, Registry, RegistryError, StatefulAction, Status};
use pyo3::exceptions::{PyStopIteration, PyValueError};
use pyo3::intern;
use pyo3::prelude::*;

use crate::errors::{node_error, raise_in_tree};
use crate::ports::PortKinds;
use crate::tree::Ctx;

/// The registry's refusal as a Python error.
pub(crate) fn refused(e: RegistryError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Ends the tick with `error`, which the leaf being called raised.
fn raised(error: PyErr) -> ! {
    let summary = format!("raised {error}");
    raise_in_tree(error, summary)
}

/// Ends the tick: the leaf returned `value`, which is not what it may return.
fn bad_return(h: &Handle<'_, Ctx>, value: &Bound<'_, PyAny>, expected: &str) -> ! {
    let shown = value
        .repr()
        .map_or_else(|_| "an object".to_owned(), |r| r.to_string());
    let message = format!("returned {shown}; {expected}");
    raise_in_tree(node_error(h, &message), message)
}

/// A Python function as a condition: `func(node, robot)` returns `True`, `False`,
/// `Status.SUCCESS` or `Status.FAILURE`.
pub(crate) struct PyCondition {
    pub(crate) func: PyObject,
    pub(crate) kinds: PortKinds,
}

impl Condition<Ctx> for PyCondition {
    fn check(&self, h: &Handle<'_, Ctx>) -> bool {
        Python::with_gil(|py| {
            let ctx = h.ctx();
            let node = ctx.node.bind(py);
            let result = {
                let _entered = node.get().enter_read(h, &self.kinds);
                self.func.bind(py).call1((node, ctx.robot.bind(py)))
            };
            match result {
                Ok(v) => {
                    if let Ok(b) = v.downcast::<pyo3::types::PyBool>() {
                        return b.is_true();
                    }
                    match crate::status::from_py(&v) {
                        Some(Status::Success) => true,
                        Some(Status::Failure) => false,
                        _ => bad_return(
                            h,
                            &v,
                            "a condition returns True, False, nt.SUCCESS or nt.FAILURE",
                        ),
                    }
                }
                Err(e) => raised(e),
            }
        })
    }
}

/// A Python function as an action: `func(node, robot)` returns a `Status`.
pub(crate) struct PyAction {
    pub(crate) func: PyObject,
    pub(crate) kinds: PortKinds,
}

impl Action<Ctx> for PyAction {
    fn tick(&self, h: &mut Handle<'_, Ctx>) -> Status {
        Python::with_gil(|py| {
            let (node, robot) = {
                let ctx = h.ctx();
                (ctx.node.clone_ref(py), ctx.robot.clone_ref(py))
            };
            let node = node.bind(py);
            let result = {
                let _entered = node.get().enter(h, &self.kinds);
                self.func.bind(py).call1((node, robot.bind(py)))
            };
            match result {
                Ok(v) => status_of(h, &v),
                Err(e) => raised(e),
            }
        })
    }
}

/// Registers `func(node, robot) -> bool | Status` as condition `name`.
pub(crate) fn register_condition(
    registry: &mut Registry<Ctx>,
    name: &str,
    func: PyObject,
    ports: Vec<neurotree::PortSpec>,
    kinds: PortKinds,
) -> PyResult<()> {
    let condition = PyCondition { func, kinds };
    registry
        .register_condition(name, ports, move |h| condition.check(h))
        .map_err(refused)
}

/// Registers `func(node, robot) -> Status` as action `name`.
pub(crate) fn register_action(
    registry: &mut Registry<Ctx>,
    name: &str,
    func: PyObject,
    ports: Vec<neurotree::PortSpec>,
    kinds: PortKinds,
) -> PyResult<()> {
    let action = PyAction { func, kinds };
    registry
        .register_action(name, ports, move |h| action.tick(h))
        .map_err(refused)
}

/// The status an action's call returned, or the end of the tick if it is none.
fn status_of(h: &Handle<'_, Ctx>, value: &Bound<'_, PyAny>) -> Status {
    crate::status::from_py(value)
        .unwrap_or_else(|| bad_return(h, value, "return nt.SUCCESS, nt.FAILURE or nt.RUNNING"))
}

/// Calls `method(node, robot)` of `object` for the leaf `h` is called for.
fn call_method<'py>(
    py: Python<'py>,
    h: &mut Handle<'_, Ctx>,
    kinds: &PortKinds,
    object: &Bound<'py, PyAny>,
    method: &Bound<'py, pyo3::types::PyString>,
) -> PyResult<Bound<'py, PyAny>> {
    let (node, robot) = {
        let ctx = h.ctx();
        (ctx.node.clone_ref(py), ctx.robot.clone_ref(py))
    };
    let node = node.bind(py);
    let _entered = node.get().enter(h, kinds);
    object.call_method1(method, (node, robot.bind(py)))
}

/// A `StatefulAction` subclass's instance, one per tree.
pub(crate) struct PyStateful {
    /// The instance, or why the class could not make one (raised on the first start).
    object: Result<PyObject, Option<PyErr>>,
    kinds: Arc<PortKinds>,
}

/// The methods of a `StatefulAction` that return a status.
#[derive(Clone, Copy)]
enum Step {
    Start,
    Running,
}

impl PyStateful {
    /// Makes an instance of `class` for each node of each tree.
    pub(crate) fn maker(
        class: PyObject,
        kinds: PortKinds,
    ) -> impl Fn() -> PyStateful + Send + Sync {
        let kinds = Arc::new(kinds);
        move || {
            Python::with_gil(|py| PyStateful {
                object: class.call0(py).map_err(Some),
                kinds: Arc::clone(&kinds),
            })
        }
    }

    fn call(&mut self, h: &mut Handle<'_, Ctx>, step: Step) -> Status {
        Python::with_gil(|py| {
            let object = match &mut self.object {
                Ok(o) => o.clone_ref(py),
                Err(e) => {
                    let error = e.take().unwrap_or_else(|| {
                        PyValueError::new_err("the action's class could not be instantiated")
                    });
                    raised(error)
                }
            };
            let method = match step {
                Step::Start => intern!(py, "on_start"),
                Step::Running => intern!(py, "on_running"),
            };
            match call_method(py, h, &self.kinds, object.bind(py), method) {
                Ok(v) => status_of(h, &v),
                Err(e) => raised(e),
            }
        })
    }
}

impl StatefulAction<Ctx> for PyStateful {
    fn on_start(&mut self, h: &mut Handle<'_, Ctx>) -> Status {
        self.call(h, Step::Start)
    }

    fn on_running(&mut self, h: &mut Handle<'_, Ctx>) -> Status {
        self.call(h, Step::Running)
    }

    /// The instance's `save_state()` (by default, `StatefulAction` pickles its attributes).
    /// An exception, or a result that is not bytes, is kept for `Tree.save_state` to raise.
    fn save_state(&self) -> Option<Vec<u8>> {
        Python::with_gil(|py| {
            let object = self.object.as_ref().ok()?;
            let saved = object
                .bind(py)
                .call_method0(intern!(py, "save_state"))
                .and_then(|saved| saved.extract::<Vec<u8>>());
            saved.map_err(crate::errors::keep_raised).ok()
        })
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        Python::with_gil(|py| {
            let Ok(object) = &self.object else {
                return false;
            };
            let bytes = pyo3::types::PyBytes::new(py, state);
            object
                .bind(py)
                .call_method1(intern!(py, "restore_state"), (bytes,))
                .is_ok()
        })
    }

    fn on_halted(&mut self, h: &mut Handle<'_, Ctx>) {
        Python::with_gil(|py| {
            let Ok(object) = &self.object else { return };
            let object = object.clone_ref(py);
            if let Err(e) = call_method(
                py,
                h,
                &self.kinds,
                object.bind(py),
                intern!(py, "on_halted"),
            ) {
                raised(e);
            }
        })
    }
}

/// Registers `class_` (a `StatefulAction` subclass) as action `name`: each tree makes one
/// instance per node with `class_()`.
pub(crate) fn register_stateful(
    registry: &mut Registry<Ctx>,
    name: &str,
    class: PyObject,
    ports: Vec<neurotree::PortSpec>,
    kinds: PortKinds,
) -> PyResult<()> {
    let make = PyStateful::maker(class, kinds);
    registry
        .register_stateful(name, ports, make)
        .map_err(refused)
}

/// An `async def` action: a coroutine per run, sent `None` once per tick.
pub(crate) struct PyCoroutine {
    func: Arc<PyObject>,
    kinds: Arc<PortKinds>,
    running: Option<PyObject>,
}

impl PyCoroutine {
    /// Makes the driver of `func`'s coroutines for each node of each tree.
    pub(crate) fn maker(
        func: PyObject,
        kinds: PortKinds,
    ) -> impl Fn() -> PyCoroutine + Send + Sync {
        let (func, kinds) = (Arc::new(func), Arc::new(kinds));
        move || PyCoroutine {
            func: Arc::clone(&func),
            kinds: Arc::clone(&kinds),
            running: None,
        }
    }

    /// Advances the coroutine by one step: Running while it awaits, its result once done.
    fn step(&mut self, py: Python<'_>, h: &mut Handle<'_, Ctx>, coroutine: PyObject) -> Status {
        let sent = {
            let node = h.ctx().node.clone_ref(py);
            let _entered = node.get().enter(h, &self.kinds);
            coroutine
                .bind(py)
                .call_method1(intern!(py, "send"), (py.None(),))
        };
        match sent {
            Ok(_) => {
                self.running = Some(coroutine);
                Status::Running
            }
            Err(e) if e.is_instance_of::<PyStopIteration>(py) => {
                let value = e.value(py).getattr(intern!(py, "value"));
                match value {
                    Ok(v) => status_of(h, &v),
                    Err(e) => raised(e),
                }
            }
            Err(e) => raised(e),
        }
    }
}

impl StatefulAction<Ctx> for PyCoroutine {
    fn on_start(&mut self, h: &mut Handle<'_, Ctx>) -> Status {
        Python::with_gil(|py| {
            let (node, robot) = {
                let ctx = h.ctx();
                (ctx.node.clone_ref(py), ctx.robot.clone_ref(py))
            };
            let made = {
                let node = node.bind(py);
                let _entered = node.get().enter(h, &self.kinds);
                self.func.bind(py).call1((node, robot.bind(py)))
            };
            match made {
                Ok(coroutine) => self.step(py, h, coroutine.unbind()),
                Err(e) => raised(e),
            }
        })
    }

    fn on_running(&mut self, h: &mut Handle<'_, Ctx>) -> Status {
        Python::with_gil(|py| match self.running.take() {
            Some(coroutine) => self.step(py, h, coroutine),
            None => self.on_start(h),
        })
    }

    /// Between runs there is nothing to save; a coroutine under way cannot be saved.
    fn save_state(&self) -> Option<Vec<u8>> {
        self.running.is_none().then(Vec::new)
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        state.is_empty()
    }

    fn on_halted(&mut self, _h: &mut Handle<'_, Ctx>) {
        Python::with_gil(|py| {
            if let Some(coroutine) = self.running.take() {
                if let Err(e) = coroutine.bind(py).call_method0(intern!(py, "close")) {
                    raised(e);
                }
            }
        })
    }
}

/// Registers `func`, an `async def (node, robot) -> Status`, as action `name`.
pub(crate) fn register_coroutine(
    registry: &mut Registry<Ctx>,
    name: &str,
    func: PyObject,
    ports: Vec<neurotree::PortSpec>,
    kinds: PortKinds,
) -> PyResult<()> {
    registry
        .register_stateful(name, ports, PyCoroutine::maker(func, kinds))
        .map_err(refused)
}
