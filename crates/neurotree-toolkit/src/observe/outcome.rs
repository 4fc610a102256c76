//! What each node returned, read from the observer events: the part [`Statistics`] and
//! [`Coverage`] share.
//!
//! The events tell of status *changes*, and a node that returns what it had stored changes
//! nothing, so a node's result is read from its stored status once the next event shows
//! its tick is over. A Running node that goes back to Idle was halted, unless its skip
//! event follows at once (a `_while` that turned false while it ran).
//!
//! [`Statistics`]: super::Statistics
//! [`Coverage`]: super::Coverage

use std::fmt;

use neurotree_core::{Blueprint, NodeId, NodeStatus, StatusChange};

/// One kind of thing a node can be seen doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Outcome {
    /// It returned Success (from its tick, or from `_successIf`).
    Success,
    /// It returned Failure (from its tick, or from `_failureIf`).
    Failure,
    /// Its tick returned Running.
    Running,
    /// It was Running and went back to Idle without completing: its parent, a
    /// precondition or [`Tree::halt`](neurotree_core::Tree::halt) halted it.
    Halted,
    /// It returned Skipped (a precondition, or a node that chose not to run).
    Skipped,
}

impl Outcome {
    /// Every outcome, in the order tables list them.
    pub const ALL: [Outcome; 5] = [
        Outcome::Success,
        Outcome::Failure,
        Outcome::Running,
        Outcome::Halted,
        Outcome::Skipped,
    ];

    /// The lower-case word tables and JSON use (`success`, `halted`, ...).
    pub const fn as_str(self) -> &'static str {
        match self {
            Outcome::Success => "success",
            Outcome::Failure => "failure",
            Outcome::Running => "running",
            Outcome::Halted => "halted",
            Outcome::Skipped => "skipped",
        }
    }

    /// The outcome [`as_str`](Self::as_str) names.
    pub fn from_name(name: &str) -> Option<Outcome> {
        Outcome::ALL.into_iter().find(|o| o.as_str() == name)
    }

    const fn bit(self) -> u8 {
        1 << self as u8
    }
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A set of [`Outcome`]s, as one byte.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct OutcomeSet(u8);

impl OutcomeSet {
    /// No outcome.
    pub const NONE: OutcomeSet = OutcomeSet(0);

    /// The set of `outcomes`.
    pub fn of(outcomes: &[Outcome]) -> OutcomeSet {
        outcomes
            .iter()
            .fold(OutcomeSet::NONE, |set, &o| set.with(o))
    }

    /// This set and `outcome`.
    #[must_use]
    pub const fn with(self, outcome: Outcome) -> OutcomeSet {
        OutcomeSet(self.0 | outcome.bit())
    }

    /// `true` if `outcome` is in the set.
    pub const fn contains(self, outcome: Outcome) -> bool {
        self.0 & outcome.bit() != 0
    }

    /// `true` for the empty set.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// How many outcomes the set holds.
    pub const fn len(self) -> usize {
        self.0.count_ones() as usize
    }

    /// The outcomes in both sets.
    #[must_use]
    pub const fn and(self, other: OutcomeSet) -> OutcomeSet {
        OutcomeSet(self.0 & other.0)
    }

    /// The outcomes of this set that `other` lacks.
    #[must_use]
    pub const fn without(self, other: OutcomeSet) -> OutcomeSet {
        OutcomeSet(self.0 & !other.0)
    }

    /// The outcomes, in [`Outcome::ALL`] order.
    pub fn iter(self) -> impl Iterator<Item = Outcome> {
        Outcome::ALL.into_iter().filter(move |o| self.contains(*o))
    }
}

/// The words of the outcomes, comma-separated (`success, halted`), or `-` for none.
impl fmt::Display for OutcomeSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_empty() {
            return f.write_str("-");
        }
        for (i, o) in self.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            f.write_str(o.as_str())?;
        }
        Ok(())
    }
}

/// Turns the observer events into the outcome of each node, told to a `seen` callback as
/// `(node, outcome)`. It does not check node ids: the observers that own it do.
pub(super) struct OutcomeReader {
    /// See [`Blueprint::subtree_ends`].
    subtree_ends: Vec<u32>,
    /// The tree's stored statuses, as the changes told them.
    stored: Vec<NodeStatus>,
    /// Nodes whose own tick began and whose result is not told yet, each the parent (or an
    /// ancestor) of the next.
    pending: Vec<NodeId>,
    /// A pending node just went from Running to Idle: a skip if its skip event follows at
    /// once, a halt otherwise.
    running_to_idle: Option<NodeId>,
}

