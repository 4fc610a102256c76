//! LoopInt, LoopDouble, LoopString and LoopBool: run the child once per element of a queue.
//!
//! Each takes the ports `queue`, `value` and `if_empty` (default SUCCESS), as
//! BehaviorTree.CPP's `LoopNode<T>` (`loop_node.h`) with `T` = `int` (`i32` here), `double`
//! (`f64`), `std::string` and `bool`.
//!
//! - On a tick from Idle a run starts: a literal queue (`queue="1;2;3"`) is copied for it.
//! - While the child is not Running, take the next element of the run's queue and write it
//!   to `value` (an `i32`, `f64`, `String` or `bool` entry); if there is none, return
//!   `if_empty` (the child is not ticked).
//! - Tick the child: Failure → Failure; otherwise Running (the next element comes on the
//!   next tick). A completed child is reset.
//!
//! A `queue` entry is read when an element is needed:
//!
//! - a [`SharedQueue<T>`] is the queue itself, shared: each element taken is gone from it,
//!   for every holder (BehaviorTree.CPP's `SharedQueue<T>`, a `shared_ptr<deque<T>>`);
//! - a `Vec<T>`, or text such as `"1;2;3"`, is copied (parsed) once, on the run's first
//!   read, and the entry is left untouched: a Repeat around the loop runs the list again.
//!   Anything else (or no entry) is an error naming the node, as BehaviorTree.CPP throws.
//!
//! Costs: taking an element and writing `value` allocate nothing. The copy made at a run's
//! start reuses the node's buffer, so a `Vec` of numbers or booleans is copied without
//! allocating once the buffer has grown to its length; copying strings, or parsing text,
//! allocates, once per run and never on the run's other ticks.

use std::any::type_name;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex};

use neurotree_core::{
    Arity, Category, CustomNode, CustomSpec, FromPortStr, NodeCtx, NodeDecl, NodeKind, NodeStatus,
    Port, PortDecl, PortDirection, PortValue,
};

use crate::registry::{MakerError, Registry};
use neurotree_core::nodes::semantics::{Order, Semantics, Statuses};

/// The ports of a loop whose elements are of type `value_type`.
const fn loop_ports(value_type: &'static str) -> [PortDecl; 3] {
    [
        PortDecl {
            direction: PortDirection::InOut,
            ..PortDecl::input(
                "queue",
                "String",
                "The queue: an entry holding one, or a literal list separated by `;`.",
            )
        },
        PortDecl::output("value", value_type, "The element the child works on."),
        PortDecl::input(
            "if_empty",
            "String",
            "The status returned when the queue is empty: SUCCESS, FAILURE or SKIPPED.",
        )
        .or("SUCCESS"),
    ]
}

/// A loop's declaration: the four differ only in name, element type and summary.
const fn loop_decl(
    name: &'static str,
    ports: &'static [PortDecl],
    summary: &'static str,
) -> NodeDecl {
    NodeDecl {
        name,
        category: Category::Decorator,
        arity: Arity::One,
        ports,
        summary,
        // Each element of the queue ticks the child again; an empty queue gives `if_empty`.
        semantics: Semantics::new(Order::again(Statuses::ANY, Statuses::ANY), |_, _| {
            Statuses::ANY
        }),
    }
}

const LOOP_INT_PORTS: [PortDecl; 3] = loop_ports("i32");
const LOOP_DOUBLE_PORTS: [PortDecl; 3] = loop_ports("f64");
const LOOP_STRING_PORTS: [PortDecl; 3] = loop_ports("String");
const LOOP_BOOL_PORTS: [PortDecl; 3] = loop_ports("bool");

/// LoopInt's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const LOOP_INT: NodeDecl = loop_decl(
    "LoopInt",
    &LOOP_INT_PORTS,
    "Runs the child once per element of a queue of integers, written to `value`.",
);

/// LoopDouble's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const LOOP_DOUBLE: NodeDecl = loop_decl(
    "LoopDouble",
    &LOOP_DOUBLE_PORTS,
    "Runs the child once per element of a queue of numbers, written to `value`.",
);

/// LoopString's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const LOOP_STRING: NodeDecl = loop_decl(
    "LoopString",
    &LOOP_STRING_PORTS,
    "Runs the child once per element of a queue of strings, written to `value`.",
);

/// LoopBool's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const LOOP_BOOL: NodeDecl = loop_decl(
    "LoopBool",
    &LOOP_BOOL_PORTS,
    "Runs the child once per element of a queue of booleans, written to `value`.",
);

