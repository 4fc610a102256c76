//! Parallel: tick every child, decide by thresholds.
//!
//! `Parallel(success_count, failure_count)`, with S = success_count, F = failure_count and N
//! the number of children:
//!
//! - Defaults -1 and 1; a negative threshold t means N+t+1 (so -1 = all).
//! - Tick only children not yet completed, checking thresholds after each.
//! - Success when successes ≥ S; Failure when N − failures < S or failures ≥ F; then halt the
//!   Running children and reset. Otherwise Running.
//! - A threshold larger than N is a load-time error.
//!
//! The [`ParallelPolicy`] shorthands are constructors over the same node: `RequireAll` =
//! (-1, 1), `RequireOne` = (1, -1), `RequireCount(M)` = (M, N−M+1). Colledanchise &
//! Ögren's Parallel (*Behavior Trees in Robotics and AI*, Algorithm 3: Success if ≥ M
//! succeed, Failure if > N−M fail) is `RequireCount(M)`.
//!
//! Which children completed is read from their stored statuses, so the node keeps no list of
//! its own. Skipped children count toward success only when the success threshold is
//! "all" (negative), as in BehaviorTree.CPP; if every child was skipped, the node is Skipped.
//!
//! A halt that takes ticks ([`slow_halt`](crate::tree::slow_halt)): when the node completes
//! and a Running child it halts answers Halting, the node returns Running instead, keeps
//! its decided outcome in its state slot, continues the halt on later ticks (ticking no
//! child), and returns the outcome on the tick the halt is done.

use crate::blueprint::builder::resolve_threshold;
use crate::blueprint::{NodeDef, ParallelPolicy};
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::blueprint::BuildErrorKind;
use crate::blueprint::{Builder, NodeKind, Param, PortBinding, PortBindingError};
use crate::nodes::built_in::Family;
use crate::nodes::built_in::{self, BuiltIn, Tick};
use crate::nodes::decl::{NodeDecl, PortDecl};
use crate::nodes::semantics::{union, Literals, Order, Semantics, Statuses};
use crate::{Arity, Category};
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

/// Parallel's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const PARALLEL: NodeDecl = NodeDecl {
    name: "Parallel",
    category: Category::Control,
    arity: Arity::AtLeast(1),
    ports: &[
        PortDecl::input("success_count", "i32", "Successes that make the node succeed; a negative count is taken from the number of children (-1: all of them).").or("-1"),
        PortDecl::input("failure_count", "i32", "Failures that make the node fail; a negative count is taken from the number of children (-1: all of them).").or("1"),
    ],
    summary: "Ticks the children not yet completed; Success at `success_count` successes, Failure at `failure_count` failures or when success became impossible.",
    semantics: Semantics::new(Order::AllAtOnce, outcomes),
};

/// What a Parallel can return, given its thresholds S and F: SUCCESS if S can be reached
/// (by successes, or by skips when S is "all"), FAILURE if a child can fail, SKIPPED if
/// every child can be skipped, RUNNING while a child runs or is skipped. Thresholds read
/// from entries: anything.
fn outcomes(l: &Literals<'_>, c: &[Statuses]) -> Statuses {
    let (Some(s), Some(f)) = (l.int("success_count"), l.int("failure_count")) else {
        return Statuses::ANY;
    };
    let n = c.len() as i64;
    let resolve = |t: i64| if t < 0 { n + t + 1 } else { t };
    let (need, limit) = (resolve(s), resolve(f));
    let all = union(c);
    let success = need <= 0 || all.can_succeed() || (s < 0 && all.can_skip());
    let failure = limit <= 0 || need > n || all.can_fail();
    Statuses::SUCCESS
        .when(success)
        .or(Statuses::FAILURE.when(failure))
        .or(Statuses::SKIPPED.when(c.iter().all(|s| s.can_skip())))
        .or(Statuses::RUNNING.when(all.meets(Statuses::RUNNING.or(Statuses::SKIPPED))))
}

#[inline(never)]
pub(crate) fn tick<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
    policy: ParallelPolicy,
) -> NodeStatus {
    let n = def.child_count;
    // The builder turned every policy into thresholds and checked them against `n`.
    let (success, failure) = match policy {
        ParallelPolicy::Thresholds { success, failure } => (success, failure),
        _ => (-1, 1),
    };
    let need = resolve_threshold(success, n) as u32;
    let max_fail = resolve_threshold(failure, n) as u32;
    // As in BehaviorTree.CPP, skipped children count toward a success threshold given as
    // negative ("all but ...") only.
    let skipped_count_as_success = success < 0;
    let slot = t.bp.slot(id);
    if t.aux[slot] != 0 {
        return finish_halt(t, id, slot);
    }
    let (mut successes, mut failures, mut skipped) = (0u32, 0u32, 0u32);
    for i in 0..n {
        match t.status(t.child(def, i)) {
            NodeStatus::Success => successes += 1,
            NodeStatus::Failure => failures += 1,
            _ => {}
        }
    }
    t.set_status(id, NodeStatus::Running);
    for i in 0..n {
        let child = t.child(def, i);
        if !t.status(child).is_completed() {
            match t.tick(child) {
                NodeStatus::Success => successes += 1,
                NodeStatus::Failure => failures += 1,
                NodeStatus::Skipped => skipped += 1,
                NodeStatus::Running | NodeStatus::Idle => {}
            }
        }
        if successes >= need || (skipped_count_as_success && successes + skipped >= need) {
            return complete(t, id, slot, NodeStatus::Success);
        }
        if n - failures < need || failures == max_fail {
            return complete(t, id, slot, NodeStatus::Failure);
        }
    }
    if skipped == n {
        NodeStatus::Skipped
    } else {
        NodeStatus::Running
    }
}

