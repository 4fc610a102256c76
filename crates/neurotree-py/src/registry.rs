//! `neurotree.Registry`: node types by name — every built-in, Python leaves, Nav2's — and
//! loading BehaviorTree.CPP XML into trees.
//!
//! The decorators (`@reg.condition(...)`, `@reg.action(...)`) are the Python subclass's, in
//! `neurotree/__init__.py`; they read the ports and call the `register_*` methods here.

use std::path::Path;
use std::sync::Arc;

use neurotree::xml::{parse_outcomes, Substitutions};
use neurotree::{Blueprint, Clock, ManualClock, Registry, Tree, XmlLoader};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::clock;
use crate::errors::{load_error, load_errors};
use crate::leaf;
use crate::ports::{self, PortTuple};
use crate::tree::{Ctx, PyTree};

/// Node types by name, and the way from XML to a tree.
#[pyclass(module = "neurotree", name = "Registry", subclass)]
pub struct PyRegistry {
    inner: Registry<Ctx>,
    /// Leaves replaced by scripted outcomes, by name or type (`mock`).
    mocks: Vec<(String, String)>,
    /// Substitution rules files' text and name (`substitute`).
    substitutions: Vec<(String, String)>,
}

impl PyRegistry {
    /// The blueprint of `xml` (or the file at `path`), with this registry's mocks and rules.
    pub(crate) fn blueprint(
        &self,
        py: Python<'_>,
        xml: Option<&str>,
        path: Option<&Path>,
    ) -> PyResult<Blueprint<Ctx>> {
        let mut loader = XmlLoader::new(&self.inner);
        for (name, outcomes) in &self.mocks {
            let outcomes = parse_outcomes(outcomes)
                .map_err(|e| PyValueError::new_err(format!("mock {name}: {e}")))?;
            loader = loader.mock(name, outcomes);
        }
        for (text, file) in &self.substitutions {
            let rules = Substitutions::from_json(text, file).map_err(|e| load_error(py, &e))?;
            loader = loader.substitute(rules);
        }
        let loaded = match (xml, path) {
            (Some(text), None) => loader.load_str(text, "<string>"),
            (None, Some(path)) => loader.load_file(path),
            _ => {
                return Err(PyValueError::new_err(
                    "give either the XML text or a path, not both",
                ))
            }
        };
        loaded.map_err(|e| load_error(py, &e))?;
        loader
            .build_main_all_errors()
            .map_err(|errors| load_errors(py, &errors))
    }

    /// The node types, without the mocks and rules of later loads: what scenario files,
    /// which say their own, run on.
    pub(crate) fn node_types_registry(&self) -> &Registry<Ctx> {
        &self.inner
    }

    fn tree(
        slf: &Bound<'_, Self>,
        xml: Option<&str>,
        path: Option<&Path>,
        clock: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyTree> {
        let py = slf.py();
        let clock: Arc<dyn Clock> = match clock {
            Some(c) => clock::shared(c)?,
            None => Arc::new(ManualClock::new()),
        };
        let blueprint = slf.borrow().blueprint(py, xml, path)?;
        let tree = Tree::with_shared_clock(Arc::new(blueprint), clock);
        PyTree::new(py, tree, Some(slf.clone().unbind()))
    }
}

#[pymethods]
impl PyRegistry {
    /// A registry holding every built-in node under its BehaviorTree.CPP name.
    #[new]
    fn new() -> Self {
        PyRegistry {
            inner: Registry::new(),
            mocks: Vec::new(),
            substitutions: Vec::new(),
        }
    }

    /// Registers `func(node, robot) -> bool` as condition `name`.
    fn register_condition(
        &mut self,
        name: &str,
        func: PyObject,
        ports: Vec<PortTuple>,
    ) -> PyResult<()> {
        let (specs, kinds) = ports::read(ports)?;
        leaf::register_condition(&mut self.inner, name, func, specs, kinds)
    }

