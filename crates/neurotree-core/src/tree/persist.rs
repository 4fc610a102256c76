//! A tree's state saved to bytes and restored into a fresh instance; see [`crate::state`].

use alloc::boxed::Box;
use alloc::string::String;
use alloc::vec::Vec;
use core::time::Duration;

use super::state::{get64, set64};
use super::ticker::Object;
use super::Tree;
use crate::clock::duration_to_nanos;
use crate::state::{RestoreError, SaveError, SavedEntry, SavedObject, SavedTree, StateCodecs};
use crate::{EntryInfo, NodeId, NodeKind, NodeStatus};

impl<C> Tree<C> {
    /// The tree's whole execution state as bytes: every node's status and state, the
    /// per-instance objects' own state, the blackboard; see [`crate::state`] for what must
    /// opt in and what cannot be saved. Blackboard values are saved with the blackboard's
    /// codecs ([`Blackboard::codecs`](crate::Blackboard::codecs), its blueprint's), else
    /// [`StateCodecs::new`]'s.
    ///
    /// ```
    /// use neurotree_core::{Blueprint, ManualClock, Status, Tree};
    ///
    /// let bp = Blueprint::<()>::builder()
    ///     .sequence_with_memory("s", |s| s.always_success("a").sleep("wait", std::time::Duration::from_secs(5)))
    ///     .build_shared()
    ///     .unwrap();
    /// let clock = ManualClock::new();
    /// let mut tree = Tree::with_clock(bp.clone(), clock.clone());
    /// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    /// let saved = tree.save_state().unwrap();
    ///
    /// // Elsewhere, later: the same blueprint, a clock where this one was.
    /// let elsewhere = ManualClock::new();
    /// let mut resumed = Tree::with_clock(bp, elsewhere.clone());
    /// resumed.restore_state(&saved).unwrap();
    /// elsewhere.advance(std::time::Duration::from_secs(5));
    /// assert_eq!(resumed.tick_once(&mut ()), Ok(Status::Success));
    /// ```
    pub fn save_state(&self) -> Result<Vec<u8>, SaveError> {
        match self.blackboard.codecs() {
            Some(codecs) => self.save_state_with(codecs),
            None => self.save_state_with(&StateCodecs::new()),
        }
    }

    /// [`save_state`](Self::save_state), with blackboard values saved by `codecs`.
    pub fn save_state_with(&self, codecs: &StateCodecs) -> Result<Vec<u8>, SaveError> {
        let bp = &*self.blueprint;
        if self.is_halting() {
            return Err(SaveError::Halting {
                node: NodeId::ROOT,
                path: bp.path(NodeId::ROOT),
            });
        }
        let mut saved = SavedTree::new(bp.structure_hash(), duration_to_nanos(self.clock.now()));
        saved.statuses = self.state.statuses().iter().map(|s| *s as u8).collect();
        // One `u64` per node that keeps state, as when slots were 64 bits.
        let aux = self.state.aux();
        for id in bp.ids() {
            let def = bp.def(id);
            let slots = def.kind.aux_slots(def.child_count) as usize;
            if slots > 0 {
                let value = read_slots(&aux[bp.slot(id)..][..slots]);
                saved.aux.push(def.kind.saved_aux(value, def.child_count));
            }
        }
        for id in bp.ids() {
            if !bp.kind(id).has_object() {
                continue;
            }
            let unsaveable = |kind| SaveError::Unsaveable {
                node: id,
                path: bp.path(id),
                kind,
            };
            let object = match &self.state.objects()[bp.slot(id)] {
                Object::Stateful(action) => {
                    action.save_state().ok_or(unsaveable("stateful action"))?
                }
                Object::Custom(node) => node.save_state().ok_or(unsaveable("custom node"))?,
                Object::Async(None) => {
                    saved.objects.push(SavedObject::Idle);
                    continue;
                }
                Object::Async(Some(_)) => {
                    return Err(SaveError::AsyncRunning {
                        node: id,
                        path: bp.path(id),
                    })
                }
                Object::Halting { .. } | Object::AsyncHalting { .. } => {
                    return Err(SaveError::Halting {
                        node: id,
                        path: bp.path(id),
                    })
                }
                Object::Vacant => return Err(unsaveable("custom node")),
            };
            saved.objects.push(SavedObject::State(object));
        }
        for (scope, key, info, untyped, value) in self.blackboard.raw_entries() {
            let (type_name, value) = match value {
                None => (None, Vec::new()),
                Some(value) => match codecs.encode(value) {
                    Some(bytes) => (Some(String::from(info.type_name)), bytes),
                    None => {
                        return Err(SaveError::Value {
                            key: String::from(key),
                            type_name: info.type_name,
                        })
                    }
                },
            };
            saved.entries.push(SavedEntry {
                scope,
                key: String::from(key),
                type_name,
                sequence: info.sequence,
                stamp_nanos: duration_to_nanos(info.stamp),
                untyped,
                value,
            });
        }
        saved.last_stamp_nanos = duration_to_nanos(self.blackboard.last_stamp());
        saved.last_root = self.last_root as u8;
        Ok(crate::state::encode(&saved))
    }

