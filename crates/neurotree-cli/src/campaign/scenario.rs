//! A variant written as a scenario file (`campaign replay --scenario`): the tree, each of
//! its leaves replaced by a mock that plays what the leaf returned in the variant's run,
//! tick for tick, and the variant's node faults; the expectation is the variant's outcome
//! at its last tick. `neurotree test` then runs the variant without the simulator.
//!
//! A mock is found by a leaf's name (else its type): leaves that share a name and played
//! differently (Nav2's navigator has two `WouldAControllerRecoveryHelp`) are said by their
//! paths instead, as faults on each of their calls (`PATH=FAILURE@2`), which a scenario's
//! `faults` reads as a campaign's do. That is possible for leaves that answer at once
//! (conditions); one that ran over several ticks is refused with why.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree::fault::{self, status_name, NodeFault};
use neurotree::{Blueprint, NodeId, NodeStatus, Observer, Status, StatusChange};
use serde_json::Value;

use super::{describe, Campaign};
use crate::demo::DemoRun;

/// A variant as a scenario: the TOML, and what its run gave.
#[derive(Clone, Debug, PartialEq)]
pub struct VariantScenario {
    /// The scenario file's text.
    pub toml: String,
    /// The root's status at the end of the run: what the scenario expects.
    pub outcome: String,
    /// The ticks the run took: the tick the expectation is checked after.
    pub ticks: u32,
}

/// Variant `n` of `campaign` as a scenario whose `tree` is `tree_file` (as the scenario
/// file names it: relative to its folder); an error says why it cannot be written.
pub fn variant_scenario(
    campaign: &Campaign,
    n: u64,
    tree_file: &str,
) -> Result<VariantScenario, String> {
    let config = campaign.config_of(n)?;
    let mut demo = DemoRun::new(&config).map_err(|e| e.to_string())?;
    let blueprint = Arc::clone(demo.blueprint());
    let plays = Plays::new(&blueprint);
    demo.add_observer(Box::new(plays.clone()));
    super::quietly(|| {
        while !demo.is_over() {
            demo.tick();
        }
    });
    let summary = demo.summary();
    if let Some(error) = &summary.error {
        return Err(format!(
            "variant {n} ended in an error ({error}): a scenario expects the root's status"
        ));
    }
    if config.duration.is_some() {
        return Err(format!(
            "variant {n} runs for a duration and is judged by where the robot is: a scenario \
             expects the root's status"
        ));
    }
    let recorded = plays.take()?;
    let paths = blueprint.paths();
    let unique = |path: &str| paths.iter().filter(|p| *p == path).count() == 1;
    // The variant's own faults, each on the nodes it landed on, by path.
    let mut faults: Vec<NodeFault> = Vec::new();
    for (_, path, f) in fault::resolve(&blueprint, &config.faults)? {
        if !unique(&path) {
            return Err(format!(
                "the fault `{f}` lands on `{path}`, a path two nodes share: a scenario \
                 could not tell them apart"
            ));
        }
        faults.push(NodeFault { node: path, ..f });
    }
    let hits = demo.fault_hits();
    // Leaves by the key a mock finds them by: their name.
    let mut by_name: BTreeMap<&str, Vec<NodeId>> = BTreeMap::new();
    for id in blueprint.ids() {
        if !recorded[id.index()].is_empty() {
            by_name.entry(blueprint.name(id)).or_default().push(id);
        }
    }
    let mut mocks = BTreeMap::new();
    for (name, ids) in by_name {
        // One mock plays for them all when each played the longest's first ticks (a mock
        // repeats its last outcome after its list).
        let longest = ids
            .iter()
            .map(|id| &recorded[id.index()])
            .max_by_key(|p| p.len())
            .expect("a group has a leaf");
        let fits = |played: &Vec<Status>| {
            played
                .iter()
                .enumerate()
                .all(|(i, s)| longest.get(i).or(longest.last()) == Some(s))
        };
        if ids.iter().all(|id| fits(&recorded[id.index()])) {
            mocks.insert(name.to_string(), outcomes(longest));
            continue;
        }
        // Told apart by path: every call of each a fault.
        for id in ids {
            let path = &paths[id.index()];
            let played = &recorded[id.index()];
            if !unique(path) || played.contains(&Status::Running) {
                return Err(format!(
                    "the leaves named `{name}` played differently, and `{path}` {}: a \
                     scenario's mocks find leaves by name, and its faults cannot say that",
                    if unique(path) {
                        "ran over several ticks"
                    } else {
                        "shares its path with another"
                    }
                ));
            }
            let faulted: Vec<u32> = hits
                .iter()
                .filter(|h| h.path == *path)
                .map(|h| h.call)
                .collect();
            let calls = (1u32..).filter(|c| !faulted.contains(c));
            for (status, call) in played.iter().zip(calls) {
                faults.push(NodeFault::new(path.clone(), call, *status));
            }
        }
    }
    let outcome = status_name(summary.outcome).to_string();
    let step_ms = config.params.period.as_millis();
    let mut toml = String::new();
    toml.push_str(&format!(
        "# Variant {n} of campaign `{}`, replayed by its leaves: each leaf is a mock that\n\
         # plays what it returned in the variant's run, tick for tick.\n",
        campaign.name
    ));
    toml.push_str(&format!(
        "name = {}\n",
        quoted(&format!("{} variant {n}", campaign.name))
    ));
    toml.push_str(&format!(
        "description = {}\n",
        quoted(&describe(&Value::Object(campaign.factors_of(n))))
    ));
    toml.push_str(&format!("tree = {}\n", quoted(tree_file)));
    toml.push_str("mock_unknown = true\n");
    toml.push_str(&format!("ticks = {}\n", summary.ticks));
    toml.push_str(&format!("step_ms = {step_ms}\n"));
    if !faults.is_empty() {
        toml.push_str("faults = [\n");
        for f in &faults {
            toml.push_str(&format!("  {},\n", quoted(&f.to_string())));
        }
        toml.push_str("]\n");
    }
    toml.push_str("\n[mocks]\n");
    for (name, outcomes) in &mocks {
        toml.push_str(&format!("{} = {}\n", quoted(name), quoted(outcomes)));
    }
    toml.push_str(&format!(
        "\n[[expect]]\ntick = {}\nroot = {}\n",
        summary.ticks,
        quoted(&outcome)
    ));
    Ok(VariantScenario {
        toml,
        outcome,
        ticks: summary.ticks,
    })
}

