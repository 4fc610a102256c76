//! Nodes that watch a blackboard entry for writes: WasEntryUpdated, SkipUnlessUpdated and
//! WaitValueUpdate.
//!
//! - **WasEntryUpdated(entry)**: Success if the entry was written since this node last looked
//!   (its sequence number changed), else Failure; Failure if there is no such entry.
//! - **SkipUnlessUpdated(entry)**: a decorator: ticks the child if the entry was written since
//!   it last looked, else Skipped; a Running child is ticked on without looking.
//! - **WaitValueUpdate(entry)**: as SkipUnlessUpdated, but Running instead of Skipped: it waits
//!   for a write.
//!
//! A write of the same value counts: the sequence number grows on every write.
//!
//! The decorators do what BehaviorTree.CPP's `EntryUpdatedDecorator` and the
//! `DecoratorNode::executeTick` around it do: a child that completed goes back to Idle once
//! the decorator's own status is stored, without a halt. So an observer sees the child's
//! result, then the decorator's, then the child's return to Idle; and the child's
//! `_skipIf`/`_successIf`/`_failureIf` are checked again each time the decorator ticks it
//! anew, never while it is Running. When nothing was written the child is not ticked at all.

use std::sync::Arc;

use neurotree_core::{
    Arity, Category, CustomNode, CustomSpec, NodeCtx, NodeDecl, NodeKind, NodeStatus, Port,
    PortDecl, PortValue,
};

use crate::registry::{MakerError, Registry};
use neurotree_core::nodes::semantics::{first, Order, Semantics, Statuses};

/// WasEntryUpdated's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const WAS_ENTRY_UPDATED: NodeDecl = NodeDecl {
    name: "WasEntryUpdated",
    category: Category::Condition,
    arity: Arity::Leaf,
    ports: &[PortDecl::input(
        "entry",
        "String",
        "The entry watched: `key` or `{key}`.",
    )],
    summary: "Success if the entry was written since the node last looked, else Failure.",
    semantics: Semantics::new(Order::AllAtOnce, |_, _| Statuses::DONE),
};

/// SkipUnlessUpdated's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const SKIP_UNLESS_UPDATED: NodeDecl = NodeDecl {
    name: "SkipUnlessUpdated",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[PortDecl::input(
        "entry",
        "String",
        "The entry watched: `key` or `{key}`.",
    )],
    summary: "Ticks the child if the entry was written since the node last looked, else Skipped.",
    semantics: Semantics::new(Order::in_turn(Statuses::ANY), |_, c| {
        first(c).or(Statuses::SKIPPED).or(Statuses::FAILURE)
    }),
};

/// WaitValueUpdate's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const WAIT_VALUE_UPDATE: NodeDecl = NodeDecl {
    name: "WaitValueUpdate",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[PortDecl::input(
        "entry",
        "String",
        "The entry watched: `key` or `{key}`.",
    )],
    summary: "Running until the entry is written, then ticks the child.",
    semantics: Semantics::new(Order::AllAtOnce, |_, _| {
        Statuses::DONE.or(Statuses::RUNNING)
    }),
};

/// Per instance: the entry's sequence number when the node last looked.
struct Watch {
    key: String,
    seen: u64,
    /// For the decorators: what to return when nothing was written; `None` for the leaf.
    not_updated: Option<NodeStatus>,
    child_running: bool,
}

impl Watch {
    /// `true` if the entry was written since the last look (and remembers this look).
    fn updated<C>(&mut self, node: &mut NodeCtx<'_, '_, C>) -> bool {
        let scope = node.scope();
        let Some(info) = node.blackboard().info_in(scope, &self.key) else {
            return false;
        };
        let previous = std::mem::replace(&mut self.seen, info.sequence);
        previous != info.sequence
    }
}

