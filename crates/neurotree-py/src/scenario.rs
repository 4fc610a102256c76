//! `neurotree.run_scenarios`: scenario files (the TOML that `neurotree test` reads) run on
//! a registry's node types, Python leaves included; the result classes are the package's
//! (`neurotree/scenarios.py`).

use std::path::PathBuf;

use neurotree::scenario::ScenarioBench;
use neurotree::Registry;
use pyo3::prelude::*;

use crate::errors::forget_raised;
use crate::node::Node;
use crate::registry::PyRegistry;
use crate::tree::Ctx;

/// One scenario's result as the package reads it: name, file, seconds, problems, and the
/// report `neurotree test` prints for it.
type Row = (String, String, f64, Vec<String>, String);

/// Runs the scenario files at `paths` on the node types of `registry` (the built-ins when
/// `None`), each tree ticked with `robot`; one row per file, in order. The GIL is released
/// while the trees tick, as for `Tree.tick_once`.
#[pyfunction]
#[pyo3(signature = (paths, registry = None, robot = None))]
pub(crate) fn _run_scenarios(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    registry: Option<PyRef<'_, PyRegistry>>,
    robot: Option<PyObject>,
) -> PyResult<Vec<Row>> {
    let built_ins;
    let types = match &registry {
        Some(registry) => registry.node_types_registry(),
        None => {
            built_ins = Registry::<Ctx>::new();
            &built_ins
        }
    };
    let node = Py::new(py, Node::detached())?;
    let robot = robot.unwrap_or_else(|| py.None());
    let rows = py.allow_threads(|| {
        let mut bench = ScenarioBench::with_registry(types, |blueprint| {
            Python::with_gil(|py| Ctx {
                robot: robot.clone_ref(py),
                node: node.clone_ref(py),
                paths: blueprint.paths().into(),
            })
        });
        paths
            .iter()
            .map(|file| {
                let result = bench.run_file(file);
                // A leaf's exception is in the scenario's problems; no tick is left to
                // raise it.
                forget_raised();
                (
                    result.name.clone(),
                    result.file.display().to_string(),
                    result.seconds,
                    result.problems.clone(),
                    result.to_string(),
                )
            })
            .collect()
    });
    Ok(rows)
}
