//! What a blackboard holds that a plain tree does not use (SubTree scopes, their links and
//! entries, value codecs), kept in one box made on first use, so that the many trees of a
//! crowd pay one pointer for all of it; and the ways to a scope's entries through it.

use alloc::boxed::Box;
use alloc::sync::Arc;
use alloc::vec::Vec;

use super::scope::{resolve, Entries, Links};
use super::{Blackboard, ScopeId};
use crate::state::StateCodecs;

/// The parts of a [`Blackboard`] that few trees use.
#[derive(Default)]
pub(super) struct Rare {
    /// `links[i]` belongs to scope `i + 1`; the root has no links.
    pub(super) links: Vec<Links>,
    /// `scopes[i]` holds the entries of scope `i + 1`. Grown on demand, so that opening a
    /// scope allocates no entries.
    pub(super) scopes: Vec<Entries>,
    /// The value types this blackboard's values are saved, shown and edited with.
    pub(super) codecs: Option<Arc<StateCodecs>>,
}

/// Entries `i` of `scopes` (scope `i + 1`), created if the vector has not grown that far
/// yet. A free function, so that it can run while a key resolved from the links is still
/// borrowed.
fn grown(scopes: &mut Vec<Entries>, i: usize) -> &mut Entries {
    if scopes.len() <= i {
        scopes.resize_with(i + 1, Entries::default);
    }
    &mut scopes[i]
}

impl Blackboard {
    /// The rare parts, made now if there were none.
    pub(super) fn rare_mut(&mut self) -> &mut Rare {
        self.rare.get_or_insert_with(Box::default)
    }

    /// The links of scopes 1 and up; none for a blackboard with only its root.
    #[inline]
    pub(super) fn links(&self) -> &[Links] {
        self.rare.as_deref().map_or(&[], |r| &r.links)
    }

    /// The entries of scopes 1 and up, as far as they were made.
    #[inline]
    fn scopes(&self) -> &[Entries] {
        self.rare.as_deref().map_or(&[], |r| &r.scopes)
    }

    /// Where `key` asked in `scope` lives: the scope and the key's name there (see
    /// [`resolve`]).
    #[inline]
    pub(super) fn resolve<'k>(&'k self, scope: ScopeId, key: &'k str) -> Option<(usize, &'k str)> {
        match self.rare.as_deref() {
            // Only the root: what `resolve` finds with no links, without its loop.
            None => (scope == ScopeId::ROOT).then(|| (0, key.strip_prefix('@').unwrap_or(key))),
            Some(r) => resolve(&r.links, &r.scopes, scope, key),
        }
    }

    /// The entries stored in scope `s` itself, if it has any.
    #[inline]
    pub(super) fn entries_at(&self, s: usize) -> Option<&Entries> {
        match s.checked_sub(1) {
            None => Some(&self.root),
            Some(i) => self.scopes().get(i),
        }
    }

    /// The entries of scope `s` to change, made if the scope had none yet; `None` if the
    /// scope does not exist.
    pub(super) fn entries_at_mut(&mut self, s: usize) -> Option<&mut Entries> {
        match s.checked_sub(1) {
            None => Some(&mut self.root),
            Some(i) => {
                let rare = self.rare.as_deref_mut().filter(|r| i < r.links.len())?;
                Some(grown(&mut rare.scopes, i))
            }
        }
    }

    /// The entries where `key` asked in `scope` lives, to write, and the key's name there;
    /// `None` if `scope` does not exist.
    #[inline]
    pub(super) fn place<'a>(
        &'a mut self,
        scope: ScopeId,
        key: &'a str,
    ) -> Option<(&'a mut Entries, &'a str)> {
        let Self { root, rare, .. } = self;
        let Some(Rare { links, scopes, .. }) = rare.as_deref_mut() else {
            // Only the root: what `resolve` finds with no links, without its loop.
            let key = key.strip_prefix('@').unwrap_or(key);
            return (scope == ScopeId::ROOT).then_some((root, key));
        };
        let (s, k) = resolve(links, scopes, scope, key)?;
        let entries = match s.checked_sub(1) {
            None => root,
            Some(i) => grown(scopes, i),
        };
        Some((entries, k))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    proptest::proptest! {
        /// A blackboard with only its root takes a shortcut past the walk over scopes: it
        /// must find what the walk finds with no links, for any scope and any key, `@` or
        /// not.
        #[test]
        fn the_root_only_shortcut_finds_what_the_walk_finds(
            scope in 0u32..4,
            key in "@{0,2}[a-z_]{0,3}",
        ) {
            let bb = Blackboard::new();
            proptest::prop_assert_eq!(
                bb.resolve(ScopeId(scope), &key),
                resolve(&[], &[], ScopeId(scope), &key)
            );
        }
    }
}
