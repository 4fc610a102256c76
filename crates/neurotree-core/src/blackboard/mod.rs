//! The blackboard: typed entries that nodes share.
//!
//! A blackboard is a key-value store through which leaves exchange data (a goal pose, the
//! last sensor reading, a retry budget) without knowing about each other. Each entry holds a
//! value of one Rust type, fixed by its first write, with a sequence number that grows by one
//! on every write and the time of the last write, so that nodes can tell whether an entry
//! changed since they last looked.
//!
//! Entries live in **scopes**. The root scope belongs to the tree; every SubTree opens a child
//! scope so that its keys do not collide with the rest of the tree. A child scope reaches its
//! parent in three ways, as in BehaviorTree.CPP:
//! - a **remap** makes a child key an alias of a parent key (`goal` → `target_pose`);
//! - **autoremap** lets every key the child does not define resolve in the parent, except
//!   keys starting with `_`, which stay private to the scope;
//! - a key starting with **`@`** always addresses the root scope, from anywhere.
//!
//! Reads of a missing key or of the wrong type return a [`BlackboardError`]; nothing panics.
//! Reads never allocate, and neither does a write to an existing entry: the value is
//! replaced in place.
//!
//! ```
//! use neurotree_core::{Blackboard, BlackboardError, ScopeId};
//! use core::time::Duration;
//!
//! let mut bb = Blackboard::new();
//! bb.set("battery", 87.5_f64).unwrap();
//! assert_eq!(bb.get::<f64>("battery"), Ok(87.5));
//! assert!(matches!(bb.get::<i32>("battery"), Err(BlackboardError::WrongType { .. })));
//!
//! // A subtree scope that calls the parent's `battery` its `level`.
//! let sub = bb.add_scope(ScopeId::ROOT, false);
//! bb.remap(sub, "level", "battery");
//! bb.set_in(sub, "level", 42.0_f64, Duration::from_secs(1)).unwrap();
//! assert_eq!(bb.get::<f64>("battery"), Ok(42.0));
//! assert_eq!(bb.info("battery").unwrap().sequence, 2);
//! ```

use alloc::boxed::Box;
use alloc::collections::BTreeMap;
use alloc::string::String;
use alloc::vec::Vec;
use core::any::{type_name, Any};
use core::fmt;
use core::time::Duration;

/// Index of a scope in a [`Blackboard`]; [`ScopeId::ROOT`] is the tree's own.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct ScopeId(pub u32);

impl ScopeId {
    /// The root scope.
    pub const ROOT: ScopeId = ScopeId(0);
}

/// What is known about an entry besides its value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EntryInfo {
    /// Grows by one on every write; 1 after the first.
    pub sequence: u64,
    /// The time of the last write, as given by the writer (a node writes its tree's clock).
    pub stamp: Duration,
    /// The Rust type of the value.
    pub type_name: &'static str,
}

/// Why a blackboard access failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum BlackboardError {
    /// No entry under this key.
    #[error("no blackboard entry `{key}`: write it before reading it, or remap the key")]
    NotFound {
        /// The key as asked.
        key: String,
    },
    /// The entry holds another type.
    #[error("blackboard entry `{key}` holds a {found}, not a {expected}")]
    WrongType {
        /// The key as asked.
        key: String,
        /// The type asked for.
        expected: &'static str,
        /// The type the entry holds.
        found: &'static str,
    },
    /// The scope does not exist in this blackboard.
    #[error("blackboard scope {scope} does not exist")]
    NoSuchScope {
        /// The scope asked for.
        scope: u32,
    },
}

struct Entry {
    value: Box<dyn Any + Send + Sync>,
    info: EntryInfo,
}

#[derive(Default)]
struct Scope {
    parent: Option<ScopeId>,
    autoremap: bool,
    /// Entries by slot; a removed entry leaves `None`.
    slots: Vec<Option<Entry>>,
    /// Key → slot, sorted by key.
    index: BTreeMap<String, usize>,
    /// Child key → parent key.
    remap: BTreeMap<String, String>,
}

