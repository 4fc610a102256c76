//! Telling what failed and why: an observer that logs every reason a node gives with its
//! Failure.

use neurotree_core::{Blueprint, NodeId, Observer, Reason};

use super::EventLog;

/// An [`Observer`] that writes `NAME failed: REASON` to an [`EventLog`] each time a node
/// gives a reason for its Failure: the Nav2 leaves give Nav2's error code with a short
/// message (`FollowPath failed: blocked (error 106)`), and the built-ins their own (a
/// Timeout that fired, a Retry that ran out).
///
/// ```
/// use neurotree::sim::nav2::{EventLog, FailureNotes};
/// use neurotree::{Action, Blueprint, Handle, ManualClock, Status, Tree};
///
/// struct Blocked;
/// impl Action<()> for Blocked {
///     fn tick(&self, h: &mut Handle<'_, ()>) -> Status {
///         h.fail_with(106, "blocked")
///     }
/// }
/// let blueprint = Blueprint::<()>::builder()
///     .action_node("FollowPath", Blocked)
///     .build_shared()
///     .unwrap();
/// let log = EventLog::new();
/// let mut tree = Tree::with_clock(blueprint, ManualClock::new());
/// tree.set_observer(FailureNotes::new(tree.blueprint(), log.clone()));
/// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Failure));
/// assert_eq!(log.take(), ["FollowPath failed: blocked (error 106)"]);
/// ```
#[derive(Clone, Debug)]
pub struct FailureNotes {
    names: Vec<String>,
    log: EventLog,
}

impl FailureNotes {
    /// Notes for trees of `bp`, written to `log`.
    pub fn new<C>(bp: &Blueprint<C>, log: EventLog) -> Self {
        Self {
            names: bp.ids().map(|id| bp.name(id).to_string()).collect(),
            log,
        }
    }
}

impl Observer for FailureNotes {
    fn on_failure_reason(&mut self, node: NodeId, reason: &Reason) {
        let name = self.names.get(node.index()).map_or("?", String::as_str);
        self.log.push(format!("{name} failed: {reason}"));
    }
}
