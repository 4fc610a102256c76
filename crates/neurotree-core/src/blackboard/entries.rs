//! The entries of one scope: a vector sorted by key. The root scope's is held in the
//! [`Blackboard`](super::Blackboard) itself, so that a read of a root entry starts from the
//! tree; each entry holds a value of a small plain type itself (see [`entry`](super::entry)),
//! so that the read ends in this vector's block.
//!
//! A tree's scope holds a handful of entries, read far more often than added. Kept in a
//! sorted vector, a lookup is a binary search over keys that sit together (in a scope of
//! up to [`FEW`] entries, a scan that compares lengths before bytes), and a scope of
//! one entry takes one small block; a `BTreeMap` gave every scope a node of eleven slots
//! (about a kilobyte), a cost each member of a large crowd paid, and a trip to memory per
//! level when a tick read its blackboard. A new key shifts the keys after it: a scope
//! of thousands of keys pays for its first writes what it saves on its reads.
//!
//! A key of up to 23 bytes (most are) is stored in the entry itself ([`SmolStr`]), so that
//! comparing keys reads the entries' own cache lines: a `String` key sent every comparison
//! to memory a second time, to the key's own allocation, which in a large crowd is
//! elsewhere and seldom cached.

use alloc::string::String;

use smol_str::SmolStr;
use thin_vec::ThinVec;

use crate::THIN_HEAD;

use super::entry::Entry;

/// Scopes of at most this many entries are searched one entry after another: a key of
/// another length is passed over in one comparison, where a binary search orders every key
/// it meets (with the root-only shortcut of `resolve`, a read of a `bool` from a scope of
/// one entry took 136 instructions rather than 209: BENCHMARKS.md, "Reads of a small
/// blackboard").
const FEW: usize = 8;

/// Bytes of a scope's block a prefetch asks for: its head and its first entry.
const PREFETCHED: usize = THIN_HEAD + core::mem::size_of::<(SmolStr, Entry)>();

// The entries follow the block's head with no padding (`prefetch` finds the head from
// them): `thin-vec` pads only for items aligned more than its head.
const _: () = assert!(core::mem::align_of::<(SmolStr, Entry)>() <= core::mem::align_of::<usize>());

/// The entries stored directly in one scope, sorted by key (searchable by `&str`, so a
/// lookup allocates nothing). A thin vector, whose length and room sit at the head of its
/// block: every tree holds its root scope's, one pointer rather than three, so a tree with
/// no entries, as a crowd's members often are, takes 16 bytes less; one with entries keeps
/// those 16 bytes at the head of their block, on the line its first entries are on.
#[derive(Default)]
pub(super) struct Entries(ThinVec<(SmolStr, Entry)>);

impl Entries {
    /// No entries; allocates nothing.
    pub(super) const fn new() -> Self {
        Self(ThinVec::new())
    }

    /// Where `key` is, or where it would go.
    #[inline]
    fn find(&self, key: &str) -> Result<usize, usize> {
        self.0.binary_search_by(|(k, _)| k.as_str().cmp(key))
    }

    /// Where `key` is, if it is: entry by entry in a scope of at most [`FEW`].
    #[inline]
    fn position(&self, key: &str) -> Option<usize> {
        if self.0.len() <= FEW {
            self.0.iter().position(|(k, _)| k.as_str() == key)
        } else {
            self.find(key).ok()
        }
    }

    pub(super) fn get(&self, key: &str) -> Option<&Entry> {
        self.position(key).map(|i| &self.0[i].1)
    }

    pub(super) fn get_mut(&mut self, key: &str) -> Option<&mut Entry> {
        self.position(key).map(|i| &mut self.0[i].1)
    }

    pub(super) fn contains_key(&self, key: &str) -> bool {
        self.find(key).is_ok()
    }

    /// Puts `entry` under `key`, giving back the one it replaces.
    pub(super) fn insert(&mut self, key: &str, entry: Entry) -> Option<Entry> {
        match self.find(key) {
            Ok(i) => Some(core::mem::replace(&mut self.0[i].1, entry)),
            Err(i) => {
                self.room_for_one();
                self.0.insert(i, (SmolStr::new(key), entry));
                None
            }
        }
    }

    /// The entry under `key`, made by `make` if there is none.
    pub(super) fn get_or_insert_with(
        &mut self,
        key: &str,
        make: impl FnOnce() -> Entry,
    ) -> &mut Entry {
        let i = match self.find(key) {
            Ok(i) => i,
            Err(i) => {
                self.room_for_one();
                self.0.insert(i, (SmolStr::new(key), make()));
                i
            }
        };
        &mut self.0[i].1
    }

    /// Makes room for one more entry, doubling from one. `Vec` makes room for four at its
    /// first insert: 352 bytes for a blackboard that holds one flag (88), which a sleeping
    /// crowd of a million agents with one entry each paid for with 273 MB (its process
    /// from 874 to 600 bytes a member; BENCHMARKS.md, "A scope's first entry").
    fn room_for_one(&mut self) {
        if self.0.len() == self.0.capacity() {
            self.0.reserve_exact(self.0.len().max(1));
        }
    }

    pub(super) fn remove(&mut self, key: &str) -> Option<Entry> {
        self.find(key).ok().map(|i| self.0.remove(i).1)
    }