    /// Restores a state [`save_state`](Self::save_state) made, of a tree of the same
    /// blueprint structure, into this instance; the tree then runs on as the saved one
    /// would have. Refused, leaving the tree as it was, for bytes that are not such a state
    /// or belong to another tree. Blackboard values are read with the codecs
    /// [`save_state`](Self::save_state) writes them with.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), RestoreError> {
        match self.blackboard.codecs().cloned() {
            Some(codecs) => self.restore_state_with(bytes, &codecs),
            None => self.restore_state_with(bytes, &StateCodecs::new()),
        }
    }

    /// [`restore_state`](Self::restore_state), with blackboard values read by `codecs`.
    pub fn restore_state_with(
        &mut self,
        bytes: &[u8],
        codecs: &StateCodecs,
    ) -> Result<(), RestoreError> {
        let saved = SavedTree::read(bytes)?;
        let bp = &*self.blueprint;
        let expected = bp.structure_hash();
        if saved.blueprint != expected {
            return Err(RestoreError::OtherTree {
                expected,
                found: saved.blueprint,
            });
        }
        let corrupt =
            |what: &str| RestoreError::Corrupt(alloc::format!("{what} do not match its tree"));
        if saved.statuses.len() != self.state.statuses().len() {
            return Err(corrupt("its node statuses"));
        }
        if saved.aux.len() != bp.ids().filter(|id| bp.aux_slots_of(*id) > 0).count() {
            return Err(corrupt("its state slots"));
        }
        if saved.objects.len() != self.state.objects().len() {
            return Err(corrupt("its objects"));
        }
        let mut statuses = Vec::with_capacity(saved.statuses.len());
        for &s in &saved.statuses {
            statuses.push(status_of(s).ok_or_else(|| corrupt("its node statuses"))?);
        }
        let last_root = status_of(saved.last_root).ok_or_else(|| corrupt("its root status"))?;
        let now = duration_to_nanos(self.clock.now());
        let mut aux = alloc::vec![0; self.state.aux().len()];
        let mut saved_aux = saved.aux.iter();
        let mut objects = Vec::with_capacity(self.state.objects().len());
        let mut saved_objects = saved.objects.into_iter();
        for id in bp.ids() {
            let kind = bp.kind(id);
            let children = bp.def(id).child_count;
            let slots = kind.aux_slots(children) as usize;
            if slots > 0 {
                let value = saved_aux
                    .next()
                    .and_then(|saved| kind.restored_aux(*saved, children))
                    .map(|value| kind.shift_aux(value, saved.clock_nanos, now));
                let Some(()) = value.and_then(|v| write_slots(&mut aux[bp.slot(id)..][..slots], v))
                else {
                    return Err(corrupt("its state slots"));
                };
            }
            if !kind.has_object() {
                continue;
            }
            let refused = || RestoreError::Node {
                node: id,
                path: bp.path(id),
            };
            let state = saved_objects.next().ok_or_else(|| corrupt("its objects"))?;
            let object = match (kind, state) {
                (NodeKind::Stateful(make), SavedObject::State(bytes)) => {
                    let mut action = make();
                    if !action.restore_state(&bytes) {
                        return Err(refused());
                    }
                    Object::Stateful(action)
                }
                (NodeKind::Custom(spec), SavedObject::State(bytes)) => {
                    let mut node = (spec.factory)();
                    if !node.restore_state(&bytes) {
                        return Err(refused());
                    }
                    Object::Custom(node)
                }
                (NodeKind::Async(_), SavedObject::Idle) => Object::Async(None),
                _ => return Err(corrupt("its objects")),
            };
            objects.push(object);
        }
        let mut entries = Vec::with_capacity(saved.entries.len());
        for entry in saved.entries {
            let value = match &entry.type_name {
                None => None,
                Some(name) => {
                    let refused = || RestoreError::Value {
                        key: entry.key.clone(),
                        type_name: name.clone(),
                    };
                    Some(codecs.decode(name, &entry.value).ok_or_else(refused)?)
                }
            };
            if entry.scope as usize >= self.blackboard.scope_count() {
                return Err(corrupt("its blackboard scopes"));
            }
            entries.push((entry, value));
        }
        // Nothing can fail from here: the tree changes all at once.
        self.blackboard.clear_entries();
        for (entry, value) in entries {
            let (type_name, value): (&'static str, Option<Box<dyn core::any::Any + Send + Sync>>) =
                match value {
                    Some((name, value)) => (name, Some(value)),
                    None => (crate::blackboard::UNWRITTEN, None),
                };
            let info = EntryInfo {
                sequence: entry.sequence,
                stamp: Duration::from_nanos(entry.stamp_nanos),
                type_name,
            };
            self.blackboard
                .put_raw_entry(entry.scope, entry.key, info, entry.untyped, value);
        }
        self.blackboard
            .set_last_stamp(Duration::from_nanos(saved.last_stamp_nanos));
        let state = self.state.parts();
        state.statuses.copy_from_slice(&statuses);
        state.aux.copy_from_slice(&aux);
        // The old objects are swapped out and dropped once the tree is whole: a drop may
        // panic.
        let mut old = objects;
        for (object, restored) in state.objects.iter_mut().zip(old.iter_mut()) {
            core::mem::swap(object, restored);
        }
        self.last_root = last_root;
        self.resting = None;
        self.forget_notes();
        drop(old);
        Ok(())
    }
}