/// Where a key resolved.
enum Found<'a> {
    /// An existing entry: scope and slot.
    Entry(usize, usize),
    /// No entry: the scope and key under which a write would create it.
    Absent(usize, &'a str),
}

/// Where a write goes.
enum Target {
    /// An existing entry: scope and slot.
    Entry(usize, usize),
    /// A new entry: scope and key.
    New(usize, String),
}

/// Typed, scoped entries shared by the nodes of a tree (see the [module docs](self)).
#[derive(Default)]
pub struct Blackboard {
    /// Scope `i` is `scopes[i]`; the root is created on first use so `new` allocates nothing.
    scopes: Vec<Scope>,
    /// The latest stamp written, for the root-scope shorthands that take none.
    last_stamp: Duration,
}

impl Blackboard {
    /// An empty blackboard with only its root scope.
    pub const fn new() -> Self {
        Self {
            scopes: Vec::new(),
            last_stamp: Duration::ZERO,
        }
    }

    fn ensure_root(&mut self) {
        if self.scopes.is_empty() {
            self.scopes.push(Scope::default());
        }
    }

    /// Opens a child scope of `parent`; with `autoremap`, keys it does not define resolve in
    /// the parent (except `_private` ones).
    ///
    /// A parent that does not exist is taken to be the root, so that every scope's parent is
    /// an earlier scope and key resolution always ends.
    pub fn add_scope(&mut self, parent: ScopeId, autoremap: bool) -> ScopeId {
        self.ensure_root();
        let parent = if (parent.0 as usize) < self.scopes.len() {
            parent
        } else {
            ScopeId::ROOT
        };
        self.scopes.push(Scope {
            parent: Some(parent),
            autoremap,
            ..Scope::default()
        });
        ScopeId(self.scopes.len() as u32 - 1)
    }

    /// In `scope`, makes `child_key` an alias of `parent_key` in the parent scope (which may
    /// itself remap it further; `@key` targets the root). The root scope has no parent, so
    /// remapping it does nothing.
    pub fn remap(&mut self, scope: ScopeId, child_key: &str, parent_key: &str) {
        if let Some(s) = self.scopes.get_mut(scope.0 as usize) {
            if s.parent.is_some() {
                s.remap
                    .insert(String::from(child_key), String::from(parent_key));
            }
        }
    }

    /// The parent of a scope; `None` for the root or an unknown scope.
    pub fn parent(&self, scope: ScopeId) -> Option<ScopeId> {
        self.scopes.get(scope.0 as usize).and_then(|s| s.parent)
    }

    /// Number of scopes, the root included.
    pub fn scope_count(&self) -> usize {
        self.scopes.len().max(1)
    }

    /// Follows `@`, remaps and autoremap from `scope` to where `key` lives, or to where a
    /// write would create it.
    fn resolve<'a>(&'a self, scope: ScopeId, key: &'a str) -> Result<Found<'a>, BlackboardError> {
        if scope != ScopeId::ROOT && scope.0 as usize >= self.scopes.len() {
            return Err(BlackboardError::NoSuchScope { scope: scope.0 });
        }
        let (mut at, mut key) = match key.strip_prefix('@') {
            Some(rooted) => (0, rooted),
            None => (scope.0 as usize, key),
        };
        // Every step moves to an earlier scope (see `add_scope`), so this ends.
        loop {
            let Some(s) = self.scopes.get(at) else {
                // Only the lazily created root can be missing.
                return Ok(Found::Absent(0, key));
            };
            if let Some(target) = s.remap.get(key) {
                match target.strip_prefix('@') {
                    Some(rooted) => {
                        at = 0;
                        key = rooted;
                    }
                    // A scope with a remap has a parent: `remap` skips the root.
                    None => {
                        at = s.parent.map_or(0, |p| p.0 as usize);
                        key = target;
                    }
                }
                continue;
            }
            if let Some(&slot) = s.index.get(key) {
                return Ok(Found::Entry(at, slot));
            }
            match s.parent {
                Some(p) if s.autoremap && !key.starts_with('_') => at = p.0 as usize,
                _ => return Ok(Found::Absent(at, key)),
            }
        }
    }