    /// Registers `func(node, robot) -> Status` as action `name`.
    fn register_action(
        &mut self,
        name: &str,
        func: PyObject,
        ports: Vec<PortTuple>,
    ) -> PyResult<()> {
        let (specs, kinds) = ports::read(ports)?;
        leaf::register_action(&mut self.inner, name, func, specs, kinds)
    }

    /// Registers an `async def (node, robot) -> Status` as action `name`.
    fn register_async_action(
        &mut self,
        name: &str,
        func: PyObject,
        ports: Vec<PortTuple>,
    ) -> PyResult<()> {
        let (specs, kinds) = ports::read(ports)?;
        leaf::register_coroutine(&mut self.inner, name, func, specs, kinds)
    }

    /// Registers `cls` (a `StatefulAction` subclass) as action `name`.
    fn register_stateful_action(
        &mut self,
        name: &str,
        cls: PyObject,
        ports: Vec<PortTuple>,
    ) -> PyResult<()> {
        let (specs, kinds) = ports::read(ports)?;
        leaf::register_stateful(&mut self.inner, name, cls, specs, kinds)
    }

    /// Adds Nav2's node types of `release` (`"jazzy"`, `"kilted"` or `"main"`): its controls
    /// and decorators, which run, and its other types as its model declares them, which
    /// check a file and run once registered (register your Python leaves of those names
    /// first: a registered type stays as it is).
    #[cfg(feature = "nav2")]
    #[pyo3(signature = (release = "main"))]
    fn add_nav2(&mut self, release: &str) -> PyResult<()> {
        let release: neurotree::nav2::Nav2Release = release
            .parse()
            .map_err(|e| PyValueError::new_err(format!("{e}")))?;
        neurotree::nav2::register_release(&mut self.inner, release).map_err(leaf::refused)
    }

    /// Replaces every leaf named (or else of type) `name` in the trees loaded from now on by
    /// one returning `outcomes`, as `neurotree run --mock` reads them (`"SUCCESS"`,
    /// `"RUNNING*3,SUCCESS"`, `"FAILURE; pose=1;2"`).
    fn mock(&mut self, name: &str, outcomes: &str) -> PyResult<()> {
        parse_outcomes(outcomes).map_err(|e| PyValueError::new_err(format!("mock {name}: {e}")))?;
        self.mocks.push((name.to_owned(), outcomes.to_owned()));
        Ok(())
    }

    /// Applies BehaviorTree.CPP's substitution rules (the JSON of `rules`) to the trees loaded
    /// from now on.
    #[pyo3(signature = (rules, file = "<rules>"))]
    fn substitute(&mut self, py: Python<'_>, rules: &str, file: &str) -> PyResult<()> {
        Substitutions::from_json(rules, file).map_err(|e| load_error(py, &e))?;
        self.substitutions.push((rules.to_owned(), file.to_owned()));
        Ok(())
    }

    /// Loads BehaviorTree.CPP XML text and returns its main tree, on `clock` (a new
    /// `ManualClock` if none).
    #[pyo3(signature = (xml, clock = None))]
    fn load_string(
        slf: &Bound<'_, Self>,
        xml: &str,
        clock: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyTree> {
        Self::tree(slf, Some(xml), None, clock)
    }

    /// Loads the BehaviorTree.CPP file at `path` (with its includes) and returns its main tree.
    #[pyo3(signature = (path, clock = None))]
    fn load_file(
        slf: &Bound<'_, Self>,
        path: std::path::PathBuf,
        clock: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyTree> {
        Self::tree(slf, None, Some(&path), clock)
    }

    /// The names of the registered node types, sorted.
    fn node_types(&self) -> Vec<String> {
        self.inner.types().map(|t| t.name.clone()).collect()
    }

    /// The `TreeNodesModel` XML of the registered leaves, for Groot2.
    fn tree_nodes_model(&self) -> String {
        self.inner.tree_nodes_model()
    }
}
