//! The blackboard: typed entries that the nodes of a tree share.
//!
//! Behaviors in a tree should not know about each other, yet they must exchange data: a
//! detector finds an object, a planner turns it into a goal pose, a navigator drives there.
//! The blackboard is the shared notebook through which they do it. A node writes an entry
//! under a key; any node that knows the key reads it. In BehaviorTree.CPP XML, the ports of a
//! node name these keys (`goal="{target_pose}"`), so a tree wires its leaves together
//! without any of them changing.
//!
//! # Entries
//!
//! An entry holds one Rust value. Its type is fixed by its first write: writing a value of
//! another type later is an error ([`BlackboardError::WrongType`]), as is reading it as
//! another type, so a typo in a port cannot silently turn a pose into a string. Numbers,
//! `bool` and text are the exception on reads: [`get`](Blackboard::get) converts them as an
//! input port does (a script's `i64` reads as the `i32` asked for, when it fits; a value
//! that does not fit is [`BlackboardError::NotConvertible`]), and
//! [`get_exact`](Blackboard::get_exact) reads only the type stored. (Loaders that
//! must retype an entry, for example to turn a text literal into the type a port declares,
//! use [`Blackboard::replace_in`].) The exception is an entry a script created
//! ([`Blackboard::set_untyped_in`]): as in BehaviorTree.CPP, no port declared its type, so a
//! later assignment may give it a value of another type.
//!
//! Each entry also carries an [`EntryInfo`]: a sequence number that grows by exactly one on
//! every write, and the time stamp of the last write. Nodes such as `WasEntryUpdated` and
//! `WaitValueUpdate` compare sequence numbers to tell whether anything was written since they
//! last looked, even when the same value was written again.
//!
//! # Scopes and remapping
//!
//! Entries live in **scopes**. The root scope ([`ScopeId::ROOT`]) belongs to the tree; each
//! SubTree opens a child scope so that its keys do not collide with those of the rest of the
//! tree, the way a function's locals do not collide with its caller's. A child scope reaches
//! its parent in three ways, as in BehaviorTree.CPP:
//!
//! - a **remap** makes a child key an alias of a parent key: with `goal` remapped to
//!   `target_pose`, the subtree reads and writes the parent's `target_pose` when it says
//!   `goal`. The parent may itself remap that key further up.
//! - **autoremap** makes every key the child does not store itself resolve in the parent,
//!   except keys starting with `_`, which stay private to the scope. A write of a key that
//!   exists nowhere creates it as high as autoremap reaches, so that child and parent share it.
//! - a key starting with **`@`** always addresses the root scope, from any depth: `@battery`
//!   is the root's `battery`.
//!
//! # Costs and failures
//!
//! Reads never allocate, and neither does a write to an existing entry of the same type: the
//! value is replaced in place. Only the first write of a key may allocate: room for one more
//! entry in its scope, a key longer than 23 bytes, a value not held inline (see below). A
//! missing key, a wrong type or an unknown scope is a [`BlackboardError`]; nothing panics.
//! Building the error allocates its key, so code that probes for an entry on every tick
//! should use [`contains_in`](Blackboard::contains_in) or [`info_in`](Blackboard::info_in),
//! which never do.
//!
//! # Layout
//!
//! A crowd ticks up to a million trees a frame, each a few reads and writes of its root
//! scope, and each on memory no cache holds: a read pays every block it goes through, one
//! trip to memory after another. The layout keeps that chain short. The [`Blackboard`]
//! (32 bytes, inside its tree) holds the root scope's entries itself, a thin vector (one
//! pointer, its length at the head of its block) sorted by key whose entries carry their
//! keys; a value of a small plain type (`bool`, the integers up to
//! 64 bits, `f32`, `f64`, [`Duration`]) sits in its entry, and only other types are boxed.
//! Reading the root's `bool` thus goes from the tree to the entries' block and no further.
//! What a plain tree does not use (the scopes SubTrees open, their links and entries, the
//! value codecs) waits behind one pointer, made on first use. How a value is held shows
//! nowhere in the API: [`get_any_in`](Blackboard::get_any_in) lends a `&dyn Any` to an
//! inline value as to a boxed one.
//!
//! # Example
//!
//! ```
//! use core::time::Duration;
//! use neurotree_core::{Blackboard, BlackboardError, ScopeId};
//!
//! let mut bb = Blackboard::new();
//! bb.set("battery", 87.5_f64).unwrap();
//! assert_eq!(bb.get::<f64>("battery"), Ok(87.5));
//! // Numbers convert as ports convert them, and never lose anything on the way.
//! bb.set("laps", 3_i64).unwrap();
//! assert_eq!(bb.get::<i32>("laps"), Ok(3));
//! assert!(matches!(
//!     bb.get::<i32>("battery"),
//!     Err(BlackboardError::NotConvertible { .. })
//! ));
//! assert_eq!(
//!     bb.get_exact::<i32>("laps"),
//!     Err(BlackboardError::WrongType {
//!         key: "laps".into(),
//!         expected: "i32",
//!         found: "i64",
//!     })
//! );
//!
//! // A subtree scope that calls the root's `battery` its `level`.
//! let sub = bb.add_scope(ScopeId::ROOT, false);
//! bb.remap(sub, "level", "battery");
//! bb.set_in(sub, "level", 42.0_f64, Duration::from_secs(1)).unwrap();
//! assert_eq!(bb.get::<f64>("battery"), Ok(42.0));
//! assert_eq!(bb.info("battery").unwrap().sequence, 2);
//!
//! // `@` reaches the root from anywhere; other keys stay in the subtree.
//! bb.set_in(sub, "@mode", "docking", Duration::from_secs(2)).unwrap();
//! bb.set_in(sub, "retries", 3_u8, Duration::from_secs(2)).unwrap();
//! assert_eq!(bb.get::<&str>("mode"), Ok("docking"));
//! assert!(!bb.contains("retries"));
//! assert_eq!(bb.keys().collect::<Vec<_>>(), ["battery", "laps", "mode"]);
//! ```