    /// `resolve` for a write: the key's name is owned, so that the blackboard can then be
    /// changed (only a first write, which creates the entry, allocates).
    fn resolve_for_write(&self, scope: ScopeId, key: &str) -> Result<Target, BlackboardError> {
        Ok(match self.resolve(scope, key)? {
            Found::Entry(s, slot) => Target::Entry(s, slot),
            Found::Absent(s, name) => Target::New(s, String::from(name)),
        })
    }

    fn entry_in(&self, scope: ScopeId, key: &str) -> Result<&Entry, BlackboardError> {
        match self.resolve(scope, key)? {
            Found::Entry(s, slot) => self.scopes[s].slots[slot]
                .as_ref()
                .ok_or_else(|| not_found(key)),
            Found::Absent(..) => Err(not_found(key)),
        }
    }

    /// Reads a copy of `key` as seen from `scope`.
    pub fn get_in<T: Any + Clone>(&self, scope: ScopeId, key: &str) -> Result<T, BlackboardError> {
        self.get_ref_in::<T>(scope, key).cloned()
    }

    /// Borrows `key` as seen from `scope`.
    pub fn get_ref_in<T: Any>(&self, scope: ScopeId, key: &str) -> Result<&T, BlackboardError> {
        let entry = self.entry_in(scope, key)?;
        entry
            .value
            .downcast_ref::<T>()
            .ok_or_else(|| BlackboardError::WrongType {
                key: String::from(key),
                expected: type_name::<T>(),
                found: entry.info.type_name,
            })
    }

    /// Borrows `key` as seen from `scope`, whatever its type.
    pub fn get_any_in(&self, scope: ScopeId, key: &str) -> Option<&(dyn Any + Send + Sync)> {
        self.entry_in(scope, key).ok().map(|e| &*e.value)
    }

    /// Writes `key` as seen from `scope` (a remapped key writes the parent's entry).
    ///
    /// An existing entry of the same type is overwritten in place, without allocating; an
    /// entry of another type is left alone and [`BlackboardError::WrongType`] returned, since
    /// an entry's type is fixed by its first write. Every write bumps the entry's sequence
    /// number and sets its stamp.
    pub fn set_in<T: Any + Send + Sync>(
        &mut self,
        scope: ScopeId,
        key: &str,
        value: T,
        stamp: Duration,
    ) -> Result<(), BlackboardError> {
        let found = self.resolve_for_write(scope, key)?;
        self.last_stamp = self.last_stamp.max(stamp);
        match found {
            Target::Entry(s, slot) => {
                let Some(entry) = self.scopes[s].slots[slot].as_mut() else {
                    return Err(not_found(key));
                };
                match entry.value.downcast_mut::<T>() {
                    Some(v) => {
                        *v = value;
                        entry.info.sequence += 1;
                        entry.info.stamp = stamp;
                        Ok(())
                    }
                    None => Err(BlackboardError::WrongType {
                        key: String::from(key),
                        expected: type_name::<T>(),
                        found: entry.info.type_name,
                    }),
                }
            }
            Target::New(s, name) => {
                self.insert(s, name, Box::new(value), type_name::<T>(), 1, stamp);
                Ok(())
            }
        }
    }

    /// Writes `key` as seen from `scope` whatever the type it held, e.g. to turn a text
    /// literal into the type a port declares. The sequence number still grows by one.
    pub fn replace_in<T: Any + Send + Sync>(
        &mut self,
        scope: ScopeId,
        key: &str,
        value: T,
        stamp: Duration,
    ) {
        let Ok(found) = self.resolve_for_write(scope, key) else {
            return;
        };
        self.last_stamp = self.last_stamp.max(stamp);
        match found {
            Target::Entry(s, slot) => {
                if let Some(entry) = self.scopes[s].slots[slot].as_mut() {
                    entry.value = Box::new(value);
                    entry.info.type_name = type_name::<T>();
                    entry.info.sequence += 1;
                    entry.info.stamp = stamp;
                }
            }
            Target::New(s, name) => {
                self.insert(s, name, Box::new(value), type_name::<T>(), 1, stamp)
            }
        }
    }