/// A queue that nodes share through the blackboard: a loop whose `queue` entry holds one
/// takes its elements out of it (BehaviorTree.CPP's `SharedQueue<T>`).
///
/// ```
/// use std::collections::VecDeque;
/// use std::sync::{Arc, Mutex};
/// use neurotree::nodes::loops::SharedQueue;
///
/// let waypoints: SharedQueue<f64> = Arc::new(Mutex::new(VecDeque::from([1.0, 2.5])));
/// let mut bb = neurotree::Blackboard::new();
/// bb.set("waypoints", Arc::clone(&waypoints)).unwrap();
/// ```
pub type SharedQueue<T> = Arc<Mutex<VecDeque<T>>>;

/// Where this run's elements come from (BehaviorTree.CPP's `current_queue_`).
enum Current<T> {
    /// Nothing read yet in this run.
    Unset,
    /// The node's own copy, in `Loop::copy`.
    Copy,
    /// A shared queue entry.
    Shared(SharedQueue<T>),
}

/// The per-instance state of a loop over elements of `T`.
struct Loop<T> {
    literal: Option<Vec<T>>,
    queue_key: Option<String>,
    value_key: Option<String>,
    /// `None`: bound to an entry, read when the queue is found empty.
    if_empty: Option<NodeStatus>,
    current: Current<T>,
    /// The run's copy of a literal, `Vec` or text queue; kept between runs for its capacity.
    copy: VecDeque<T>,
    child_running: bool,
}

impl<T> Loop<T>
where
    T: FromPortStr + Clone + Send + Sync + 'static,
{
    /// Reads the `queue` entry as BehaviorTree.CPP does when an element is needed: a shared
    /// queue is taken as it is; a `Vec` or text is copied only if this run has no queue
    /// yet. `Err` with a message if the run has no queue and the entry is none of these.
    fn read_entry<C>(&mut self, node: &mut NodeCtx<'_, '_, C>, key: &str) -> Result<(), String> {
        let scope = node.scope();
        let any = node.blackboard().get_any_in(scope, key);
        if let Some(shared) = any.and_then(|a| a.downcast_ref::<SharedQueue<T>>()) {
            self.current = Current::Shared(Arc::clone(shared));
            return Ok(());
        }
        if !matches!(self.current, Current::Unset) {
            return Ok(());
        }
        if let Some(items) = any.and_then(|a| a.downcast_ref::<Vec<T>>()) {
            self.copy.clear();
            self.copy.extend(items.iter().cloned());
        } else if let Some(text) = any.and_then(|a| a.downcast_ref::<String>()) {
            let items = Vec::<T>::from_port_str(text).map_err(|()| {
                format!(
                    "port `queue`: cannot read `{text}` as a list of {}",
                    type_name::<T>()
                )
            })?;
            self.copy.clear();
            self.copy.extend(items);
        } else {
            return Err(format!(
                "port `queue` (entry `{key}`) must hold a SharedQueue<{t}>, a Vec<{t}> or text",
                t = type_name::<T>()
            ));
        }
        self.current = Current::Copy;
        Ok(())
    }

    /// Takes the next element of the run's queue.
    fn pop(&mut self) -> Option<T> {
        match &self.current {
            Current::Unset => None,
            Current::Copy => self.copy.pop_front(),
            // A poisoned lock only means another holder panicked mid-push or mid-pop; the
            // deque itself is still a deque.
            Current::Shared(q) => q.lock().unwrap_or_else(|e| e.into_inner()).pop_front(),
        }
    }

    /// Writes `value` to the `value` entry; an entry of another type is retyped, as the
    /// loop has always written its own type there.
    fn write_value<C>(&self, node: &mut NodeCtx<'_, '_, C>, value: T) {
        let Some(key) = &self.value_key else { return };
        let (scope, now) = (node.scope(), node.now());
        let bb = node.blackboard();
        // Checked first so that the usual write (same type) neither builds an error nor
        // boxes a new entry.
        let same = bb
            .info_in(scope, key)
            .is_none_or(|i| i.sequence == 0 || i.type_name == type_name::<T>());
        if same {
            // Cannot fail: the entry is missing, unwritten or of type T.
            let _ = bb.set_in(scope, key, value, now);
        } else {
            bb.replace_in(scope, key, value, now);
        }
    }
}

