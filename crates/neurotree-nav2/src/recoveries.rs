//! Counting what a Nav2 navigator did to recover: an observer over the tree's recovery
//! branches.

use std::sync::{Arc, Mutex, MutexGuard};

use neurotree_core::{Blueprint, NodeId, NodeStatus, Observer, StatusChange};

use crate::EventLog;

/// An [`Observer`] that counts the runs of a Nav2 tree's recovery branches.
///
/// The branches are found in the blueprint: the second child of every `RecoveryNode` (the
/// controller's and the planner's recovery sequences, in Nav2's navigators), except that a
/// branch holding a `RoundRobin` (the navigator's own recovery list) is counted by the
/// RoundRobin's children instead: each clearing, spin, wait or back-up is one recovery. A
/// run is a branch leaving Idle, which it does once each time it is started, however many
/// ticks it then takes.
///
/// Clones share their counts: keep one to read while the tree owns the other.
#[derive(Clone, Debug, Default)]
pub struct RecoveryCounter {
    counts: Arc<Mutex<Counts>>,
    log: Option<EventLog>,
}

#[derive(Debug, Default)]
struct Counts {
    /// For each node id, the branch it starts, if any.
    branch_of: Vec<Option<usize>>,
    /// Each branch's label and runs, in tree order.
    branches: Vec<(String, u32)>,
}

impl RecoveryCounter {
    /// A counter for trees of `bp`.
    pub fn new<C>(bp: &Blueprint<C>) -> Self {
        let mut watched: Vec<(NodeId, String)> = Vec::new();
        for node in bp.ids().filter(|id| bp.type_id(*id) == "RecoveryNode") {
            let Some(&branch) = bp.children(node).get(1) else {
                continue;
            };
            let round_robins: Vec<NodeId> = bp
                .ids()
                .filter(|id| bp.type_id(*id) == "RoundRobin" && is_within(bp, *id, branch))
                .collect();
            if round_robins.is_empty() {
                watched.push((branch, format!("{} recovery", bp.name(node))));
            }
            for round_robin in round_robins {
                for &child in bp.children(round_robin) {
                    watched.push((child, bp.name(child).to_string()));
                }
            }
        }
        // Pre-order ids: sorting puts the branches in the order the tree reads.
        watched.sort_by_key(|(id, _)| *id);
        watched.dedup_by_key(|(id, _)| *id);
        let mut counts = Counts {
            branch_of: vec![None; bp.len()],
            branches: Vec::with_capacity(watched.len()),
        };
        for (id, label) in watched {
            counts.branch_of[id.index()] = Some(counts.branches.len());
            counts.branches.push((label, 0));
        }
        Self {
            counts: Arc::new(Mutex::new(counts)),
            log: None,
        }
    }

    /// Also writing `recovery: LABEL` to `log` each time a branch starts.
    pub fn with_log(mut self, log: EventLog) -> Self {
        self.log = Some(log);
        self
    }

    /// Recovery runs so far, all branches together.
    pub fn total(&self) -> u32 {
        self.lock().branches.iter().map(|(_, n)| n).sum()
    }

    /// Each branch's label and runs so far, in tree order: `FollowPath recovery` for the
    /// recovery child of the RecoveryNode named `FollowPath`, a RoundRobin child's own
    /// name.
    pub fn branches(&self) -> Vec<(String, u32)> {
        self.lock().branches.clone()
    }

    /// Sets each branch's runs back to `branches` (what [`branches`](Self::branches) said
    /// earlier): the run went back to then.
    pub fn set_branches(&self, branches: &[(String, u32)]) {
        let mut counts = self.lock();
        for ((label, runs), (was_label, was)) in counts.branches.iter_mut().zip(branches) {
            if label == was_label {
                *runs = *was;
            }
        }
    }

    fn lock(&self) -> MutexGuard<'_, Counts> {
        // Plain counters: still whole if a holder panicked.
        self.counts.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// `true` if `id` is `ancestor` or lies below it.
fn is_within<C>(bp: &Blueprint<C>, id: NodeId, ancestor: NodeId) -> bool {
    let mut at = Some(id);
    while let Some(node) = at {
        if node == ancestor {
            return true;
        }
        at = bp.parent(node);
    }
    false
}

impl Observer for RecoveryCounter {
    fn on_status_change(&mut self, change: StatusChange) {
        if change.from != NodeStatus::Idle
            || matches!(change.to, NodeStatus::Idle | NodeStatus::Skipped)
        {
            return;
        }
        let mut counts = self.lock();
        if let Some(Some(branch)) = counts.branch_of.get(change.node.index()).copied() {
            let (label, runs) = &mut counts.branches[branch];
            *runs += 1;
            if let Some(log) = &self.log {
                log.push(format!("recovery: {label}"));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate as nav2;
    use neurotree_toolkit::{ManualClock, Registry, Status, Tree, XmlLoader};

    /// A navigator shaped like Nav2's: leaves scripted by the context.
    #[derive(Default)]
    struct Script {
        /// Outcomes of `Act`, one per call (then Success).
        act: Vec<bool>,
    }

    fn tree() -> Tree<Script> {
        let mut r = Registry::<Script>::new();
        nav2::register_controls(&mut r).unwrap();
        r.register_action("Act", vec![], |h| {
            let ctx = h.ctx_mut();
            let succeeds = ctx.act.is_empty() || ctx.act.remove(0);
            succeeds.into()
        })
        .unwrap();
        let mut loader = XmlLoader::new(&r);
        loader
            .load_str(
                r#"<root BTCPP_format="4"><BehaviorTree ID="T">
                     <RecoveryNode number_of_retries="4" name="Navigate">
                       <RecoveryNode name="Follow">
                         <Act/>
                         <AlwaysSuccess/>
                       </RecoveryNode>
                       <RoundRobin name="Recoveries" wrap_around="true">
                         <AlwaysSuccess name="Clear"/>
                         <AlwaysSuccess name="Spin"/>
                       </RoundRobin>
                     </RecoveryNode>
                   </BehaviorTree></root>"#,
                "t.xml",
            )
            .unwrap();
        Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new())
    }

    #[test]
    fn each_start_of_a_branch_counts_once() {
        let mut t = tree();
        let log = EventLog::new();
        let counter = RecoveryCounter::new(t.blueprint()).with_log(log.clone());
        t.set_observer(counter.clone());
        let labels: Vec<String> = counter.branches().into_iter().map(|(l, _)| l).collect();
        assert_eq!(labels, ["Follow recovery", "Clear", "Spin"]);
        // Act fails, the follow recovery runs, Act fails again: Follow fails; the
        // navigator's recovery clears; Follow runs again: fail, recover, fail; Spin; then
        // Act succeeds.
        let mut script = Script {
            act: vec![false, false, false, false],
        };
        assert_eq!(t.tick_once(&mut script), Ok(Status::Success));
        assert_eq!(
            counter.branches(),
            [
                ("Follow recovery".to_string(), 2),
                ("Clear".to_string(), 1),
                ("Spin".to_string(), 1)
            ]
        );
        assert_eq!(counter.total(), 4);
        assert_eq!(
            log.take(),
            [
                "recovery: Follow recovery",
                "recovery: Clear",
                "recovery: Follow recovery",
                "recovery: Spin"
            ]
        );
    }
}