mod entries;
mod entry;
mod error;
mod json;
mod rare;
mod raw;
mod scope;

use crate::blueprint::FromPortStr;
use crate::clock::duration_to_nanos;
use alloc::boxed::Box;
use alloc::collections::BTreeMap;
use alloc::string::String;
use core::any::{type_name, Any, TypeId};
use core::fmt;
use core::time::Duration;

use entry::Entry;
pub use error::BlackboardError;
pub use json::{short_type_name, JsonWriteError};
use rare::Rare;
use scope::{Entries, Links};

/// Index of a scope in a [`Blackboard`], in creation order; [`ScopeId::ROOT`] is the tree's
/// own.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct ScopeId(pub u32);

impl ScopeId {
    /// The root scope, which every blackboard has.
    pub const ROOT: ScopeId = ScopeId(0);
}

/// What is known about an entry besides its value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EntryInfo {
    /// Grows by one on every write; 1 after the first.
    pub sequence: u64,
    /// The time of the last write, as given by the writer (a node writes its tree's clock),
    /// to the nanosecond; a stamp past `u64::MAX` nanoseconds (584 years) is kept as that.
    pub stamp: Duration,
    /// The Rust type of the value, as [`core::any::type_name`] spells it.
    pub type_name: &'static str,
}

/// Typed, scoped entries shared by the nodes of a tree (see the [module docs](self)).
///
/// 32 bytes, laid out for the tree that reads its root scope's entries and little else:
/// those entries are held here, so reading one goes from this struct to the entries' block
/// and no further; the rest waits behind one pointer.
#[derive(Default)]
pub struct Blackboard {
    /// The root scope's entries: an empty vector until the first write, so that `new`
    /// allocates nothing and a tree that never writes its blackboard never pays for it.
    root: Entries,
    /// The other scopes, their links and the value codecs: made on first use.
    rare: Option<Box<Rare>>,
    /// The latest stamp written, in nanoseconds (saturating), for the shorthands that take
    /// none.
    last_stamp: u64,
    /// Writes so far (see [`writes`](Self::writes)).
    writes: u64,
}

impl Blackboard {
    /// An empty blackboard with only its root scope. Allocates nothing.
    pub const fn new() -> Self {
        Self {
            root: Entries::new(),
            rare: None,
            last_stamp: 0,
            writes: 0,
        }
    }

    /// Records `stamp` as written, for the shorthands that take none.
    #[inline]
    fn saw(&mut self, stamp: Duration) {
        self.last_stamp = self.last_stamp.max(duration_to_nanos(stamp));
    }

    /// How many times the blackboard was written (a value set, changed, removed, a key
    /// remapped), wrapping: a sleeping tree compares it to wake on any write.
    #[inline]
    pub fn writes(&self) -> u64 {
        self.writes
    }

