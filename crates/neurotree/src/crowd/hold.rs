//! Holding one member still, and the other hooks a debugger watching one member of a crowd
//! needs: an observer on that member alone, the members by slot, and a count that changes
//! when members join or leave.
//!
//! A held member is not ticked by any frame, whatever wakes it, until it is released; the
//! others are ticked as if it were not there. It is held as a sleeper is: its bit in the
//! awake set is cleared, so a frame does not visit it, and each frame's start puts it back
//! to sleep if something woke it (a wake, a deadline, a changed tree). A frame thus pays
//! nothing for holding, and a crowd with nobody held pays one test of an empty list.

use super::member::FrameStatus;
use super::sleep::AWAKE;
use super::{Crowd, MemberId};
use crate::Observer;

/// The members held still, in the order they were held. A debugger holds one or two.
#[derive(Debug, Default)]
pub(super) struct Held {
    ids: Vec<MemberId>,
}

impl<C: Send> Crowd<C> {
    /// Holds member `id` still: no frame ticks it until [`release`](Self::release), even
    /// if it is woken; the other members are ticked exactly as they would be without it.
    /// A held member counts as asleep in [`FrameReport::asleep`](super::FrameReport); a
    /// tick a [budget](Self::set_budget) owed it is forgotten (it is due again once
    /// released). `false` if `id` names no member.
    pub fn hold(&mut self, id: MemberId) -> bool {
        if self.get(id).is_none() {
            return false;
        }
        if !self.held.ids.contains(&id) {
            self.held.ids.push(id);
        }
        self.keep_held();
        true
    }

    /// Lets a held member be ticked again: it is woken, so the next frame in which it is
    /// due ticks it (a tree woken early ticks as a tree ticked every frame would). `false`
    /// if it was not held.
    pub fn release(&mut self, id: MemberId) -> bool {
        let Some(at) = self.held.ids.iter().position(|h| *h == id) else {
            return false;
        };
        self.held.ids.swap_remove(at);
        self.wake(id);
        true
    }

    /// `true` while member `id` is held ([`hold`](Self::hold)).
    pub fn is_held(&self, id: MemberId) -> bool {
        // A member that left is forgotten at the next frame; it is not held meanwhile.
        self.held.ids.contains(&id) && self.get(id).is_some()
    }

    /// Puts the held members back to sleep if anything woke them, and forgets those that
    /// left: called at the start of every frame, after the wakes.
    pub(super) fn keep_held(&mut self) {
        if self.held.ids.is_empty() {
            return;
        }
        let Self {
            plans,
            held,
            awake,
            timers,
            backlog,
            ..
        } = self;
        held.ids.retain(|id| {
            let slot = id.index as usize;
            let Some(plan) = plans.get_mut(slot) else {
                return false;
            };
            if !plan.present() || plan.generation != id.generation {
                return false;
            }
            if plan.sleeps_until == AWAKE {
                awake.clear(slot);
            }
            // Only a wake wakes it; its own deadline, if it had one, is forgotten: the
            // release wakes it, and its tree says again when it sleeps. Fallen asleep in the
            // last frame, it is not handled as a sleeper at the next frame's start either.
            plan.sleeps_until = u64::MAX;
            timers.forget_fallen(slot);
            plan.status = FrameStatus::Asleep;
            // A tick a budget owed it is forgotten: picked from the queue, it would take a
            // share of the budget no frame spends on it, and the queue would not hold it
            // once released.
            if plan.is_owed() || plan.picked() {
                plan.forgive();
                backlog.retain(|&s| s as usize != slot);
            }
            true
        });
    }

    /// The member in slot `slot` now, if any ([`MemberId::slot`]).
    pub fn id_at(&self, slot: usize) -> Option<MemberId> {
        let plan = self.plans.get(slot)?;
        plan.present().then_some(MemberId {
            index: slot as u32,
            generation: plan.generation,
        })
    }

    /// A number that grows each time a member joins or leaves: a program that keeps its
    /// own list of the members rebuilds it only when this changed.
    pub fn membership(&self) -> u64 {
        // Members added, plus members removed (added less present).
        2 * self.added - self.len as u64
    }

    /// Sets `observer` on member `id`'s tree (`None`: removes it), without waking the
    /// member, and gives back the observer it replaced; `None` also when `id` names no
    /// member. The other members' trees are untouched: a debugger watching one member of a
    /// crowd costs the others nothing.
    pub fn set_observer(
        &mut self,
        id: MemberId,
        observer: Option<Box<dyn Observer>>,
    ) -> Option<Box<dyn Observer>> {
        self.get(id)?;
        let body = self.bodies[id.index as usize].as_mut()?;
        match observer {
            Some(o) => body.tree.set_boxed_observer(o),
            None => body.tree.take_observer(),
        }
    }
}

#[cfg(feature = "studio")]
impl MemberId {
    /// The id as one number, its slot above its generation: ordered by slot, and naming
    /// no later member of the same slot, as a debugger that keys members by number needs.
    pub(crate) fn bits(self) -> u64 {
        (u64::from(self.index) << 32) | u64::from(self.generation)
    }
}

impl<C: Send> Crowd<C> {
    /// Member `id`'s tree, to write between frames (a blackboard entry, say); wakes it, as
    /// [`MemberMut::tree_mut`](super::MemberMut::tree_mut) does. `None` if `id` names no
    /// member.
    pub fn member_tree_mut(&mut self, id: MemberId) -> Option<&mut crate::Tree<C>> {
        self.get(id)?;
        let slot = id.index as usize;
        self.awake.wake(&mut self.plans[slot], slot);
        let body = self.bodies[slot].as_mut()?;
        body.tree.wake_up();
        Some(&mut body.tree)
    }
}
