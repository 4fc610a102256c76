//! How scopes link to each other, and how a key finds its entry through them.

use alloc::collections::BTreeMap;
use alloc::string::String;

use super::ScopeId;

pub(super) use super::entries::Entries;

/// How a child scope reaches its parent. The root has none, which is why it needs no
/// `Links` of its own: `links[i]` belongs to scope `i + 1`.
pub(super) struct Links {
    /// Always an earlier scope (see `Blackboard::add_scope`), so that resolution ends.
    pub(super) parent: ScopeId,
    pub(super) autoremap: bool,
    /// Child key → parent key.
    pub(super) remap: BTreeMap<String, String>,
}

/// Where `key`, asked in `scope`, lives: the scope and the key's name there (the entry may
/// not exist yet; this is then where a write creates it). `None` if `scope` does not exist.
///
/// `scopes[i]` holds the entries of scope `i + 1` (shorter when the later scopes have none
/// yet); the root's are not needed, since a key that reaches the root lives there. The name
/// borrows from `links` or from `key` only, never from the entries, so that a caller can
/// resolve and then change them without copying the name.
///
/// In each scope, in this order: `@key` goes to the root; a remapped key goes to its parent
/// key in the parent scope; an entry stored here is the answer; with autoremap, a key not
/// starting with `_` goes on to the parent; otherwise the key lives (or would live) here.
pub(super) fn resolve<'k>(
    links: &'k [Links],
    scopes: &[Entries],
    scope: ScopeId,
    key: &'k str,
) -> Option<(usize, &'k str)> {
    let scope = scope.0 as usize;
    if scope > links.len() {
        return None;
    }
    let (mut at, mut key) = match key.strip_prefix('@') {
        Some(rooted) => (0, rooted),
        None => (scope, key),
    };
    // Every step that does not return moves to a strictly earlier scope, so this ends even
    // if the remaps form a cycle by name.
    loop {
        let Some(i) = at.checked_sub(1) else {
            // The root: no remaps, no parent.
            return Some((0, key));
        };
        let l = &links[i];
        if let Some(target) = l.remap.get(key) {
            (at, key) = match target.strip_prefix('@') {
                Some(rooted) => (0, rooted),
                None => (l.parent.0 as usize, target.as_str()),
            };
            continue;
        }
        if scopes.get(i).is_some_and(|e| e.contains_key(key)) {
            return Some((at, key));
        }
        if l.autoremap && !key.starts_with('_') {
            at = l.parent.0 as usize;
        } else {
            return Some((at, key));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;
    use alloc::vec::Vec;

    fn link(parent: u32, autoremap: bool, remaps: &[(&str, &str)]) -> Links {
        Links {
            parent: ScopeId(parent),
            autoremap,
            remap: remaps
                .iter()
                .map(|&(c, p)| (String::from(c), String::from(p)))
                .collect(),
        }
    }

    #[test]
    fn remaps_that_name_each_other_still_end() {
        // Scope 2 maps a → b, its parent scope 1 maps b → a: by name a cycle, but each step
        // goes up one scope, so `a` asked in scope 2 lands on `a` in the root. So does `b`,
        // which scope 2 autoremaps to scope 1, which remaps it to `a`.
        let links = vec![link(0, true, &[("b", "a")]), link(1, true, &[("a", "b")])];
        let entries: Vec<Entries> = Vec::new();
        assert_eq!(resolve(&links, &entries, ScopeId(2), "a"), Some((0, "a")));
        assert_eq!(resolve(&links, &entries, ScopeId(2), "b"), Some((0, "a")));
        assert_eq!(resolve(&links, &entries, ScopeId(1), "a"), Some((0, "a")));
    }

    #[test]
    fn remap_targets_can_be_rooted() {
        let links = vec![link(0, false, &[]), link(1, false, &[("x", "@y")])];
        assert_eq!(resolve(&links, &[], ScopeId(2), "x"), Some((0, "y")));
        assert_eq!(resolve(&links, &[], ScopeId(2), "@x"), Some((0, "x")));
    }

    #[test]
    fn unknown_keys_stop_at_the_first_scope_without_autoremap() {
        let links = vec![link(0, false, &[]), link(1, true, &[])];
        assert_eq!(resolve(&links, &[], ScopeId(2), "k"), Some((1, "k")));
        assert_eq!(resolve(&links, &[], ScopeId(2), "_k"), Some((2, "_k")));
        assert_eq!(resolve(&links, &[], ScopeId(3), "k"), None);
    }
}
