//! The budget on the nodes of a built tree: how many nodes a loaded tree expands to, and
//! where its expansion crosses the budget, both worked out without building anything.
//!
//! Each use of a subtree is a copy of it, so 24 tiny trees each using the next one twice
//! make a 2 KB file of 2^26 nodes. The sizes are counted from the XML alone, once per tree
//! (kept in the loader until it loads more), and without recursion, since subtrees may
//! chain thousands deep; a tree too big is then refused at the SubTrees that cross the
//! budget, and one within it is built with its nodes counted as a backstop.

use std::collections::BTreeSet;
use std::sync::PoisonError;

use super::build::only_child;
use super::source::Element;
use super::{LoadError, LoadErrorKind, XmlLoader};

/// The start of the message of a tree refused for its size, which a command may follow
/// with a hint of its own.
pub const TOO_MANY_NODES: &str = "the tree expands past the limit of";

/// How many nodes the loaded tree `id` expands to, subtrees expanded (saturating). A
/// subtree the registry builds counts for its SubTree node only; so does a SubTree of a
/// cycle where it closes the cycle (the expansion reports the cycle).
pub(super) fn expanded_size<C: 'static>(loader: &XmlLoader<'_, C>, id: &str) -> u64 {
    // Only this function touches the sizes, and it leaves them whole.
    let mut known = loader.sizes.lock().unwrap_or_else(PoisonError::into_inner);
    // Trees met but not yet counted: one met again before it is counted closes a cycle.
    let mut met = BTreeSet::new();
    // `(tree, whether the trees it uses are counted)`.
    let mut todo = vec![(id, false)];
    while let Some((at, below_counted)) = todo.pop() {
        if known.contains_key(at) {
            continue;
        }
        let Some(tree) = loader.tree(at) else {
            continue;
        };
        if below_counted {
            let size = count(tree, |used| known.get(used).copied().unwrap_or(0));
            known.insert(at.to_string(), size);
        } else if met.insert(at) {
            // Counted in this one walk when every tree it uses is counted already (a tree
            // of no SubTree, the common case); else counted again once they are.
            let mark = todo.len();
            let mut waits = false;
            let size = count(tree, |used| match known.get(used) {
                Some(size) => *size,
                None => {
                    waits = true;
                    if !met.contains(used) {
                        todo.push((used, false));
                    }
                    0
                }
            });
            if waits {
                todo.insert(mark, (at, true));
            } else {
                known.insert(at.to_string(), size);
            }
        }
    }
    known.get(id).copied().unwrap_or(0)
}

/// The errors of the `<BehaviorTree>` `tree`, too big for the budget, at the first `limit`
/// SubTrees where its expansion crosses it, in document order: what expanding it would
/// meet, with a SubTree refused counted as one node as `validate_all` leaves it.
pub(super) fn crossings<C: 'static>(
    loader: &XmlLoader<'_, C>,
    tree: Element<'_>,
    limit: usize,
) -> Vec<LoadError> {
    let max = loader.max_nodes as u64;
    let mut nodes = 0u64;
    let mut errors = Vec::new();
    let mut todo = vec![only_child(tree)];
    while let Some(el) = todo.pop() {
        if errors.len() >= limit {
            break;
        }
        nodes += 1;
        if nodes > max {
            errors.push(too_many_nodes(el, loader.max_nodes));
            break;
        }
        if el.tag() != "SubTree" {
            // Document order: the first child on top.
            let children: Vec<Element<'_>> = el.children().collect();
            todo.extend(children.into_iter().rev());
            continue;
        }
        let Some(id) = el.attr("ID") else { continue };
        let size = expanded_size(loader, id);
        // A subtree that fits is not entered: no SubTree inside it can cross.
        if nodes.saturating_add(size) <= max {
            nodes += size;
            continue;
        }
        errors.push(el.error(LoadErrorKind::TooManyNodes, format!(
            "{TOO_MANY_NODES} {max} nodes here: SubTree `{id}` adds {size} nodes to the {nodes} counted so far (each use of a subtree is a copy of it); raise the limit with XmlLoader::max_nodes if the tree is meant to be this big"
        )));
    }
    errors
}

/// The error of the element `el` that would be node `max + 1`.
#[cold]
pub(super) fn too_many_nodes(el: Element<'_>, max: usize) -> LoadError {
    el.error(LoadErrorKind::TooManyNodes, format!(
        "{TOO_MANY_NODES} {max} nodes here; raise the limit with XmlLoader::max_nodes if the tree is meant to be this big"
    ))
}

/// The nodes of the `<BehaviorTree>` `tree`, each `<SubTree>` counted as itself and the
/// nodes `used` says its ID expands to; `used` sees every SubTree's ID in turn.
fn count<'a>(tree: Element<'a>, mut used: impl FnMut(&'a str) -> u64) -> u64 {
    let root = only_child(tree);
    let mut nodes = 0u64;
    // Elements are stored in document order, each followed by its descendants: one pass
    // over the tree's range, jumping over what a SubTree holds (it is not expanded).
    let mut at = root;
    let end = root.subtree_end();
    loop {
        nodes = nodes.saturating_add(1);
        let next = if at.tag() == "SubTree" {
            if let Some(id) = at.attr("ID") {
                nodes = nodes.saturating_add(used(id));
            }
            at.subtree_end()
        } else {
            at.id() + 1
        };
        if next >= end {
            return nodes;
        }
        at = at.sibling_or_descendant(next);
    }
}
