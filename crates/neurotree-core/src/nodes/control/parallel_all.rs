//! ParallelAll: run every child to completion, then judge by the number of failures.
//!
//! `ParallelAll(max_failures)`: tick every child until all completed; Failure if failures ≥
//! max_failures, else Success.
//!
//! `max_failures` defaults to 1 in BehaviorTree.CPP; a negative value t means N+t+1. Completed
//! children are not ticked again; skipped children count as completed for the end of the run
//! and, if every child was skipped, the node is Skipped.

use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::blueprint::builder::resolve_threshold;
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

/// ParallelAll's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const PARALLEL_ALL: NodeDecl = NodeDecl {
    name: "ParallelAll",
    category: Category::Control,
    arity: Arity::AtLeast(1),
    ports: &[
        PortDecl::input("max_failures", "i32", "Once every child completed, the node fails if at least this many failed (negative: counted from the number of children).").or("1"),
    ],
    summary: "Ticks every child to completion; Failure if `max_failures` of them failed, else Success.",
    semantics: Semantics::new(Order::AllAtOnce, outcomes),
};

/// What a ParallelAll can return: SUCCESS unless `max_failures` is no more than 0, FAILURE
/// if a child can fail (or always, for such a `max_failures`), SKIPPED if every child can be
/// skipped, RUNNING if a child can run.
fn outcomes(l: &Literals<'_>, c: &[Statuses]) -> Statuses {
    let n = c.len() as i64;
    let limit = l
        .int("max_failures")
        .map(|t| if t < 0 { n + t + 1 } else { t });
    let all = union(c);
    let always_fails = limit.is_none_or(|m| m <= 0);
    Statuses::SUCCESS
        .when(limit.is_none_or(|m| m > 0))
        .or(Statuses::FAILURE.when(always_fails || all.can_fail()))
        .or(Statuses::SKIPPED.when(c.iter().all(|s| s.can_skip())))
        .or(Statuses::RUNNING.when(all.can_run()))
}

#[inline(never)]
pub(crate) fn tick<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
    max_failures: i32,
) -> NodeStatus {
    let n = def.child_count;
    let (mut completed, mut failures, mut skipped) = (0u32, 0u32, 0u32);
    t.set_status(id, NodeStatus::Running);
    for i in 0..n {
        let child = t.child(def, i);
        let status = match t.status(child) {
            done @ (NodeStatus::Success | NodeStatus::Failure) => done,
            _ => t.tick(child),
        };
        match status {
            NodeStatus::Success => completed += 1,
            NodeStatus::Failure => {
                completed += 1;
                failures += 1;
            }
            NodeStatus::Skipped => skipped += 1,
            NodeStatus::Running | NodeStatus::Idle => {}
        }
    }
    if skipped == n {
        return NodeStatus::Skipped;
    }
    if skipped + completed >= n {
        t.reset_children(id);
        // The builder resolved the threshold to a non-negative count.
        return if failures >= max_failures as u32 {
            NodeStatus::Failure
        } else {
            NodeStatus::Success
        };
    }
    NodeStatus::Running
}

/// The ParallelAll node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParallelAll {
    /// Failures that make it fail (negative: counted from the number of children).
    pub max_failures: Param<i32>,
}

impl BuiltIn for ParallelAll {
    fn family(&self) -> Option<Family> {
        Some(Family::Concurrent)
    }

    fn port_values(&self, _: usize) -> Vec<Option<String>> {
        vec![built_in::text(&self.max_failures)]
    }
}

impl Tick for ParallelAll {
    const DECL: &'static NodeDecl = &PARALLEL_ALL;

    fn from_ports(port: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(ParallelAll {
            max_failures: built_in::param(port, "max_failures")?,
        })
    }

    fn close(&mut self, n: u32) -> Result<(), BuildErrorKind> {
        // A port is read at each tick; BehaviorTree.CPP checks it then too.
        let Param::Value(max_failures) = self.max_failures else {
            return Ok(());
        };
        let f = resolve_threshold(max_failures, n);
        if f > i64::from(n) {
            return Err(BuildErrorKind::Threshold {
                type_name: String::from(PARALLEL_ALL.name),
                which: "max_failures",
                value: f,
                children: n,
            });
        }
        self.max_failures = Param::Value(f as i32);
        Ok(())
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        match t.param(id, self.max_failures, "max_failures") {
            Some(max) => tick(t, id, def, max),
            None => NodeStatus::Failure,
        }
    }
}

impl<C> Builder<C> {
    /// A [ParallelAll](self).
    pub fn parallel_all(
        self,
        name: &str,
        max_failures: i32,
        children: impl FnOnce(Self) -> Self,
    ) -> Self {
        let node = ParallelAll {
            max_failures: max_failures.into(),
        };
        self.node(NodeKind::ParallelAll(node), name, children)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn waits_for_every_child() {
        let mut lab = Lab::new(&[&[F], &[R, R, S], &[R, S]]);
        let mut tree =
            lab.tree(|b| b.parallel_all("pa", 2, |p| p.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [1, 3, 2]);
    }

    #[test]
    fn fails_at_max_failures() {
        let mut lab = Lab::new(&[&[F], &[R, F], &[S]]);
        let mut tree =
            lab.tree(|b| b.parallel_all("pa", 2, |p| p.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1, 2, 1]);
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    }

    #[test]
    fn halt_stops_the_running_children() {
        let mut lab = Lab::new(&[&[R], &[S], &[R]]);
        let mut tree =
            lab.tree(|b| b.parallel_all("pa", 1, |p| p.scripted(0).scripted(1).scripted(2)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.halt(&mut tree);
        assert_eq!(lab.halts, [1, 0, 1]);
    }
}
