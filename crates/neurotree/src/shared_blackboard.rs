//! A blackboard shared across threads.
//!
//! A tree's own [`Blackboard`] lives in its instance and is reached through `&mut` while
//! ticking, which costs nothing. Work that runs beside the tree (a planner thread, an async
//! task, a ROS callback) needs a handle it can keep: [`SharedBlackboard`] is that handle, a
//! cloneable `Arc<RwLock<Blackboard>>` with the same typed access. Use it as the tree's
//! context, or inside your own, so that leaves and background work see the same entries.

use std::any::Any;
use std::sync::{Arc, RwLock, RwLockReadGuard, RwLockWriteGuard};
use std::time::Duration;

use neurotree_core::{Blackboard, BlackboardError, ScopeId};

/// A [`Blackboard`] behind a lock, cheap to clone and safe to send to other threads.
///
/// ```
/// use neurotree::SharedBlackboard;
///
/// let bb = SharedBlackboard::new();
/// let writer = bb.clone();
/// std::thread::spawn(move || writer.set("goal", (3.0_f64, 4.0_f64)).unwrap())
///     .join()
///     .unwrap();
/// assert_eq!(bb.get::<(f64, f64)>("goal"), Ok((3.0, 4.0)));
/// ```
#[derive(Clone, Default, Debug)]
pub struct SharedBlackboard {
    inner: Arc<RwLock<Blackboard>>,
}

impl SharedBlackboard {
    /// An empty shared blackboard.
    pub fn new() -> Self {
        Self::default()
    }

    /// Read access to the whole blackboard (all scopes).
    pub fn read(&self) -> RwLockReadGuard<'_, Blackboard> {
        // A writer that panicked left the map consistent (each write is one assignment), so
        // a poisoned lock is still safe to use.
        self.inner.read().unwrap_or_else(|e| e.into_inner())
    }

    /// Write access to the whole blackboard.
    pub fn write(&self) -> RwLockWriteGuard<'_, Blackboard> {
        self.inner.write().unwrap_or_else(|e| e.into_inner())
    }

    /// Reads a copy of `key` in the root scope.
    pub fn get<T: Any + Clone>(&self, key: &str) -> Result<T, BlackboardError> {
        self.read().get(key)
    }

    /// Writes `key` in the root scope.
    pub fn set<T: Any + Send + Sync>(&self, key: &str, value: T) -> Result<(), BlackboardError> {
        self.write().set(key, value)
    }

    /// Reads a copy of `key` as seen from `scope`.
    pub fn get_in<T: Any + Clone>(&self, scope: ScopeId, key: &str) -> Result<T, BlackboardError> {
        self.read().get_in(scope, key)
    }

    /// Writes `key` as seen from `scope`, with the given stamp.
    pub fn set_in<T: Any + Send + Sync>(
        &self,
        scope: ScopeId,
        key: &str,
        value: T,
        stamp: Duration,
    ) -> Result<(), BlackboardError> {
        self.write().set_in(scope, key, value, stamp)
    }
}

impl From<Blackboard> for SharedBlackboard {
    fn from(bb: Blackboard) -> Self {
        Self {
            inner: Arc::new(RwLock::new(bb)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_threads_see_every_write() {
        const WRITES: u64 = 1000;
        let bb = SharedBlackboard::new();
        bb.set("n", 0_u64).unwrap();
        let writer = bb.clone();
        let reader = bb.clone();
        let w = std::thread::spawn(move || {
            for i in 1..=WRITES {
                writer.set("n", i).unwrap();
            }
        });
        let r = std::thread::spawn(move || {
            // Values only grow, whatever interleaving the threads get.
            let mut last = 0;
            for _ in 0..WRITES {
                let now = reader.get::<u64>("n").unwrap();
                assert!(now >= last);
                last = now;
            }
        });
        w.join().unwrap();
        r.join().unwrap();
        assert_eq!(bb.get::<u64>("n"), Ok(WRITES));
        // One first write plus WRITES updates.
        assert_eq!(bb.read().info("n").unwrap().sequence, WRITES + 1);
    }

    #[test]
    fn a_poisoned_lock_still_works() {
        let bb = SharedBlackboard::new();
        let clone = bb.clone();
        let _ = std::thread::spawn(move || {
            let _guard = clone.write();
            panic!("a writer fails while holding the lock");
        })
        .join();
        bb.set("k", 1_u8).unwrap();
        assert_eq!(bb.get::<u8>("k"), Ok(1));
    }

    #[test]
    fn wrong_types_are_errors_across_threads_too() {
        let bb = SharedBlackboard::from(Blackboard::new());
        bb.set("k", 1_u8).unwrap();
        assert!(matches!(
            bb.get::<i64>("k"),
            Err(BlackboardError::WrongType { .. })
        ));
    }
}
