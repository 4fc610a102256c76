//! The built-in leaves that work on the blackboard: Script, ScriptCondition, SetBlackboard
//! and UnsetBlackboard.
//!
//! - **Script(code)**: runs the script (parsed when the tree is loaded); Success. A script that
//!   fails at run time (an unknown key, a type mismatch) is an error of the tick
//!   ([`TickError::Node`](neurotree_core::TickError::Node)), as BehaviorTree.CPP throws one.
//! - **ScriptCondition(code)**: Success if the script's value is true (a non-zero number counts
//!   as true), else Failure.
//! - **SetBlackboard(value, output_key)**: writes `value` (text, converted by whoever reads it)
//!   to the entry named by `output_key`; Success.
//! - **UnsetBlackboard(key)**: removes the entry named by `key`; Success.
//! - **Precondition(if, else=FAILURE)**: a decorator: evaluates `if` only when its child has
//!   not been started; false → the `else` status without ticking the child; true → ticks the
//!   child, then on later ticks without `if`, until the child completes (Success or Failure;
//!   a Skipped child is ticked on, as BehaviorTree.CPP's `_children_running` stays set).
//!   (BehaviorTree.CPP forgets, on halt, that the child was started; here a halt clears it.)

use std::sync::Arc;

use neurotree_core::nodes::stand_in;
use neurotree_core::{
    Action, Arity, Builder, Category, CustomNode, CustomSpec, Handle, NodeCtx, NodeDecl, NodeKind,
    NodeStatus, Port, PortDecl, PortDirection, PortValue, Status,
};

use crate::registry::{MakerError, Registry};
use crate::script::{Enums, Script, ScriptEnv, Value};
use neurotree_core::nodes::semantics::{first, Order, Semantics, Statuses};

/// Script's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const SCRIPT: NodeDecl = NodeDecl {
    name: "Script",
    category: Category::Action,
    arity: Arity::Leaf,
    ports: &[PortDecl::input(
        "code",
        "String",
        "The script to run; it is parsed when the tree is loaded.",
    )],
    summary: "Runs a script on the blackboard; Success.",
    semantics: Semantics::new(Order::AllAtOnce, |_, _| Statuses::DONE),
};

/// ScriptCondition's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const SCRIPT_CONDITION: NodeDecl = NodeDecl {
    name: "ScriptCondition",
    category: Category::Condition,
    arity: Arity::Leaf,
    ports: &[PortDecl::input(
        "code",
        "String",
        "The script to evaluate; true (or a non-zero number) gives Success.",
    )],
    summary: "Success if the value of a script is true, else Failure.",
    semantics: Semantics::new(Order::AllAtOnce, |_, _| Statuses::DONE),
};

/// SetBlackboard's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const SET_BLACKBOARD: NodeDecl = NodeDecl {
    name: "SetBlackboard",
    category: Category::Action,
    arity: Arity::Leaf,
    ports: &[
        PortDecl::input(
            "value",
            "String",
            "The text to write, converted by whoever reads the entry.",
        ),
        PortDecl {
            direction: PortDirection::InOut,
            ..PortDecl::input("output_key", "String", "The entry written.")
        },
    ],
    summary: "Writes `value` into the entry named by `output_key`; Success.",
    semantics: Semantics::new(Order::AllAtOnce, |l, _| {
        // A value read from an entry fails when the entry cannot be read.
        Statuses::SUCCESS.or(Statuses::FAILURE.when(l.text("value").is_none()))
    }),
};

/// UnsetBlackboard's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const UNSET_BLACKBOARD: NodeDecl = NodeDecl {
    name: "UnsetBlackboard",
    category: Category::Action,
    arity: Arity::Leaf,
    ports: &[PortDecl::input("key", "String", "The entry removed.")],
    summary: "Removes the entry named by `key`; Success.",
    semantics: Semantics::new(Order::AllAtOnce, |_, _| Statuses::SUCCESS),
};

/// Precondition's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const PRECONDITION: NodeDecl = NodeDecl {
    name: "Precondition",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[
        PortDecl::input(
            "if",
            "String",
            "The script checked before the child starts.",
        ),
        PortDecl::input(
            "else",
            "String",
            "The status returned, without ticking the child, when `if` is false.",
        )
        .or("FAILURE"),
    ],
    summary:
        "Checks a script before its child starts; false gives the `else` status without ticking it.",
    semantics: Semantics::new(Order::in_turn(Statuses::ANY), |l, c| {
        // A script that does not evaluate fails.
        let otherwise = l.status("else").unwrap_or(Statuses::ANY);
        first(c).or(otherwise).or(Statuses::FAILURE)
    }),
};

