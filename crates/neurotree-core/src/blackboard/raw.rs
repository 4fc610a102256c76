//! A blackboard's entries taken out and put back raw: what saving, restoring and reloading
//! a tree's state see of it.

use alloc::boxed::Box;
use alloc::string::String;
use alloc::vec::Vec;
use core::any::Any;
use core::time::Duration;

use super::scope::Entry;
use super::{entries_mut, Blackboard, EntryInfo, Unwritten};

/// What saving and restoring a tree's state sees of a blackboard: its entries, raw.
impl Blackboard {
    /// Every entry of every scope, in scope then key order: `(scope, key, info, untyped,
    /// value)`; `value` is `None` for an entry declared and not written yet.
    pub(crate) fn raw_entries(
        &self,
    ) -> impl Iterator<
        Item = (
            u32,
            &str,
            &EntryInfo,
            bool,
            Option<&(dyn Any + Send + Sync)>,
        ),
    > + '_ {
        self.entries.iter().enumerate().flat_map(|(s, entries)| {
            entries.iter().map(move |(key, e)| {
                let value = (!e.value.is::<Unwritten>()).then_some(&*e.value);
                (s as u32, key, &e.info, e.untyped, value)
            })
        })
    }

    /// Takes every entry out, in scope then key order: `(scope, key, info, untyped,
    /// value)`, `None` for an entry declared and not written yet.
    #[allow(clippy::type_complexity)]
    pub(crate) fn take_raw_entries(
        &mut self,
    ) -> Vec<(
        u32,
        String,
        EntryInfo,
        bool,
        Option<Box<dyn Any + Send + Sync>>,
    )> {
        let mut out = Vec::new();
        for (s, entries) in core::mem::take(&mut self.entries).into_iter().enumerate() {
            for (key, e) in entries.into_pairs() {
                let value = (!e.value.is::<Unwritten>()).then_some(e.value);
                out.push((s as u32, key, e.info, e.untyped, value));
            }
        }
        out
    }

    /// Forgets every entry, keeping the scopes and their links.
    pub(crate) fn clear_entries(&mut self) {
        self.writes = self.writes.wrapping_add(1);
        self.entries.clear();
    }

    /// Puts back an entry [`raw_entries`](Self::raw_entries) gave, `None` for one not
    /// written yet; `false` if scope `scope` does not exist.
    pub(crate) fn put_raw_entry(
        &mut self,
        scope: u32,
        key: String,
        info: EntryInfo,
        untyped: bool,
        value: Option<Box<dyn Any + Send + Sync>>,
    ) -> bool {
        if scope as usize >= self.scope_count() {
            return false;
        }
        let value = value.unwrap_or_else(|| alloc::boxed::Box::new(Unwritten));
        let entry = Entry {
            value,
            info,
            untyped,
        };
        entries_mut(&mut self.entries, scope as usize).insert(&key, entry);
        true
    }

    /// The latest stamp written.
    pub(crate) fn last_stamp(&self) -> Duration {
        self.last_stamp
    }

    /// Sets the latest stamp written, as a saved state had it.
    pub(crate) fn set_last_stamp(&mut self, stamp: Duration) {
        self.last_stamp = stamp;
    }
}
