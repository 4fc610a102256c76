//! RetryUntilSuccessful(num_attempts): try a failing child again, up to `num_attempts` times.
//!
//! Mirror of [Repeat](super::repeat) on Failure. 0 attempts, or any negative count other than
//! −1 → Failure with no tick (BehaviorTree.CPP: `try_count < num_attempts || num_attempts == -1`).
//!
//! Some behavior-tree libraries return Running between attempts, others (Colledanchise & Ögren's)
//! retry within one tick. Both are this node: under
//! [`Tree::tick_exactly_once`](crate::Tree::tick_exactly_once) an instant failure yields Running,
//! under [`Tree::tick_once`](crate::Tree::tick_once) the attempts follow each other in the same
//! call. Exactly `-1` retries forever. Halt resets the count.
//!
//! A Retry that runs out gives its own [reason](crate::Reason) for its Failure: "gave up
//! after 3 attempts", code 0.

use crate::blueprint::NodeDef;
use crate::blueprint::{Builder, NodeKind, Param, PortBinding, PortBindingError};
use crate::nodes::built_in::{self, BuiltIn, Tick};
use crate::nodes::decl::{NodeDecl, PortDecl};
use crate::nodes::semantics::{first, Literals, Order, Semantics, Statuses};
use crate::tree::Ticker;
use crate::{Arity, Category};
use crate::{NodeId, NodeStatus};
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

/// RetryUntilSuccessful's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const RETRY_UNTIL_SUCCESSFUL: NodeDecl = NodeDecl {
    name: "RetryUntilSuccessful",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[PortDecl::input(
        "num_attempts",
        "i32",
        "How many times a failing child is tried before the node fails; -1 retries forever.",
    )],
    summary: "Retries a failing child `num_attempts` times (-1: forever); a success succeeds.",
    semantics: Semantics::new(Order::again(Statuses::ANY, Statuses::FAILURE), outcomes),
};

/// What a RetryUntilSuccessful can return: its child's statuses, with FAILURE only once
/// the attempts run out (never with -1) and RUNNING between attempts; FAILURE at once,
/// without a tick, for 0 attempts (or a negative count other than -1).
fn outcomes(l: &Literals<'_>, c: &[Statuses]) -> Statuses {
    super::repeat::loop_outcomes(l.int("num_attempts"), first(c), Statuses::FAILURE)
}

// The loop is Repeat's, mirrored: see `repeat::tick`.

/// The RetryUntilSuccessful node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RetryUntilSuccessful {
    /// How many times; -1 forever, another negative value none.
    pub num_attempts: Param<i32>,
}

impl BuiltIn for RetryUntilSuccessful {
    fn port_values(&self, _: usize) -> Vec<Option<String>> {
        vec![built_in::text(&self.num_attempts)]
    }
}

impl Tick for RetryUntilSuccessful {
    /// As Repeat's: with a fixed count only.
    fn passes_through(&self) -> bool {
        matches!(self.num_attempts, Param::Value(_))
    }

    const DECL: &'static NodeDecl = &RETRY_UNTIL_SUCCESSFUL;
    const AUX_SLOTS: u32 = 1;

    /// The attempts made, saturating as [`Repeat`](super::repeat)'s count does.
    fn restored_aux(saved: u64, children: u32) -> Option<u64> {
        let _ = children;
        Some(saved.min(u64::from(u32::MAX)))
    }

    fn from_ports(port: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(RetryUntilSuccessful {
            num_attempts: built_in::param(port, "num_attempts")?,
        })
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        match t.param(id, self.num_attempts, "num_attempts") {
            Some(n) => super::repeat::tick::<C, false>(t, id, def, n),
            None => NodeStatus::Failure,
        }
    }

    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, _: &NodeDef<C>) {
        t.halt_afresh(id);
    }
}

impl<C> Builder<C> {
    /// A [RetryUntilSuccessful](self); exactly `-1` retries forever, another negative count makes
    /// no attempt.
    pub fn retry(self, name: &str, num_attempts: i32, child: impl FnOnce(Self) -> Self) -> Self {
        let node = RetryUntilSuccessful {
            num_attempts: num_attempts.into(),
        };
        self.node(NodeKind::RetryUntilSuccessful(node), name, child)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn retries_until_success() {
        let mut lab = Lab::new(&[&[F, F, S]]);
        let mut tree = lab.tree(|b| b.retry("r", 5, |r| r.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [3]);
    }

    #[test]
    fn gives_up_after_the_attempts() {
        let mut lab = Lab::new(&[&[F]]);
        let mut tree = lab.tree(|b| b.retry("r", 3, |r| r.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [3]);
    }

    #[test]
    fn one_pass_per_call_is_running_between_attempts() {
        let mut lab = Lab::new(&[&[F, F, S]]);
        let mut tree = lab.tree(|b| b.retry("r", 5, |r| r.scripted(0)));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [3]);
    }

    #[test]
    fn zero_attempts_fail_without_a_tick() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| b.retry("r", 0, |r| r.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [0]);
    }

    #[test]
    fn only_minus_one_retries_forever_another_negative_count_fails_without_a_tick() {
        // BehaviorTree.CPP: `try_count_ < max_attempts_ || max_attempts_ == -1`.
        let mut lab = Lab::new(&[&[F]]);
        let mut tree = lab.tree(|b| b.retry("r", -3, |r| r.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [0]);
        let mut lab = Lab::new(&[&[F]]);
        let mut tree = lab.tree(|b| b.retry("r", -1, |r| r.scripted(0)));
        for _ in 0..5 {
            assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        }
        assert_eq!(lab.ticks, [5]);
        assert_eq!(lab.halts, [0]);
    }
}