/// The literal text of port `name`, or why it is missing.
fn literal<'a>(ports: &'a [Port], name: &str) -> Result<&'a str, MakerError> {
    match ports.iter().find(|p| p.name == name).map(|p| &p.value) {
        Some(PortValue::Literal(text)) => Ok(text),
        Some(PortValue::Entry(_)) => Err(MakerError::BadValue(format!(
            "port `{name}` must be literal text here"
        ))),
        None => Err(MakerError::MissingPort(format!("missing port `{name}`"))),
    }
}

/// A parsed script run as an action (`condition: false`) or a condition.
struct ScriptNode {
    script: Script,
    condition: bool,
    enums: Arc<Enums>,
}

impl<C> Action<C> for ScriptNode {
    fn tick(&self, h: &mut Handle<'_, C>) -> Status {
        let scope = h.scope();
        let stamp = h.now();
        let mut env = ScriptEnv {
            blackboard: h.blackboard_mut(),
            scope,
            enums: &self.enums,
            stamp,
            max_string_len: crate::script::DEFAULT_MAX_STRING_LEN,
        };
        match self.script.eval(&mut env) {
            Ok(value) if self.condition => Status::from(truthy(&value)),
            Ok(_) => Status::Success,
            Err(e) => {
                h.fail(format!("script `{}`: {e}", e.excerpt(self.script.source())));
                Status::Failure
            }
        }
    }

    fn reads_only_blackboard(&self) -> bool {
        // A script sees the blackboard and the enums, which are fixed at load.
        true
    }
}

fn truthy(value: &Value) -> bool {
    match value {
        Value::Bool(b) => *b,
        Value::Int(n) => *n != 0,
        Value::Real(r) => *r != 0.0,
        Value::Str(_) | Value::Empty => false,
    }
}

struct SetBlackboard {
    key: String,
}

impl<C> Action<C> for SetBlackboard {
    fn tick(&self, h: &mut Handle<'_, C>) -> Status {
        let (scope, stamp) = (h.scope(), h.now());
        // A literal written into a text entry reuses the entry's buffer: no allocation
        // once the entry exists.
        let ports = h.ports();
        if let Some(PortValue::Literal(text)) =
            ports.iter().find(|p| p.name == "value").map(|p| &p.value)
        {
            let written = h
                .blackboard_mut()
                .modify_in::<String>(scope, &self.key, stamp, |s| {
                    s.clear();
                    s.push_str(text);
                });
            if !written {
                h.blackboard_mut()
                    .replace_in(scope, &self.key, text.clone(), stamp);
            }
            return Status::Success;
        }
        let Ok(value) = h.input::<String>("value") else {
            return Status::Failure;
        };
        h.blackboard_mut()
            .replace_in(scope, &self.key, value, stamp);
        Status::Success
    }
}

struct UnsetBlackboard {
    key: String,
}

impl<C> Action<C> for UnsetBlackboard {
    fn tick(&self, h: &mut Handle<'_, C>) -> Status {
        let scope = h.scope();
        h.blackboard_mut().unset_in(scope, &self.key);
        Status::Success
    }
}

/// The entry named by port `name`: written as plain text (`key`) or as `{key}`.
fn key_of(ports: &[Port], name: &str) -> Result<String, MakerError> {
    match ports.iter().find(|p| p.name == name).map(|p| &p.value) {
        Some(PortValue::Literal(key) | PortValue::Entry(key)) => Ok(key.clone()),
        None => Err(MakerError::MissingPort(format!("missing port `{name}`"))),
    }
}

fn parse(ports: &[Port]) -> Result<Script, MakerError> {
    let code = literal(ports, "code")?;
    Script::parse(code)
        .map_err(|e| MakerError::Script(format!("in script `{}`: {e}", e.excerpt(code))))
}

