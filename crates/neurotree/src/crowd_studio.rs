//! A [`Crowd`] in the studio: one member watched at a time, the rest running on.
//!
//! ```no_run
//! use std::sync::Arc;
//! use neurotree::crowd::Crowd;
//! use neurotree::crowd_studio::watched_frame;
//! use neurotree::prelude::*;
//! use neurotree::studio::{Studio, StudioOptions};
//!
//! let walk = Blueprint::<()>::builder()
//!     .action("walk", |_: &mut ()| Status::Running)
//!     .build_shared()?;
//! let clock = ManualClock::new();
//! let mut crowd = Crowd::new(clock.clone());
//! for _ in 0..1000 {
//!     crowd.add(Arc::clone(&walk), ());
//! }
//! let studio = Studio::serve(StudioOptions::default(), Registry::new)?;
//! eprintln!("studio: {}", studio.url());
//! let mut watch = studio.watch_crowd("walkers");
//! loop {
//!     // `None`: the page stood the whole crowd still.
//!     let _report = watched_frame(&mut crowd, &mut watch);
//!     clock.advance(std::time::Duration::from_millis(16));
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A member's id in the studio is its slot ([`MemberId::slot`]). The studio keys it by its
//! slot and generation, so that a member that takes the slot of one that left is another
//! agent to the studio: the observer and the hold it set on the one that left are not
//! thought to be on the newcomer.

use neurotree_studio::{AgentEntry, Agents, CrowdWatch};

use crate::crowd::{Crowd, FrameReport, MemberId};
use crate::{Observer, Tree};

/// The studio reaches a crowd's members by slot and generation, through the crowd's hooks for one member
/// ([`Crowd::set_observer`], [`Crowd::hold`], [`Crowd::membership`]).
impl<C: Send> Agents for Crowd<C> {
    type Context = C;

    fn membership(&self) -> u64 {
        Crowd::membership(self)
    }

    fn list(&self, out: &mut Vec<AgentEntry>) {
        out.extend(self.iter().map(|m| AgentEntry {
            key: agent_key(m.id()),
            id: m.id().slot().to_string(),
            label: String::new(),
        }));
    }

    fn tree(&self, key: u64) -> Option<&Tree<C>> {
        Some(self.get(self.id_of(key)?)?.tree())
    }

    fn tree_mut(&mut self, key: u64) -> Option<&mut Tree<C>> {
        let id = self.id_of(key)?;
        self.member_tree_mut(id)
    }

    fn set_observer(
        &mut self,
        key: u64,
        observer: Option<Box<dyn Observer>>,
    ) -> Option<Box<dyn Observer>> {
        let id = self.id_of(key)?;
        Crowd::set_observer(self, id, observer)
    }

    fn hold(&mut self, key: u64, held: bool) {
        if let Some(id) = self.id_of(key) {
            if held {
                Crowd::hold(self, id);
            } else {
                self.release(id);
            }
        }
    }
}

/// The key the studio finds member `id` by ([`AgentEntry::key`]): its slot and its
/// generation, so that a later member of the same slot has another. A program that lists
/// a crowd's members under ids of its own (the Bevy plugin, by entity) keys them so.
pub fn agent_key(id: MemberId) -> u64 {
    id.bits()
}

impl<C: Send> Crowd<C> {
    fn id_of(&self, key: u64) -> Option<MemberId> {
        let id = self.id_at(usize::try_from(key >> 32).ok()?)?;
        (id.bits() == key).then_some(id)
    }
}

/// One frame of `crowd` with `watch` around it ([`CrowdWatch::before_frame`], then
/// [`Crowd::frame`], then [`CrowdWatch::after_frame`]); `None` when the page stood the
/// whole crowd still, and no member was ticked.
pub fn watched_frame<C: Send>(crowd: &mut Crowd<C>, watch: &mut CrowdWatch) -> Option<FrameReport> {
    let go = watch.before_frame(crowd);
    let report = go.then(|| crowd.frame());
    watch.after_frame(crowd);
    report
}
