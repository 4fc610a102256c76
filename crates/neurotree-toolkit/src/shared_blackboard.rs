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

use neurotree_core::{Blackboard, BlackboardError, EntryInfo, ScopeId};

/// A [`Blackboard`] behind a lock, cheap to clone and safe to send to other threads. Every
/// clone is a handle to the same entries.
///
/// Each method takes the lock for one operation; to read or write several entries as one
/// consistent step, hold a guard from [`read`](Self::read) or [`write`](Self::write).
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
/// assert_eq!(bb.info("goal").map(|i| i.sequence), Some(1));
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

    /// Read access to the whole blackboard (all scopes), held until the guard is dropped.
    pub fn read(&self) -> RwLockReadGuard<'_, Blackboard> {
        // No blackboard operation can be interrupted half-way by a panic, so the data behind
        // a lock poisoned by a panicking holder is still a valid blackboard: keep going
        // rather than spreading the panic to every other thread.
        self.inner.read().unwrap_or_else(|e| e.into_inner())
    }

    /// Write access to the whole blackboard, held until the guard is dropped.
    pub fn write(&self) -> RwLockWriteGuard<'_, Blackboard> {
        self.inner.write().unwrap_or_else(|e| e.into_inner())
    }

    /// Reads a copy of `key` in the root scope, numbers, `bool` and text converted as ports
    /// convert them (see [`Blackboard::get_in`]).
    pub fn get<T: Any + Clone>(&self, key: &str) -> Result<T, BlackboardError> {
        self.read().get(key)
    }

    /// Reads a copy of `key` in the root scope only if it holds a `T` exactly (see
    /// [`Blackboard::get_exact`]).
    pub fn get_exact<T: Any + Clone>(&self, key: &str) -> Result<T, BlackboardError> {
        self.read().get_exact(key)
    }

    /// Writes `key` in the root scope (see [`Blackboard::set`]).
    pub fn set<T: Any + Send + Sync>(&self, key: &str, value: T) -> Result<(), BlackboardError> {
        self.write().set(key, value)
    }

    /// Reads a copy of `key` as seen from `scope`, converted as [`Blackboard::get_in`]
    /// converts.
    pub fn get_in<T: Any + Clone>(&self, scope: ScopeId, key: &str) -> Result<T, BlackboardError> {
        self.read().get_in(scope, key)
    }

    /// Reads a copy of `key` as seen from `scope` only if it holds a `T` exactly.
    pub fn get_exact_in<T: Any + Clone>(
        &self,
        scope: ScopeId,
        key: &str,
    ) -> Result<T, BlackboardError> {
        self.read().get_exact_in(scope, key)
    }

    /// Writes `key` as seen from `scope`, with the given stamp (see [`Blackboard::set_in`]).
    pub fn set_in<T: Any + Send + Sync>(
        &self,
        scope: ScopeId,
        key: &str,
        value: T,
        stamp: Duration,
    ) -> Result<(), BlackboardError> {
        self.write().set_in(scope, key, value, stamp)
    }

    /// Sequence number, stamp and type of `key` in the root scope: compare sequence numbers
    /// to tell whether another thread wrote the entry since you last looked.
    pub fn info(&self, key: &str) -> Option<EntryInfo> {
        self.read().info(key)
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
    fn handles_can_be_sent_and_shared() {
        fn send_sync<T: Send + Sync + 'static>() {}
        send_sync::<SharedBlackboard>();
    }

    #[test]
    fn a_reader_thread_sees_every_write_of_a_writer_thread_in_order() {
        const WRITES: u64 = 2000;
        let bb = SharedBlackboard::new();
        let writer = bb.clone();
        let reader = bb.clone();
        let w = std::thread::spawn(move || {
            for i in 1..=WRITES {
                writer.set("n", i).unwrap();
            }
        });
        let r = std::thread::spawn(move || {
            let mut last = 0;
            let mut looks = 0_u64;
            while last < WRITES {
                let guard = reader.read();
                match guard.get::<u64>("n") {
                    Ok(now) => {
                        // Value and sequence number change under the same lock, so the
                        // i-th write is seen whole: value i, sequence i.
                        assert_eq!(guard.info("n").map(|i| i.sequence), Some(now));
                        assert!(now >= last, "went back from {last} to {now}");
                        last = now;
                    }
                    Err(e) => assert_eq!(e, BlackboardError::NotFound { key: "n".into() }),
                }
                drop(guard);
                looks += 1;
                if looks.is_multiple_of(64) {
                    std::thread::yield_now();
                }
            }
            last
        });
        w.join().unwrap();
        assert_eq!(r.join().unwrap(), WRITES);
        assert_eq!(bb.get::<u64>("n"), Ok(WRITES));
        assert_eq!(bb.info("n").map(|i| i.sequence), Some(WRITES));
    }

    #[test]
    fn a_poisoned_lock_still_works() {
        let bb = SharedBlackboard::new();
        bb.set("k", 1_u8).unwrap();
        let clone = bb.clone();
        let panicked = std::thread::spawn(move || {
            let mut guard = clone.write();
            guard.set("k", 2_u8).unwrap();
            panic!("a writer fails while holding the lock");
        })
        .join();
        assert!(panicked.is_err());
        assert!(bb.inner.is_poisoned());
        assert_eq!(bb.get::<u8>("k"), Ok(2));
        bb.set("k", 3_u8).unwrap();
        assert_eq!(bb.get::<u8>("k"), Ok(3));
        assert_eq!(bb.info("k").map(|i| i.sequence), Some(3));
    }

    #[test]
    fn scoped_access_goes_through_the_handle() {
        let mut inner = Blackboard::new();
        let sub = inner.add_scope(ScopeId::ROOT, false);
        inner.remap(sub, "goal", "target");
        let bb = SharedBlackboard::from(inner);
        bb.set_in(sub, "goal", 5_i32, Duration::from_secs(2))
            .unwrap();
        assert_eq!(bb.get::<i32>("target"), Ok(5));
        assert_eq!(bb.get_in::<i32>(sub, "goal"), Ok(5));
        assert_eq!(
            bb.info("target").map(|i| i.stamp),
            Some(Duration::from_secs(2))
        );
        // The ordinary read converts the number; the exact one does not.
        assert_eq!(bb.get::<i64>("target"), Ok(5));
        assert_eq!(
            bb.get_exact::<i64>("target"),
            Err(BlackboardError::WrongType {
                key: "target".into(),
                expected: "i64",
                found: "i32",
            })
        );
        assert_eq!(
            bb.get_in::<i32>(ScopeId(9), "goal"),
            Err(BlackboardError::NoSuchScope { scope: 9 })
        );
    }
}