/// BehaviorTree.CPP's Precondition decorator (see the module doc).
struct Precondition {
    /// The `if` script, parsed at load from a literal; with `if` bound to an entry, the
    /// script last read from it, parsed again only when the text changes (as
    /// BehaviorTree.CPP's `ScriptPrecondition` does).
    script: Option<Script>,
    /// `if` is read from the blackboard at each check.
    script_from_entry: bool,
    enums: Arc<Enums>,
    /// `else`: `None` when bound to an entry, read when `if` is false.
    otherwise: Option<NodeStatus>,
    child_running: bool,
}

impl Precondition {
    /// The script to check now: the literal's, or the entry's, parsed if it changed.
    fn script<C>(&mut self, node: &mut NodeCtx<'_, '_, C>) -> Result<&Script, String> {
        if self.script_from_entry {
            let code = node.input::<String>("if").map_err(|e| e.to_string())?;
            if self.script.as_ref().is_none_or(|s| s.source() != code) {
                let script = Script::parse(&code)
                    .map_err(|e| format!("in script `{}`: {e}", e.excerpt(&code)))?;
                self.script = Some(script);
            }
        }
        self.script
            .as_ref()
            .ok_or_else(|| String::from("no `if` script"))
    }

    /// `else`: the literal's status, or the entry's, read now.
    fn otherwise<C>(&self, node: &mut NodeCtx<'_, '_, C>) -> Result<NodeStatus, String> {
        match self.otherwise {
            Some(status) => Ok(status),
            None => status_of(&node.input::<String>("else").map_err(|e| e.to_string())?),
        }
    }
}

impl<C> CustomNode<C> for Precondition {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(self.child_running,)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(child_running,)| {
                self.child_running = child_running;
            })
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        // Its own answer reads the blackboard alone: a tree may sleep under it.
        node.wakes_with_children();
        if !self.child_running {
            let enums = Arc::clone(&self.enums);
            let script = match self.script(node) {
                Ok(script) => script.clone(),
                Err(message) => {
                    node.fail(message);
                    return NodeStatus::Failure;
                }
            };
            let (scope, stamp) = (node.scope(), node.now());
            let mut env = ScriptEnv {
                blackboard: node.blackboard(),
                scope,
                enums: &enums,
                stamp,
                max_string_len: crate::script::DEFAULT_MAX_STRING_LEN,
            };
            let holds = match script.eval(&mut env) {
                Ok(v) => truthy(&v),
                Err(e) => {
                    node.fail(format!("script `{}`: {e}", e.excerpt(script.source())));
                    return NodeStatus::Failure;
                }
            };
            if !holds {
                return match self.otherwise(node) {
                    Ok(status) => status,
                    Err(message) => {
                        node.fail(message);
                        NodeStatus::Failure
                    }
                };
            }
        }
        // As BehaviorTree.CPP's `_children_running`: set once `if` held, cleared only when
        // the child completes, so a Skipped child is ticked on without `if` again.
        self.child_running = true;
        let status = node.tick_child(0);
        if status.is_completed() {
            node.reset_children();
            self.child_running = false;
        }
        status
    }

    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {
        self.child_running = false;
    }
}

/// A status written in XML (`SUCCESS`, `FAILURE`, `RUNNING`, `SKIPPED`).
fn status_of(text: &str) -> Result<NodeStatus, String> {
    match text.trim().parse::<NodeStatus>() {
        Ok(NodeStatus::Idle) | Err(()) => Err(format!(
            "`{text}` is not a status; write SUCCESS, FAILURE, RUNNING or SKIPPED"
        )),
        Ok(status) => Ok(status),
    }
}

/// A Script (`condition: false`) or a ScriptCondition of the literal `code` in `ports`,
/// parsed now.
fn script_kind<C>(
    ports: &[Port],
    enums: &Arc<Enums>,
    condition: bool,
) -> Result<NodeKind<C>, MakerError> {
    let script = parse(ports)?;
    Ok(NodeKind::Action(Arc::new(ScriptNode {
        script,
        condition,
        enums: Arc::clone(enums),
    })))
}

