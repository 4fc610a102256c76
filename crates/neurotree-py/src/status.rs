//! `neurotree.Status` (a Python `IntEnum`, defined in `neurotree/__init__.py`) and the
//! engine's statuses.
//!
//! The members are looked up once, when the package binds them, so that a leaf's return
//! value is recognised by identity, without a call into Python.

use neurotree::{NodeStatus, Status};
use pyo3::prelude::*;
use pyo3::sync::GILOnceCell;

/// The members of `neurotree.Status`, by the engine's status code (Idle = 0 … Skipped = 4).
static MEMBERS: GILOnceCell<[PyObject; 5]> = GILOnceCell::new();

/// Keeps the members of `status` (the `Status` enum class).
pub(crate) fn bind(py: Python<'_>, status: &Bound<'_, PyAny>) -> PyResult<()> {
    let member = |name: &str| status.getattr(name).map(Bound::unbind);
    let members = [
        member("IDLE")?,
        member("RUNNING")?,
        member("SUCCESS")?,
        member("FAILURE")?,
        member("SKIPPED")?,
    ];
    // A second bind (a reloaded package) keeps the first members, which leaves compare to.
    let _ = MEMBERS.set(py, members);
    Ok(())
}

fn members(py: Python<'_>) -> &[PyObject; 5] {
    MEMBERS
        .get(py)
        .expect("neurotree/__init__.py binds Status before anything ticks")
}

/// The Python member for `status`.
pub(crate) fn to_py(py: Python<'_>, status: NodeStatus) -> PyObject {
    members(py)[status as usize].clone_ref(py)
}

/// The status `value` is, if it is `Status.SUCCESS`, `FAILURE` or `RUNNING`.
#[inline]
pub(crate) fn from_py(value: &Bound<'_, PyAny>) -> Option<Status> {
    let m = members(value.py());
    let p = value.as_ptr();
    if p == m[2].as_ptr() {
        Some(Status::Success)
    } else if p == m[3].as_ptr() {
        Some(Status::Failure)
    } else if p == m[1].as_ptr() {
        Some(Status::Running)
    } else {
        None
    }
}