/// Resets the children, halting the Running ones, and returns `outcome`; or Running, with
/// `outcome` kept, when such a halt takes ticks.
#[inline(always)]
fn complete<C>(t: &mut Ticker<'_, C>, id: NodeId, slot: usize, outcome: NodeStatus) -> NodeStatus {
    if t.halting_for(id, |t| t.reset_children(id)) {
        t.aux[slot] = outcome as u32;
        return NodeStatus::Running;
    }
    outcome
}

/// A tick of a Parallel that completed and waits for its children's halts: Running until
/// they are done, then the outcome it kept.
#[cold]
#[inline(never)]
fn finish_halt<C>(t: &mut Ticker<'_, C>, id: NodeId, slot: usize) -> NodeStatus {
    if t.waits_for_halts(id) {
        return NodeStatus::Running;
    }
    let outcome = if t.aux[slot] == NodeStatus::Success as u32 {
        NodeStatus::Success
    } else {
        NodeStatus::Failure
    };
    t.aux[slot] = 0;
    outcome
}

/// The Parallel node: its policy, thresholds or a shorthand resolved when its children are
/// known.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Parallel {
    /// How it decides.
    pub policy: ParallelPolicy,
}

impl BuiltIn for Parallel {
    fn family(&self) -> Option<Family> {
        Some(Family::Concurrent)
    }

    fn port_values(&self, children: usize) -> Vec<Option<String>> {
        let n = children as i32;
        let (success, failure) = match self.policy {
            ParallelPolicy::Thresholds { success, failure } => {
                (Param::Value(success), Param::Value(failure))
            }
            ParallelPolicy::Ports { success, failure } => (success, failure),
            ParallelPolicy::RequireAll => (Param::Value(-1), Param::Value(1)),
            ParallelPolicy::RequireOne => (Param::Value(1), Param::Value(-1)),
            ParallelPolicy::RequireCount(m) => {
                (Param::Value(m as i32), Param::Value(n - m as i32 + 1))
            }
        };
        vec![built_in::text(&success), built_in::text(&failure)]
    }
}

impl Tick for Parallel {
    const DECL: &'static NodeDecl = &PARALLEL;
    const AUX_SLOTS: u32 = 1;

    /// The outcome a saved state keeps: none, Success or Failure.
    fn restored_aux(saved: u64, children: u32) -> Option<u64> {
        let _ = children;
        let kept = [0, NodeStatus::Success as u64, NodeStatus::Failure as u64];
        kept.contains(&saved).then_some(saved)
    }

    fn from_ports(port: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        let success = built_in::param::<i32>(port, "success_count")?;
        let failure = built_in::param::<i32>(port, "failure_count")?;
        let policy = match (success, failure) {
            (Param::Value(success), Param::Value(failure)) => {
                ParallelPolicy::Thresholds { success, failure }
            }
            (success, failure) => ParallelPolicy::Ports { success, failure },
        };
        Ok(Parallel { policy })
    }

    fn close(&mut self, n: u32) -> Result<(), BuildErrorKind> {
        let (s, f) = match self.policy {
            ParallelPolicy::Thresholds { success, failure } => (success, failure),
            // Read at each tick, and checked then.
            ParallelPolicy::Ports { .. } => return Ok(()),
            ParallelPolicy::RequireAll => (-1, 1),
            ParallelPolicy::RequireOne => (1, -1),
            ParallelPolicy::RequireCount(m) => {
                let m = i32::try_from(m).unwrap_or(i32::MAX);
                (m, (n as i32 - m + 1).max(1))
            }
        };
        for (which, t) in [("success", s), ("failure", f)] {
            let resolved = resolve_threshold(t, n);
            if resolved > i64::from(n) {
                return Err(BuildErrorKind::Threshold {
                    type_name: String::from(PARALLEL.name),
                    which,
                    value: resolved,
                    children: n,
                });
            }
        }
        // Signs are kept: a negative success threshold also counts skipped children.
        self.policy = ParallelPolicy::Thresholds {
            success: s,
            failure: f,
        };
        Ok(())
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        match thresholds(t, id, def, self.policy) {
            Some(policy) => tick(t, id, def, policy),
            None => NodeStatus::Failure,
        }
    }

    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, _: &NodeDef<C>) {
        t.halt_afresh(id);
    }
}