/// `text` as a TOML basic string.
fn quoted(text: &str) -> String {
    // JSON's escapes are TOML's for every character a name or path holds.
    Value::String(text.to_string()).to_string()
}

/// A mock's outcomes: `RUNNING*3,SUCCESS`.
fn outcomes(played: &[Status]) -> String {
    let mut runs: Vec<(Status, u32)> = Vec::new();
    for s in played {
        match runs.last_mut() {
            Some((last, count)) if last == s => *count += 1,
            _ => runs.push((*s, 1)),
        }
    }
    runs.iter()
        .map(|(s, count)| match count {
            1 => status_name(*s).to_string(),
            _ => format!("{}*{count}", status_name(*s)),
        })
        .collect::<Vec<_>>()
        .join(",")
}

/// What each leaf returned at each of its own ticks (not those a fault answered for it).
#[derive(Clone)]
struct Plays(Arc<Mutex<Record>>);

struct Record {
    leaf: Vec<bool>,
    status: Vec<NodeStatus>,
    /// The leaf whose tick is under way.
    open: Option<NodeId>,
    played: Vec<Vec<Status>>,
    refused: Option<String>,
    paths: Vec<String>,
}

impl Plays {
    fn new<C>(blueprint: &Blueprint<C>) -> Self {
        let n = blueprint.len();
        Plays(Arc::new(Mutex::new(Record {
            leaf: blueprint
                .ids()
                .map(|id| blueprint.children(id).is_empty())
                .collect(),
            status: vec![NodeStatus::Idle; n],
            open: None,
            played: vec![Vec::new(); n],
            refused: None,
            paths: blueprint.paths(),
        })))
    }

    fn with(&self, f: impl FnOnce(&mut Record)) {
        f(&mut self.0.lock().unwrap_or_else(|e| e.into_inner()));
    }

    /// What each leaf played, by node id.
    fn take(&self) -> Result<Vec<Vec<Status>>, String> {
        let mut r = self.0.lock().unwrap_or_else(|e| e.into_inner());
        r.close();
        match r.refused.take() {
            Some(why) => Err(why),
            None => Ok(std::mem::take(&mut r.played)),
        }
    }
}

impl Record {
    /// The open leaf's tick ended with no change of status: it returned what it held.
    fn close(&mut self) {
        if let Some(id) = self.open.take() {
            let held = self.status[id.index()];
            self.push(id, held);
        }
    }

    fn push(&mut self, id: NodeId, status: NodeStatus) {
        let played = match status {
            NodeStatus::Success => Status::Success,
            NodeStatus::Failure => Status::Failure,
            NodeStatus::Running => Status::Running,
            other => {
                self.refused.get_or_insert_with(|| {
                    format!(
                        "`{}` returned {}, which a mock does not play",
                        self.paths[id.index()],
                        other.as_str()
                    )
                });
                return;
            }
        };
        self.played[id.index()].push(played);
    }
}

impl Observer for Plays {
    fn on_node_tick(&mut self, node: NodeId) {
        self.with(|r| {
            r.close();
            if r.leaf[node.index()] {
                r.open = Some(node);
            }
        });
    }

    fn on_status_change(&mut self, change: StatusChange) {
        self.with(|r| {
            if r.open == Some(change.node) && change.to != NodeStatus::Idle {
                r.open = None;
                r.push(change.node, change.to);
            } else {
                r.close();
            }
            r.status[change.node.index()] = change.to;
        });
    }

    fn on_node_skipped(&mut self, node: NodeId) {
        self.with(|r| {
            if r.open == Some(node) {
                r.open = None;
                r.push(node, NodeStatus::Skipped);
            }
        });
    }

    fn on_tick_end(&mut self, _status: NodeStatus, _now: Duration) {
        self.with(Record::close);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outcomes_are_written_as_runs() {
        use Status::*;
        assert_eq!(
            outcomes(&[Running, Running, Success, Failure, Failure]),
            "RUNNING*2,SUCCESS,FAILURE*2"
        );
        assert_eq!(outcomes(&[Success]), "SUCCESS");
    }
}