/// A Precondition of `ports` (`if`, and `else`), its literal script parsed now.
fn precondition_kind<C>(ports: &[Port], enums: &Arc<Enums>) -> Result<NodeKind<C>, MakerError> {
    let enums = Arc::clone(enums);
    let bound = |name: &str| {
        matches!(
            ports.iter().find(|p| p.name == name).map(|p| &p.value),
            Some(PortValue::Entry(_))
        )
    };
    let script_from_entry = bound("if");
    let script = if script_from_entry {
        None
    } else {
        let code = literal(ports, "if")?;
        let parsed = Script::parse(code)
            .map_err(|e| MakerError::Script(format!("in script `{}`: {e}", e.excerpt(code))))?;
        Some(parsed)
    };
    let otherwise = if bound("else") {
        None
    } else {
        Some(status_of(literal(ports, "else")?)?)
    };
    Ok(NodeKind::Custom(Box::new(CustomSpec::new(
        PRECONDITION.name,
        Arity::One,
        Box::new(move || {
            Box::new(Precondition {
                script: script.clone(),
                script_from_entry,
                enums: Arc::clone(&enums),
                otherwise,
                child_running: false,
            })
        }),
    ))))
}

/// Adds the nodes of this module to `registry`.
pub(crate) fn register<C: 'static>(registry: &mut Registry<C>) {
    registry.register_declared(
        &SCRIPT,
        Arc::new(|ports, enums| script_kind(ports, enums, false)),
    );
    registry.register_declared(
        &SCRIPT_CONDITION,
        Arc::new(|ports, enums| script_kind(ports, enums, true)),
    );
    registry.register_declared(
        &SET_BLACKBOARD,
        Arc::new(|ports, _| {
            let key = key_of(ports, "output_key")?;
            Ok(NodeKind::Action(Arc::new(SetBlackboard { key })))
        }),
    );
    registry.register_declared(&PRECONDITION, Arc::new(precondition_kind));
    registry.register_declared(
        &UNSET_BLACKBOARD,
        Arc::new(|ports, _| {
            let key = key_of(ports, "key")?;
            Ok(NodeKind::Action(Arc::new(UnsetBlackboard { key })))
        }),
    );
}

/// Script, ScriptCondition and Precondition in the [`Builder`]: the same nodes as in XML
/// (saved as `<Script code="…"/>` and so on), their scripts parsed when added. A script
/// that does not parse fails [`Builder::build`] at its node
/// ([`BuildErrorKind::Rejected`](neurotree_core::BuildErrorKind::Rejected)). Scripts built
/// so know no enum values (a [`Registry`]'s belong to the trees it loads).
///
/// ```
/// use neurotree::prelude::*;
///
/// let blueprint = Blueprint::<()>::builder()
///     .sequence("setup", |s| {
///         s.script("laps", "laps := 2; done := false")
///             .precondition("", "laps > 1", |p| p.script("", "done := true"))
///             .script_condition("check", "done == true")
///     })
///     .build_shared()
///     .unwrap();
/// let mut tree = Tree::with_clock(blueprint, ManualClock::new());
/// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
/// assert_eq!(tree.blackboard().get::<bool>("done"), Ok(true));
///
/// let bad = Blueprint::<()>::builder().script("oops", "x := ").build();
/// assert!(bad.unwrap_err().to_string().starts_with("oops: in script"));
/// ```
pub trait ScriptBuilder: Sized {
    /// A Script: runs `code` on the blackboard; Success.
    fn script(self, name: &str, code: &str) -> Self;

    /// A ScriptCondition: Success if the value of `code` is true, else Failure.
    fn script_condition(self, name: &str, code: &str) -> Self;

    /// A Precondition: ticks the child `child` adds only if the script `condition` holds
    /// when the child has not been started; else Failure, without ticking it.
    fn precondition(self, name: &str, condition: &str, child: impl FnOnce(Self) -> Self) -> Self;
}

impl<C: 'static> ScriptBuilder for Builder<C> {
    fn script(self, name: &str, code: &str) -> Self {
        script_leaf(self, &SCRIPT, name, code)
    }

    fn script_condition(self, name: &str, code: &str) -> Self {
        script_leaf(self, &SCRIPT_CONDITION, name, code)
    }

    fn precondition(self, name: &str, condition: &str, child: impl FnOnce(Self) -> Self) -> Self {
        let name = if name.is_empty() {
            PRECONDITION.name
        } else {
            name
        };
        let ports = [
            Port::literal("if", condition),
            Port::literal("else", "FAILURE"),
        ];
        match precondition_kind(&ports, &Arc::default()) {
            Ok(kind) => self.node(kind, name, |b| {
                child(b.type_id(PRECONDITION.name).ports(ports))
            }),
            Err(e) => self.node(stand_in(Category::Decorator), name, |b| {
                child(b.reject(e.into_parts().1))
            }),
        }
    }
}

