//! Pre- and post-conditions written as scripts, from BehaviorTree.CPP's `_failureIf`,
//! `_successIf`, `_skipIf`, `_while`, `_onSuccess`, `_onFailure`, `_post` and `_onHalted`
//! attributes. The engine's [`NodeHooks`] says when each runs; this module runs them.
//!
//! A script whose evaluation fails (an unknown key, a type mismatch) is an error of the tick
//! ([`TickError::Node`](neurotree_core::TickError::Node)), as BehaviorTree.CPP throws one; a
//! failed condition script decides nothing.

pub use neurotree_core::nodes::hooks::NodeHooks;

use std::sync::Arc;

use neurotree_core::{Handle, NodeStatus};

use crate::script::{Enums, Script, ScriptEnv, Value};

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
    /// The registry's enum names, which the scripts may use.
    pub(crate) enums: Arc<Enums>,
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

/// Runs `script`; a failure is reported as the tick's error and gives `None`.
fn run<C>(script: &Script, enums: &Enums, h: &mut Handle<'_, C>) -> Option<Value> {
    let scope = h.scope();
    let stamp = h.now();
    let mut env = ScriptEnv {
        blackboard: h.blackboard_mut(),
        scope,
        enums,
        stamp,
        max_string_len: crate::script::DEFAULT_MAX_STRING_LEN,
    };
    match script.eval(&mut env) {
        Ok(value) => Some(value),
        Err(e) => {
            h.fail(format!("script `{}`: {e}", e.excerpt(script.source())));
            None
        }
    }
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

impl ScriptHooks {
    /// Whether the condition script holds: `Ok(None)` if there is none, `Err` if it failed to
    /// run (the error is already reported).
    fn holds<C>(&self, script: &Option<Script>, h: &mut Handle<'_, C>) -> Result<Option<bool>, ()> {
        let Some(script) = script else {
            return Ok(None);
        };
        let value = run(script, &self.enums, h).ok_or(())?;
        Ok(Some(match value {
            Value::Bool(b) => b,
            Value::Int(n) => n != 0,
            Value::Real(r) => r != 0.0,
            _ => false,
        }))
    }

    /// The decision of the checks made while the node is Idle, in BehaviorTree.CPP's order.
    fn decide<C>(&self, h: &mut Handle<'_, C>) -> Result<Option<NodeStatus>, ()> {
        if self.holds(&self.failure_if, h)? == Some(true) {
            return Ok(Some(NodeStatus::Failure));
        }
        if self.holds(&self.success_if, h)? == Some(true) {
            return Ok(Some(NodeStatus::Success));
        }
        if self.holds(&self.skip_if, h)? == Some(true) {
            return Ok(Some(NodeStatus::Skipped));
        }
        if self.holds(&self.while_true, h)? == Some(false) {
            return Ok(Some(NodeStatus::Skipped));
        }
        Ok(None)
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
        // A script that failed to run has made the tick an error; the node does not run.
        if stored == NodeStatus::Running {
            return match self.holds(&self.while_true, h) {
                Ok(Some(false)) => Some(NodeStatus::Skipped),
                Ok(_) => None,
                Err(()) => Some(NodeStatus::Failure),
            };
        }
        self.decide(h).unwrap_or(Some(NodeStatus::Failure))
    }

    fn after(&self, h: &mut Handle<'_, C>, status: NodeStatus) {
        let first = match status {
            NodeStatus::Success => &self.on_success,
            _ => &self.on_failure,
        };
        for script in [first, &self.post].into_iter().flatten() {
            run(script, &self.enums, h);
        }
    }

    fn halted(&self, h: &mut Handle<'_, C>) {
        if let Some(script) = &self.on_halted {
            run(script, &self.enums, h);
        }
    }
}
