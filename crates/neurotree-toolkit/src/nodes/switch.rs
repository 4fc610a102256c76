//! Switch2 … Switch6: pick a child by the value of a variable.
//!
//! Ports `variable`, `case_1..N`; last child is the default. Re-evaluated every tick (string
//! equality, then integer, then float); a change of match halts the previous branch.
//!
//! `variable` and the cases are literal text or blackboard entries (of text, integer, real or
//! boolean type). Comparing them allocates nothing.

use std::sync::Arc;

use neurotree_core::{
    Arity, Blackboard, Category, CustomNode, CustomSpec, NodeCtx, NodeKind, NodeStatus, Port,
    PortValue, ScopeId,
};

use crate::registry::{PortSpec, Registry};

/// A value to compare, borrowed from the blueprint or the blackboard.
#[derive(Clone, Copy)]
enum Val<'a> {
    Text(&'a str),
    Int(i64),
    Real(f64),
}

impl Val<'_> {
    fn int(self) -> Option<i64> {
        match self {
            Val::Int(i) => Some(i),
            Val::Text(t) => t.trim().parse().ok(),
            Val::Real(_) => None,
        }
    }

    fn real(self) -> Option<f64> {
        match self {
            Val::Int(i) => Some(i as f64),
            Val::Real(r) => Some(r),
            Val::Text(t) => t.trim().parse().ok(),
        }
    }

    /// BehaviorTree.CPP's rule: equal as text, else as integers, else as reals.
    fn matches(self, other: Val<'_>) -> bool {
        if let (Val::Text(a), Val::Text(b)) = (self, other) {
            if a == b {
                return true;
            }
        }
        if let (Some(a), Some(b)) = (self.int(), other.int()) {
            return a == b;
        }
        matches!((self.real(), other.real()), (Some(a), Some(b)) if (a - b).abs() <= f64::EPSILON)
    }
}

/// Where a value comes from.
#[derive(Clone)]
enum Source {
    Literal(String),
    Entry(String),
}

impl Source {
    fn read<'a>(&'a self, bb: &'a Blackboard, scope: ScopeId) -> Option<Val<'a>> {
        let key = match self {
            Source::Literal(text) => return Some(Val::Text(text)),
            Source::Entry(key) => key,
        };
        let any = bb.get_any_in(scope, key)?;
        if let Some(s) = any.downcast_ref::<String>() {
            Some(Val::Text(s))
        } else if let Some(i) = any.downcast_ref::<i64>() {
            Some(Val::Int(*i))
        } else if let Some(i) = any.downcast_ref::<i32>() {
            Some(Val::Int(i64::from(*i)))
        } else if let Some(r) = any.downcast_ref::<f64>() {
            Some(Val::Real(*r))
        } else {
            any.downcast_ref::<bool>().map(|b| Val::Int(i64::from(*b)))
        }
    }
}

struct Switch {
    variable: Option<Source>,
    cases: Vec<Option<Source>>,
    running: Option<usize>,
}

impl Switch {
    /// The index of the first matching case, else the default (the last child).
    fn choose(&self, bb: &Blackboard, scope: ScopeId) -> usize {
        let default = self.cases.len();
        let Some(variable) = self.variable.as_ref().and_then(|v| v.read(bb, scope)) else {
            return default;
        };
        self.cases
            .iter()
            .position(|case| {
                case.as_ref()
                    .and_then(|c| c.read(bb, scope))
                    .is_some_and(|value| variable.matches(value))
            })
            .unwrap_or(default)
    }
}

impl<C> CustomNode<C> for Switch {
    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let scope = node.scope();
        let chosen = self.choose(node.blackboard(), scope);
        if let Some(previous) = self.running.filter(|&p| p != chosen) {
            node.halt_child(previous);
        }
        let status = node.tick_child(chosen);
        match status {
            NodeStatus::Running => self.running = Some(chosen),
            NodeStatus::Skipped => self.running = None,
            _ => {
                node.reset_children();
                self.running = None;
            }
        }
        status
    }

    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {
        self.running = None;
    }
}

fn source(ports: &[Port], name: &str) -> Option<Source> {
    ports
        .iter()
        .find(|p| p.name == name)
        .map(|p| match &p.value {
            PortValue::Literal(text) => Source::Literal(text.clone()),
            PortValue::Entry(key) => Source::Entry(key.clone()),
        })
}

/// Adds Switch2 … Switch6 to `registry`.
pub(crate) fn register<C: 'static>(registry: &mut Registry<C>) {
    for n in 2..=6_usize {
        let name = format!("Switch{n}");
        let mut ports = vec![PortSpec::input::<String>("variable")];
        ports.extend((1..=n).map(|i| PortSpec::input::<String>(&format!("case_{i}"))));
        let type_name = name.clone();
        registry
            .register_leaf(
                &name,
                Category::Control,
                ports,
                Arc::new(move |ports, _| {
                    let variable = source(ports, "variable");
                    let cases: Vec<Option<Source>> = (1..=n)
                        .map(|i| source(ports, &format!("case_{i}")))
                        .collect();
                    Ok(NodeKind::Custom(Box::new(CustomSpec {
                        type_name: type_name.clone(),
                        arity: Arity::Range {
                            min: n as u32 + 1,
                            max: n as u32 + 1,
                        },
                        factory: Box::new(move || {
                            Box::new(Switch {
                                variable: variable.clone(),
                                cases: cases.clone(),
                                running: None,
                            })
                        }),
                    })))
                }),
            )
            // Registry::new registers each built-in name once.
            .expect("built-in node names are distinct");
    }
}
