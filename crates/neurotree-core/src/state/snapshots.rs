//! A run's saved states, every K ticks: what rewinding and forking a run restore.

use alloc::collections::VecDeque;
use alloc::vec::Vec;

use super::{SaveError, StateCodecs};
use crate::Tree;

/// Saved states of one run, one every `every` ticks, the oldest dropped past `keep`.
///
/// Call [`after_tick`](Self::after_tick) after each tick with the tick's number; restore
/// [`at_or_before`](Self::at_or_before) a tick into a fresh instance to go back there, and
/// change the context or the blackboard to try again differently.
///
/// ```
/// use neurotree_core::state::Snapshots;
/// use neurotree_core::{Blueprint, ManualClock, Status, Tree};
///
/// let bp = Blueprint::<()>::builder()
///     .repeat("r", 3, |r| r.always_success("a"))
///     .build_shared()
///     .unwrap();
/// let mut tree = Tree::with_clock(bp.clone(), ManualClock::new());
/// let mut snapshots = Snapshots::new(2, 10);
/// let mut statuses = Vec::new();
/// for tick in 1..=4 {
///     tree.tick_exactly_once(&mut ()).unwrap();
///     statuses.push(tree.statuses().to_vec());
///     snapshots.after_tick(&tree, tick).unwrap();
/// }
/// // Back to tick 2, the latest state at or before tick 3.
/// let (tick, state) = snapshots.at_or_before(3).unwrap();
/// assert_eq!(tick, 2);
/// let mut back = Tree::with_clock(bp, ManualClock::new());
/// back.restore_state(state).unwrap();
/// assert_eq!(back.statuses(), &statuses[1][..]);
/// ```
#[derive(Debug)]
pub struct Snapshots {
    every: u64,
    keep: usize,
    states: VecDeque<(u64, Vec<u8>)>,
    codecs: StateCodecs,
}

impl Snapshots {
    /// A state every `every` ticks (at least 1), at most `keep` of them (at least 1).
    pub fn new(every: u64, keep: usize) -> Self {
        Self {
            every: every.max(1),
            keep: keep.max(1),
            states: VecDeque::new(),
            codecs: StateCodecs::new(),
        }
    }

    /// The same, saving blackboard values with `codecs`.
    pub fn with_codecs(mut self, codecs: StateCodecs) -> Self {
        self.codecs = codecs;
        self
    }

    /// After tick number `tick` (counted from 1): saves the tree's state if `tick` is a
    /// multiple of the period. Returns whether it saved.
    pub fn after_tick<C>(&mut self, tree: &Tree<C>, tick: u64) -> Result<bool, SaveError> {
        if tick % self.every != 0 {
            return Ok(false);
        }
        let state = tree.save_state_with(&self.codecs)?;
        if self.states.len() == self.keep {
            self.states.pop_front();
        }
        self.states.push_back((tick, state));
        Ok(true)
    }

    /// The latest state saved at or before tick `tick`, with its tick.
    pub fn at_or_before(&self, tick: u64) -> Option<(u64, &[u8])> {
        self.states
            .iter()
            .rev()
            .find(|(t, _)| *t <= tick)
            .map(|(t, s)| (*t, s.as_slice()))
    }

    /// The ticks whose states are kept, oldest first.
    pub fn ticks(&self) -> impl Iterator<Item = u64> + '_ {
        self.states.iter().map(|(t, _)| *t)
    }

    /// Drops the states of the ticks after `tick`: the run forked from there, and what it
    /// did after no longer happened.
    pub fn forget_after(&mut self, tick: u64) {
        while self.states.back().is_some_and(|(t, _)| *t > tick) {
            self.states.pop_back();
        }
    }

    /// Drops every state kept.
    pub fn clear(&mut self) {
        self.states.clear();
    }

    /// The codecs blackboard values are saved with: restore the states with them.
    pub fn codecs(&self) -> &StateCodecs {
        &self.codecs
    }

    /// The number of states kept.
    pub fn len(&self) -> usize {
        self.states.len()
    }

    /// `true` if no state is kept.
    pub fn is_empty(&self) -> bool {
        self.states.is_empty()
    }

    /// The bytes the kept states take (their encodings, not counting the vectors' spare
    /// room).
    pub fn bytes(&self) -> usize {
        self.states.iter().map(|(_, s)| s.len()).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Blueprint, ManualClock};

    #[test]
    fn a_fork_forgets_the_later_states_and_the_window_stays_bounded() {
        let bp = Blueprint::<()>::builder()
            .repeat("r", -1, |r| r.always_success("a"))
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut snapshots = Snapshots::new(1, 5);
        for tick in 1..=8 {
            tree.tick_exactly_once(&mut ()).unwrap();
            snapshots.after_tick(&tree, tick).unwrap();
        }
        assert_eq!(snapshots.ticks().collect::<Vec<_>>(), [4, 5, 6, 7, 8]);
        assert!(snapshots.bytes() > 0);
        snapshots.forget_after(6);
        assert_eq!(snapshots.ticks().collect::<Vec<_>>(), [4, 5, 6]);
        assert_eq!(snapshots.len(), 3);
        snapshots.clear();
        assert!(snapshots.is_empty());
    }
}