impl<C, T> CustomNode<C> for Loop<T>
where
    T: FromPortStr + Clone + Send + Sync + 'static + serde::Serialize + serde::de::DeserializeOwned,
{
    /// A run that pops a shared queue entry cannot be saved: the queue is the
    /// blackboard's, shared with whoever fills it.
    fn save_state(&self) -> Option<Vec<u8>> {
        let copying = match self.current {
            Current::Unset => false,
            Current::Copy => true,
            Current::Shared(_) => return None,
        };
        Some(neurotree_core::state::encode(&(
            copying,
            &self.copy,
            self.child_running,
        )))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(
                |(copying, copy, child_running): (bool, VecDeque<T>, bool)| {
                    self.current = if copying {
                        Current::Copy
                    } else {
                        Current::Unset
                    };
                    self.copy = copy;
                    self.child_running = child_running;
                },
            )
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        if node.previous_status() == NodeStatus::Idle {
            self.child_running = false;
            self.current = Current::Unset;
            if let Some(items) = &self.literal {
                self.copy.clear();
                self.copy.extend(items.iter().cloned());
                self.current = Current::Copy;
            }
        }
        if !self.child_running {
            // Taken out for the call (and put back: no allocation), as it borrows `self`.
            if let Some(key) = self.queue_key.take() {
                let read = self.read_entry(node, &key);
                self.queue_key = Some(key);
                if let Err(message) = read {
                    node.fail(message);
                    return NodeStatus::Failure;
                }
            }
            let Some(value) = self.pop() else {
                return match self.if_empty {
                    Some(status) => status,
                    None => match node.input::<String>("if_empty").map(|t| status_of(&t)) {
                        Ok(Ok(status)) => status,
                        Ok(Err(message)) => {
                            node.fail(message);
                            NodeStatus::Failure
                        }
                        Err(e) => {
                            node.fail(e.to_string());
                            NodeStatus::Failure
                        }
                    },
                };
            };
            self.write_value(node, value);
        }
        // As LoopNode's `setStatus(RUNNING)` on a run's first element.
        if node.previous_status() == NodeStatus::Idle {
            node.set_running();
        }
        let status = node.tick_child(0);
        self.child_running = status == NodeStatus::Running;
        if status.is_completed() {
            node.reset_children();
        }
        if status == NodeStatus::Failure {
            return NodeStatus::Failure;
        }
        NodeStatus::Running
    }

    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {
        self.child_running = false;
        self.current = Current::Unset;
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

fn register_loop<C: 'static, T>(registry: &mut Registry<C>, decl: &'static NodeDecl)
where
    T: FromPortStr + Clone + Send + Sync + 'static + serde::Serialize + serde::de::DeserializeOwned,
{
    let name = decl.name;
    registry.register_declared(
        decl,
        Arc::new(move |ports: &[Port], _| {
            let value_of = |n: &str| ports.iter().find(|p| p.name == n).map(|p| &p.value);
            let (literal, queue_key) =
                match value_of("queue") {
                    Some(PortValue::Literal(text)) => (
                        Some(Vec::<T>::from_port_str(text).map_err(|()| {
                            format!("port `queue` of `{name}`: cannot read `{text}`")
                        })?),
                        None,
                    ),
                    Some(PortValue::Entry(key)) => (None, Some(key.clone())),
                    None => {
                        return Err(MakerError::MissingPort(format!(
                            "missing port `queue` of `{name}`"
                        )))
                    }
                };
            let value_key = match value_of("value") {
                Some(PortValue::Entry(key)) => Some(key.clone()),
                _ => None,
            };
            // Bound to an entry: read when the queue is found empty (`None`).
            let if_empty = match value_of("if_empty") {
                Some(PortValue::Literal(text)) => Some(status_of(text)?),
                Some(PortValue::Entry(_)) => None,
                None => Some(NodeStatus::Success),
            };
            Ok(NodeKind::Custom(Box::new(CustomSpec::new(
                name,
                Arity::One,
                Box::new(move || {
                    Box::new(Loop::<T> {
                        literal: literal.clone(),
                        queue_key: queue_key.clone(),
                        value_key: value_key.clone(),
                        if_empty,
                        current: Current::Unset,
                        copy: VecDeque::new(),
                        child_running: false,
                    })
                }),
            ))))
        }),
    );
}

/// Adds the four loops to `registry`.
pub(crate) fn register<C: 'static>(registry: &mut Registry<C>) {
    register_loop::<C, i32>(registry, &LOOP_INT);
    register_loop::<C, f64>(registry, &LOOP_DOUBLE);
    register_loop::<C, String>(registry, &LOOP_STRING);
    register_loop::<C, bool>(registry, &LOOP_BOOL);
}

#[cfg(test)]
mod tests {
    use super::SharedQueue;
    use crate::testing::*;
    use neurotree_core::TickError;
    use std::collections::VecDeque;
    use std::sync::{Arc, Mutex};

    /// Repeat(2) around a LoopInt over `queue`, whose child adds the value to `sum` and
    /// ticks L0.
    const TWICE: &str = r#"<Repeat num_cycles="2">
          <LoopInt queue="{q}" value="{n}">
            <Sequence><Script code="sum += n"/><L0/></Sequence>
          </LoopInt>
        </Repeat>"#;