    pub(super) fn clear(&mut self) {
        self.0.clear();
    }

    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        self.0.len()
    }

    #[cfg(test)]
    fn capacity(&self) -> usize {
        self.0.capacity()
    }

    /// The entries, by key.
    pub(super) fn iter(&self) -> impl Iterator<Item = (&str, &Entry)> {
        self.0.iter().map(|(k, e)| (k.as_str(), e))
    }

    /// The keys, sorted.
    pub(super) fn keys(&self) -> impl Iterator<Item = &str> {
        self.0.iter().map(|(k, _)| k.as_str())
    }

    /// Asks the processor to start loading the entries (see [`hint`](crate::hint)).
    #[inline]
    pub(super) fn prefetch(&self) {
        // From the block's head, found from where its entries begin without reading the
        // block (its length is in it, the very memory asked for): the head and the first
        // entry, most scopes' all.
        let head = self.0.as_ptr().cast::<u8>().wrapping_sub(THIN_HEAD);
        crate::hint::prefetch_bytes(head, PREFETCHED);
    }
}

impl Entries {
    /// Takes the entries out, by key.
    pub(super) fn into_pairs(self) -> impl Iterator<Item = (String, Entry)> {
        self.0
            .into_iter()
            .map(|(k, e)| (String::from(k.as_str()), e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec::Vec;
    use core::time::Duration;

    fn keys(e: &Entries) -> Vec<&str> {
        e.keys().collect()
    }

    #[test]
    fn entries_stay_sorted_and_are_found_replaced_and_removed_by_key() {
        let mut e = Entries::default();
        for (k, v) in [("b", 2u8), ("a", 1), ("c", 3)] {
            assert!(e.insert(k, Entry::new(v, Duration::ZERO)).is_none());
        }
        assert_eq!(keys(&e), ["a", "b", "c"]);
        let old = e.insert("b", Entry::new(20u8, Duration::ZERO));
        assert_eq!(
            old.and_then(|o| o.value.downcast_ref::<u8>().copied()),
            Some(2)
        );
        assert_eq!(
            e.get("b")
                .and_then(|b| b.value.downcast_ref::<u8>().copied()),
            Some(20)
        );
        assert!(e.get("d").is_none() && !e.contains_key("d") && e.contains_key("a"));
        e.get_or_insert_with("ab", || Entry::new(5u8, Duration::ZERO));
        e.get_or_insert_with("ab", || unreachable!("the entry exists"));
        assert_eq!(keys(&e), ["a", "ab", "b", "c"]);
        assert!(e.remove("a").is_some() && e.remove("a").is_none());
        assert_eq!((e.len(), keys(&e)), (3, ["ab", "b", "c"].to_vec()));
        let owned: Vec<String> = e.into_pairs().map(|(k, _)| k).collect();
        assert_eq!(owned, ["ab", "b", "c"]);
    }

    #[test]
    fn a_scope_makes_room_for_one_entry_then_doubles() {
        let mut e = Entries::default();
        assert_eq!(e.capacity(), 0);
        // Both ways in make room for one more, not `Vec`'s four.
        e.insert("alert", Entry::new(false, Duration::ZERO));
        assert_eq!(e.capacity(), 1);
        e.get_or_insert_with("target", || Entry::new(3u8, Duration::ZERO));
        assert_eq!(e.capacity(), 2);
        // A write to a key that exists lands in its entry: a crowd's alerts grow nothing.
        e.insert("alert", Entry::new(true, Duration::ZERO));
        assert_eq!((e.len(), e.capacity()), (2, 2));
        // Doubling keeps a scope of many keys from moving its block at every write.
        let mut grew = 0;
        for n in 3..=40usize {
            let before = e.capacity();
            e.insert(&alloc::format!("k{n}"), Entry::new(n, Duration::ZERO));
            grew += usize::from(e.capacity() != before);
            assert!(
                e.capacity() >= n && e.capacity() < 2 * n,
                "{n}: {}",
                e.capacity()
            );
        }
        assert_eq!((e.capacity(), grew), (64, 5));
    }

    proptest::proptest! {
        /// Scopes of a few entries are searched one by one, larger ones by halves: either
        /// way every lookup finds what a map of the same writes holds, as the scope grows
        /// past `FEW` and shrinks back (keys longer than `SmolStr`'s inline 23 bytes too).
        #[test]
        fn lookups_agree_with_a_map_at_every_size(
            ops in proptest::collection::vec((0u8..24, proptest::bool::ANY, 0u8..3), 0..80),
        ) {
            let key = |k: u8, long: u8| match long {
                0 => alloc::format!("k{k}"),
                1 => alloc::format!("{k}"),
                _ => alloc::format!("{k:0>30}"),
            };
            let mut e = Entries::default();
            let mut model = alloc::collections::BTreeMap::new();
            for (n, &(k, write, long)) in ops.iter().enumerate() {
                let k = key(k, long);
                if write {
                    e.insert(&k, Entry::new(n as u32, Duration::ZERO));
                    model.insert(k, n as u32);
                } else {
                    proptest::prop_assert_eq!(e.remove(&k).is_some(), model.remove(&k).is_some());
                }
                for probe in 0..24u8 {
                    for long in 0..3 {
                        let p = key(probe, long);
                        let found = e.get(&p).and_then(|x| x.value.downcast_ref::<u32>().copied());
                        proptest::prop_assert_eq!(found, model.get(&p).copied());
                        let found_mut = e
                            .get_mut(&p)
                            .and_then(|x| x.value.downcast_ref::<u32>().copied());
                        proptest::prop_assert_eq!(found_mut, model.get(&p).copied());
                    }
                }
            }
            let sorted: Vec<&str> = model.keys().map(String::as_str).collect();
            proptest::prop_assert_eq!(keys(&e), sorted);
        }
    }
}
