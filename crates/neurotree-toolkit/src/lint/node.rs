//! What the lints need to know of an element: the node type it names, and its place.

use crate::registry::{NodeType, Registry};
use crate::xml::{is_explicit, Element};
use neurotree_core::Category;

/// The node an element of a tree stands for.
pub(crate) struct Node<'r, C> {
    /// Its type's name as registered (an alias resolved): `Sequence`, `SubTree`.
    pub(crate) name: &'r str,
    /// Its family.
    pub(crate) category: Category,
    /// Its registered type; `None` for a SubTree.
    pub(crate) node_type: Option<&'r NodeType<C>>,
}

/// The node `el` stands for, if its type is known (a tree that validated knows them all,
/// but for `--mock-unknown` leaves).
pub(crate) fn resolve<'r, C: 'static>(
    registry: &'r Registry<C>,
    el: Element<'_>,
) -> Option<Node<'r, C>> {
    let tag = el.tag();
    if tag == "SubTree" {
        return Some(Node {
            name: "SubTree",
            category: Category::SubTree,
            node_type: None,
        });
    }
    let name = if is_explicit(tag) {
        el.attr("ID")?
    } else {
        tag
    };
    let node_type = registry
        .get(name)
        .or_else(|| registry.alias(name).map(|(_, t)| t))?;
    Some(Node {
        name: &node_type.name,
        category: node_type.category,
        node_type: Some(node_type),
    })
}

/// The name a message gives `el`: its `name` attribute, else its type.
pub(crate) fn shown(el: Element<'_>) -> String {
    let tag = el.tag();
    let type_name = if is_explicit(tag) || tag == "SubTree" {
        el.attr("ID").unwrap_or(tag)
    } else {
        tag
    };
    match el.attr("name") {
        Some(name) if name != type_name && !name.is_empty() => format!("{name} ({type_name})"),
        _ => type_name.to_string(),
    }
}

/// The line `el` starts on.
pub(crate) fn line(el: Element<'_>) -> u32 {
    el.line_col().0
}

/// `el`'s place under the `<BehaviorTree>` `tree`: each element's tag and index among its
/// siblings, from the tree's root node down (`Sequence[0]/Fallback[1]`).
pub(crate) fn path_in_tree(tree: Element<'_>, el: Element<'_>) -> String {
    let mut parts = Vec::new();
    let mut at = tree;
    while at.id() != el.id() {
        let Some((index, child)) = at
            .children()
            .enumerate()
            .find(|(_, c)| c.id() <= el.id() && el.id() < c.subtree_end())
        else {
            break;
        };
        parts.push(format!("{}[{index}]", child.tag()));
        at = child;
    }
    parts.join("/")
}