impl OutcomeReader {
    pub(super) fn new<C>(blueprint: &Blueprint<C>) -> Self {
        Self {
            subtree_ends: blueprint.subtree_ends(),
            stored: vec![NodeStatus::Idle; blueprint.len()],
            pending: Vec::new(),
            running_to_idle: None,
        }
    }

    pub(super) fn knows(&self, id: NodeId) -> bool {
        id.index() < self.stored.len()
    }

    fn is_in_subtree(&self, node: NodeId, of: NodeId) -> bool {
        of.0 <= node.0 && node.0 < self.subtree_ends[of.index()]
    }

    /// Ends the ticks of the pending nodes for which `keep` is false, innermost first.
    fn end_ticks_until(
        &mut self,
        keep: impl Fn(&Self, NodeId) -> bool,
        seen: &mut dyn FnMut(NodeId, Outcome),
    ) {
        while let Some(&top) = self.pending.last() {
            if keep(self, top) {
                break;
            }
            self.pending.pop();
            tell(top, self.stored[top.index()], seen);
        }
    }

    /// Settles a Running-to-Idle change that was not followed by its skip: a halt.
    fn settle(&mut self, seen: &mut dyn FnMut(NodeId, Outcome)) {
        if let Some(id) = self.running_to_idle.take() {
            seen(id, Outcome::Halted);
        }
    }

    /// A pass of the root starts, or one ended: every tick under way is over.
    pub(super) fn pass_boundary(&mut self, seen: &mut dyn FnMut(NodeId, Outcome)) {
        self.settle(seen);
        self.end_ticks_until(|_, _| false, seen);
    }

    pub(super) fn node_tick(&mut self, node: NodeId, seen: &mut dyn FnMut(NodeId, Outcome)) {
        self.settle(seen);
        // A node ticked again within the same pass (a retry) ended its previous tick.
        self.end_ticks_until(|s, p| p != node && s.is_in_subtree(node, p), seen);
        self.pending.push(node);
    }

    pub(super) fn status_change(&mut self, c: StatusChange, seen: &mut dyn FnMut(NodeId, Outcome)) {
        self.settle(seen);
        self.end_ticks_until(|s, p| s.is_in_subtree(c.node, p), seen);
        let pending = self.pending.last() == Some(&c.node);
        match (c.from, c.to) {
            // Its own result: told when its tick is over, in case it changes again (a
            // control marks itself Running before it ticks its children).
            (_, NodeStatus::Running | NodeStatus::Success | NodeStatus::Failure) if pending => {}
            (NodeStatus::Running, NodeStatus::Idle) if pending => {
                self.pending.pop();
                self.running_to_idle = Some(c.node);
            }
            // Returned its result and was reset at once (the root, by the tree).
            (from, NodeStatus::Idle) if pending => {
                self.pending.pop();
                tell(c.node, from, seen);
            }
            (NodeStatus::Running, NodeStatus::Idle) => seen(c.node, Outcome::Halted),
            // Decided by a precondition, without a tick (or a reset to Idle: no outcome).
            (_, to) => tell(c.node, to, seen),
        }
        self.stored[c.node.index()] = c.to;
    }

    pub(super) fn node_skipped(&mut self, node: NodeId, seen: &mut dyn FnMut(NodeId, Outcome)) {
        if self.running_to_idle != Some(node) {
            self.settle(seen);
        }
        // Its Running-to-Idle change just before was the skip, not a halt.
        self.running_to_idle = None;
        self.end_ticks_until(|s, p| s.is_in_subtree(node, p), seen);
        if self.pending.last() == Some(&node) {
            self.pending.pop();
        }
        seen(node, Outcome::Skipped);
    }
}

/// Tells of a node's result, read from a status; Idle is no result.
fn tell(id: NodeId, status: NodeStatus, seen: &mut dyn FnMut(NodeId, Outcome)) {
    let outcome = match status {
        NodeStatus::Success => Outcome::Success,
        NodeStatus::Failure => Outcome::Failure,
        NodeStatus::Running => Outcome::Running,
        NodeStatus::Idle | NodeStatus::Skipped => return,
    };
    seen(id, outcome);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outcome_sets_hold_name_and_print_their_outcomes() {
        let set = OutcomeSet::of(&[Outcome::Halted, Outcome::Success]);
        assert_eq!(set.len(), 2);
        assert!(set.contains(Outcome::Halted) && !set.contains(Outcome::Running));
        assert_eq!(set.to_string(), "success, halted");
        assert_eq!(OutcomeSet::NONE.to_string(), "-");
        assert_eq!(
            set.without(OutcomeSet::of(&[Outcome::Success])),
            OutcomeSet::of(&[Outcome::Halted])
        );
        for o in Outcome::ALL {
            assert_eq!(Outcome::from_name(o.as_str()), Some(o));
        }
        assert_eq!(Outcome::from_name("SUCCESS"), None);
    }
}