/// A node's state slots read as one value: one slot, or two (see [`get64`]).
fn read_slots(slots: &[u32]) -> u64 {
    match slots.len() {
        2 => get64(slots, 0),
        _ => slots.first().copied().map_or(0, u64::from),
    }
}

/// The inverse of [`read_slots`]; `None` if one slot cannot hold the value.
fn write_slots(slots: &mut [u32], value: u64) -> Option<()> {
    match slots.len() {
        2 => set64(slots, 0, value),
        1 => slots[0] = u32::try_from(value).ok()?,
        _ => {}
    }
    Some(())
}

/// The status a saved byte stands for.
fn status_of(byte: u8) -> Option<NodeStatus> {
    Some(match byte {
        0 => NodeStatus::Idle,
        1 => NodeStatus::Running,
        2 => NodeStatus::Success,
        3 => NodeStatus::Failure,
        4 => NodeStatus::Skipped,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use crate::clock::moment;
    use crate::state::SavedTree;
    use crate::testing::*;

    #[test]
    fn a_saved_state_keeps_a_u64_per_node_as_when_slots_were_64_bits() {
        let (mut tree, clock) = build(|b| {
            b.sequence("s", |s| {
                s.run_once("once", true, |o| o.always_success("a"))
                    .sleep("nap", ms(1000))
            })
        });
        assert_eq!(tick(&mut tree), Ok(R));
        clock.advance(ms(1000));
        assert_eq!(tick(&mut tree), Ok(S));
        // The run-once child is skipped now, and the nap begins at 1 s.
        assert_eq!(tick(&mut tree), Ok(R));
        let bytes = tree.save_state().unwrap();
        let saved = SavedTree::read(&bytes).unwrap();
        // The Sequence: cursor 1 and one child skipped; the RunOnce: its child succeeded;
        // the Sleep: the moment it began, in its two slots.
        assert_eq!(saved.aux, [1 | (1 << 32), 1, moment::at(1_000_000_000)]);
        assert_eq!(tree.state.aux().len(), 1 + 1 + 2);

        let mut resumed = Tree::with_clock(Arc::clone(tree.blueprint()), clock.clone());
        resumed.restore_state(&bytes).unwrap();
        assert_eq!(resumed.state.aux(), tree.state.aux());
        assert_eq!(resumed.statuses(), tree.statuses());
        clock.advance(ms(999));
        assert_eq!(tick(&mut resumed), Ok(R));
        clock.advance(ms(1));
        assert_eq!(tick(&mut resumed), Ok(S));
    }

    /// `tree` with its first node's saved state replaced by `value`, restored.
    fn restored_with(tree: &mut Tree<()>, value: u64) -> Result<(), crate::state::RestoreError> {
        let mut saved = SavedTree::read(&tree.save_state().unwrap()).unwrap();
        saved.aux[0] = value;
        tree.restore_state(&crate::state::encode(&saved))
    }

    #[test]
    fn a_saved_count_past_what_one_slot_holds_saturates() {
        let (mut tree, clock) = build(|b| b.repeat("r", 3, |r| r.sleep("nap", ms(10))));
        assert_eq!(tick(&mut tree), Ok(R));
        // A count saved when slots were 64 bits, past 2^32: only a Repeat of -1 reaches it.
        restored_with(&mut tree, 1 << 40).unwrap();
        assert_eq!(tree.state.aux()[0], u32::MAX);
        clock.advance(ms(10));
        assert_eq!(tick(&mut tree), Ok(S));
    }

    #[test]
    fn saved_states_no_node_keeps_are_refused_and_the_tree_is_left_as_it_was() {
        type Make = fn(Builder<()>) -> Builder<()>;
        let cases: [(&str, Make, u64); 6] = [
            (
                "an IfThenElse of two children on its else branch",
                |b| b.if_then_else("ite", |c| c.always_success("if").sleep("then", ms(10))),
                2,
            ),
            (
                "an IfThenElse on a branch past the children",
                |b| b.if_then_else("ite", |c| c.always_success("if").sleep("then", ms(10))),
                7,
            ),
            (
                "a ReactiveSequence running a child it does not have",
                |b| b.reactive_sequence("rs", |c| c.always_success("a").sleep("nap", ms(10))),
                3,
            ),
            (
                "a Parallel keeping a Running outcome",
                |b| {
                    b.parallel_policy("p", crate::ParallelPolicy::RequireAll, |c| {
                        c.sleep("nap", ms(10))
                    })
                },
                NodeStatus::Running as u64,
            ),
            (
                "a RunOnce with a third outcome",
                |b| {
                    b.sequence("s", |s| {
                        s.run_once("once", true, |o| o.always_success("a"))
                            .sleep("nap", ms(10))
                    })
                },
                3,
            ),
            (
                "a TryCatch whose catch waits for a halt",
                |b| {
                    b.try_catch("tc", true, |c| {
                        c.sleep("try", ms(10)).always_success("catch")
                    })
                },
                1 << 62,
            ),
        ];
        for (what, make, value) in cases {
            let (mut tree, _) = build(make);
            assert_eq!(tick(&mut tree), Ok(R), "{what}");
            let before = (tree.state.aux().to_vec(), tree.statuses().to_vec());
            let slot = usize::from(what.contains("RunOnce"));
            let mut saved = SavedTree::read(&tree.save_state().unwrap()).unwrap();
            saved.aux[slot] = value;
            assert!(
                matches!(
                    tree.restore_state(&crate::state::encode(&saved)),
                    Err(crate::state::RestoreError::Corrupt(_))
                ),
                "{what}"
            );
            assert_eq!(
                (tree.state.aux().to_vec(), tree.statuses().to_vec()),
                before,
                "{what}"
            );
            // The tree still ticks.
            assert_eq!(tick(&mut tree), Ok(R), "{what}");
        }
    }
}