impl<C> CustomNode<C> for Watch {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(
            self.seen,
            self.child_running,
        )))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(seen, child_running)| {
                self.seen = seen;
                self.child_running = child_running;
            })
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let Some(not_updated) = self.not_updated else {
            return if self.updated(node) {
                NodeStatus::Success
            } else {
                NodeStatus::Failure
            };
        };
        if !self.child_running && !self.updated(node) {
            return not_updated;
        }
        let status = node.tick_child(0);
        self.child_running = status == NodeStatus::Running;
        node.reset_completed_children_after_tick();
        status
    }

    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {
        self.child_running = false;
    }
}

/// The entry named by the `entry` port: `key` or `{key}`.
fn entry_key(ports: &[Port]) -> Result<String, MakerError> {
    match ports.iter().find(|p| p.name == "entry").map(|p| &p.value) {
        Some(PortValue::Literal(key) | PortValue::Entry(key)) => Ok(key.clone()),
        None => Err(MakerError::MissingPort("missing port `entry`".into())),
    }
}

fn register_watch<C: 'static>(
    registry: &mut Registry<C>,
    decl: &'static NodeDecl,
    not_updated: Option<NodeStatus>,
) {
    registry.register_declared(
        decl,
        Arc::new(move |ports, _| {
            let key = entry_key(ports)?;
            Ok(NodeKind::Custom(Box::new(
                CustomSpec::new(
                    decl.name,
                    decl.arity,
                    Box::new(move || {
                        Box::new(Watch {
                            key: key.clone(),
                            seen: 0,
                            not_updated,
                            child_running: false,
                        })
                    }),
                )
                // WasEntryUpdated is a condition, the two others decorators.
                .in_category(decl.category),
            )))
        }),
    );
}

/// Adds the three nodes to `registry`.
pub(crate) fn register<C: 'static>(registry: &mut Registry<C>) {
    register_watch(registry, &WAS_ENTRY_UPDATED, None);
    register_watch(registry, &SKIP_UNLESS_UPDATED, Some(NodeStatus::Skipped));
    register_watch(registry, &WAIT_VALUE_UPDATE, Some(NodeStatus::Running));
}

#[cfg(test)]
mod tests {
    use crate::testing::*;
    use neurotree_core::{NodeId, NodeStatus, Observer, StatusChange};
    use std::sync::{Arc, Mutex};

    /// What an observer saw, in order: (node, from, to); a skip is recorded as
    /// (node, Idle, Skipped).
    type Seen = Arc<Mutex<Vec<(usize, NodeStatus, NodeStatus)>>>;

    struct Changes(Seen);

    impl Observer for Changes {
        fn on_status_change(&mut self, c: StatusChange) {
            self.0.lock().unwrap().push((c.node.index(), c.from, c.to));
        }
        fn on_node_skipped(&mut self, node: NodeId) {
            let skip = (node.index(), NodeStatus::Idle, NodeStatus::Skipped);
            self.0.lock().unwrap().push(skip);
        }
    }

    fn take(seen: &Seen) -> Vec<(usize, NodeStatus, NodeStatus)> {
        std::mem::take(&mut *seen.lock().unwrap())
    }

