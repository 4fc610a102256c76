//! The fields of a [`Tree`] that few trees set (an observer, a wake signal, a pass bound of
//! their own, a reload in progress), kept in one box made on first use, so that the many
//! trees of a crowd pay one pointer for all of them; and the methods that reach them.

use alloc::boxed::Box;

use super::{reload, HaltHandle, Tree, TreeWake, WakeSignal, DEFAULT_MAX_PASSES};
use crate::observer::Observer;

/// The fields of a [`Tree`] that few trees set.
pub(super) struct Rare<C> {
    pub(super) observer: Option<Box<dyn Observer>>,
    /// Made when the blueprint has async actions, or when a runner asks for the signal.
    pub(super) wake: Option<Box<TreeWake>>,
    /// The most passes one [`Tree::tick_once`] makes.
    pub(super) max_passes: u32,
    /// A reload that waits for the halts it started (see [`Tree::reload`]).
    pub(super) pending_reload: Option<Box<reload::Pending<C>>>,
}

impl<C> Rare<C> {
    pub(super) fn new() -> Self {
        Self {
            observer: None,
            wake: None,
            max_passes: DEFAULT_MAX_PASSES,
            pending_reload: None,
        }
    }
}

impl<C> Tree<C> {
    /// Attaches an observer, returning the one it replaces.
    pub fn set_observer(&mut self, observer: impl Observer + 'static) -> Option<Box<dyn Observer>> {
        self.set_boxed_observer(Box::new(observer))
    }

    /// Attaches an observer already boxed (one given back by [`set_observer`](Self::set_observer)
    /// or [`take_observer`](Self::take_observer), say), returning the one it replaces.
    pub fn set_boxed_observer(&mut self, observer: Box<dyn Observer>) -> Option<Box<dyn Observer>> {
        self.rare_mut().observer.replace(observer)
    }

    /// Detaches the observer.
    pub fn take_observer(&mut self) -> Option<Box<dyn Observer>> {
        self.rare.as_deref_mut()?.observer.take()
    }

    /// The attached observer.
    pub fn observer_mut(&mut self) -> Option<&mut (dyn Observer + 'static)> {
        self.rare.as_deref_mut()?.observer.as_deref_mut()
    }

    /// The attached observer, to read.
    #[inline]
    pub(super) fn observer(&self) -> Option<&dyn Observer> {
        self.rare.as_deref()?.observer.as_deref()
    }

    /// The rare fields, made now if the tree had none.
    pub(super) fn rare_mut(&mut self) -> &mut Rare<C> {
        self.rare.get_or_insert_with(|| Box::new(Rare::new()))
    }

    /// The tree's wake signal and waker, if it has them.
    #[inline]
    pub(super) fn wake(&self) -> Option<&TreeWake> {
        self.rare.as_deref()?.wake.as_deref()
    }

    /// The signal the futures of the tree's async actions set when they wake, for a runner
    /// that ticks early on a wake rather than waiting for its next period. Made on first
    /// use when the blueprint has no async action (such a tree never sets it).
    pub fn wake_signal(&mut self) -> &WakeSignal {
        &self
            .rare_mut()
            .wake
            .get_or_insert_with(|| Box::new(TreeWake::new()))
            .signal
    }

    /// A handle that asks this tree to halt at its next tick boundary, from any thread (see
    /// [`halt`](super::halt)). The first call makes the tree's [`WakeSignal`] if it had none; a tree that
    /// never makes a handle pays one branch per tick call for the feature.
    pub fn halt_handle(&mut self) -> HaltHandle {
        let wake = self
            .rare_mut()
            .wake
            .get_or_insert_with(|| Box::new(TreeWake::new()));
        wake.halt_handle = true;
        HaltHandle::new(wake.signal.clone())
    }

    /// `true` if the tree has a [`HaltHandle`]; its waits between ticks then watch for
    /// requests (see [`HALT_POLL_PERIOD`](super::HALT_POLL_PERIOD)).
    pub fn has_halt_handle(&self) -> bool {
        self.wake().is_some_and(|w| w.halt_handle)
    }

    /// Sets the most passes one [`tick_once`](Self::tick_once) makes (at least 1).
    pub fn set_max_passes(&mut self, passes: u32) {
        let passes = passes.max(1);
        if passes != DEFAULT_MAX_PASSES || self.rare.is_some() {
            self.rare_mut().max_passes = passes;
        }
    }

    /// The most passes one [`tick_once`](Self::tick_once) makes.
    pub(super) fn max_passes(&self) -> u32 {
        self.rare
            .as_deref()
            .map_or(DEFAULT_MAX_PASSES, |r| r.max_passes)
    }
}
