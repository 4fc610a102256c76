//! Watching a tree from Python: status changes and trace lines handed to callables, the
//! last failure, and coverage.
//!
//! A callback runs inside the tick, so it takes the GIL for its call; one that raises ends
//! the tick as a leaf that raises does (`NodeError`, the callback's exception as its cause).

use std::io::{self, Write};
use std::sync::Arc;
use std::time::Duration;

use neurotree::observe::Coverage;
use neurotree::{
    Blueprint, Failure, FailureLink, NodeId, NodeStatus, Observer, Reason, StatusChange,
};
use pyo3::prelude::*;

use crate::errors::raise_in_tree;
use crate::tree::Ctx;

/// Several observers, each told every event in turn.
pub(crate) struct Fanout(pub(crate) Vec<Box<dyn Observer>>);

impl Observer for Fanout {
    fn on_tick_start(&mut self, now: Duration) {
        self.0.iter_mut().for_each(|o| o.on_tick_start(now));
    }
    fn on_status_change(&mut self, change: StatusChange) {
        self.0.iter_mut().for_each(|o| o.on_status_change(change));
    }
    fn on_node_tick(&mut self, node: NodeId) {
        self.0.iter_mut().for_each(|o| o.on_node_tick(node));
    }
    fn on_node_skipped(&mut self, node: NodeId) {
        self.0.iter_mut().for_each(|o| o.on_node_skipped(node));
    }
    fn on_tick_end(&mut self, status: NodeStatus, now: Duration) {
        self.0.iter_mut().for_each(|o| o.on_tick_end(status, now));
    }
    fn on_failure_reason(&mut self, node: NodeId, reason: &Reason) {
        self.0
            .iter_mut()
            .for_each(|o| o.on_failure_reason(node, reason));
    }
    fn on_node_score(&mut self, node: NodeId, score: f64) {
        self.0.iter_mut().for_each(|o| o.on_node_score(node, score));
    }
}

/// `Tree.on_status_change`: `callback(path, previous, status, seconds)`.
pub(crate) struct CallbackObserver {
    pub(crate) callback: PyObject,
    pub(crate) paths: Arc<[String]>,
}

impl Observer for CallbackObserver {
    fn on_status_change(&mut self, change: StatusChange) {
        Python::with_gil(|py| {
            let args = (
                self.paths[change.node.index()].as_str(),
                crate::status::to_py(py, change.from),
                crate::status::to_py(py, change.to),
                change.at.as_secs_f64(),
            );
            if let Err(e) = self.callback.call1(py, args) {
                let summary = format!("a status-change observer raised {e}");
                raise_in_tree(e, summary);
            }
        });
    }
}

/// The writer a `JsonlTrace` writes to: each finished line goes to `callback(line)`.
pub(crate) struct LineWriter {
    callback: PyObject,
    pending: Vec<u8>,
}

impl LineWriter {
    pub(crate) fn new(callback: PyObject) -> Self {
        LineWriter {
            callback,
            pending: Vec::new(),
        }
    }
}

impl Write for LineWriter {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.pending.extend_from_slice(buf);
        while let Some(end) = self.pending.iter().position(|b| *b == b'\n') {
            let line: Vec<u8> = self.pending.drain(..=end).collect();
            let text = String::from_utf8_lossy(&line[..end]).into_owned();
            Python::with_gil(|py| {
                if let Err(e) = self.callback.call1(py, (text,)) {
                    let summary = format!("a trace observer raised {e}");
                    raise_in_tree(e, summary);
                }
            });
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// `Tree.last_failure()`: the chain from the root to the node whose failure decided it.
#[pyclass(module = "neurotree", name = "Failure", frozen)]
pub struct PyFailure {
    /// The path of the node where the chain ends.
    #[pyo3(get)]
    path: String,
    /// The deepest reason given on the chain, or `None`.
    #[pyo3(get)]
    reason: Option<String>,
    /// That reason's code (0 without one).
    #[pyo3(get)]
    code: u32,
    /// `(path, reason)` for each node from the root down.
    #[pyo3(get)]
    chain: Vec<(String, Option<String>)>,
    /// `(path, reason)` for every node that failed in the tick and is part of why: the
    /// chain's, and those below each child a Fallback tried.
    #[pyo3(get)]
    nodes: Vec<(String, Option<String>)>,
    text: String,
}

/// A link as Python sees it: `(path, reason)`.
fn entry(l: &FailureLink) -> (String, Option<String>) {
    (
        l.path.clone(),
        l.reason.as_ref().map(|r| r.message().into_owned()),
    )
}

impl From<Failure> for PyFailure {
    fn from(f: Failure) -> Self {
        let reason = f.reason();
        PyFailure {
            path: f.leaf().path.clone(),
            reason: reason.map(|r| r.message().into_owned()),
            code: reason.map_or(0, Reason::code),
            chain: f.links.iter().map(entry).collect(),
            nodes: f.all_links().into_iter().map(entry).collect(),
            text: f.to_string(),
        }
    }
}

#[pymethods]
impl PyFailure {
    fn __str__(&self) -> String {
        self.text.clone()
    }

    fn __repr__(&self) -> String {
        format!("<neurotree.Failure at {}>", self.path)
    }
}

/// `Tree.start_coverage()`: which outcomes each node has had since.
#[pyclass(module = "neurotree", name = "Coverage", frozen)]
pub struct PyCoverage {
    pub(crate) coverage: Coverage,
    pub(crate) blueprint: Arc<Blueprint<Ctx>>,
}

#[pymethods]
impl PyCoverage {
    /// The share of the possible outcomes seen, in percent.
    #[getter]
    fn percent(&self) -> f64 {
        self.coverage.report(&self.blueprint).percent()
    }

    /// The paths of the nodes never reached.
    fn never_reached(&self) -> Vec<String> {
        let report = self.coverage.report(&self.blueprint);
        report.never_reached().map(|n| n.path.clone()).collect()
    }

    /// The report `neurotree test --coverage` prints.
    fn report(&self) -> String {
        self.coverage.report(&self.blueprint).to_string()
    }
}