    fn run(lab: &mut Lab, tree: &mut neurotree_core::Tree<Lab>) -> Vec<Status> {
        let mut seen = Vec::new();
        loop {
            let s = lab.tick(tree).unwrap();
            seen.push(s);
            if s != R || seen.len() > 20 {
                return seen;
            }
        }
    }

    #[test]
    fn a_vector_entry_is_copied_once_per_run_and_left_untouched() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(TWICE);
        tree.blackboard_mut().set("q", vec![1_i32, 2, 3]).unwrap();
        tree.blackboard_mut().set("sum", 0_i64).unwrap();
        // One element per tick; the 4th tick finds the copy empty, so Repeat starts its
        // second cycle at once (the loop ran over several ticks: no yield) with a new copy.
        assert_eq!(run(&mut lab, &mut tree), [R, R, R, R, R, R, S]);
        assert_eq!(lab.ticks, [6]);
        assert_eq!(lab.halts, [0]);
        let bb = tree.blackboard();
        assert_eq!(bb.get::<i64>("sum"), Ok(12));
        assert_eq!(bb.get::<Vec<i32>>("q"), Ok(vec![1, 2, 3]));
        // LoopInt writes `int`, as BehaviorTree.CPP's LoopNode<int> does.
        assert_eq!(bb.get::<i32>("n"), Ok(3));
    }

    #[test]
    fn a_text_entry_is_parsed_once_per_run_and_left_untouched() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(TWICE);
        tree.blackboard_mut().set("q", "4;5".to_string()).unwrap();
        tree.blackboard_mut().set("sum", 0_i64).unwrap();
        assert_eq!(run(&mut lab, &mut tree), [R, R, R, R, S]);
        assert_eq!(lab.ticks, [4]);
        assert_eq!(tree.blackboard().get::<i64>("sum"), Ok(18));
        assert_eq!(tree.blackboard().get::<String>("q"), Ok("4;5".to_string()));
    }

    #[test]
    fn a_literal_queue_is_copied_for_each_run() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(&TWICE.replace("{q}", "1;2"));
        tree.blackboard_mut().set("sum", 0_i64).unwrap();
        assert_eq!(run(&mut lab, &mut tree), [R, R, R, R, S]);
        assert_eq!(lab.ticks, [4]);
        assert_eq!(tree.blackboard().get::<i64>("sum"), Ok(6));
    }

    #[test]
    fn a_shared_queue_entry_is_consumed() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(TWICE);
        let queue: SharedQueue<i32> = Arc::new(Mutex::new(VecDeque::from([1, 2])));
        tree.blackboard_mut().set("q", Arc::clone(&queue)).unwrap();
        tree.blackboard_mut().set("sum", 0_i64).unwrap();
        // The second cycle finds the shared queue empty: if_empty (Success) at once.
        assert_eq!(run(&mut lab, &mut tree), [R, R, S]);
        assert_eq!(lab.ticks, [2]);
        assert_eq!(tree.blackboard().get::<i64>("sum"), Ok(3));
        assert!(queue.lock().unwrap().is_empty());
        // Refilled from outside, the same entry feeds the next run.
        queue.lock().unwrap().push_back(7);
        assert_eq!(run(&mut lab, &mut tree), [R, S]);
        assert_eq!(tree.blackboard().get::<i64>("sum"), Ok(10));
    }

    #[test]
    fn a_running_child_keeps_its_element_and_halt_starts_over() {
        let mut lab = Lab::new(&[&[R, S, R]]);
        let mut tree = lab.tree(
            r#"<LoopString queue="{q}" value="{w}"><Sequence><Say message="{w}"/><L0/></Sequence></LoopString>"#,
        );
        tree.blackboard_mut()
            .set("q", vec!["a".to_string(), "b".to_string()])
            .unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(lab.said, ["a", "b"]);
        tree.halt(&mut lab);
        assert_eq!(lab.halts, [1]);
        // After the halt, a new run copies the whole list again.
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(lab.said, ["a", "b", "a"]);
    }

    #[test]
    fn an_entry_that_is_no_queue_is_an_error_naming_the_node() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree =
            lab.tree(r#"<LoopDouble name="walk" queue="{q}" value="{x}"><L0/></LoopDouble>"#);
        tree.blackboard_mut().set("q", 3_i64).unwrap();
        match lab.tick(&mut tree) {
            Err(TickError::Node { path, .. }) => assert!(path.contains("walk"), "{path}"),
            other => panic!("expected a node error, got {other:?}"),
        }
        assert_eq!(lab.ticks, [0]);
    }
}
