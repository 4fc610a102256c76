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

use std::sync::Arc;

use neurotree_core::{
    Arity, Category, CustomNode, CustomSpec, NodeCtx, NodeDecl, NodeKind, NodeStatus, Port,
    PortDecl, PortValue,
};

use crate::registry::Registry;

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
        if status.is_completed() {
            node.reset_children();
        }
        status
    }

    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {
        self.child_running = false;
    }
}

/// The entry named by the `entry` port: `key` or `{key}`.
fn entry_key(ports: &[Port]) -> Result<String, String> {
    match ports.iter().find(|p| p.name == "entry").map(|p| &p.value) {
        Some(PortValue::Literal(key) | PortValue::Entry(key)) => Ok(key.clone()),
        None => Err("missing port `entry`".into()),
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
            Ok(NodeKind::Custom(Box::new(CustomSpec {
                type_name: decl.name.into(),
                arity: decl.arity,
                factory: Box::new(move || {
                    Box::new(Watch {
                        key: key.clone(),
                        seen: 0,
                        not_updated,
                        child_running: false,
                    })
                }),
            })))
        }),
    );
}

/// Adds the three nodes to `registry`.
pub(crate) fn register<C: 'static>(registry: &mut Registry<C>) {
    register_watch(registry, &WAS_ENTRY_UPDATED, None);
    register_watch(registry, &SKIP_UNLESS_UPDATED, Some(NodeStatus::Skipped));
    register_watch(registry, &WAIT_VALUE_UPDATE, Some(NodeStatus::Running));
}
