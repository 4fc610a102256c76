//! LoopInt, LoopDouble, LoopString and LoopBool: run the child once per element of a queue.
//!
//! Each takes the ports `queue`, `value` and `if_empty` (default SUCCESS).
//!
//! - While the child is not Running, pop the next element of `queue` into the `value` entry; if
//!   there is none, return `if_empty`.
//! - Tick the child: Failure → Failure; otherwise Running (the next element comes on the next
//!   tick).
//!
//! `queue` is a literal `;`-separated list (copied afresh for each run) or a blackboard entry
//! holding a `Vec` of the element type or such a list as text; an entry is consumed: each
//! popped element is removed from it, as BehaviorTree.CPP's shared queues are.

use std::collections::VecDeque;
use std::sync::Arc;

use neurotree_core::{
    Arity, Category, CustomNode, CustomSpec, FromPortStr, NodeCtx, NodeKind, NodeStatus, Port,
    PortValue,
};

use crate::registry::{PortSpec, Registry};

/// The per-instance state of a loop over elements of `T`.
struct Loop<T> {
    literal: Option<Vec<T>>,
    queue_key: Option<String>,
    value_key: Option<String>,
    if_empty: NodeStatus,
    current: VecDeque<T>,
    /// A run is under way (a literal queue was copied for it).
    started: bool,
    child_running: bool,
}

impl<T> Loop<T>
where
    T: FromPortStr + Clone + Send + Sync + 'static,
{
    /// The next element: from the literal run's copy, or taken out of the queue entry.
    fn pop<C>(&mut self, node: &mut NodeCtx<'_, '_, C>) -> Option<T> {
        let Some(key) = &self.queue_key else {
            return self.current.pop_front();
        };
        let scope = node.scope();
        let now = node.now();
        let bb = node.blackboard();
        let mut items: Vec<T> = match bb.get_in::<Vec<T>>(scope, key) {
            Ok(items) => items,
            Err(_) => match bb.get_in::<String>(scope, key) {
                Ok(text) => Vec::<T>::from_port_str(&text).ok()?,
                Err(_) => return None,
            },
        };
        if items.is_empty() {
            return None;
        }
        let first = items.remove(0);
        bb.replace_in(scope, key, items, now);
        Some(first)
    }
}

impl<C, T> CustomNode<C> for Loop<T>
where
    T: FromPortStr + Clone + Send + Sync + 'static,
{
    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        if !self.started {
            self.started = true;
            if let Some(items) = &self.literal {
                self.current = items.iter().cloned().collect();
            }
        }
        if !self.child_running {
            let Some(value) = self.pop(node) else {
                self.started = false;
                return self.if_empty;
            };
            if let Some(key) = &self.value_key {
                let (scope, now) = (node.scope(), node.now());
                node.blackboard().replace_in(scope, key, value, now);
            }
        }
        let status = node.tick_child(0);
        self.child_running = status == NodeStatus::Running;
        if status.is_completed() {
            node.reset_children();
        }
        if status == NodeStatus::Failure {
            self.started = false;
            return NodeStatus::Failure;
        }
        NodeStatus::Running
    }

    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {
        self.child_running = false;
        self.started = false;
    }
}

fn status_of(text: &str) -> Result<NodeStatus, String> {
    match text.trim().parse::<NodeStatus>() {
        Ok(status @ (NodeStatus::Success | NodeStatus::Failure | NodeStatus::Skipped)) => {
            Ok(status)
        }
        _ => Err(format!(
            "`{text}` is not a status for if_empty; write SUCCESS, FAILURE or SKIPPED"
        )),
    }
}

fn register_loop<C: 'static, T>(registry: &mut Registry<C>, name: &'static str)
where
    T: FromPortStr + Clone + Send + Sync + 'static,
{
    registry
        .register_leaf(
            name,
            Category::Decorator,
            vec![
                PortSpec::input::<String>("queue"),
                PortSpec::output::<T>("value"),
                PortSpec::input::<String>("if_empty").default_value("SUCCESS"),
            ],
            Arc::new(move |ports: &[Port], _| {
                let value_of = |n: &str| ports.iter().find(|p| p.name == n).map(|p| &p.value);
                let (literal, queue_key) = match value_of("queue") {
                    Some(PortValue::Literal(text)) => (
                        Some(Vec::<T>::from_port_str(text).map_err(|()| {
                            format!("port `queue` of `{name}`: cannot read `{text}`")
                        })?),
                        None,
                    ),
                    Some(PortValue::Entry(key)) => (None, Some(key.clone())),
                    None => return Err(format!("missing port `queue` of `{name}`")),
                };
                let value_key = match value_of("value") {
                    Some(PortValue::Entry(key)) => Some(key.clone()),
                    _ => None,
                };
                let if_empty = match value_of("if_empty") {
                    Some(PortValue::Literal(text)) => status_of(text)?,
                    _ => NodeStatus::Success,
                };
                Ok(NodeKind::Custom(Box::new(CustomSpec {
                    type_name: name.into(),
                    arity: Arity::One,
                    factory: Box::new(move || {
                        Box::new(Loop::<T> {
                            literal: literal.clone(),
                            queue_key: queue_key.clone(),
                            value_key: value_key.clone(),
                            if_empty,
                            current: VecDeque::new(),
                            started: false,
                            child_running: false,
                        })
                    }),
                })))
            }),
        )
        // Registry::new registers each built-in name once.
        .expect("built-in node names are distinct");
}

/// Adds the four loops to `registry`.
pub(crate) fn register<C: 'static>(registry: &mut Registry<C>) {
    register_loop::<C, i64>(registry, "LoopInt");
    register_loop::<C, f64>(registry, "LoopDouble");
    register_loop::<C, String>(registry, "LoopString");
    register_loop::<C, bool>(registry, "LoopBool");
}
