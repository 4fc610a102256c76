//! Which statuses each node can return: the ground reachability and liveness stand on.
//!
//! A node's [`Statuses`] are worked out from its kind and its children's: a Sequence can
//! succeed only if every child it reaches can, an Inverter swaps its child's, a `Repeat
//! num_cycles="-1"` never succeeds. Where a node's behaviour is not known for sure (an
//! action, a node of another library, a literal read from the blackboard, a precondition
//! attribute that can end a node early) it is taken to return any status, so that what the
//! rules conclude from the sets always holds.

use std::collections::HashMap;

use neurotree_core::Category;

use super::node::{self, is, Node, FALLBACKS, SEQUENCES};
use crate::xml::{Element, XmlLoader};
use neurotree_core::nodes::control::service;
use neurotree_core::nodes::decorator::{
    delay, force, inverter, keep_running, repeat, retry, timeout,
};
use neurotree_core::nodes::leaf::{always, sleep};

/// A set of the statuses SUCCESS, FAILURE and RUNNING.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Statuses(u8);

impl Statuses {
    /// None of them.
    pub const NONE: Self = Self(0);
    /// SUCCESS.
    pub const SUCCESS: Self = Self(1);
    /// FAILURE.
    pub const FAILURE: Self = Self(2);
    /// RUNNING.
    pub const RUNNING: Self = Self(4);
    /// Any status: what is assumed of a node whose behaviour is not known.
    pub const ANY: Self = Self(7);

    /// Whether it holds every status of `other`.
    pub fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// The statuses of both.
    pub fn or(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    /// `other` if `yes`, else none.
    fn when(yes: bool, other: Self) -> Self {
        if yes {
            other
        } else {
            Self::NONE
        }
    }

    /// Whether it can succeed.
    pub fn can_succeed(self) -> bool {
        self.contains(Self::SUCCESS)
    }

    /// Whether it can fail.
    pub fn can_fail(self) -> bool {
        self.contains(Self::FAILURE)
    }

    /// Whether it can run.
    pub fn can_run(self) -> bool {
        self.contains(Self::RUNNING)
    }
}

/// The toolkit's leaves that always succeed: they act on the blackboard.
const TOOLKIT_SUCCEEDS: [&str; 3] = ["Script", "SetBlackboard", "UnsetBlackboard"];
/// The toolkit's conditions on the blackboard.
const TOOLKIT_CHECKS: [&str; 2] = ["ScriptCondition", "WasEntryUpdated"];

/// The attributes that can end a node with a status of their own before it is ticked.
const PRECONDITIONS: [&str; 4] = ["_skipIf", "_successIf", "_failureIf", "_while"];

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

    /// The statuses the node `el` can return.
    pub(crate) fn of(&mut self, el: Element<'_>) -> Statuses {
        let key = (el.document_key(), el.id());
        if let Some(known) = self.known.get(&key) {
            return *known;
        }
        // A SubTree cycle is refused by the loader; until the answer is known, assume any.
        self.known.insert(key, Statuses::ANY);
        let statuses = self.work_out(el);
        self.known.insert(key, statuses);
        statuses
    }

    fn work_out(&mut self, el: Element<'_>) -> Statuses {
        let Some(node) = self.node(el) else {
            return Statuses::ANY;
        };
        let own = self.by_kind(el, &node);
        if PRECONDITIONS.iter().any(|a| el.attr(a).is_some()) {
            return Statuses::ANY;
        }
        own
    }

    fn by_kind(&mut self, el: Element<'_>, node: &Node<'r, C>) -> Statuses {
        let child = |this: &mut Self| el.children().next().map_or(Statuses::ANY, |c| this.of(c));
        let (s, f, r) = (Statuses::SUCCESS, Statuses::FAILURE, Statuses::RUNNING);
        let name = node.name;
        if is(name, &[&always::ALWAYS_SUCCESS]) || TOOLKIT_SUCCEEDS.contains(&name) {
            s
        } else if is(name, &[&always::ALWAYS_FAILURE]) {
            f
        } else if TOOLKIT_CHECKS.contains(&name) {
            s.or(f)
        } else if is(name, &[&sleep::SLEEP]) {
            s.or(r)
        } else if is(name, &SEQUENCES) {
            self.chain(el, true)
        } else if is(name, &FALLBACKS) {
            self.chain(el, false)
        } else if is(name, &[&inverter::INVERTER]) {
            let c = child(self);
            Statuses::when(c.can_succeed(), f)
                .or(Statuses::when(c.can_fail(), s))
                .or(Statuses::when(c.can_run(), r))
        } else if is(name, &[&force::FORCE_SUCCESS, &force::FORCE_FAILURE]) {
            let c = child(self);
            let forced = if is(name, &[&force::FORCE_SUCCESS]) {
                s
            } else {
                f
            };
            Statuses::when(c.can_succeed() || c.can_fail(), forced)
                .or(Statuses::when(c.can_run(), r))
        } else if is(name, &[&keep_running::KEEP_RUNNING_UNTIL_FAILURE]) {
            Statuses::when(child(self).can_fail(), f).or(r)
        } else if is(name, &[&repeat::REPEAT]) {
            match literal_count(el, "num_cycles") {
                Some(-1) => Statuses::when(child(self).can_fail(), f).or(r),
                Some(_) => child(self).or(r),
                None => Statuses::ANY,
            }
        } else if is(name, &[&retry::RETRY_UNTIL_SUCCESSFUL]) {
            match literal_count(el, "num_attempts") {
                Some(-1) => Statuses::when(child(self).can_succeed(), s).or(r),
                Some(_) => child(self).or(r),
                None => Statuses::ANY,
            }
        } else if is(name, &[&timeout::TIMEOUT, &delay::DELAY]) {
            child(self).or(f).or(r)
        } else if is(name, &[&service::SERVICE]) {
            // The branch's (second child's) statuses; the service's are ignored. An interval
            // read from an entry may not convert: Failure.
            let mut children = el.children();
            let service = children.next().map(|c| self.of(c));
            let branch = children.next().map_or(Statuses::ANY, |c| self.of(c));
            let _ = service;
            match literal_count(el, "interval_msec") {
                Some(_) => branch,
                None => branch.or(f),
            }
        } else if node.category == Category::SubTree {
            match el.attr("ID").and_then(|id| self.loader.tree(id)) {
                Some(tree) => match tree.children().next() {
                    Some(root) => self.of(root),
                    None => Statuses::ANY,
                },
                None => Statuses::ANY,
            }
        } else if node.category == Category::Condition {
            s.or(f)
        } else {
            Statuses::ANY
        }
    }

    /// A Sequence's statuses (`sequence`) or a Fallback's: each child is reached only if
    /// the one before can return the status that goes on (success in a Sequence).
    fn chain(&mut self, el: Element<'_>, sequence: bool) -> Statuses {
        let (go_on, stop) = if sequence {
            (Statuses::SUCCESS, Statuses::FAILURE)
        } else {
            (Statuses::FAILURE, Statuses::SUCCESS)
        };
        let mut result = Statuses::NONE;
        for c in el.children() {
            let statuses = self.of(c);
            result = result.or(Statuses::when(statuses.contains(stop), stop));
            result = result.or(Statuses::when(statuses.can_run(), Statuses::RUNNING));
            if !statuses.contains(go_on) {
                return result;
            }
        }
        result.or(go_on)
    }
}

/// The integer literal of attribute `name`, if it is one (not `{key}`).
pub(crate) fn literal_count(el: Element<'_>, name: &str) -> Option<i64> {
    el.attr(name)?.trim().parse().ok()
}