    /// Opens a child scope of `parent` and returns it; with `autoremap`, keys the child does
    /// not store resolve in the parent (except `_private` ones).
    ///
    /// A parent that does not exist is taken to be the root. Every scope's parent is thus an
    /// earlier scope, which is what guarantees that resolving a key always ends.
    pub fn add_scope(&mut self, parent: ScopeId, autoremap: bool) -> ScopeId {
        let links = &mut self.rare_mut().links;
        let parent = if parent.0 as usize <= links.len() {
            parent
        } else {
            ScopeId::ROOT
        };
        links.push(Links {
            parent,
            autoremap,
            remap: BTreeMap::new(),
        });
        ScopeId(u32::try_from(links.len()).unwrap_or(u32::MAX))
    }

    /// In `scope`, makes `child_key` an alias of `parent_key` in the parent scope. The parent
    /// may remap that key further; a `parent_key` starting with `@` names a root key.
    ///
    /// Remapping a key again replaces its target. The root (which has no parent) and unknown
    /// scopes are left unchanged.
    pub fn remap(&mut self, scope: ScopeId, child_key: &str, parent_key: &str) {
        self.writes = self.writes.wrapping_add(1);
        let Some(i) = (scope.0 as usize).checked_sub(1) else {
            return;
        };
        let links = self.rare.as_deref_mut().map(|r| &mut r.links);
        if let Some(l) = links.and_then(|l| l.get_mut(i)) {
            l.remap
                .insert(String::from(child_key), String::from(parent_key));
        }
    }

    /// The parent of a scope; `None` for the root or an unknown scope.
    pub fn parent(&self, scope: ScopeId) -> Option<ScopeId> {
        let i = (scope.0 as usize).checked_sub(1)?;
        self.links().get(i).map(|l| l.parent)
    }

    /// Number of scopes, the root included.
    pub fn scope_count(&self) -> usize {
        self.links().len() + 1
    }

    /// The entry `key` resolves to from `scope`, if any.
    #[inline]
    fn entry(&self, scope: ScopeId, key: &str) -> Option<&Entry> {
        let (s, k) = self.resolve(scope, key)?;
        self.entries_at(s)?.get(k)
    }

    /// Asks the processor to start loading the root scope's entries, whose address sits in
    /// this struct (see [`hint`](crate::hint)): with the inline values, all that reading a
    /// root entry of a small plain type touches beyond the tree itself.
    #[inline]
    pub(crate) fn prefetch(&self) {
        self.root.prefetch();
    }

    /// [`entry`](Self::entry), with the reason when there is none.
    #[inline]
    fn entry_or_err(&self, scope: ScopeId, key: &str) -> Result<&Entry, BlackboardError> {
        self.entry(scope, key)
            .ok_or_else(|| self.missing(scope, key))
    }

    #[cold]
    fn missing(&self, scope: ScopeId, key: &str) -> BlackboardError {
        if scope.0 as usize > self.links().len() {
            BlackboardError::NoSuchScope { scope: scope.0 }
        } else {
            BlackboardError::NotFound {
                key: String::from(key),
            }
        }
    }

    /// Declares `key` as seen from `scope` without writing it, as BehaviorTree.CPP does for
    /// every entry a port names: the entry then exists (for [`contains_in`](Self::contains_in)
    /// and a script's `=`), reads fail until the first write, and the first write of any
    /// type fixes the entry's type. An existing entry is left as it is.
    pub fn declare_in(&mut self, scope: ScopeId, key: &str) {
        self.writes = self.writes.wrapping_add(1);
        let Some((entries, k)) = self.place(scope, key) else {
            return;
        };
        if !entries.contains_key(k) {
            entries.insert(k, Entry::unwritten());
        }
    }

    /// Reads a copy of `key` as seen from `scope`, converted as an input port converts it:
    /// when `T` is a number, `bool` or `String`, an entry of another number type, `bool`
    /// or text converts to it by [`FromPortStr`]'s rules (checked: a value that does not
    /// fit is [`BlackboardError::NotConvertible`], never wrapped). Other types are read
    /// exactly, as [`get_exact_in`](Self::get_exact_in) reads them.
    ///
    /// Scripts write `i64` and `f64` and XML literals are text, so a reader asking for the
    /// `i32` it works with should not have to know which wrote the entry.
    pub fn get_in<T: Any + Clone>(&self, scope: ScopeId, key: &str) -> Result<T, BlackboardError> {
        let entry = self.entry_or_err(scope, key)?;
        if let Some(value) = entry.value.downcast_ref::<T>() {
            return Ok(value.clone());
        }
        let Some(value) = entry.value.as_any() else {
            return Err(self.missing(scope, key));
        };
        match convert::<T>(value) {
            Some(Ok(value)) => Ok(value),
            Some(Err(value)) => Err(BlackboardError::NotConvertible {
                key: String::from(key),
                value,
                expected: type_name::<T>(),
                found: entry.type_name,
            }),
            None => Err(wrong_type::<T>(key, entry)),
        }
    }

