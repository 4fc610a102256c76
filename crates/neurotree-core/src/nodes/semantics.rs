//! What a node type can return and how it ticks its children, as data: the ground the
//! toolkit's lint stands on.
//!
//! Each node type may declare [`Semantics`] beside its tick: an outcome signature (which
//! [`Statuses`] it can return, given what its children can return and its ports' literals)
//! and an [`Order`] (how it ticks its children). A built-in declares it in its
//! [`NodeDecl`](super::NodeDecl); a registered type through its registration. The
//! declaration must hold for every run: it may name a status the node never returns, never
//! leave out one it can return. A type that declares nothing may return anything and tick
//! its children in any order, so what is concluded from the declarations is never false,
//! only less precise.
//!
//! Declaring a control is one line: a control that ticks child 0 at an interval, then
//! child 1 whose status it returns, is
//!
//! ```
//! use neurotree_core::nodes::semantics::{Order, Semantics, Statuses};
//!
//! const SERVICE: Semantics = Semantics::new(Order::again(Statuses::ANY, Statuses::ANY), |_, c| {
//!     c[1].or(Statuses::RUNNING)
//! });
//! ```

use core::fmt;

/// A set of the statuses a node can return: SUCCESS, FAILURE, RUNNING and SKIPPED.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
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
    /// SKIPPED.
    pub const SKIPPED: Self = Self(8);
    /// SUCCESS or FAILURE: a condition's.
    pub const DONE: Self = Self(3);
    /// Any status: what is assumed of a node whose behaviour is not declared.
    pub const ANY: Self = Self(15);

    /// Whether it holds every status of `other`.
    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// Whether it holds a status of `other`.
    pub const fn meets(self, other: Self) -> bool {
        self.0 & other.0 != 0
    }

    /// The statuses of both.
    pub const fn or(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    /// Its statuses that are not in `other`.
    pub const fn without(self, other: Self) -> Self {
        Self(self.0 & !other.0)
    }

    /// `self` if `yes`, else none.
    pub const fn when(self, yes: bool) -> Self {
        if yes {
            self
        } else {
            Self::NONE
        }
    }

    /// Whether it can succeed.
    pub const fn can_succeed(self) -> bool {
        self.contains(Self::SUCCESS)
    }

    /// Whether it can fail.
    pub const fn can_fail(self) -> bool {
        self.contains(Self::FAILURE)
    }

    /// Whether it can run.
    pub const fn can_run(self) -> bool {
        self.contains(Self::RUNNING)
    }

    /// Whether it can be skipped.
    pub const fn can_skip(self) -> bool {
        self.contains(Self::SKIPPED)
    }

    /// Whether it can end: return anything but RUNNING.
    pub const fn can_end(self) -> bool {
        self.meets(Self::SUCCESS.or(Self::FAILURE).or(Self::SKIPPED))
    }
}

impl fmt::Debug for Statuses {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

impl fmt::Display for Statuses {
    /// `SUCCESS|RUNNING`; `none` for the empty set.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names = [
            (Self::SUCCESS, "SUCCESS"),
            (Self::FAILURE, "FAILURE"),
            (Self::RUNNING, "RUNNING"),
            (Self::SKIPPED, "SKIPPED"),
        ];
        let mut first = true;
        for (s, name) in names {
            if self.contains(s) {
                f.write_str(if first { "" } else { "|" })?;
                f.write_str(name)?;
                first = false;
            }
        }
        if first {
            f.write_str("none")?;
        }
        Ok(())
    }
}

/// How a node ticks its children.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// One after another from the first, each at most once in a run of the node: the next
    /// only after the one before returned one of `next_after` (a Sequence: SUCCESS or
    /// SKIPPED; [`Statuses::ANY`] when the next does not depend on it).
    InTurn {
        /// What the one before must have returned for the next to be ticked.
        next_after: Statuses,
    },
    /// As [`InTurn`](Order::InTurn), and again from an earlier child once a child returned
    /// one of `again_after` (a Repeat after a SUCCESS, a retry after a FAILURE, a reactive
    /// control on its next tick: [`Statuses::ANY`]).
    Again {
        /// What the one before must have returned for the next to be ticked.
        next_after: Statuses,
        /// What makes the node tick an earlier child again.
        again_after: Statuses,
    },
    /// All at once, or in an order not declared: any child may run before or beside any
    /// other.
    AllAtOnce,
}

impl Order {
    /// One after another, each once; the next after the one before returned `next_after`.
    pub const fn in_turn(next_after: Statuses) -> Self {
        Order::InTurn { next_after }
    }

    /// One after another, and again after a child returned `again_after`.
    pub const fn again(next_after: Statuses, again_after: Statuses) -> Self {
        Order::Again {
            next_after,
            again_after,
        }
    }

    /// What the child before must have returned for the next to be ticked (`ANY` when the
    /// children run all at once).
    pub const fn next_after(self) -> Statuses {
        match self {
            Order::InTurn { next_after } | Order::Again { next_after, .. } => next_after,
            Order::AllAtOnce => Statuses::ANY,
        }
    }

    /// Whether a child may be ticked again after a later one, or after it ended (a loop).
    pub const fn loops(self) -> bool {
        matches!(self, Order::Again { .. })
    }
}

/// The literal values of a node's ports, as its file writes them: `None` for a port read
/// from a blackboard entry (its value is known only when the tree runs).
pub struct Literals<'a> {
    text: &'a dyn Fn(&str) -> Option<&'a str>,
}

impl<'a> Literals<'a> {
    /// The literals `text` gives (the attribute's text, else the port's default).
    pub fn new(text: &'a dyn Fn(&str) -> Option<&'a str>) -> Self {
        Self { text }
    }

