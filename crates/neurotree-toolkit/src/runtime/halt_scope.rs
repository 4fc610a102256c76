//! Halting the trees a piece of work runs, from outside it: a server that runs a request on
//! a thread of its own (a tree to check, a scenario to run) and must stop it at a time limit
//! or when the request is cancelled, without knowing what trees the request's code makes.
//!
//! The server opens a [`HaltScope`] and [enters](HaltScope::enter) it on the thread that
//! does the work; the code that makes and ticks a tree on that thread calls [`attach`],
//! which gives the scope the tree's [`HaltHandle`]. [`HaltScope::halt`], from any thread,
//! then asks every tree attached so far to halt at its next tick boundary (between two
//! passes of `tick_once`), and every tree attached later at once: each tick call then
//! returns [`TickError::HaltRequested`](crate::TickError::HaltRequested) and the work ends
//! as on any tick error. Outside a scope, [`attach`] does nothing.
//!
//! ```
//! use neurotree_toolkit::runtime::{attach, HaltScope};
//! use neurotree_toolkit::{Blueprint, ManualClock, TickError, Tree};
//!
//! let scope = HaltScope::new();
//! let worker = {
//!     let scope = scope.clone();
//!     std::thread::spawn(move || {
//!         let _entered = scope.enter();
//!         let bp = Blueprint::<()>::builder()
//!             .repeat("forever", -1, |r| r.always_success("step"))
//!             .build_shared()
//!             .unwrap();
//!         let mut tree = Tree::with_clock(bp, ManualClock::new());
//!         attach(&mut tree);
//!         loop {
//!             if let Err(e) = tree.tick_once(&mut ()) {
//!                 return e;
//!             }
//!         }
//!     })
//! };
//! scope.halt();
//! assert_eq!(worker.join().unwrap(), TickError::HaltRequested);
//! ```

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use neurotree_core::{HaltHandle, Tree};

thread_local! {
    /// The scope the current thread works in.
    static CURRENT: RefCell<Option<HaltScope>> = const { RefCell::new(None) };
}

/// The trees a piece of work runs, to halt together from any thread. Clones share them.
#[derive(Clone, Debug, Default)]
pub struct HaltScope {
    inner: Arc<Inner>,
}

#[derive(Debug, Default)]
struct Inner {
    handles: Mutex<Vec<HaltHandle>>,
    halted: AtomicBool,
}

/// The current thread works in a scope until this is dropped ([`HaltScope::enter`]).
#[derive(Debug)]
pub struct Entered {
    previous: Option<HaltScope>,
}

impl HaltScope {
    /// A scope with no tree, not halted.
    pub fn new() -> Self {
        Self::default()
    }

    /// Makes this the scope of the current thread, until the guard is dropped.
    pub fn enter(&self) -> Entered {
        let previous = CURRENT.with(|c| c.borrow_mut().replace(self.clone()));
        Entered { previous }
    }

    /// Asks every tree attached to halt at its next tick boundary, and every tree attached
    /// from now on at once.
    pub fn halt(&self) {
        // Set before the handles are read: a tree attached meanwhile sees it.
        self.inner.halted.store(true, Ordering::SeqCst);
        let handles = self
            .inner
            .handles
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        for handle in handles.iter() {
            handle.request();
        }
    }

    /// `true` once [`halt`](Self::halt) was called.
    pub fn is_halted(&self) -> bool {
        self.inner.halted.load(Ordering::SeqCst)
    }

    fn add(&self, handle: HaltHandle) {
        let mut handles = self
            .inner
            .handles
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        if self.is_halted() {
            handle.request();
        }
        handles.push(handle);
    }
}

impl Drop for Entered {
    fn drop(&mut self) {
        let previous = self.previous.take();
        CURRENT.with(|c| *c.borrow_mut() = previous);
    }
}

/// Attaches `tree` to the current thread's [`HaltScope`], if it works in one: the scope's
/// [`halt`](HaltScope::halt) then halts it. Nothing outside a scope.
pub fn attach<C>(tree: &mut Tree<C>) {
    let scope = CURRENT.with(|c| c.borrow().clone());
    if let Some(scope) = scope {
        scope.add(tree.halt_handle());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_core::{Blueprint, ManualClock, Status, TickError};

    fn forever() -> Tree<()> {
        let bp = Blueprint::<()>::builder()
            .repeat("forever", -1, |r| r.always_success("step"))
            .build_shared()
            .unwrap();
        Tree::with_clock(bp, ManualClock::new())
    }

    #[test]
    fn a_tree_attached_after_the_halt_is_halted_at_its_first_tick() {
        let scope = HaltScope::new();
        scope.halt();
        let _entered = scope.enter();
        let mut tree = forever();
        attach(&mut tree);
        assert_eq!(tree.tick_once(&mut ()), Err(TickError::HaltRequested));
    }

    #[test]
    fn outside_a_scope_attach_does_nothing() {
        let scope = HaltScope::new();
        {
            let _entered = scope.enter();
        }
        scope.halt();
        let mut tree = forever();
        attach(&mut tree);
        tree.set_max_passes(10);
        assert!(matches!(
            tree.tick_once(&mut ()),
            Err(TickError::TooManyPasses { .. })
        ));
        let bp = Blueprint::<()>::builder()
            .always_success("done")
            .build_shared()
            .unwrap();
        let mut done = Tree::with_clock(bp, ManualClock::new());
        attach(&mut done);
        assert_eq!(done.tick_once(&mut ()), Ok(Status::Success));
    }
}
