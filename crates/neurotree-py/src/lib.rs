//! NeuroTree from Python: the `neurotree._native` extension module, which the `neurotree`
//! package (`python/neurotree`) wraps.
//!
//! Python leaves run inside the Rust engine's ticks: `leaf` adapts Python callables,
//! classes and coroutines to the engine's leaf traits; `node` is what a leaf sees; `tree`
//! ticks with the GIL released; `value` converts blackboard values; `errors` turns load and
//! tick errors into Python exceptions. The package's guide is `docs/guide/python.md`.

mod builder;
mod campaign;
mod clock;
mod errors;
mod leaf;
mod node;
mod observe;
mod ports;
mod registry;
mod scenario;
mod status;
mod tree;
mod value;

use pyo3::prelude::*;
use pyo3::types::PyType;

/// Hands the module the package's `Status` enum and exception classes, which it returns
/// and raises.
#[pyfunction]
fn _bind(
    py: Python<'_>,
    status: &Bound<'_, PyAny>,
    load_error: &Bound<'_, PyType>,
    node_error: &Bound<'_, PyType>,
) -> PyResult<()> {
    status::bind(py, status)?;
    errors::bind(py, load_error, node_error);
    Ok(())
}

/// Hands the module the package's `TreeBusy` class, which it raises when a tree is used
/// while it is ticked.
#[pyfunction]
fn _bind_busy(py: Python<'_>, tree_busy: &Bound<'_, PyType>) {
    errors::bind_busy(py, tree_busy);
}

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(_bind, m)?)?;
    m.add_function(wrap_pyfunction!(_bind_busy, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::_run_scenarios, m)?)?;
    m.add_function(wrap_pyfunction!(campaign::_merge_campaign_results, m)?)?;
    m.add_class::<campaign::PyCampaign>()?;
    m.add_class::<registry::PyRegistry>()?;
    m.add_class::<builder::PyBuilder>()?;
    m.add_class::<tree::PyTree>()?;
    m.add_class::<tree::PyBlackboard>()?;
    m.add_class::<node::Node>()?;
    m.add_class::<clock::PyManualClock>()?;
    m.add_class::<clock::PySystemClock>()?;
    m.add_class::<observe::PyFailure>()?;
    m.add_class::<observe::PyCoverage>()?;
    Ok(())
}