/// Adds the Script or ScriptCondition `decl` of `code`, named `name` (its type without one).
fn script_leaf<C: 'static>(b: Builder<C>, decl: &NodeDecl, name: &str, code: &str) -> Builder<C> {
    let name = if name.is_empty() { decl.name } else { name };
    let ports = [Port::literal("code", code)];
    let condition = decl.category == Category::Condition;
    match script_kind(&ports, &Arc::default(), condition) {
        Ok(kind) => b.leaf(kind, name).type_id(decl.name).ports(ports),
        Err(e) => b
            .leaf(stand_in(decl.category), name)
            .reject(e.into_parts().1),
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn precondition_keeps_ticking_a_child_that_returned_skipped() {
        // BehaviorTree.CPP clears its "children running" flag only when the child completes
        // (Success or Failure): after a Skipped child, `if` is not evaluated again.
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(r#"<Precondition if="go"><L0 _skipIf="skip"/></Precondition>"#);
        tree.blackboard_mut().set("go", true).unwrap();
        tree.blackboard_mut().set("skip", true).unwrap();
        assert_eq!(lab.tick(&mut tree), Err(TickError::RootSkipped));
        tree.blackboard_mut().set("go", false).unwrap();
        assert_eq!(lab.tick(&mut tree), Err(TickError::RootSkipped));
        tree.blackboard_mut().set("skip", false).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!((lab.ticks[0], lab.halts[0]), (1, 0));
        // Completed: the flag is cleared, `if` (now false) decides: the `else` status.
        assert_eq!(lab.tick(&mut tree), Ok(F));
        assert_eq!(lab.ticks, [1]);
    }

    #[test]
    fn the_builder_adds_the_script_nodes_as_a_file_writes_them() {
        use crate::xml::{write_xml, SaveOptions};
        use crate::Registry;
        use neurotree_core::{Blueprint, BuildErrorKind, ManualClock, Status as St, Tree};

        use super::ScriptBuilder;

        let bp = Blueprint::<u32>::builder()
            .sequence("root", |s| {
                s.script("", "n := n + 1")
                    .precondition("gate", "n > 1", |p| {
                        p.action("count", |c: &mut u32| {
                            *c += 1;
                            St::Success
                        })
                    })
                    .script_condition("small", "n < 3")
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        tree.blackboard_mut().set("n", 0i64).unwrap();
        let mut counted = 0;
        // n = 1: the gate is shut (Failure), the condition never reached.
        assert_eq!(tree.tick_once(&mut counted), Ok(St::Failure));
        assert_eq!(counted, 0);
        // n = 2: the gate opens, n < 3 holds.
        assert_eq!(tree.tick_once(&mut counted), Ok(St::Success));
        assert_eq!(counted, 1);
        // n = 3: the gate opens, n < 3 fails.
        assert_eq!(tree.tick_once(&mut counted), Ok(St::Failure));
        assert_eq!(counted, 2);
        assert!(tree.blueprint().find("root/Script").is_some());

        // Written as a file names them.
        let registry = Registry::<u32>::new();
        let xml = write_xml(tree.blueprint(), &registry, &SaveOptions::default());
        assert!(
            xml.contains(r#"<Script name="Script" code="n := n + 1"/>"#),
            "{xml}"
        );
        assert!(
            xml.contains(r#"<ScriptCondition name="small" code="n &lt; 3"/>"#),
            "{xml}"
        );
        assert!(
            xml.contains(r#"<Precondition name="gate" if="n &gt; 1" else="FAILURE">"#),
            "{xml}"
        );

        // A script that does not parse fails the build at its node; the first such node is named.
        let e = Blueprint::<u32>::builder()
            .sequence("root", |s| {
                s.script_condition("bad", "n <")
                    .precondition("worse", "(", |p| p.script("", ")"))
            })
            .build()
            .unwrap_err();
        assert_eq!(e.path, "root/bad");
        assert!(matches!(e.kind, BuildErrorKind::Rejected { .. }), "{e}");
        let e = Blueprint::<u32>::builder()
            .precondition("worse", "(", |p| p.script("", "n := 1"))
            .build()
            .unwrap_err();
        assert_eq!(e.path, "worse");
    }
}
