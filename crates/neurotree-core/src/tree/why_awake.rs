//! Why a tree is awake: the first thing of its last tick that kept it from sleeping (see
//! [`sleep`](super::sleep)).
//!
//! Nothing is computed while ticking beyond what sleeping needs: the reason and its node
//! are kept where the tree decides to stay awake, and [`Tree::why_awake`] reads them.

use alloc::string::String;
use core::fmt;

use crate::{NodeId, NodeStatus, Tree};

/// What keeps a tree awake (see [`Tree::why_awake`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum AwakeReason {
    /// The root is not Running (never ticked, completed, halted or failed): its next tick
    /// starts it.
    NotRunning = 0,
    /// A stateful action returned Running and declared no wait.
    UndeclaredLeaf,
    /// An async action is Running: its future may rely on being polled every tick.
    AsyncLeaf,
    /// A custom node was ticked and declared nothing.
    UndeclaredCustom,
    /// A reactive node (ReactiveSequence, ReactiveFallback, WhileDoElse) re-checks, every
    /// tick, a condition that may read more than the blackboard.
    ReactiveCondition,
    /// A node returns Running with nothing under it waiting (KeepRunningUntilFailure
    /// between runs of its child).
    RestartsChild,
    /// The root is Running, but no node declared what it waits on.
    NothingDeclared,
    /// The tick wrote to the blackboard.
    WroteBlackboard,
    /// A node asked for another pass, or a halt is under way.
    AnotherPass,
    /// An observer is attached: it sees every tick.
    Observed,
    /// Sleeping is turned off ([`Tree::set_sleep_allowed`]).
    SleepOff,
}

impl AwakeReason {
    /// How many reasons there are: the length of a table indexed by [`index`](Self::index).
    pub const COUNT: usize = 11;

    /// Every reason, in the order of [`index`](Self::index).
    pub const ALL: [AwakeReason; Self::COUNT] = [
        AwakeReason::NotRunning,
        AwakeReason::UndeclaredLeaf,
        AwakeReason::AsyncLeaf,
        AwakeReason::UndeclaredCustom,
        AwakeReason::ReactiveCondition,
        AwakeReason::RestartsChild,
        AwakeReason::NothingDeclared,
        AwakeReason::WroteBlackboard,
        AwakeReason::AnotherPass,
        AwakeReason::Observed,
        AwakeReason::SleepOff,
    ];

    /// The reason's place in [`ALL`](Self::ALL), `0..COUNT`.
    pub const fn index(self) -> usize {
        self as usize
    }

    /// A short name, in snake case (`undeclared_leaf`): for counters and logs.
    pub const fn name(self) -> &'static str {
        match self {
            AwakeReason::NotRunning => "not_running",
            AwakeReason::UndeclaredLeaf => "undeclared_leaf",
            AwakeReason::AsyncLeaf => "async_leaf",
            AwakeReason::UndeclaredCustom => "undeclared_custom",
            AwakeReason::ReactiveCondition => "reactive_condition",
            AwakeReason::RestartsChild => "restarts_child",
            AwakeReason::NothingDeclared => "nothing_declared",
            AwakeReason::WroteBlackboard => "wrote_blackboard",
            AwakeReason::AnotherPass => "another_pass",
            AwakeReason::Observed => "observed",
            AwakeReason::SleepOff => "sleep_off",
        }
    }

    /// What the reason means, in a sentence's words, after the node's path.
    const fn says(self) -> &'static str {
        match self {
            AwakeReason::NotRunning => "is not Running: its next tick starts it",
            AwakeReason::UndeclaredLeaf => {
                "is a Running action that declared no wait (sleep_until, wake_on, wake_on_handle)"
            }
            AwakeReason::AsyncLeaf => "is a Running async action: its future is polled every tick",
            AwakeReason::UndeclaredCustom => {
                "is a custom node that declared nothing (wakes_with_children, wake_on, sleep_until)"
            }
            AwakeReason::ReactiveCondition => {
                "is re-checked every tick by a reactive node and may read more than the blackboard"
            }
            AwakeReason::RestartsChild => "starts its child again on its next tick",
            AwakeReason::NothingDeclared => "is Running, and no node declared what it waits on",
            AwakeReason::WroteBlackboard => "wrote to the blackboard in the last tick",
            AwakeReason::AnotherPass => "asked for another pass, or waits for a halt",
            AwakeReason::Observed => "has an observer attached",
            AwakeReason::SleepOff => "may not sleep (set_sleep_allowed(false))",
        }
    }
}