    fn insert(
        &mut self,
        scope: usize,
        key: String,
        value: Box<dyn Any + Send + Sync>,
        type_name: &'static str,
        sequence: u64,
        stamp: Duration,
    ) {
        self.ensure_root();
        let s = &mut self.scopes[scope];
        let info = EntryInfo {
            sequence,
            stamp,
            type_name,
        };
        s.index.insert(key, s.slots.len());
        s.slots.push(Some(Entry { value, info }));
    }

    /// Removes `key` as seen from `scope`; `true` if there was an entry.
    pub fn unset_in(&mut self, scope: ScopeId, key: &str) -> bool {
        let Ok(Found::Entry(s, slot)) = self.resolve(scope, key) else {
            return false;
        };
        let scope = &mut self.scopes[s];
        scope.slots[slot] = None;
        scope.index.retain(|_, v| *v != slot);
        true
    }

    /// `true` if `key` resolves to an entry from `scope`.
    pub fn contains_in(&self, scope: ScopeId, key: &str) -> bool {
        self.entry_in(scope, key).is_ok()
    }

    /// Sequence number, stamp and type of `key` as seen from `scope`.
    pub fn info_in(&self, scope: ScopeId, key: &str) -> Option<EntryInfo> {
        self.entry_in(scope, key).ok().map(|e| e.info)
    }

    /// The keys stored in `scope` itself (not those it remaps), sorted.
    pub fn keys_in(&self, scope: ScopeId) -> impl Iterator<Item = &str> + '_ {
        self.scopes
            .get(scope.0 as usize)
            .into_iter()
            .flat_map(|s| s.index.keys().map(String::as_str))
    }

    /// Reads a copy of `key` in the root scope.
    pub fn get<T: Any + Clone>(&self, key: &str) -> Result<T, BlackboardError> {
        self.get_in(ScopeId::ROOT, key)
    }

    /// Borrows `key` in the root scope.
    pub fn get_ref<T: Any>(&self, key: &str) -> Result<&T, BlackboardError> {
        self.get_ref_in(ScopeId::ROOT, key)
    }

    /// Writes `key` in the root scope, stamped with the latest stamp this blackboard saw
    /// (trees stamp their writes with their clock; use [`set_in`](Self::set_in) to choose).
    pub fn set<T: Any + Send + Sync>(
        &mut self,
        key: &str,
        value: T,
    ) -> Result<(), BlackboardError> {
        let stamp = self.last_stamp;
        self.set_in(ScopeId::ROOT, key, value, stamp)
    }

    /// Removes `key` from the root scope; `true` if there was an entry.
    pub fn unset(&mut self, key: &str) -> bool {
        self.unset_in(ScopeId::ROOT, key)
    }

    /// `true` if the root scope has `key`.
    pub fn contains(&self, key: &str) -> bool {
        self.contains_in(ScopeId::ROOT, key)
    }

    /// Sequence number, stamp and type of `key` in the root scope.
    pub fn info(&self, key: &str) -> Option<EntryInfo> {
        self.info_in(ScopeId::ROOT, key)
    }

    /// The root scope's keys, sorted.
    pub fn keys(&self) -> impl Iterator<Item = &str> + '_ {
        self.keys_in(ScopeId::ROOT)
    }

    /// Removes every entry of every scope; scopes and remaps stay.
    pub fn clear(&mut self) {
        for s in &mut self.scopes {
            s.slots.clear();
            s.index.clear();
        }
    }
}

fn not_found(key: &str) -> BlackboardError {
    BlackboardError::NotFound {
        key: String::from(key),
    }
}

impl fmt::Debug for Blackboard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut map = f.debug_map();
        for (i, s) in self.scopes.iter().enumerate() {
            for (key, &slot) in &s.index {
                if let Some(e) = &s.slots[slot] {
                    map.entry(
                        &format_args!("{i}:{key}"),
                        &format_args!("{} #{}", e.info.type_name, e.info.sequence),
                    );
                }
            }
        }
        map.finish()
    }
}

#[cfg(test)]
mod tests;
