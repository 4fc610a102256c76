//! Sequence, SequenceWithMemory and AsyncSequence: do all children, in order.
//!
//! - **Sequence**: resume at the stored child index (earlier successes are not re-ticked).
//!   - Child Failure: halt/reset children, index 0, Failure.
//!   - Running: Running.
//!   - All succeeded: reset, Success.
//! - **SequenceWithMemory**: as Sequence, but a Failure keeps the index (the failed child is
//!   retried next tick) and halt keeps it too; yields after each child success.
//! - **AsyncSequence**: as Sequence, but yields (Running + wake-up) after each child that
//!   completes.
//!
//! "Yields" follows BehaviorTree.CPP: only after a child that went from Idle to Success within
//! this tick, and only when children remain; [`Tree::tick_once`](crate::Tree::tick_once) then
//! ticks again at once, [`Tree::tick_exactly_once`](crate::Tree::tick_exactly_once) returns
//! Running. Skipped children count as absent; if all were skipped, the node is Skipped.

use super::ordered;
use crate::blueprint::NodeDef;
use crate::blueprint::{Builder, NodeKind, PortBinding, PortBindingError};
use crate::nodes::built_in::{BuiltIn, Family, Tick};
use crate::nodes::decl::NodeDecl;
use crate::nodes::semantics::{chain, Order, Semantics, Statuses};
use crate::tree::Ticker;
use crate::{Arity, Category};
use crate::{NodeId, NodeStatus};

/// Sequence's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const SEQUENCE: NodeDecl = NodeDecl {
    name: "Sequence",
    category: Category::Control,
    arity: Arity::AtLeast(1),
    ports: &[],
    summary: "Ticks children in order, resuming at the running one; a failure resets it and fails; all succeeded: Success.",
    semantics: Semantics::new(
        Order::in_turn(Statuses::SUCCESS.or(Statuses::SKIPPED)),
        |_, c| chain(c, Statuses::SUCCESS),
    ),
};

/// SequenceWithMemory's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const SEQUENCE_WITH_MEMORY: NodeDecl = NodeDecl {
    name: "SequenceWithMemory",
    category: Category::Control,
    arity: Arity::AtLeast(1),
    ports: &[],
    summary: "As Sequence, but a failure or a halt keeps its place: the failed child is retried next tick.",
    semantics: Semantics::new(
        Order::again(Statuses::SUCCESS.or(Statuses::SKIPPED), Statuses::FAILURE),
        // It yields (RUNNING) after a child that succeeded from Idle, as AsyncSequence does.
        |_, c| chain(c, Statuses::SUCCESS).or(Statuses::RUNNING.when(c.len() > 1)),
    ),
};

/// AsyncSequence's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const ASYNC_SEQUENCE: NodeDecl = NodeDecl {
    name: "AsyncSequence",
    category: Category::Control,
    arity: Arity::AtLeast(1),
    ports: &[],
    summary: "As Sequence, but yields (Running, woken at once by `tick_once`) after each child that completes.",
    semantics: Semantics::new(
        Order::in_turn(Statuses::SUCCESS.or(Statuses::SKIPPED)),
        |_, c| chain(c, Statuses::SUCCESS).or(Statuses::RUNNING),
    ),
};

/// The Sequence node. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sequence;

impl BuiltIn for Sequence {
    fn family(&self) -> Option<Family> {
        Some(Family::Sequential)
    }
}

impl Tick for Sequence {
    /// A Running Sequence resumes at its Running child (its cursor), and returns Running
    /// with the cursor where it was when that child does.
    fn passes_through(&self) -> bool {
        true
    }

    const DECL: &'static NodeDecl = &SEQUENCE;
    super::ordered_state!();
    const PLAIN_ORDER: Option<bool> = Some(true);

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(Sequence)
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        ordered::tick::<C, true, { ordered::PLAIN }>(t, id, def)
    }
    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, _: &NodeDef<C>) {
        t.halt_afresh(id);
    }
}

impl<C> Builder<C> {
    /// A [Sequence](self): children in order, until one fails.
    pub fn sequence(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::Sequence(Sequence), name, children)
    }
}
/// The SequenceWithMemory node. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SequenceWithMemory;

impl BuiltIn for SequenceWithMemory {
    fn family(&self) -> Option<Family> {
        Some(Family::Sequential)
    }
}