/// A Parallel's thresholds, read from its ports if they are bound there, and checked
/// against its number of children as BehaviorTree.CPP checks them at each tick.
#[inline(always)]
fn thresholds<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
    policy: ParallelPolicy,
) -> Option<ParallelPolicy> {
    let ParallelPolicy::Ports { success, failure } = policy else {
        return Some(policy);
    };
    let success = t.param(id, success, "success_count")?;
    let failure = t.param(id, failure, "failure_count")?;
    let n = def.child_count;
    for (which, threshold) in [("succeed", success), ("fail", failure)] {
        if resolve_threshold(threshold, n) > i64::from(n) {
            let message = alloc::format!(
                "its threshold {threshold} is more than its {n} children: it can never {which}"
            );
            t.fault_node(id, message);
            return None;
        }
    }
    Some(ParallelPolicy::Thresholds { success, failure })
}

impl<C> Builder<C> {
    /// A [Parallel](self) with BehaviorTree.CPP's thresholds.
    pub fn parallel(
        self,
        name: &str,
        success: i32,
        failure: i32,
        children: impl FnOnce(Self) -> Self,
    ) -> Self {
        let policy = ParallelPolicy::Thresholds { success, failure };
        self.parallel_policy(name, policy, children)
    }

    /// A [Parallel](self) with a [`ParallelPolicy`]: thresholds, or one of the shorthands
    /// `RequireAll`, `RequireOne`, `RequireCount(M)`.
    pub fn parallel_policy(
        self,
        name: &str,
        policy: ParallelPolicy,
        children: impl FnOnce(Self) -> Self,
    ) -> Self {
        self.node(NodeKind::Parallel(Parallel { policy }), name, children)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn all_must_succeed_by_default() {
        let mut lab = Lab::new(&[&[S], &[R, S], &[R, R, S]]);
        let mut tree =
            lab.tree(|b| b.parallel("p", -1, 1, |p| p.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        // Completed children are not ticked again.
        assert_eq!(lab.ticks, [1, 2, 3]);
        assert_eq!(lab.halts, [0, 0, 0]);
    }

    #[test]
    fn thresholds_three_and_minus_two_halt_the_slower_child() {
        // Four children, success_count 3, failure_count -2 (= 3): the third success ends it
        // and the fourth, still Running, is halted.
        let mut lab = Lab::new(&[&[S], &[R, S], &[S], &[R]]);
        let mut tree = lab.tree(|b| {
            b.parallel("p", 3, -2, |p| {
                p.scripted(0).scripted(1).scripted(2).scripted(3)
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 2, 1, 1]);
        assert_eq!(lab.halts, [0, 0, 0, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn failure_when_success_becomes_impossible() {
        // Need 2 of 3; two failures make it impossible before failure_count (3) is reached.
        let mut lab = Lab::new(&[&[F], &[R], &[F]]);
        let mut tree =
            lab.tree(|b| b.parallel("p", 2, 3, |p| p.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1, 1, 1]);
        assert_eq!(lab.halts, [0, 1, 0]);
    }

    #[test]
    fn require_one_succeeds_on_the_first_success() {
        let mut lab = Lab::new(&[&[R], &[S], &[R]]);
        let mut tree = lab.tree(|b| {
            b.parallel_policy("p", ParallelPolicy::RequireOne, |p| {
                p.scripted(0).scripted(1).scripted(2)
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        // Child 2 was never ticked: the threshold is checked after each child.
        assert_eq!(lab.ticks, [1, 1, 0]);
        assert_eq!(lab.halts, [1, 0, 0]);
    }

    #[test]
    fn require_all_fails_on_the_first_failure() {
        let mut lab = Lab::new(&[&[R], &[F], &[R]]);
        let mut tree = lab.tree(|b| {
            b.parallel_policy("p", ParallelPolicy::RequireAll, |p| {
                p.scripted(0).scripted(1).scripted(2)
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1, 1, 0]);
        assert_eq!(lab.halts, [1, 0, 0]);
    }

    #[test]
    fn require_count_is_colledanchise_and_ogrens_parallel() {
        // M = 2 of 3: fails once more than N - M = 1 children failed.
        let mut lab = Lab::new(&[&[F], &[R, R], &[R, F]]);
        let mut tree = lab.tree(|b| {
            b.parallel_policy("p", ParallelPolicy::RequireCount(2), |p| {
                p.scripted(0).scripted(1).scripted(2)
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1, 2, 2]);
        assert_eq!(lab.halts, [0, 1, 0]);
    }

    #[test]
    fn skipped_children_count_only_toward_a_negative_threshold() {
        let mut lab = Lab::new(&[&[S], &[S]]);
        let mut tree = lab.tree(|b| {
            b.parallel("p", -1, 1, |p| {
                p.run_once("once", true, |o| o.scripted(0)).scripted(1)
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        // RunOnce is skipped now; with "all" (-1) the skipped child counts as done.
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 2]);

        let mut lab = Lab::new(&[&[S], &[S]]);
        let mut tree = lab.tree(|b| {
            b.parallel("p", 2, 1, |p| {
                p.run_once("once", true, |o| o.scripted(0)).scripted(1)
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        // With an explicit 2, one success and one skip never reach the threshold.
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.ticks, [1, 2]);
    }
}
