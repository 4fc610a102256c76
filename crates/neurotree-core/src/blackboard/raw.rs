//! A blackboard's entries taken out and put back raw: what saving, restoring and reloading
//! a tree's state see of it.

use alloc::boxed::Box;
use alloc::string::String;
use alloc::vec::Vec;
use core::any::Any;
use core::time::Duration;

use super::entry::Entry;
use super::scope::Entries;
use super::{Blackboard, EntryInfo};

/// What saving and restoring a tree's state sees of a blackboard: its entries, raw.
impl Blackboard {
    /// Every entry of every scope, in scope then key order: `(scope, key, info, untyped,
    /// value)`; `value` is `None` for an entry declared and not written yet.
    pub(crate) fn raw_entries(
        &self,
    ) -> impl Iterator<Item = (u32, &str, EntryInfo, bool, Option<&(dyn Any + Send + Sync)>)> + '_
    {
        let scopes = self.rare.iter().flat_map(|r| &r.scopes);
        core::iter::once(&self.root)
            .chain(scopes)
            .enumerate()
            .flat_map(|(s, entries)| {
                entries
                    .iter()
                    .map(move |(key, e)| (s as u32, key, e.info(), e.untyped, e.value.as_any()))
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
        let root = core::mem::take(&mut self.root);
        let scopes = self
            .rare
            .as_deref_mut()
            .map(|r| core::mem::take(&mut r.scopes));
        let all = core::iter::once(root).chain(scopes.into_iter().flatten());
        for (s, entries) in all.enumerate() {
            for (key, e) in entries.into_pairs() {
                let info = e.info();
                out.push((s as u32, key, info, e.untyped, e.value.into_box()));
            }
        }
        out
    }

    /// Forgets every entry, keeping the scopes and their links.
    pub(crate) fn clear_entries(&mut self) {
        self.writes = self.writes.wrapping_add(1);
        self.root = Entries::new();
        if let Some(rare) = self.rare.as_deref_mut() {
            rare.scopes.clear();
        }
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
        let Some(entries) = self.entries_at_mut(scope as usize) else {
            return false;
        };
        entries.insert(&key, Entry::from_raw(info, untyped, value));
        true
    }

    /// The latest stamp written.
    pub(crate) fn last_stamp(&self) -> Duration {
        Duration::from_nanos(self.last_stamp)
    }

    /// Sets the latest stamp written, as a saved state had it.
    pub(crate) fn set_last_stamp(&mut self, stamp: Duration) {
        self.last_stamp = crate::clock::duration_to_nanos(stamp);
    }
}