impl Tick for SequenceWithMemory {
    const DECL: &'static NodeDecl = &SEQUENCE_WITH_MEMORY;
    super::ordered_state!();

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(SequenceWithMemory)
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        ordered::tick::<C, true, { ordered::MEMORY }>(t, id, def)
    }
}

impl<C> Builder<C> {
    /// A [SequenceWithMemory](self): a Sequence that keeps its place.
    pub fn sequence_with_memory(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(
            NodeKind::SequenceWithMemory(SequenceWithMemory),
            name,
            children,
        )
    }
}
/// The AsyncSequence node. It has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AsyncSequence;

impl BuiltIn for AsyncSequence {
    fn family(&self) -> Option<Family> {
        Some(Family::Sequential)
    }
}

impl Tick for AsyncSequence {
    const DECL: &'static NodeDecl = &ASYNC_SEQUENCE;
    super::ordered_state!();

    fn from_ports(_: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(AsyncSequence)
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        ordered::tick::<C, true, { ordered::ASYNC }>(t, id, def)
    }
    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, _: &NodeDef<C>) {
        t.halt_afresh(id);
    }
}

impl<C> Builder<C> {
    /// An [AsyncSequence](self): a Sequence that yields between children.
    pub fn async_sequence(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::AsyncSequence(AsyncSequence), name, children)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn resumes_at_the_running_child() {
        let mut lab = Lab::new(&[&[S], &[R, S], &[S]]);
        let mut tree = lab.tree(|b| b.sequence("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 2, 1]);
        assert_eq!(lab.halts, [0, 0, 0]);
    }

    #[test]
    fn failure_resets_to_the_first_child() {
        let mut lab = Lab::new(&[&[S], &[F, S], &[S]]);
        let mut tree = lab.tree(|b| b.sequence("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1, 1, 0]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [2, 2, 1]);
    }

    #[test]
    fn memory_retries_the_failed_child() {
        let mut lab = Lab::new(&[&[S], &[F, S], &[S]]);
        let mut tree =
            lab.tree(|b| b.sequence_with_memory("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        // Child 0 is not ticked again: the sequence remembered its place.
        assert_eq!(lab.ticks, [1, 2, 1]);
    }

    #[test]
    fn memory_keeps_its_place_across_a_halt() {
        let mut lab = Lab::new(&[&[S], &[R, R, S], &[S]]);
        let mut tree =
            lab.tree(|b| b.sequence_with_memory("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [0, 1, 0]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 3, 1]);
    }

    #[test]
    fn memory_yields_after_each_success() {
        let mut lab = Lab::new(&[&[S], &[S], &[S]]);
        let mut tree =
            lab.tree(|b| b.sequence_with_memory("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [1, 0, 0]);
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 1, 1]);
        // tick_once re-ticks while woken: one call does all three.
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [2, 2, 2]);
    }

    #[test]
    fn async_yields_only_after_an_immediate_completion() {
        let mut lab = Lab::new(&[&[R, S], &[S], &[S]]);
        let mut tree =
            lab.tree(|b| b.async_sequence("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        // Child 0 was Running before its success, so no yield: child 1 runs in the same tick
        // and yields because it completed from Idle.
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [2, 1, 0]);
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [2, 1, 1]);
    }

    #[test]
    fn plain_sequence_never_yields() {
        let mut lab = Lab::new(&[&[S], &[S], &[S]]);
        let mut tree = lab.tree(|b| b.sequence("seq", |s| s.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 1, 1]);
    }

    #[test]
    fn all_children_skipped_is_skipped() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| {
            b.sequence("root", |r| {
                r.sequence("inner", |s| s.run_once("once", true, |o| o.scripted(0)))
                    .always_success("after")
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1]);
        let mut lab2 = Lab::new(&[&[S]]);
        let mut solo =
            lab2.tree(|b| b.sequence("inner", |s| s.run_once("once", true, |o| o.scripted(0))));
        assert_eq!(lab2.tick(&mut solo), Ok(Status::Success));
        assert_eq!(lab2.tick(&mut solo), Err(TickError::RootSkipped));
    }

    #[test]
    fn children_are_reset_to_idle_on_completion() {
        let mut lab = Lab::new(&[&[S], &[S]]);
        let mut tree = lab.tree(|b| b.sequence("seq", |s| s.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }
}
