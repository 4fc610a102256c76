//! What a live view shows of a tick: the statuses the nodes reached during it.

use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use neurotree_core::{Blueprint, NodeId, NodeStatus, Observer, StatusChange, Tree};

use super::render_statuses;

/// An [`Observer`] that records, for each node, the last status other than Idle it had
/// during the latest tick: what a live view should show once the tick is over, since a
/// root that completes resets every stored status to Idle.
///
/// The rules, per pass of the root:
/// - when the pass starts, the record is reset to the stored statuses (a node that was
///   Running, or a completed child a Sequence will not re-tick, keeps showing that status
///   even if the pass does not change it);
/// - each change to Running, Success or Failure is recorded;
/// - a reset (a completed node back to Idle) keeps the completed status in the record;
/// - a halt (a Running node back to Idle) clears it, so a halted node shows Idle rather
///   than a run it did not finish.
///
/// [`Tree::tick_once`] may make several passes when a node asks to be woken (Repeat,
/// RetryUntilSuccessful, the Async composites); the record is then that of the last pass.
///
/// The observer is a handle: clones share one record, so keep a clone to read it while the
/// tree owns the other. Attach it to a fresh tree, or build it with
/// [`LastTickStatuses::for_tree`] for a tree that has already run. Recording allocates
/// only the first time it sees a node.
#[derive(Clone, Debug, Default)]
pub struct LastTickStatuses {
    record: Arc<Mutex<Record>>,
}

#[derive(Debug, Default)]
struct Record {
    /// A mirror of the tree's stored statuses, kept by the change events.
    stored: Vec<NodeStatus>,
    /// What the latest pass showed of each node.
    last_tick: Vec<NodeStatus>,
}

impl LastTickStatuses {
    /// A record for a tree that has not been ticked yet (every node Idle).
    pub fn new() -> Self {
        Self::default()
    }

    /// A record for `tree` as it stands now, for an observer attached after it ran.
    pub fn for_tree<C>(tree: &Tree<C>) -> Self {
        let record = Record {
            stored: tree.statuses().to_vec(),
            last_tick: tree.statuses().to_vec(),
        };
        Self {
            record: Arc::new(Mutex::new(record)),
        }
    }

    /// The recorded status of every node, indexed by [`NodeId`]; nodes never seen are
    /// left out of the end and read as Idle by [`render_statuses`].
    pub fn statuses(&self) -> Vec<NodeStatus> {
        self.lock().last_tick.clone()
    }

    /// The recorded status of one node.
    pub fn status(&self, id: NodeId) -> NodeStatus {
        self.lock()
            .last_tick
            .get(id.index())
            .copied()
            .unwrap_or_default()
    }

    /// Draws `bp` with the recorded statuses; see [`render_statuses`].
    pub fn render<C>(&self, bp: &Blueprint<C>, unicode: bool) -> String {
        render_statuses(bp, &self.lock().last_tick, unicode)
    }

    fn lock(&self) -> MutexGuard<'_, Record> {
        // A panic while holding the lock cannot leave the record half-written in a way
        // that matters for display, so a poisoned lock is still read.
        self.record.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl Observer for LastTickStatuses {
    fn on_tick_start(&mut self, _now: Duration) {
        let mut record = self.lock();
        let Record { stored, last_tick } = &mut *record;
        last_tick.clear();
        last_tick.extend_from_slice(stored);
    }

    fn on_status_change(&mut self, change: StatusChange) {
        let mut record = self.lock();
        let i = change.node.index();
        if record.stored.len() <= i {
            record.stored.resize(i + 1, NodeStatus::Idle);
            record.last_tick.resize(i + 1, NodeStatus::Idle);
        }
        record.stored[i] = change.to;
        match (change.from, change.to) {
            (NodeStatus::Running, NodeStatus::Idle) => record.last_tick[i] = NodeStatus::Idle,
            (_, NodeStatus::Idle | NodeStatus::Skipped) => {}
            (_, to) => record.last_tick[i] = to,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::fixtures::Work;
    use neurotree_core::{Builder, ManualClock, Status};

    #[test]
    fn last_tick_keeps_completed_statuses_and_unchanged_ones() {
        let bp = Builder::<u32>::new()
            .sequence("job", |s| {
                s.always_success("prepare")
                    .stateful("work", || Work { left: 0, n: 2 })
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let seen = LastTickStatuses::new();
        tree.set_observer(seen.clone());
        let mut n = 0;
        let (r, s) = (NodeStatus::Running, NodeStatus::Success);
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        assert_eq!(seen.statuses(), [r, s, r]);
        // Nothing changes in the second tick: every status is carried over from the first.
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        assert_eq!(seen.statuses(), [r, s, r]);
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Success));
        assert_eq!(tree.statuses(), [NodeStatus::Idle; 3]);
        assert_eq!(seen.statuses(), [s, s, s]);
        assert_eq!(seen.status(NodeId(2)), s);
        assert_eq!(
            seen.render(tree.blueprint(), false),
            "[S] job (Sequence)\n\
             +-- [S] prepare (AlwaysSuccess)\n\
             \\-- [S] work (StatefulAction)\n"
        );
    }

    #[test]
    fn last_tick_clears_halted_nodes_and_resets_each_tick() {
        // The work runs while the guard holds; a failing guard halts it.
        let bp = Builder::<u32>::new()
            .reactive_sequence("guarded", |s| {
                s.condition("allowed", |n: &u32| *n == 0)
                    .stateful("work", || Work { left: 0, n: 5 })
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let seen = LastTickStatuses::new();
        tree.set_observer(seen.clone());
        let (i, r, s, f) = (
            NodeStatus::Idle,
            NodeStatus::Running,
            NodeStatus::Success,
            NodeStatus::Failure,
        );
        let mut n = 0;
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        assert_eq!(seen.statuses(), [r, s, r]);
        n = 1;
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Failure));
        assert_eq!(n, 101, "the work was halted");
        assert_eq!(seen.statuses(), [f, f, i]);
        // A new tick starts from the stored statuses (all Idle), not from the last record.
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Failure));
        assert_eq!(seen.statuses(), [f, f, i]);
    }

    #[test]
    fn attached_late_it_starts_from_the_stored_statuses() {
        let bp = Builder::<u32>::new()
            .sequence("job", |s| {
                s.always_success("prepare")
                    .stateful("work", || Work { left: 0, n: 3 })
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut n = 0;
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        let seen = LastTickStatuses::for_tree(&tree);
        tree.set_observer(seen.clone());
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        let (r, s) = (NodeStatus::Running, NodeStatus::Success);
        assert_eq!(seen.statuses(), [r, s, r]);
    }
}