    /// The literal text of port `name`, trimmed.
    pub fn text(&self, name: &str) -> Option<&'a str> {
        (self.text)(name).map(str::trim)
    }

    /// The integer literal of port `name`.
    pub fn int(&self, name: &str) -> Option<i64> {
        self.text(name)?.parse().ok()
    }

    /// The boolean literal of port `name`, as BehaviorTree.CPP reads one.
    pub fn bool(&self, name: &str) -> Option<bool> {
        match self.text(name)? {
            "true" | "TRUE" | "True" | "1" => Some(true),
            "false" | "FALSE" | "False" | "0" => Some(false),
            _ => None,
        }
    }

    /// The status literal of port `name` (`SUCCESS`, `FAILURE`, `RUNNING`, `SKIPPED`).
    pub fn status(&self, name: &str) -> Option<Statuses> {
        Some(match self.text(name)? {
            "SUCCESS" => Statuses::SUCCESS,
            "FAILURE" => Statuses::FAILURE,
            "RUNNING" => Statuses::RUNNING,
            "SKIPPED" => Statuses::SKIPPED,
            _ => return None,
        })
    }
}

/// An outcome signature: what a node can return, given its ports' literals and what each
/// of its children can return.
pub type Signature = fn(&Literals<'_>, &[Statuses]) -> Statuses;

/// A node type's semantics: its outcome signature and the order it ticks its children in.
#[derive(Clone, Copy)]
pub struct Semantics {
    /// How it ticks its children.
    pub order: Order,
    returns: Signature,
}

impl Semantics {
    /// What a node that declares nothing is taken to be: it may return anything and tick its
    /// children in any order.
    pub const ANY: Semantics = Semantics::new(Order::AllAtOnce, |_, _| Statuses::ANY);

    /// A node that ticks its children in `order` and returns what `returns` says.
    pub const fn new(order: Order, returns: Signature) -> Self {
        Self { order, returns }
    }

    /// What a node can return, given its literals and what its children can return.
    pub fn outcomes(&self, literals: &Literals<'_>, children: &[Statuses]) -> Statuses {
        (self.returns)(literals, children)
    }
}

impl fmt::Debug for Semantics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Semantics")
            .field("order", &self.order)
            .finish_non_exhaustive()
    }
}

impl PartialEq for Semantics {
    /// Declarations are compared by their order and by what they return for a node without
    /// literals over children that may return anything (signatures are functions).
    fn eq(&self, other: &Self) -> bool {
        let none = |_: &str| None;
        let literals = Literals::new(&none);
        let any = [Statuses::ANY; 4];
        self.order == other.order
            && self.outcomes(&literals, &any) == other.outcomes(&literals, &any)
    }
}

impl Eq for Semantics {}

/// The statuses of a chain of children ticked one after another while each returns one of
/// `go_on` (SUCCESS in a Sequence, FAILURE in a Fallback); the others (`stop`) end the chain
/// with that status. A SKIPPED child is passed over; if every child was skipped the chain is
/// SKIPPED, else, past the last, it returns `go_on`.
pub fn chain(children: &[Statuses], go_on: Statuses) -> Statuses {
    let stop = Statuses::SUCCESS.or(Statuses::FAILURE).without(go_on);
    let (mut all_skipped, mut some_done) = (true, false);
    let mut result = Statuses::NONE;
    for &c in children {
        if !all_skipped && !some_done {
            return result;
        }
        result = result
            .or(stop.when(c.meets(stop)))
            .or(Statuses::RUNNING.when(c.can_run()));
        let done = (all_skipped || some_done) && c.meets(go_on);
        some_done = done || (some_done && c.can_skip());
        all_skipped = all_skipped && c.can_skip();
    }
    result
        .or(Statuses::SKIPPED.when(all_skipped))
        .or(go_on.when(some_done))
}

/// A decorator's statuses that pass its child's through, with `done` for the child's
/// SUCCESS and FAILURE (ForceSuccess: SUCCESS for both).
pub fn pass(child: Statuses, success: Statuses, failure: Statuses) -> Statuses {
    success
        .when(child.can_succeed())
        .or(failure.when(child.can_fail()))
        .or(child.without(Statuses::DONE))
}

/// The first child's statuses (a decorator's child; ANY when there is none).
pub fn first(children: &[Statuses]) -> Statuses {
    children.first().copied().unwrap_or(Statuses::ANY)
}

/// Every child's statuses together.
pub fn union(children: &[Statuses]) -> Statuses {
    children.iter().fold(Statuses::NONE, |a, &c| a.or(c))
}

#[cfg(test)]
mod tests {
    use super::*;
    const S: Statuses = Statuses::SUCCESS;
    const F: Statuses = Statuses::FAILURE;
    const R: Statuses = Statuses::RUNNING;
    const K: Statuses = Statuses::SKIPPED;

    #[test]
    fn a_chain_goes_on_through_its_go_on_and_skipped_children() {
        assert_eq!(chain(&[S, S], S), S);
        assert_eq!(chain(&[F, S.or(R)], S), F);
        assert_eq!(chain(&[S.or(F), R], S), F.or(R));
        assert_eq!(chain(&[K, K], S), K);
        assert_eq!(chain(&[K, F], S), F);
        assert_eq!(chain(&[K.or(S), K], S), S.or(K));
        assert_eq!(chain(&[S, F], F), S);
        assert_eq!(chain(&[K, S], F), S);
        assert_eq!(chain(&[F, K], F), F);
    }

    #[test]
    fn sets_print_their_statuses() {
        assert_eq!(alloc::format!("{}", S.or(R)), "SUCCESS|RUNNING");
        assert_eq!(alloc::format!("{}", Statuses::NONE), "none");
        assert_eq!(pass(S.or(K), S, S), S.or(K));
        assert_eq!(pass(F.or(R), F, S), S.or(R));
    }
}
