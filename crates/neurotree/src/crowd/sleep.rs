//! Sleeping members: a member whose tree [sleeps](crate::tree::sleep) is skipped by the
//! frames until it wakes, without its tree or its context being touched.
//!
//! After each tick the member's schedule ([`Plan`](super::member::Plan)) keeps when its
//! tree wakes on its own (the earliest deadline its nodes declared), so a frame reads that
//! one number, next to the interval it reads anyway, and goes on. A sleeping member wakes
//! when the crowd's clock reaches its deadline, or earlier when:
//!
//! - the program changes its tree between frames ([`MemberMut::tree_mut`] and
//!   [`MemberMut::tree_and_context_mut`] wake it, since the blackboard may be written);
//! - the program wakes it: [`MemberMut::wake`], [`Crowd::wake`], or from any thread a
//!   [`CrowdWaker`], whose wakes the next frame applies.
//!
//! A tree's own [`WakeHandle`](crate::WakeHandle) is not seen by a crowd until the member
//! is ticked again: in a crowd, wake members through the crowd. Writing a member's context
//! does not wake it: a leaf that declared what it waits on promised that its result does
//! not depend on anything else.
//!
//! [`MemberMut::tree_mut`]: super::MemberMut::tree_mut
//! [`MemberMut::tree_and_context_mut`]: super::MemberMut::tree_and_context_mut
//! [`MemberMut::wake`]: super::MemberMut::wake

use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use super::{Crowd, MemberId};
use crate::Tree;

/// `Plan::sleeps_until` of a member that is awake.
pub(super) const AWAKE: u64 = 0;

/// When a member whose tree was just ticked wakes: [`AWAKE`] if its tree is awake, the
/// clock reading in nanoseconds of its earliest deadline, `u64::MAX` if it waits only for
/// a wake.
pub(super) fn sleeps_until<C>(tree: &Tree<C>) -> u64 {
    if !tree.is_asleep() {
        return AWAKE;
    }
    tree.wakes_at().map_or(u64::MAX, nanos).max(1)
}

/// A clock reading in nanoseconds.
pub(super) fn nanos(d: Duration) -> u64 {
    u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)
}

/// Wakes members of a crowd from any thread: the next frame ticks them whatever they wait
/// on. Clones share one queue.
#[derive(Clone, Debug, Default)]
pub struct CrowdWaker {
    queue: Arc<Mutex<Vec<MemberId>>>,
}

impl CrowdWaker {
    /// Wakes member `id` at the start of the crowd's next frame (nothing if it has left).
    pub fn wake(&self, id: MemberId) {
        self.queue
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(id);
    }
}

impl<C: Send> Crowd<C> {
    /// A waker for this crowd's members, to hand to other threads or event handlers.
    pub fn waker(&self) -> CrowdWaker {
        self.waker.clone()
    }

    /// Wakes member `id`: its next due frame ticks it. `false` if `id` names no member.
    pub fn wake(&mut self, id: MemberId) -> bool {
        match self.get_mut(id) {
            Some(mut member) => {
                member.wake();
                true
            }
            None => false,
        }
    }

    /// Members whose tree sleeps now.
    pub fn asleep(&self) -> usize {
        self.plans
            .iter()
            .filter(|p| p.present && p.sleeps_until != AWAKE)
            .count()
    }

    /// Applies the wakes queued through [`CrowdWaker`]s; the clock reading the frame
    /// compares the members' deadlines with.
    pub(super) fn start_sleep_frame(&mut self) -> u64 {
        let woken = std::mem::take(
            &mut *self
                .waker
                .queue
                .lock()
                .unwrap_or_else(PoisonError::into_inner),
        );
        for id in woken {
            self.wake(id);
        }
        nanos(self.clock.now())
    }
}