impl fmt::Display for AwakeReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Why a tree is awake: the reason, the node it is about and that node's path.
///
/// Displays as ``"`patrol/look` is a Running action that declared no wait (…)"``.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WhyAwake {
    /// What keeps the tree awake.
    pub reason: AwakeReason,
    /// The node it is about (the root for a reason of the whole tree).
    pub node: NodeId,
    /// The node's path in the blueprint (`ROOT/seq/look`, see
    /// [`Blueprint::path`](crate::Blueprint::path)).
    pub path: String,
}

impl fmt::Display for WhyAwake {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "`{}` {}", self.path, self.reason.says())
    }
}

impl<C> Tree<C> {
    /// Why the tree did not fall asleep after its last tick; `None` while it sleeps. Reads
    /// what the tick left: asking costs a path's text, not asking costs nothing.
    pub fn why_awake(&self) -> Option<WhyAwake> {
        let (reason, node) = self.awake_reason()?;
        Some(WhyAwake {
            reason,
            node,
            path: self.blueprint.path(node),
        })
    }

    /// [`why_awake`](Self::why_awake) without the path: what a runner counting reasons
    /// over many trees asks.
    pub fn awake_reason(&self) -> Option<(AwakeReason, NodeId)> {
        if self.sleeping {
            return None;
        }
        if self.last_root != NodeStatus::Running {
            return Some((AwakeReason::NotRunning, NodeId::ROOT));
        }
        if !self.sleep_allowed {
            return Some((AwakeReason::SleepOff, NodeId::ROOT));
        }
        if self.keeps_awake_observer() {
            return Some((AwakeReason::Observed, NodeId::ROOT));
        }
        if let Some(reason) = self.out.reason {
            return Some(reason);
        }
        if let Some(leaf) = self.resting.filter(|_| !self.out.declared) {
            return Some((AwakeReason::UndeclaredLeaf, leaf));
        }
        Some((AwakeReason::AnotherPass, NodeId::ROOT))
    }
}

/// How many trees are awake for each [`AwakeReason`]: a fixed-size table, `Copy`, that a
/// runner of many trees fills after each tick (a crowd's frame report holds one).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct AwakeCounts {
    counts: [u32; AwakeReason::COUNT],
}

impl AwakeCounts {
    /// Counts one tree awake for `reason`.
    #[inline]
    pub fn add(&mut self, reason: AwakeReason) {
        self.counts[reason.index()] += 1;
    }

    /// Counts `tree` if it is awake.
    #[inline]
    pub fn count<C>(&mut self, tree: &Tree<C>) {
        if let Some((reason, _)) = tree.awake_reason() {
            self.add(reason);
        }
    }

    /// The trees counted awake for `reason`.
    pub fn get(&self, reason: AwakeReason) -> u32 {
        self.counts[reason.index()]
    }

    /// The trees counted awake, for any reason.
    pub fn total(&self) -> u64 {
        self.counts.iter().map(|&n| u64::from(n)).sum()
    }

    /// The reasons with at least one tree, and how many.
    pub fn iter(&self) -> impl Iterator<Item = (AwakeReason, u32)> + '_ {
        AwakeReason::ALL
            .iter()
            .zip(self.counts.iter())
            .filter(|(_, n)| **n != 0)
            .map(|(&r, &n)| (r, n))
    }

    /// Both tables summed.
    #[inline]
    #[must_use]
    pub fn merged(mut self, other: AwakeCounts) -> AwakeCounts {
        for (a, b) in self.counts.iter_mut().zip(other.counts) {
            *a += b;
        }
        self
    }
}
