//! Fallback (Colledanchise & Ögren's Selector) and AsyncFallback: try children in order until one
//! succeeds.
//!
//! - **Fallback** (Selector): mirror of [Sequence](super::sequence): resume at the stored child
//!   index.
//!   - Child Success: halt/reset children, index 0, Success.
//!   - Failure: move on.
//!   - Running: Running.
//!   - All failed: reset, Failure.
//! - **AsyncFallback**: as Fallback, but yields (Running + wake-up) after each child that failed
//!   from Idle within this tick, while children remain.
//!
//! Skipped children count as absent; if all were skipped, the node is Skipped.

use super::ordered;
use crate::blueprint::NodeDef;
use crate::blueprint::{Builder, NodeKind, PortBinding, PortBindingError};
use crate::nodes::built_in::{BuiltIn, Family, Tick};
use crate::nodes::decl::NodeDecl;
use crate::nodes::semantics::{chain, Order, Semantics, Statuses};
use crate::tree::Ticker;
use crate::{Arity, Category};
use crate::{NodeId, NodeStatus};

/// Fallback's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const FALLBACK: NodeDecl = NodeDecl {
    name: "Fallback",
    category: Category::Control,
    arity: Arity::AtLeast(1),
    ports: &[],
    summary: "Mirror of Sequence: the first success ends it; all failed: Failure.",
    semantics: Semantics::new(
        Order::in_turn(Statuses::FAILURE.or(Statuses::SKIPPED)),
        |_, c| chain(c, Statuses::FAILURE),
    ),
};

/// AsyncFallback's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const ASYNC_FALLBACK: NodeDecl = NodeDecl {
    name: "AsyncFallback",
    category: Category::Control,
    arity: Arity::AtLeast(1),
    ports: &[],
    summary: "As Fallback, yielding after each child that fails.",
    semantics: Semantics::new(
        Order::in_turn(Statuses::FAILURE.or(Statuses::SKIPPED)),
        |_, c| chain(c, Statuses::FAILURE).or(Statuses::RUNNING),
    ),
};

/// The Fallback node. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Fallback;

impl BuiltIn for Fallback {
    fn family(&self) -> Option<Family> {
        Some(Family::Alternative)
    }
}

impl Tick for Fallback {
    /// A Running Fallback resumes at its Running child (its cursor), and returns Running
    /// with the cursor where it was when that child does.
    fn passes_through(&self) -> bool {
        true
    }

    const DECL: &'static NodeDecl = &FALLBACK;
    super::ordered_state!();
    const PLAIN_ORDER: Option<bool> = Some(false);

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(Fallback)
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        ordered::tick::<C, false, { ordered::PLAIN }>(t, id, def)
    }
    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, _: &NodeDef<C>) {
        t.halt_afresh(id);
    }
}

impl<C> Builder<C> {
    /// A [Fallback](self) (Colledanchise & Ögren's Selector).
    pub fn fallback(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::Fallback(Fallback), name, children)
    }
}

impl<C> Builder<C> {
    /// A [Fallback](Self::fallback), under the name Colledanchise & Ögren and many libraries
    /// give it.
    pub fn selector(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.fallback(name, children)
    }
}
/// The AsyncFallback node. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AsyncFallback;

impl BuiltIn for AsyncFallback {
    fn family(&self) -> Option<Family> {
        Some(Family::Alternative)
    }
}

impl Tick for AsyncFallback {
    const DECL: &'static NodeDecl = &ASYNC_FALLBACK;
    super::ordered_state!();

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(AsyncFallback)
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        ordered::tick::<C, false, { ordered::ASYNC }>(t, id, def)
    }
    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, _: &NodeDef<C>) {
        t.halt_afresh(id);
    }
}

impl<C> Builder<C> {
    /// An [AsyncFallback](self): a Fallback that yields between children.
    pub fn async_fallback(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::AsyncFallback(AsyncFallback), name, children)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn first_success_wins() {
        let mut lab = Lab::new(&[&[F], &[S], &[S]]);
        let mut tree = lab.tree(|b| b.fallback("fb", |f| f.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 1, 0]);
    }

    #[test]
    fn resumes_at_the_running_child() {
        let mut lab = Lab::new(&[&[F], &[R, F], &[F]]);
        let mut tree = lab.tree(|b| b.fallback("fb", |f| f.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1, 2, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn async_yields_after_an_immediate_failure() {
        let mut lab = Lab::new(&[&[F], &[F], &[S]]);
        let mut tree =
            lab.tree(|b| b.async_fallback("fb", |f| f.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [1, 0, 0]);
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 1, 1]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [2, 2, 2]);
    }

    #[test]
    fn halt_restarts_from_the_first_child() {
        let mut lab = Lab::new(&[&[F], &[R]]);
        let mut tree = lab.tree(|b| b.fallback("fb", |f| f.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [0, 1]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [2, 2]);
    }
}
