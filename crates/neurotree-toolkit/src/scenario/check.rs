//! A scenario's expectations, checked after each tick of its run.

use std::sync::{Arc, Mutex};

use neurotree_core::{NodeId, NodeStatus, Observer, ScopeId, StatusChange, Tree};
use serde_json::{json, Value};

use super::{Expect, FailureExpect, Scenario};
use crate::observe::Coverage;
use crate::render::LastTickStatuses;

/// Checks the expectations as the run goes.
pub(super) struct Checker {
    /// Expectations by tick (`None`: the end), with whether each was checked.
    due: Vec<(Option<u32>, bool)>,
    statuses: LastTickStatuses,
    halts: Halts,
    coverage: Option<Coverage>,
    problems: Vec<String>,
    /// The problems of the end expectations, as of the latest tick.
    at_end: Vec<String>,
    /// The last tick and the root's status then.
    last: Option<(u32, String)>,
    /// The expectations of the scenario.
    expects: Vec<Expect>,
    /// Outcomes covered and possible as of the latest tick, if the scenario asks for a
    /// coverage (`Some((0, 0))` until the first tick).
    covered: Option<(usize, usize)>,
}

impl Checker {
    pub(super) fn new(s: &Scenario) -> Self {
        let expects = s.expect.clone();
        Self {
            due: expects.iter().map(|e| (e.tick, false)).collect(),
            statuses: LastTickStatuses::new(),
            halts: Halts::default(),
            coverage: None,
            problems: Vec::new(),
            at_end: Vec::new(),
            last: None,
            expects,
            // The observer is made once the tree is known (`attach`).
            covered: s.coverage.map(|_| (0, 0)),
        }
    }

    /// The observers to watch `tree`, loaded with `registry`, with.
    pub(super) fn attach<C: 'static>(
        &mut self,
        tree: &Tree<C>,
        registry: &crate::Registry<C>,
    ) -> Vec<Box<dyn Observer>> {
        let mut attached: Vec<Box<dyn Observer>> = vec![
            Box::new(self.statuses.clone()),
            Box::new(self.halts.clone()),
        ];
        if self.covered.is_some() {
            let coverage = Coverage::with_registry(tree.blueprint(), registry);
            attached.push(Box::new(coverage.clone()));
            self.coverage = Some(coverage);
        }
        attached
    }

    /// Checks what is due after tick `tick`, which left the root `status` (or failed with
    /// `error`).
    pub(super) fn after_tick<C>(
        &mut self,
        tick: u32,
        status: &str,
        error: Option<&str>,
        tree: &Tree<C>,
    ) {
        if let Some(error) = error {
            self.problems
                .push(format!("tick {tick}: the tick failed: {error}"));
        }
        for i in 0..self.expects.len() {
            match self.due[i] {
                (Some(at), false) if at <= tick => {
                    let found = self.check(&self.expects[i], tick, status, tree);
                    self.problems.extend(found);
                    self.due[i].1 = true;
                }
                _ => {}
            }
        }
        // The end expectations hold or not as of the latest tick.
        let mut at_end = Vec::new();
        for i in 0..self.expects.len() {
            if self.due[i].0.is_none() {
                at_end.extend(self.check(&self.expects[i], tick, status, tree));
            }
        }
        self.at_end = at_end;
        if let Some(coverage) = &self.coverage {
            let report = coverage.report(tree.blueprint());
            self.covered = Some((report.covered_outcomes(), report.possible_outcomes()));
        }
        self.last = Some((tick, status.to_string()));
        self.halts
            .0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
    }

    /// The problems once the run is over.
    pub(super) fn finish(mut self, s: &Scenario) -> Vec<String> {
        let (last_tick, last_status) = self.last.clone().unwrap_or((0, "IDLE".into()));
        for (tick, checked) in &self.due {
            if let (Some(tick), false) = (tick, checked) {
                self.problems.push(format!(
                    "tick {tick}: not reached; the run ended after tick {last_tick} with \
                     {last_status}"
                ));
            }
        }
        self.problems.append(&mut self.at_end);
        if let (Some(least), Some((covered, possible))) = (s.coverage, self.covered) {
            let share = if possible == 0 {
                1.0
            } else {
                covered as f64 / possible as f64
            };
            if share < least {
                self.problems.push(format!(
                    "coverage {covered}/{possible} ({:.0}%) is below the {:.0}% asked for",
                    share * 100.0,
                    least * 100.0
                ));
            }
        }
        self.problems
    }

    /// The problems of `e` after tick `tick`.
    fn check<C>(&self, e: &Expect, tick: u32, status: &str, tree: &Tree<C>) -> Vec<String> {
        let at = match e.tick {
            Some(_) => format!("tick {tick}"),
            None => format!("end (tick {tick})"),
        };
        let mut problems = Vec::new();
        if let Some(root) = &e.root
            && !root.eq_ignore_ascii_case(status)
        {
            problems.push(format!("{at}: root is {status}, expected {root}"));
        }
        let paths = tree.blueprint().paths();
        for (key, expected) in &e.nodes {
            let ids = nodes_for(tree, &paths, key);
            if ids.is_empty() {
                problems.push(format!("{at}: no node has the path, name or type `{key}`"));
                continue;
            }
            let seen: Vec<&str> = ids
                .iter()
                .map(|&id| self.statuses.status(id).as_str())
                .collect();
            if !seen.iter().any(|s| s.eq_ignore_ascii_case(expected)) {
                problems.push(format!(
                    "{at}: node `{key}` is {}, expected {expected}",
                    seen.join("/")
                ));
            }
        }
        for (key, expected) in &e.blackboard {
            problems.extend(blackboard_problem(tree, key, expected, &at));
        }
        let halted = self
            .halts
            .0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone();
        for key in &e.halted {
            let ids = nodes_for(tree, &paths, key);
            if !ids.iter().any(|id| halted.contains(id)) {
                problems.push(format!("{at}: `{key}` was not halted"));
            }
        }
        if let Some(f) = &e.failure {
            problems.extend(failure_problems(tree, f, &at, status));
        }
        problems
    }
}

