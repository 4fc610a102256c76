//! Pre- and post-conditions written as scripts, from BehaviorTree.CPP's `_failureIf`,
//! `_successIf`, `_skipIf`, `_while`, `_onSuccess`, `_onFailure`, `_post` and `_onHalted`
//! attributes. The engine's [`NodeHooks`] says when each runs; this module runs them.
//!
//! A condition script whose evaluation fails (an unknown key, a type mismatch) counts as
//! false.

use neurotree_core::{Handle, NodeHooks, NodeStatus};

use crate::script::{Enums, Script, ScriptEnv, Value};

static NO_ENUMS: Enums = Enums::new();

/// The attribute names, in the order BehaviorTree.CPP checks them.
pub(crate) const ATTRIBUTES: [&str; 8] = [
    "_failureIf",
    "_successIf",
    "_skipIf",
    "_while",
    "_onSuccess",
    "_onFailure",
    "_post",
    "_onHalted",
];

/// One node's condition and action scripts.
#[derive(Default)]
pub(crate) struct ScriptHooks {
    pub(crate) failure_if: Option<Script>,
    pub(crate) success_if: Option<Script>,
    pub(crate) skip_if: Option<Script>,
    pub(crate) while_true: Option<Script>,
    pub(crate) on_success: Option<Script>,
    pub(crate) on_failure: Option<Script>,
    pub(crate) post: Option<Script>,
    pub(crate) on_halted: Option<Script>,
}

impl ScriptHooks {
    /// Sets the script of attribute `name` (one of [`ATTRIBUTES`]).
    pub(crate) fn set(&mut self, name: &str, script: Script) {
        let slot = match name {
            "_failureIf" => &mut self.failure_if,
            "_successIf" => &mut self.success_if,
            "_skipIf" => &mut self.skip_if,
            "_while" => &mut self.while_true,
            "_onSuccess" => &mut self.on_success,
            "_onFailure" => &mut self.on_failure,
            "_post" => &mut self.post,
            _ => &mut self.on_halted,
        };
        *slot = Some(script);
    }
}

fn run<C>(script: &Script, h: &mut Handle<'_, C>) -> Option<Value> {
    let scope = h.scope();
    let stamp = h.now();
    let mut env = ScriptEnv {
        blackboard: h.blackboard_mut(),
        scope,
        enums: &NO_ENUMS,
        stamp,
    };
    script.eval(&mut env).ok()
}

fn holds<C>(script: &Option<Script>, h: &mut Handle<'_, C>) -> Option<bool> {
    script.as_ref().map(|s| match run(s, h) {
        Some(Value::Bool(b)) => b,
        Some(Value::Int(n)) => n != 0,
        Some(Value::Real(r)) => r != 0.0,
        _ => false,
    })
}

impl ScriptHooks {
    /// The scripts with their attribute names, in [`ATTRIBUTES`] order.
    fn scripts(&self) -> [(&'static str, &Option<Script>); 8] {
        [
            ("_failureIf", &self.failure_if),
            ("_successIf", &self.success_if),
            ("_skipIf", &self.skip_if),
            ("_while", &self.while_true),
            ("_onSuccess", &self.on_success),
            ("_onFailure", &self.on_failure),
            ("_post", &self.post),
            ("_onHalted", &self.on_halted),
        ]
    }
}

impl<C> NodeHooks<C> for ScriptHooks {
    fn attributes(&self, f: &mut dyn FnMut(&str, &str)) {
        for (name, script) in self.scripts() {
            if let Some(script) = script {
                f(name, script.source());
            }
        }
    }

    fn before(&self, h: &mut Handle<'_, C>, stored: NodeStatus) -> Option<NodeStatus> {
        if stored == NodeStatus::Running {
            return match holds(&self.while_true, h) {
                Some(false) => Some(NodeStatus::Skipped),
                _ => None,
            };
        }
        if holds(&self.failure_if, h) == Some(true) {
            return Some(NodeStatus::Failure);
        }
        if holds(&self.success_if, h) == Some(true) {
            return Some(NodeStatus::Success);
        }
        if holds(&self.skip_if, h) == Some(true) {
            return Some(NodeStatus::Skipped);
        }
        if holds(&self.while_true, h) == Some(false) {
            return Some(NodeStatus::Skipped);
        }
        None
    }

    fn after(&self, h: &mut Handle<'_, C>, status: NodeStatus) {
        let first = match status {
            NodeStatus::Success => &self.on_success,
            _ => &self.on_failure,
        };
        for script in [first, &self.post].into_iter().flatten() {
            run(script, h);
        }
    }

    fn halted(&self, h: &mut Handle<'_, C>) {
        if let Some(script) = &self.on_halted {
            run(script, h);
        }
    }
}
