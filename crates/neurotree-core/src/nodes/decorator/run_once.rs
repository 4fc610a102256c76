//! RunOnce(then_skip): run the child to completion once in the tree's life.
//!
//! `then_skip` defaults to true. After the first completion return Skipped forever (or the
//! cached status).
//!
//! Halts and resets do not make it forget; a new tree instance starts afresh.

use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

use crate::blueprint::{Builder, NodeKind, Param, PortBinding, PortBindingError};
use crate::nodes::built_in::{self, BuiltIn, Tick};
use crate::nodes::decl::{NodeDecl, PortDecl};
use crate::nodes::semantics::{first, Order, Semantics, Statuses};
use crate::{Arity, Category};
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

/// RunOnce's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const RUN_ONCE: NodeDecl = NodeDecl {
    name: "RunOnce",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[
        PortDecl::input("then_skip", "bool", "After the first run, return Skipped if true, else the status the child returned that once.").or("true"),
    ],
    summary: "Runs the child to completion once; afterwards Skipped (or the first outcome again).",
    semantics: Semantics::new(Order::in_turn(Statuses::ANY), |l, c| {
        first(c).or(Statuses::SKIPPED.when(l.bool("then_skip") != Some(false)))
    }),
};

const SUCCEEDED: u32 = 1;
const FAILED: u32 = 2;

#[inline(never)]
pub(crate) fn tick<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
    then_skip: bool,
) -> NodeStatus {
    let slot = t.bp.slot(id);
    match t.aux[slot] {
        0 => {}
        _ if then_skip => return NodeStatus::Skipped,
        SUCCEEDED => return NodeStatus::Success,
        _ => return NodeStatus::Failure,
    }
    t.set_status(id, NodeStatus::Running);
    let child = t.child(def, 0);
    let status = t.tick(child);
    if status.is_completed() {
        t.aux[slot] = if status == NodeStatus::Success {
            SUCCEEDED
        } else {
            FAILED
        };
        t.halt_child(child);
        t.answers_otherwise_next(id);
    }
    status
}

/// The RunOnce node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunOnce {
    /// After the first completion return Skipped (true) or the cached status (false).
    pub then_skip: Param<bool>,
}

impl BuiltIn for RunOnce {
    fn port_values(&self, _: usize) -> Vec<Option<String>> {
        vec![built_in::text(&self.then_skip)]
    }
}

impl Tick for RunOnce {
    const DECL: &'static NodeDecl = &RUN_ONCE;
    const AUX_SLOTS: u32 = 1;

    /// Not run yet (0), succeeded or failed.
    fn restored_aux(saved: u64, children: u32) -> Option<u64> {
        let _ = children;
        (saved <= u64::from(FAILED)).then_some(saved)
    }

    fn from_ports(port: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError> {
        Ok(RunOnce {
            then_skip: built_in::param(port, "then_skip")?,
        })
    }

    #[inline]
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
        match t.param(id, self.then_skip, "then_skip") {
            Some(skip) => tick(t, id, def, skip),
            None => NodeStatus::Failure,
        }
    }
}

impl<C> Builder<C> {
    /// A [RunOnce](self): run the child to completion once, then skip.
    pub fn run_once(self, name: &str, then_skip: bool, child: impl FnOnce(Self) -> Self) -> Self {
        let node = RunOnce {
            then_skip: then_skip.into(),
        };
        self.node(NodeKind::RunOnce(node), name, child)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn inside_a_sequence_ticked_five_times() {
        let mut lab = Lab::new(&[&[S], &[S]]);
        let mut tree = lab.tree(|b| {
            b.sequence("seq", |s| {
                s.run_once("once", true, |o| o.scripted(0)).scripted(1)
            })
        });
        for _ in 0..5 {
            assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        }
        assert_eq!(lab.ticks, [1, 5]);
    }

    #[test]
    fn cached_status_without_skip() {
        let mut lab = Lab::new(&[&[F, S]]);
        let mut tree = lab.tree(|b| b.run_once("once", false, |o| o.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1]);
    }

    #[test]
    fn a_running_child_is_ticked_until_it_completes() {
        let mut lab = Lab::new(&[&[R, R, S]]);
        let mut tree = lab.tree(|b| b.run_once("once", true, |o| o.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.tick(&mut tree), Err(TickError::RootSkipped));
        assert_eq!(lab.ticks, [3]);
    }
}
