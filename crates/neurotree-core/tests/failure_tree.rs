//! "Why it failed" holds on random trees: after every tick whose root failed, each node of
//! the failure `Tree::last_failure` builds failed in that tick, each leaf named in it
//! returned Failure in that tick, and each chain in it ends at a leaf or at a node that
//! says why. The tree is the same whether an observer is attached or not (the unobserved
//! loops mark the failures of conditions whose statuses they never store).

use std::collections::HashSet;
use std::sync::{Arc, Mutex};

use crate::common::{self, Ctx, Event, Op, Spec, What};
use neurotree_core::{
    Failure, FailureLink, ManualClock, NodeId, NodeStatus, Observer, Status, StatusChange, Tree,
};
use proptest::prelude::*;

/// Which nodes returned Failure, from the observer's reports alone: a change to Failure,
/// or a tick of a node already Failure that changed nothing (or only reset it later, not
/// for a skip).
#[derive(Clone)]
struct Failed(Arc<Mutex<Seen>>);

struct Seen {
    /// The stored statuses, mirrored from the changes.
    mirror: Vec<NodeStatus>,
    /// Nodes written Failure since the last take.
    failed: HashSet<NodeId>,
    /// Nodes ticked while Failure, and whether a change since showed what they returned.
    unsure: HashSet<NodeId>,
}

impl Failed {
    fn new(nodes: usize) -> Self {
        Self(Arc::new(Mutex::new(Seen {
            mirror: vec![NodeStatus::Idle; nodes],
            failed: HashSet::new(),
            unsure: HashSet::new(),
        })))
    }

    /// The nodes that returned Failure since the last take.
    fn take(&self) -> HashSet<NodeId> {
        let mut seen = self.0.lock().unwrap();
        let unsure = std::mem::take(&mut seen.unsure);
        let mut failed = std::mem::take(&mut seen.failed);
        failed.extend(unsure);
        failed
    }
}

impl Observer for Failed {
    fn on_node_tick(&mut self, node: NodeId) {
        let mut seen = self.0.lock().unwrap();
        if seen.mirror[node.index()] == NodeStatus::Failure {
            seen.unsure.insert(node);
        }
    }
    fn on_status_change(&mut self, c: StatusChange) {
        let mut seen = self.0.lock().unwrap();
        seen.mirror[c.node.index()] = c.to;
        if c.to == NodeStatus::Failure {
            seen.failed.insert(c.node);
        } else if c.to != NodeStatus::Idle {
            // Ticked while Failure, it returned something else.
            seen.unsure.remove(&c.node);
        }
    }
    fn on_node_skipped(&mut self, node: NodeId) {
        self.0.lock().unwrap().unsure.remove(&node);
    }
}

/// Every link of a failure: its chain and, for each Fallback, the chains of what it tried.
fn links(chain: &[FailureLink], out: &mut Vec<FailureLink>, ends: &mut Vec<FailureLink>) {
    for link in chain {
        out.push(link.clone());
        for tried in &link.tried {
            assert_eq!(tried.chain.first().map(|l| l.node), Some(tried.node));
            links(&tried.chain, out, ends);
        }
    }
    ends.push(chain.last().expect("a chain is never empty").clone());
}

fn check(spec: &Spec, ops: &[Op]) -> Result<(), TestCaseError> {
    let leaves: HashSet<usize> = spec
        .flatten()
        .iter()
        .enumerate()
        .filter(|(_, f)| matches!(f.node, common::FlatKind::Leaf(_)))
        .map(|(i, _)| i)
        .collect();
    let bp = common::blueprint(spec);
    let mut quiet = Tree::with_clock(bp.clone(), ManualClock::new());
    let mut watched = Tree::with_clock(bp.clone(), ManualClock::new());
    let failed = Failed::new(spec.len());
    watched.set_observer(failed.clone());
    let (mut cq, mut cw) = (Ctx::new(spec), Ctx::new(spec));
    for &op in ops {
        let (rq, events, _) = common::step(&mut quiet, &mut cq, op);
        let rw = common::step(&mut watched, &mut cw, op).0;
        let tick_failed = failed.take();
        prop_assert_eq!(&rq, &rw);
        if rq.is_none() {
            // A halt is no tick: the last tick's failure still stands.
            continue;
        }
        let explained = quiet.last_failure();
        prop_assert_eq!(&explained, &watched.last_failure());
        prop_assert_eq!(explained.is_some(), rq == Some(Ok(Status::Failure)));
        let Some(f): Option<Failure> = explained else {
            continue;
        };
        prop_assert_eq!(f.links[0].node, NodeId::ROOT);
        let (mut all, mut ends) = (Vec::new(), Vec::new());
        links(&f.links, &mut all, &mut ends);
        let leaf_failures: HashSet<usize> = events
            .iter()
            .filter_map(|e: &Event| match e.what {
                What::Start(Status::Failure)
                | What::Running(Status::Failure)
                | What::Tick(Status::Failure) => Some(e.leaf),
                _ => None,
            })
            .collect();
        for link in &all {
            prop_assert!(
                tick_failed.contains(&link.node),
                "{} is in the failure but did not fail:\n{}",
                link.path,
                f
            );
            let i = link.node.index();
            if leaves.contains(&i) {
                // Called, it answered Failure; or, not called, it answered its stored
                // Failure (a stateful action not yet reset, as in BehaviorTree.CPP).
                let called = events.iter().any(|e| e.leaf == i);
                prop_assert!(
                    leaf_failures.contains(&i) || !called,
                    "leaf {} is in the failure but returned no Failure:\n{}\n{:?}",
                    link.path,
                    f,
                    events
                );
            }
        }
        for end in &ends {
            prop_assert!(
                leaves.contains(&end.node.index()) || end.reason.is_some(),
                "the chain ends at {}, no leaf, with no reason:\n{}",
                end.path,
                f
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 512,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn every_node_of_the_failure_failed_and_every_chain_reaches_a_leaf(
        spec in common::tree(false),
        ops in common::ops(),
    ) {
        check(&spec, &ops)?;
    }

    #[test]
    fn the_same_with_async_leaves_and_with_the_nodes_that_read_the_clock(
        spec in prop_oneof![common::tree_with(false, true), common::timed_tree()],
        ops in common::ops(),
    ) {
        check(&spec, &ops)?;
    }
}
