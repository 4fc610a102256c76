//! Which statuses each node can return: the ground reachability and liveness stand on.
//!
//! A node's [`Statuses`] are worked out from its type's declared
//! [`Semantics`] (see [`NodeType::semantics`]), its
//! ports' literals and its children's statuses, and widened by its precondition
//! attributes: `_successIf` adds SUCCESS, `_failureIf` FAILURE, `_skipIf` and `_while`
//! SKIPPED. A SubTree returns what its tree's root does. A node of a type that declares
//! nothing (an action, a control of another library) is taken to return any status, a port
//! read from the blackboard to hold any value, so that what the rules conclude from the sets
//! always holds.
//!
//! [`NodeType::semantics`]: crate::registry::NodeType::semantics

use std::collections::HashMap;

use neurotree_core::nodes::semantics::first;
use neurotree_core::nodes::{Literals, Order, Semantics};
use neurotree_core::{Category, PortValue};

use super::node::{self, Node};
use crate::xml::{binding, Element, XmlLoader};

pub use neurotree_core::nodes::Statuses;

/// The attributes that end a node with a status of their own instead of ticking it.
const PRECONDITIONS: [(&str, Statuses); 4] = [
    ("_skipIf", Statuses::SKIPPED),
    ("_successIf", Statuses::SUCCESS),
    ("_failureIf", Statuses::FAILURE),
    ("_while", Statuses::SKIPPED),
];

/// A SubTree: its one child, the tree's root, ticked through.
const SUBTREE: Semantics = Semantics::new(Order::in_turn(Statuses::ANY), |_, c| first(c));

/// The statuses of the nodes of the trees a loader holds, worked out once each.
pub struct Outcomes<'l, 'r, C> {
    loader: &'l XmlLoader<'r, C>,
    /// By document and element number.
    known: HashMap<(usize, usize), Statuses>,
}

impl<'l, 'r, C: 'static> Outcomes<'l, 'r, C> {
    /// The statuses of the nodes of `loader`'s trees.
    pub(crate) fn new(loader: &'l XmlLoader<'r, C>) -> Self {
        Self {
            loader,
            known: HashMap::new(),
        }
    }

    /// The node `el` stands for.
    pub(crate) fn node(&self, el: Element<'_>) -> Option<Node<'r, C>> {
        node::resolve(self.loader.registry(), el)
    }

    /// The semantics of the node `el`: its type's declaration ([`Semantics::ANY`] for a
    /// type not known).
    pub(crate) fn semantics(&self, el: Element<'_>) -> Semantics {
        semantics(self.loader, el)
    }

    /// The statuses the node `el` can return.
    pub(crate) fn of(&mut self, el: Element<'_>) -> Statuses {
        let key = (el.document_key(), el.id());
        if let Some(known) = self.known.get(&key) {
            return *known;
        }
        // A SubTree cycle is refused by the loader; until the answer is known, assume any.
        self.known.insert(key, Statuses::ANY);
        let statuses = PRECONDITIONS
            .iter()
            .filter(|(attr, _)| el.attr(attr).is_some())
            .fold(self.work_out(el), |s, (_, added)| s.or(*added));
        self.known.insert(key, statuses);
        statuses
    }

    fn work_out(&mut self, el: Element<'_>) -> Statuses {
        let Some(node) = self.node(el) else {
            return Statuses::ANY;
        };
        if node.category == Category::SubTree {
            let root = el
                .attr("ID")
                .and_then(|id| self.loader.tree(id))
                .and_then(|tree| tree.children().next());
            return root.map_or(Statuses::ANY, |root| self.of(root));
        }
        let children: Vec<Statuses> = el.children().map(|c| self.of(c)).collect();
        let Some(node_type) = node.node_type else {
            return Statuses::ANY;
        };
        let text = |port: &str| {
            literal(
                el,
                node_type.port(port).and_then(|p| p.default.as_deref()),
                port,
            )
        };
        node_type
            .semantics()
            .outcomes(&Literals::new(&text), &children)
    }
}

/// The semantics of the node `el` in `loader`'s registry.
pub(crate) fn semantics<C: 'static>(loader: &XmlLoader<'_, C>, el: Element<'_>) -> Semantics {
    match node::resolve(loader.registry(), el) {
        Some(Node {
            node_type: Some(t), ..
        }) => t.semantics(),
        Some(_) => SUBTREE,
        None => Semantics::ANY,
    }
}

/// Whether `el` has no attribute that may end it before it is ticked.
pub(crate) fn unguarded(el: Element<'_>) -> bool {
    PRECONDITIONS.iter().all(|(a, _)| el.attr(a).is_none())
}

/// The literal text of port `port` of `el` (else its `default`); `None` when it names a
/// blackboard entry.
fn literal<'a>(el: Element<'a>, default: Option<&'a str>, port: &str) -> Option<&'a str> {
    let text = el.attr(port).or(default)?;
    match binding(port, text) {
        PortValue::Literal(_) => Some(text),
        PortValue::Entry(_) => None,
    }
}
