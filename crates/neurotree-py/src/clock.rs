//! `neurotree.ManualClock` and `neurotree.SystemClock`: the time trees read.

use std::sync::Arc;
use std::time::Duration;

use neurotree::{Clock, ManualClock, SystemClock};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// A clock that moves only when told: runs are deterministic and as fast as the ticks.
#[pyclass(module = "neurotree", name = "ManualClock", frozen)]
pub struct PyManualClock(ManualClock);

fn duration(seconds: f64) -> PyResult<Duration> {
    Duration::try_from_secs_f64(seconds)
        .map_err(|_| PyValueError::new_err(format!("{seconds} is no number of seconds")))
}

#[pymethods]
impl PyManualClock {
    /// A clock at 0 s.
    #[new]
    fn new() -> Self {
        PyManualClock(ManualClock::new())
    }

    /// Moves the clock `seconds` forward.
    fn advance(&self, seconds: f64) -> PyResult<()> {
        self.0.advance(duration(seconds)?);
        Ok(())
    }

    /// Sets the clock to `seconds`.
    fn set(&self, seconds: f64) -> PyResult<()> {
        self.0.set(duration(seconds)?);
        Ok(())
    }

    /// The clock's time, in seconds.
    #[getter]
    fn now(&self) -> f64 {
        self.0.now().as_secs_f64()
    }
}

/// Wall time since the clock was made.
#[pyclass(module = "neurotree", name = "SystemClock", frozen)]
pub struct PySystemClock(Arc<SystemClock>);

#[pymethods]
impl PySystemClock {
    /// A clock at 0 s now.
    #[new]
    fn new() -> Self {
        PySystemClock(Arc::new(SystemClock::new()))
    }

    /// Seconds since the clock was made.
    #[getter]
    fn now(&self) -> f64 {
        self.0.now().as_secs_f64()
    }
}

/// The clock `clock` (a `ManualClock` or a `SystemClock`), shared with the tree.
pub(crate) fn shared(clock: &Bound<'_, PyAny>) -> PyResult<Arc<dyn Clock>> {
    if let Ok(manual) = clock.downcast::<PyManualClock>() {
        return Ok(Arc::new(manual.get().0.clone()));
    }
    if let Ok(system) = clock.downcast::<PySystemClock>() {
        return Ok(system.get().0.clone());
    }
    Err(PyTypeError::new_err(format!(
        "clock= takes a neurotree.ManualClock or a neurotree.SystemClock, not {}",
        clock.get_type().name()?
    )))
}