    /// Reads a copy of `key` as seen from `scope` only if the entry holds a `T` exactly: no
    /// number or text conversion (see [`get_in`](Self::get_in)).
    pub fn get_exact_in<T: Any + Clone>(
        &self,
        scope: ScopeId,
        key: &str,
    ) -> Result<T, BlackboardError> {
        self.get_ref_in::<T>(scope, key).cloned()
    }

    /// Borrows `key` as seen from `scope`.
    pub fn get_ref_in<T: Any>(&self, scope: ScopeId, key: &str) -> Result<&T, BlackboardError> {
        let entry = self.entry_or_err(scope, key)?;
        if !entry.value.is_written() {
            return Err(self.missing(scope, key));
        }
        entry
            .value
            .downcast_ref::<T>()
            .ok_or_else(|| wrong_type::<T>(key, entry))
    }

    /// Borrows `key` as seen from `scope`, whatever its type (for loggers and for code that
    /// tries several types).
    pub fn get_any_in(&self, scope: ScopeId, key: &str) -> Option<&(dyn Any + Send + Sync)> {
        self.entry(scope, key)?.value.as_any()
    }

    /// Writes `key` as seen from `scope`, stamped `stamp`.
    ///
    /// The write lands where the key resolves (see the [module docs](self)): a remapped key
    /// writes the parent's entry; a key that exists nowhere is created as high as autoremap
    /// reaches. An existing entry of the same type is overwritten in place, without
    /// allocating; one of another type is left unchanged and
    /// [`BlackboardError::WrongType`] returned. Every write bumps the entry's sequence number
    /// by one and sets its stamp.
    pub fn set_in<T: Any + Send + Sync>(
        &mut self,
        scope: ScopeId,
        key: &str,
        value: T,
        stamp: Duration,
    ) -> Result<(), BlackboardError> {
        self.writes = self.writes.wrapping_add(1);
        let Some((entries, k)) = self.place(scope, key) else {
            return Err(BlackboardError::NoSuchScope { scope: scope.0 });
        };
        match entries.get_mut(k) {
            Some(entry) if !entry.value.is_written() => *entry = Entry::new(value, stamp),
            Some(entry) => {
                let Some(slot) = entry.value.downcast_mut::<T>() else {
                    return Err(wrong_type::<T>(key, entry));
                };
                *slot = value;
                entry.touch(stamp);
            }
            None => {
                entries.insert(k, Entry::new(value, stamp));
            }
        }
        self.saw(stamp);
        Ok(())
    }

    /// Changes the value of `key` as seen from `scope` in place, if its entry holds a `T`:
    /// a write (the sequence number grows, the stamp is `stamp`) that reuses what the value
    /// already owns, such as a `String`'s buffer. `false`, changing nothing, when there is
    /// no such entry or it holds another type.
    pub fn modify_in<T: Any + Send + Sync>(
        &mut self,
        scope: ScopeId,
        key: &str,
        stamp: Duration,
        change: impl FnOnce(&mut T),
    ) -> bool {
        self.writes = self.writes.wrapping_add(1);
        let Some(entry) = self.place(scope, key).and_then(|(e, k)| e.get_mut(k)) else {
            return false;
        };
        let Some(value) = entry.value.downcast_mut::<T>() else {
            return false;
        };
        change(value);
        entry.touch(stamp);
        self.saw(stamp);
        true
    }

    /// Writes `key` as seen from `scope` whatever type its entry held, and fixes the entry's
    /// type to `T` from now on; the sequence number still grows by one. For loaders that turn
    /// a text entry into the type a port declares. An unknown scope is ignored.
    pub fn replace_in<T: Any + Send + Sync>(
        &mut self,
        scope: ScopeId,
        key: &str,
        value: T,
        stamp: Duration,
    ) {
        self.writes = self.writes.wrapping_add(1);
        let Some((entries, k)) = self.place(scope, key) else {
            return;
        };
        match entries.get_mut(k) {
            // The same type: written in place, so that a value rewritten every tick (a
            // flag a leaf clears) costs no allocation.
            Some(entry) if entry.value.is::<T>() => {
                if let Some(slot) = entry.value.downcast_mut::<T>() {
                    *slot = value;
                }
                entry.untyped = false;
                entry.type_name = type_name::<T>();
                entry.touch(stamp);
            }
            Some(entry) => entry.retype(value, stamp),
            None => {
                entries.insert(k, Entry::new(value, stamp));
            }
        }
        self.saw(stamp);
    }