/// The problem of the root entry `key` not holding `expected`, if it does not.
fn blackboard_problem<C>(
    tree: &Tree<C>,
    key: &str,
    expected: &toml::Value,
    at: &str,
) -> Option<String> {
    let expected = match value_json(expected) {
        Ok(v) => v,
        Err(err) => return Some(format!("{at}: blackboard `{key}`: {err}")),
    };
    let actual = crate::blackboard_json::entry_json(tree.blackboard(), ScopeId::ROOT, key);
    if same_value(&actual, &expected) {
        return None;
    }
    let actual = if actual.is_null() {
        "not set".to_string()
    } else {
        actual.to_string()
    };
    Some(format!(
        "{at}: blackboard `{key}` is {actual}, expected {expected}"
    ))
}

/// The JSON a blackboard entry of a TOML value prints as.
fn value_json(value: &toml::Value) -> Result<Value, String> {
    match value {
        toml::Value::String(s) => Ok(json!(s)),
        toml::Value::Integer(i) => Ok(json!(i)),
        toml::Value::Float(f) => Ok(json!(f)),
        toml::Value::Boolean(b) => Ok(json!(b)),
        other => Err(format!(
            "a {} is no blackboard value; use a string, number or boolean",
            other.type_str()
        )),
    }
}

/// The nodes `key` names: by path, else name, else type.
fn nodes_for<C>(tree: &Tree<C>, paths: &[String], key: &str) -> Vec<NodeId> {
    let bp = tree.blueprint();
    let ids: Vec<NodeId> = bp.ids().collect();
    let by_path: Vec<NodeId> = ids
        .iter()
        .copied()
        .filter(|id| paths[id.index()] == key)
        .collect();
    if !by_path.is_empty() {
        return by_path;
    }
    let by_name: Vec<NodeId> = ids
        .iter()
        .copied()
        .filter(|&id| bp.name(id) == key)
        .collect();
    if !by_name.is_empty() {
        return by_name;
    }
    ids.into_iter()
        .filter(|&id| bp.type_id(id) == key)
        .collect()
}

/// Two JSON values equal as the blackboard means them: numbers by value.
fn same_value(a: &Value, b: &Value) -> bool {
    match (a.as_f64(), b.as_f64()) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// The problems of a failure expectation.
fn failure_problems<C>(tree: &Tree<C>, f: &FailureExpect, at: &str, status: &str) -> Vec<String> {
    let Some(failure) = tree.last_failure() else {
        return vec![format!(
            "{at}: expected the root to fail, but it is {status}"
        )];
    };
    let mut problems = Vec::new();
    let chain: Vec<(&str, Option<String>)> = failure
        .all_links()
        .into_iter()
        .flat_map(|link| {
            std::iter::once((link.path.as_str(), link.reason.as_ref())).chain(
                link.tried
                    .iter()
                    .map(|t| (t.path.as_str(), t.reason.as_ref())),
            )
        })
        .map(|(path, reason)| (path, reason.map(|r| r.message().into_owned())))
        .collect();
    let names = |node: &str, path: &str| path == node || path.ends_with(&format!("/{node}"));
    if let Some(node) = &f.node
        && !chain.iter().any(|(path, _)| names(node, path))
    {
        let paths: Vec<&str> = failure.links.iter().map(|l| l.path.as_str()).collect();
        problems.push(format!(
            "{at}: `{node}` is not in the failure chain ({})",
            paths.join(" <- ")
        ));
    }
    if let Some(reason) = &f.reason {
        let given: Vec<&str> = chain.iter().filter_map(|(_, r)| r.as_deref()).collect();
        if !given.iter().any(|r| r.contains(reason.as_str())) {
            problems.push(format!(
                "{at}: no failure reason contains `{reason}` (reasons: {})",
                if given.is_empty() {
                    "none".to_string()
                } else {
                    given.join("; ")
                }
            ));
        }
    }
    problems
}

/// The nodes halted since the last tick's check.
#[derive(Clone, Default)]
struct Halts(Arc<Mutex<Vec<NodeId>>>);

impl Observer for Halts {
    fn on_status_change(&mut self, c: StatusChange) {
        if c.from == NodeStatus::Running && c.to == NodeStatus::Idle {
            self.0
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(c.node);
        }
    }
}