    #[test]
    fn the_child_is_ticked_anew_with_its_preconditions_after_each_write() {
        let mut lab = Lab::new(&[&[R, S], &[S]]);
        let mut tree = lab.tree(
            r#"<Sequence>
                 <SkipUnlessUpdated entry="{goal}"><L0 _successIf="done" _skipIf="skip"/></SkipUnlessUpdated>
                 <L1/>
               </Sequence>"#,
        );
        let bb = tree.blackboard_mut();
        bb.set("done", false).unwrap();
        bb.set("skip", false).unwrap();
        bb.set("goal", 1_i64).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(
            (lab.ticks.as_slice(), lab.halts.as_slice()),
            (&[1, 0][..], &[0, 0][..])
        );
        // Preconditions are not checked while the child runs: it is ticked to its end.
        tree.blackboard_mut().set("done", true).unwrap();
        tree.blackboard_mut().set("skip", true).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(lab.ticks, [2, 1]);
        // No write: the decorator is skipped without ticking its child; the Sequence goes on.
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(lab.ticks, [2, 2]);
        // A write: the child was reset to Idle, so `_successIf` decides, without a tick.
        tree.blackboard_mut().set("goal", 2_i64).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(lab.ticks, [2, 3]);
        // Then `_skipIf`: the child is skipped, so is the decorator.
        tree.blackboard_mut().set("done", false).unwrap();
        tree.blackboard_mut().set("goal", 3_i64).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(lab.ticks, [2, 4]);
        // Then no precondition holds: a new run of the child.
        tree.blackboard_mut().set("skip", false).unwrap();
        tree.blackboard_mut().set("goal", 4_i64).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(lab.ticks, [3, 5]);
        assert_eq!(lab.halts, [0, 0]);
    }

    #[test]
    fn an_observer_sees_the_decorators_change_before_its_childs_reset() {
        use NodeStatus::{Idle, Running as Run, Skipped as Skip, Success as Succ};
        let seen: Seen = Arc::default();
        let mut lab = Lab::new(&[&[S], &[S]]);
        // Nodes: 0 Sequence, 1 SkipUnlessUpdated, 2 L0, 3 L1.
        let mut tree = lab.tree(
            r#"<Sequence><SkipUnlessUpdated entry="goal"><L0/></SkipUnlessUpdated><L1/></Sequence>"#,
        );
        tree.set_observer(Changes(Arc::clone(&seen)));
        tree.blackboard_mut().set("goal", 1_i64).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(
            take(&seen),
            [
                (0, Idle, Run),
                (2, Idle, Succ),
                (1, Idle, Succ),
                (2, Succ, Idle),
                (3, Idle, Succ),
                (1, Succ, Idle),
                (3, Succ, Idle),
                (0, Run, Succ),
                (0, Succ, Idle),
            ]
        );
        // Not written since: skipped, and the child sees nothing at all.
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(
            take(&seen),
            [
                (0, Idle, Run),
                (1, Idle, Skip),
                (3, Idle, Succ),
                (3, Succ, Idle),
                (0, Run, Succ),
                (0, Succ, Idle),
            ]
        );
        assert_eq!(lab.ticks, [1, 2]);
    }

    #[test]
    fn wait_value_update_waits_and_forgets_a_halted_child() {
        let mut lab = Lab::new(&[&[R, S, R]]);
        let mut tree = lab.tree(r#"<WaitValueUpdate entry="{ping}"><L0/></WaitValueUpdate>"#);
        // No entry yet: Running, the child untouched.
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(lab.ticks, [0]);
        tree.blackboard_mut().set("ping", true).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        // A Running child is ticked on without looking at the entry.
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(lab.ticks, [2]);
        // Halted while waiting: the child is Idle, nothing to halt.
        tree.halt(&mut lab);
        assert_eq!(lab.halts, [0]);
        tree.blackboard_mut().set("ping", true).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(lab.ticks, [3]);
        // Halted while its child runs: the child is halted, and the next tick looks at the
        // entry again (unwritten) instead of resuming the child.
        tree.halt(&mut lab);
        assert_eq!(lab.halts, [1]);
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(lab.ticks, [3]);
        tree.blackboard_mut().set("ping", false).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!((lab.ticks[0], lab.halts[0]), (4, 1));
    }

    #[test]
    fn was_entry_updated_fails_without_an_entry_and_then_sees_each_write_once() {
        let mut lab = Lab::new(&[]);
        let mut tree = lab.tree(r#"<WasEntryUpdated entry="x"/>"#);
        assert_eq!(lab.tick(&mut tree), Ok(F));
        tree.blackboard_mut().set("x", 0_u8).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(lab.tick(&mut tree), Ok(F));
        tree.blackboard_mut().set("x", 0_u8).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(S));
    }
}