    /// Writes `key` as seen from `scope` as a script's assignment does: an entry this call
    /// creates is *untyped*, as BehaviorTree.CPP's script-created entries are (no port
    /// declared a type for them), and an untyped entry takes a value of another type, which
    /// replaces the old one (the sequence number still grows by one). An entry written
    /// first some other way ([`set_in`](Self::set_in), or declared by a port with
    /// [`declare_in`](Self::declare_in)) is typed: this then behaves as `set_in`.
    ///
    /// Which values of other types an untyped entry should take is the writer's business
    /// (the script language converts numbers as BehaviorTree.CPP's `Any::copyInto` does).
    pub fn set_untyped_in<T: Any + Send + Sync>(
        &mut self,
        scope: ScopeId,
        key: &str,
        value: T,
        stamp: Duration,
    ) -> Result<(), BlackboardError> {
        self.writes = self.writes.wrapping_add(1);
        let Some((entries, k)) = self.place(scope, key) else {
            return Err(BlackboardError::NoSuchScope { scope: scope.0 });
        };
        match entries.get_mut(k) {
            Some(entry) if entry.untyped => match entry.value.downcast_mut::<T>() {
                Some(slot) => {
                    *slot = value;
                    entry.touch(stamp);
                }
                None => {
                    entry.retype(value, stamp);
                    entry.untyped = true;
                }
            },
            Some(_) => return self.set_in(scope, key, value, stamp),
            None => {
                let mut entry = Entry::new(value, stamp);
                entry.untyped = true;
                entries.insert(k, entry);
            }
        }
        self.saw(stamp);
        Ok(())
    }

    /// `true` if `key` resolves from `scope` to an entry whose type is not fixed (see
    /// [`set_untyped_in`](Self::set_untyped_in)).
    pub fn is_untyped_in(&self, scope: ScopeId, key: &str) -> bool {
        self.entry(scope, key).is_some_and(|e| e.untyped)
    }

    /// Writes `key` in `scope` itself, whatever type its entry there held, without
    /// following a remap or autoremap: what a SubTree's literal port sets, which
    /// BehaviorTree.CPP writes with autoremapping turned off, so that it never lands in the
    /// parent. An unknown scope is ignored.
    pub fn replace_own_in<T: Any + Send + Sync>(
        &mut self,
        scope: ScopeId,
        key: &str,
        value: T,
        stamp: Duration,
    ) {
        self.writes = self.writes.wrapping_add(1);
        let Some(entries) = self.entries_at_mut(scope.0 as usize) else {
            return;
        };
        match entries.get_mut(key) {
            Some(entry) => entry.retype(value, stamp),
            None => {
                entries.insert(key, Entry::new(value, stamp));
            }
        }
        self.saw(stamp);
    }

    /// Removes the entry `key` resolves to from `scope` (a remapped key removes the parent's
    /// entry); `true` if there was one. Remaps stay.
    pub fn unset_in(&mut self, scope: ScopeId, key: &str) -> bool {
        self.writes = self.writes.wrapping_add(1);
        // A key that resolves to no entry has none to remove: looked up first, so that
        // unsetting it does not make the tables of a scope that holds nothing yet.
        self.contains_in(scope, key)
            && self
                .place(scope, key)
                .is_some_and(|(e, k)| e.remove(k).is_some())
    }

    /// `true` if `key` resolves to an entry from `scope`.
    pub fn contains_in(&self, scope: ScopeId, key: &str) -> bool {
        self.entry(scope, key).is_some()
    }

    /// Sequence number, stamp and type of the entry `key` resolves to from `scope`.
    pub fn info_in(&self, scope: ScopeId, key: &str) -> Option<EntryInfo> {
        self.entry(scope, key).map(Entry::info)
    }

