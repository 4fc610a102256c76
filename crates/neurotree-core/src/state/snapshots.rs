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
}
