//! `neurotree.Tree`: a loaded tree, ticked from Python.
//!
//! The tree sits behind a mutex, so that any Python thread may tick it (one at a time); the
//! tick runs with the GIL released, and Python leaves take the GIL for their own call only.
//! A call that uses the tree while another call ticks it, from another thread or from a
//! leaf of that very tick, raises `TreeBusy` at once rather than waiting: a leaf that waits
//! for a thread ticking its own tree would otherwise wait for ever.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use neurotree::observe::{Coverage, JsonlTrace};
use neurotree::{Blueprint, Observer, ScopeId, Status, Tree};
use pyo3::exceptions::{PyKeyError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::errors::{forget_raised, take_raised, tick_error, tree_busy};
use crate::node::Node;
use crate::observe::{CallbackObserver, Fanout, LineWriter};
use crate::registry::PyRegistry;
use crate::value::{self, Stored};

/// What a tick hands every leaf: the object the tree is ticked with, the tree's `Node`, and
/// the node paths errors name.
pub(crate) struct Ctx {
    pub(crate) robot: PyObject,
    pub(crate) node: Py<Node>,
    pub(crate) paths: Arc<[String]>,
}

/// The tree and what goes with it, under the tree's lock.
pub(crate) struct Inner {
    pub(crate) tree: Tree<Ctx>,
    paths: Arc<[String]>,
    /// The studio showing the tree, and its side of the run (`neurotree.studio.watch`).
    #[cfg(feature = "studio")]
    studio: Option<(neurotree::studio::Studio, neurotree::studio::Watch, String)>,
}

/// A tree loaded from XML (`Registry.load_string`, `Registry.load_file`) or built
/// (`Builder.build`), with its blackboard and clock.
#[pyclass(module = "neurotree", name = "Tree", frozen)]
pub struct PyTree {
    inner: Mutex<Inner>,
    /// The thread whose tick holds the lock, or 0.
    ticking: AtomicU64,
    node: Py<Node>,
    /// The registry it was loaded with, for `reload`.
    registry: Option<Py<PyRegistry>>,
}

/// A number for the current thread, never 0.
fn thread_number() -> u64 {
    thread_local!(static NUMBER: u64 = {
        static NEXT: AtomicU64 = AtomicU64::new(1);
        NEXT.fetch_add(1, Ordering::Relaxed)
    });
    NUMBER.with(|n| *n)
}

/// `TreeBusy` for a use of a tree that thread `ticker` is ticking.
fn busy(py: Python<'_>, ticker: u64) -> PyErr {
    if ticker == thread_number() {
        tree_busy(
            py,
            "this tree is being ticked by this thread: a leaf reads and writes its tree's blackboard through its node (node.get, node.set)",
        )
    } else {
        tree_busy(
            py,
            "this tree is being ticked by another thread; ticks of one tree do not wait for each other (a leaf waiting for a thread that ticks its own tree would wait for ever): try again once that tick is done",
        )
    }
}

impl PyTree {
    pub(crate) fn new(
        py: Python<'_>,
        tree: Tree<Ctx>,
        registry: Option<Py<PyRegistry>>,
    ) -> PyResult<Self> {
        let paths: Arc<[String]> = tree.blueprint().paths().into();
        Ok(PyTree {
            inner: Mutex::new(Inner {
                tree,
                paths,
                #[cfg(feature = "studio")]
                studio: None,
            }),
            ticking: AtomicU64::new(0),
            node: Py::new(py, Node::detached())?,
            registry,
        })
    }

    /// The tree's lock, for a short use between ticks: `TreeBusy` while a call ticks it.
    pub(crate) fn lock(&self, py: Python<'_>) -> PyResult<MutexGuard<'_, Inner>> {
        self.acquire(py, true)
    }

    /// The tree's lock, waited for without the GIL while another thread uses the tree
    /// shortly; with `refuse_ticked`, `TreeBusy` as soon as a call ticks it (every tick
    /// marks itself in `ticking` before it takes the lock, so that none waits for another).
    fn acquire(&self, py: Python<'_>, refuse_ticked: bool) -> PyResult<MutexGuard<'_, Inner>> {
        loop {
            let ticker = self.ticking.load(Ordering::Acquire);
            if refuse_ticked && ticker != 0 {
                return Err(busy(py, ticker));
            }
            match self.inner.try_lock() {
                Ok(guard) => return Ok(guard),
                // A panic is caught inside the tick, so a poisoned lock guards a whole tree.
                Err(std::sync::TryLockError::Poisoned(p)) => return Ok(p.into_inner()),
                // A short use by another thread, which may need the GIL to finish.
                Err(std::sync::TryLockError::WouldBlock) => {
                    py.allow_threads(std::thread::yield_now)
                }
            }
        }
    }

    fn ctx(&self, py: Python<'_>, inner: &Inner, robot: Option<&Bound<'_, PyAny>>) -> Ctx {
        Ctx {
            robot: robot.map_or_else(|| py.None(), |r| r.clone().unbind()),
            node: self.node.clone_ref(py),
            paths: Arc::clone(&inner.paths),
        }
    }

    /// Runs `work` on the locked tree with the GIL released, marked as ticked by this thread.
    fn with_tree_released<T: Send>(
        &self,
        py: Python<'_>,
        robot: Option<&Bound<'_, PyAny>>,
        work: impl FnOnce(&mut Tree<Ctx>, &mut Ctx) -> T + Send,
    ) -> PyResult<T> {
        self.with_inner_released(py, robot, |inner, ctx| work(&mut inner.tree, ctx))
    }

    /// As [`with_tree_released`](Self::with_tree_released), with all that is under the lock.
    fn with_inner_released<T: Send>(
        &self,
        py: Python<'_>,
        robot: Option<&Bound<'_, PyAny>>,
        work: impl FnOnce(&mut Inner, &mut Ctx) -> T + Send,
    ) -> PyResult<T> {
        // Marked before the lock is taken, so that a second tick is refused rather than
        // waiting for this one.
        if let Err(ticker) =
            self.ticking
                .compare_exchange(0, thread_number(), Ordering::AcqRel, Ordering::Acquire)
        {
            return Err(busy(py, ticker));
        }
        let mut inner = match self.acquire(py, false) {
            Ok(inner) => inner,
            Err(e) => {
                self.ticking.store(0, Ordering::Release);
                return Err(e);
            }
        };
        let mut ctx = self.ctx(py, &inner, robot);
        forget_raised();
        let inner = &mut *inner;
        let out = py.allow_threads(|| work(inner, &mut ctx));
        self.ticking.store(0, Ordering::Release);
        Ok(out)
    }

    fn tick(&self, py: Python<'_>, robot: Option<&Bound<'_, PyAny>>) -> PyResult<Status> {
        self.with_inner_released(py, robot, |inner, ctx| {
            #[cfg(feature = "studio")]
            if let Some((_, watch, _)) = &mut inner.studio {
                return watch.tick_once(&mut inner.tree, ctx);
            }
            inner.tree.tick_once(ctx)
        })?
        .map_err(|e| tick_error(py, e))
    }

    /// Adds `observer` beside those the tree has.
    fn observe(&self, py: Python<'_>, observer: Box<dyn Observer>) -> PyResult<()> {
        let mut inner = self.lock(py)?;
        let observers = match inner.tree.take_observer() {
            Some(old) => vec![old, observer],
            None => vec![observer],
        };
        inner.tree.set_observer(Fanout(observers));
        Ok(())
    }

    pub(crate) fn blueprint(&self, py: Python<'_>) -> PyResult<Arc<Blueprint<Ctx>>> {
        Ok(Arc::clone(self.lock(py)?.tree.blueprint()))
    }
}

#[pymethods]
impl PyTree {
    /// Ticks the tree once (again at once while a node asks to be woken) with `robot` handed
    /// to every leaf, and returns the root's status.
    #[pyo3(signature = (robot = None))]
    fn tick_once(&self, py: Python<'_>, robot: Option<&Bound<'_, PyAny>>) -> PyResult<PyObject> {
        let status = self.tick(py, robot)?;
        Ok(crate::status::to_py(py, status.into()))
    }

    /// Ticks until the root is no longer Running, letting `period` seconds pass on the tree's
    /// clock between ticks (a `ManualClock` is advanced, a `SystemClock` sleeps). Returns the
    /// last status: `RUNNING` if `max_ticks` ticks did not finish it. Ctrl-C between ticks
    /// halts the tree and raises `KeyboardInterrupt`.
    #[pyo3(signature = (robot = None, max_ticks = None, period = 0.01))]
    fn tick_while_running(
        &self,
        py: Python<'_>,
        robot: Option<&Bound<'_, PyAny>>,
        max_ticks: Option<u64>,
        period: f64,
    ) -> PyResult<PyObject> {
        let period = Duration::try_from_secs_f64(period).map_err(|_| {
            PyValueError::new_err(format!("period {period} is no number of seconds"))
        })?;
        let mut ticks = 0_u64;
        loop {
            let status = self.tick(py, robot)?;
            ticks += 1;
            if status != Status::Running || max_ticks.is_some_and(|m| ticks >= m) {
                return Ok(crate::status::to_py(py, status.into()));
            }
            self.with_tree_released(py, robot, |tree, _| tree.clock().wait(period))?;
            if let Err(interrupt) = py.check_signals() {
                self.halt(py, robot)?;
                return Err(interrupt);
            }
        }
    }

    /// Ticks `count` times in one call, as `tick_once` would `count` times, and returns the
    /// last status: for loops that need no Python between ticks (a simulation's steps).
    #[pyo3(signature = (count, robot = None))]
    fn tick_times(
        &self,
        py: Python<'_>,
        count: u64,
        robot: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyObject> {
        let last = self.with_tree_released(py, robot, |tree, ctx| {
            let mut last = Ok(Status::Running);
            for _ in 0..count {
                last = tree.tick_once(ctx);
                if last.is_err() {
                    break;
                }
            }
            last
        })?;
        let status = last.map_err(|e| tick_error(py, e))?;
        Ok(crate::status::to_py(py, status.into()))
    }

    /// Halts every Running node (each Running stateful action's `on_halted` runs once). An
    /// exception an `on_halted` raises is raised from here, once the whole tree is halted.
    #[pyo3(signature = (robot = None))]
    fn halt(&self, py: Python<'_>, robot: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        // An `on_halted` that raises is caught by the tree, which halts the others all the
        // same; its exception is raised here once the tree is halted.
        match self.with_tree_released(py, robot, |tree, ctx| {
            tree.halt(ctx);
            take_raised()
        })? {
            Some(raised) => Err(raised),
            None => Ok(()),
        }
    }

    /// The tree's blackboard (its root scope), as a mapping.
    #[getter]
    fn blackboard(slf: &Bound<'_, Self>) -> PyBlackboard {
        PyBlackboard {
            tree: slf.clone().unbind(),
        }
    }

    /// The status of every node by path, as stored now.
    fn statuses(&self, py: Python<'_>) -> PyResult<Vec<(String, PyObject)>> {
        let inner = self.lock(py)?;
        Ok(inner
            .paths
            .iter()
            .zip(inner.tree.statuses())
            .map(|(p, s)| (p.clone(), crate::status::to_py(py, *s)))
            .collect())
    }

    /// The node paths, root first (depth-first, as the file lists them).
    fn paths(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        Ok(self.lock(py)?.paths.to_vec())
    }

    /// The tree's clock, in seconds.
    #[getter]
    fn now(&self, py: Python<'_>) -> PyResult<f64> {
        Ok(self.lock(py)?.tree.now().as_secs_f64())
    }

    /// Why the root failed on the last tick, or `None` if it did not fail.
    fn last_failure(&self, py: Python<'_>) -> PyResult<Option<crate::observe::PyFailure>> {
        Ok(self
            .lock(py)?
            .tree
            .last_failure()
            .map(crate::observe::PyFailure::from))
    }

    /// Calls `callback(path, previous, status, seconds)` on every change of a node's status.
    fn on_status_change(&self, py: Python<'_>, callback: PyObject) -> PyResult<()> {
        let paths = Arc::clone(&self.lock(py)?.paths);
        self.observe(py, Box::new(CallbackObserver { callback, paths }))
    }

    /// Calls `callback(line)` with each JSON line of the trace `neurotree run --jsonl` prints.
    fn on_trace_line(&self, py: Python<'_>, callback: PyObject) -> PyResult<()> {
        let trace = JsonlTrace::new(&*self.blueprint(py)?, LineWriter::new(callback));
        self.observe(py, Box::new(trace))
    }

    /// Starts recording which outcomes each node has had; the returned object reports them.
    fn start_coverage(&self, py: Python<'_>) -> PyResult<crate::observe::PyCoverage> {
        let blueprint = self.blueprint(py)?;
        let coverage = Coverage::new(&*blueprint);
        self.observe(py, Box::new(coverage.clone()))?;
        Ok(crate::observe::PyCoverage {
            coverage,
            blueprint,
        })
    }

    /// The tree's whole state (node statuses, leaf state, blackboard) as bytes.
    fn save_state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let inner = self.lock(py)?;
        forget_raised();
        let saved = inner.tree.save_state();
        // A leaf's `save_state` that raised: its exception, rather than the tree's account
        // of a node that saved nothing.
        if let Some(raised) = take_raised() {
            return Err(raised);
        }
        let bytes = saved.map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(PyBytes::new(py, &bytes))
    }

    /// Puts back a state `save_state` gave, of a tree of the same structure.
    fn restore_state(&self, py: Python<'_>, state: &[u8]) -> PyResult<()> {
        self.lock(py)?
            .tree
            .restore_state(state)
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// Swaps in the tree of `xml` (or of the file at `path`), loaded with the same registry:
    /// unchanged nodes keep their state, changed ones that were Running are halted. Returns
    /// `(kept, restarted, halted)` node counts.
    #[pyo3(signature = (xml = None, *, path = None, robot = None))]
    fn reload(
        &self,
        py: Python<'_>,
        xml: Option<&str>,
        path: Option<std::path::PathBuf>,
        robot: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<(usize, usize, usize)> {
        let Some(registry) = &self.registry else {
            return Err(PyRuntimeError::new_err(
                "only a tree loaded from XML can be reloaded",
            ));
        };
        let blueprint = registry.borrow(py).blueprint(py, xml, path.as_deref())?;
        let report =
            self.with_tree_released(py, robot, |tree, ctx| tree.reload(Arc::new(blueprint), ctx))?;
        let report = report.map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        {
            let mut inner = self.lock(py)?;
            let inner = &mut *inner;
            inner.paths = inner.tree.blueprint().paths().into();
            #[cfg(feature = "studio")]
            if let Some((_, watch, name)) = &mut inner.studio {
                watch.reattach(&inner.tree, name);
            }
        }
        Ok((report.kept, report.restarted, report.halted))
    }

    /// Shows the tree in the studio, served on 127.0.0.1:`port` (0: a free port), and returns
    /// the page's URL. From then on each tick applies the page's blackboard edits first and
    /// waits while the page holds the run paused; `neurotree.studio.watch` calls this.
    #[cfg(feature = "studio")]
    #[pyo3(signature = (port = 0, name = "tree"))]
    fn _watch_in_studio(&self, py: Python<'_>, port: u16, name: &str) -> PyResult<String> {
        use neurotree::studio::{Studio, StudioOptions};
        let options = StudioOptions {
            port,
            // The page's editor knows the built-ins only: a Python program's own types are
            // not in the registry it checks with.
            unknown_type_advice: "the studio's editor knows the built-in node types only",
            ..StudioOptions::default()
        };
        let studio = py
            .allow_threads(|| Studio::serve(options, neurotree::Registry::new))
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        let url = studio.url();
        let (observer, watch) = studio.attach(&self.lock(py)?.tree, name);
        self.observe(py, Box::new(observer))?;
        self.lock(py)?.studio = Some((studio, watch, name.to_owned()));
        Ok(url)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        match self.lock(py) {
            Ok(inner) => format!("<neurotree.Tree of {} nodes>", inner.paths.len()),
            Err(_) => "<neurotree.Tree (ticking)>".to_owned(),
        }
    }
}

/// `Tree.blackboard`: the root scope's entries, as a mapping.
#[pyclass(module = "neurotree", name = "Blackboard", frozen)]
pub struct PyBlackboard {
    tree: Py<PyTree>,
}

#[pymethods]
impl PyBlackboard {
    fn __getitem__(&self, py: Python<'_>, key: &str) -> PyResult<PyObject> {
        let tree = self.tree.get();
        let inner = tree.lock(py)?;
        let bb = inner.tree.blackboard();
        if !bb.contains_in(ScopeId::ROOT, key) {
            return Err(PyKeyError::new_err(key.to_owned()));
        }
        Ok(value::read(py, bb, ScopeId::ROOT, key))
    }

    fn __setitem__(&self, py: Python<'_>, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let stored = Stored::from_py(value)?;
        let tree = self.tree.get();
        let mut inner = tree.lock(py)?;
        let now = inner.tree.now();
        stored.write(inner.tree.blackboard_mut(), ScopeId::ROOT, key, now)
    }

    fn __delitem__(&self, py: Python<'_>, key: &str) -> PyResult<()> {
        let tree = self.tree.get();
        if tree
            .lock(py)?
            .tree
            .blackboard_mut()
            .unset_in(ScopeId::ROOT, key)
        {
            Ok(())
        } else {
            Err(PyKeyError::new_err(key.to_owned()))
        }
    }

    fn __contains__(&self, py: Python<'_>, key: &str) -> PyResult<bool> {
        Ok(self
            .tree
            .get()
            .lock(py)?
            .tree
            .blackboard()
            .contains_in(ScopeId::ROOT, key))
    }

    fn __len__(&self, py: Python<'_>) -> PyResult<usize> {
        Ok(self
            .tree
            .get()
            .lock(py)?
            .tree
            .blackboard()
            .keys_in(ScopeId::ROOT)
            .count())
    }

    /// The keys of the root scope, sorted.
    fn keys(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        let tree = self.tree.get();
        let inner = tree.lock(py)?;
        let mut keys: Vec<String> = inner
            .tree
            .blackboard()
            .keys_in(ScopeId::ROOT)
            .map(str::to_owned)
            .collect();
        keys.sort();
        Ok(keys)
    }

    /// The entry `key`, or `default` if there is none.
    #[pyo3(signature = (key, default = None))]
    fn get(&self, py: Python<'_>, key: &str, default: Option<PyObject>) -> PyResult<PyObject> {
        match self.__getitem__(py, key) {
            Err(e) if e.is_instance_of::<PyKeyError>(py) => {
                Ok(default.unwrap_or_else(|| py.None()))
            }
            other => other,
        }
    }

    /// Every entry of the root scope, as a dict.
    fn to_dict(&self, py: Python<'_>) -> PyResult<PyObject> {
        let dict = pyo3::types::PyDict::new(py);
        let tree = self.tree.get();
        let inner = tree.lock(py)?;
        let bb = inner.tree.blackboard();
        for key in bb.keys_in(ScopeId::ROOT) {
            dict.set_item(key, value::read(py, bb, ScopeId::ROOT, key))?;
        }
        Ok(dict.into_any().unbind())
    }
}