    /// The keys stored in `scope` itself (not those it remaps or reaches by autoremap),
    /// sorted.
    pub fn keys_in(&self, scope: ScopeId) -> impl Iterator<Item = &str> + '_ {
        self.entries_at(scope.0 as usize)
            .into_iter()
            .flat_map(Entries::keys)
    }

    /// Reads a copy of `key` in the root scope, numbers, `bool` and text converted as ports
    /// convert them (see [`get_in`](Self::get_in)).
    pub fn get<T: Any + Clone>(&self, key: &str) -> Result<T, BlackboardError> {
        self.get_in(ScopeId::ROOT, key)
    }

    /// Reads a copy of `key` in the root scope only if it holds a `T` exactly.
    pub fn get_exact<T: Any + Clone>(&self, key: &str) -> Result<T, BlackboardError> {
        self.get_exact_in(ScopeId::ROOT, key)
    }

    /// Borrows `key` in the root scope; a borrow cannot convert, so the entry must hold a
    /// `T` exactly.
    pub fn get_ref<T: Any>(&self, key: &str) -> Result<&T, BlackboardError> {
        self.get_ref_in(ScopeId::ROOT, key)
    }

    /// Writes `key` in the root scope, stamped with the latest stamp this blackboard has
    /// seen (trees stamp their writes with their clock; use [`set_in`](Self::set_in) to
    /// choose the stamp).
    pub fn set<T: Any + Send + Sync>(
        &mut self,
        key: &str,
        value: T,
    ) -> Result<(), BlackboardError> {
        let stamp = Duration::from_nanos(self.last_stamp);
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

    /// Removes every entry of every scope; the scopes and their remaps stay, so a tree can
    /// start a new run on the same wiring.
    pub fn clear(&mut self) {
        self.writes = self.writes.wrapping_add(1);
        self.root.clear();
        for e in self.rare.iter_mut().flat_map(|r| &mut r.scopes) {
            e.clear();
        }
    }
}

/// The type name of an entry declared and not written yet.
pub(crate) const UNWRITTEN: &str = "(not written yet)";

/// `value` read as `T` by the rules an input port reads an entry with, when `T` is one of
/// the types those rules cover (the numbers, `bool`, `String`): text through
/// [`FromPortStr::from_port_str`], other numbers through [`FromPortStr::from_other`].
/// `None` for any other `T`, or a value those rules do not convert from; `Err` with the
/// value printed when they do, but it does not fit.
fn convert<T: Any>(value: &dyn Any) -> Option<Result<T, String>> {
    /// The conversion to `U`, handed back as `T` (the same type, checked by the caller).
    fn to<U: FromPortStr + Any, T: Any>(value: &dyn Any) -> Option<Result<T, String>> {
        let converted = match value.downcast_ref::<String>() {
            Some(text) => U::from_port_str(text).map_err(|()| alloc::format!("{text:?}")),
            None => U::from_other(value)?,
        };
        Some(match converted {
            Ok(u) => {
                let mut slot = Some(u);
                Ok((&mut slot as &mut dyn Any)
                    .downcast_mut::<Option<T>>()?
                    .take()?)
            }
            Err(printed) => Err(printed),
        })
    }
    macro_rules! dispatch {
        ($($t:ty),*) => {$(
            if TypeId::of::<T>() == TypeId::of::<$t>() {
                return to::<$t, T>(value);
            }
        )*};
    }
    dispatch!(
        i32, i64, f64, bool, String, u32, u64, usize, f32, i8, i16, u8, u16, isize, i128, u128
    );
    None
}

fn wrong_type<T: Any>(key: &str, entry: &Entry) -> BlackboardError {
    BlackboardError::WrongType {
        key: String::from(key),
        expected: type_name::<T>(),
        found: entry.type_name,
    }
}

/// Prints each scope's entries (key, type and sequence number) and remaps, not the values,
/// which need not be `Debug`.
impl fmt::Debug for Blackboard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        struct ScopeView<'a>(Option<&'a Entries>, Option<&'a Links>);
        impl fmt::Debug for ScopeView<'_> {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                let mut map = f.debug_map();
                for (key, e) in self.0.into_iter().flat_map(Entries::iter) {
                    map.entry(&key, &format_args!("{} #{}", e.type_name, e.sequence));
                }
                for (child, parent) in self.1.into_iter().flat_map(|l| &l.remap) {
                    map.entry(child, &format_args!("-> {parent:?}"));
                }
                map.finish()
            }
        }
        let mut map = f.debug_map();
        for s in 0..self.scope_count() {
            let links = s.checked_sub(1).map(|i| &self.links()[i]);
            map.entry(&s, &ScopeView(self.entries_at(s), links));
        }
        map.finish()
    }
}

#[cfg(test)]
mod tests;
