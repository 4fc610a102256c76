//! Pre- and post-conditions written as scripts, from BehaviorTree.CPP's `_failureIf`,
//! `_successIf`, `_skipIf`, `_while`, `_onSuccess`, `_onFailure`, `_post` and `_onHalted`
//! attributes. The engine's [`NodeHooks`] says when each runs; this module runs them.
//!
//! As BehaviorTree.CPP's `TreeNode::checkPreConditions`: `_failureIf`, `_successIf`,
//! `_skipIf` and `_while` are checked in that order only while the node is Idle (or was
//! skipped), the first that decides wins; while it is Running only `_while` is (false: halt
//! it, Skipped); a node that completed and was not reset yet by its parent (a two-child
//! IfThenElse's failed condition, a PipelineSequence's finished child) is ticked with no
//! check. After a Success or Failure, `_onSuccess` or `_onFailure`, then `_post`;
//! `_onHalted` after a halt of a Running node.
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
    fn reads_only_blackboard(&self) -> bool {
        // Scripts see the blackboard and the enums fixed at load.
        true
    }

    fn attributes(&self, f: &mut dyn FnMut(&str, &str)) {
        for (name, script) in self.scripts() {
            if let Some(script) = script {
                f(name, script.source());
            }
        }
    }

    fn before(&self, h: &mut Handle<'_, C>, stored: NodeStatus) -> Option<NodeStatus> {
        // As BehaviorTree.CPP's `checkPreConditions`: all four while Idle (or Skipped), only
        // `_while` while Running, none on a completed node its parent has not reset yet.
        // A script that failed to run has made the tick an error; the node does not run.
        match stored {
            NodeStatus::Idle | NodeStatus::Skipped => {
                self.decide(h).unwrap_or(Some(NodeStatus::Failure))
            }
            NodeStatus::Running => match self.holds(&self.while_true, h) {
                Ok(Some(false)) => Some(NodeStatus::Skipped),
                Ok(_) => None,
                // BehaviorTree.CPP's exception leaves the node Running, not halted.
                Err(()) => Some(NodeStatus::Running),
            },
            NodeStatus::Success | NodeStatus::Failure => None,
        }
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

#[cfg(test)]
mod tests {
    use crate::testing::*;

    /// `Nope`: a sync action that records "nope" and fails.
    fn lab_with_nope(scripts: &[&[Status]]) -> (Lab, crate::Registry<Lab>) {
        let lab = Lab::new(scripts);
        let mut r = lab.registry();
        r.register_action("Nope", vec![], |h| {
            h.ctx_mut().said.push("nope".into());
            Status::Failure
        })
        .unwrap();
        (lab, r)
    }

    #[test]
    fn conditions_are_checked_only_while_the_node_is_idle() {
        // A two-child IfThenElse leaves its failed condition un-reset: on the next tick the
        // condition is Failure, not Idle, so BehaviorTree.CPP's checkPreConditions skips
        // `_successIf` and ticks it.
        let (mut lab, r) = lab_with_nope(&[&[S]]);
        let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="T">
              <IfThenElse><Nope _successIf="flag"/><L0/></IfThenElse>
            </BehaviorTree></root>"#;
        let mut tree = lab.load_with(&r, xml).unwrap();
        tree.blackboard_mut().set("flag", false).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(F));
        tree.blackboard_mut().set("flag", true).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(F));
        assert_eq!(lab.said, ["nope", "nope"]);
        assert_eq!(lab.ticks, [0]);
        // Once the tree is halted (and so reset), the condition is Idle: `_successIf` decides.
        tree.halt(&mut lab);
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(lab.said, ["nope", "nope"]);
        assert_eq!(lab.ticks, [1]);
    }

    #[test]
    fn a_while_that_fails_to_run_ends_the_tick_before_the_parent_moves_on() {
        // BehaviorTree.CPP's exception leaves the node Running and ticks nothing after it:
        // the Fallback does not try L1. The tick is an error, which halts the tree.
        let mut lab = Lab::new(&[&[R, R, S], &[S]]);
        let mut tree = lab.tree(r#"<Fallback><L0 _while="n * 2 > 0"/><L1/></Fallback>"#);
        tree.blackboard_mut().set("n", 1i64).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        tree.blackboard_mut().set("n", i64::MAX).unwrap();
        assert!(lab.tick(&mut tree).is_err());
        assert_eq!((lab.ticks.as_slice(), lab.halts[0]), ([1, 0].as_slice(), 1));
    }

    #[test]
    fn skip_if_is_not_checked_while_running() {
        let mut lab = Lab::new(&[&[R, R, S]]);
        let mut tree = lab.tree(r#"<L0 _skipIf="skip"/>"#);
        tree.blackboard_mut().set("skip", false).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        tree.blackboard_mut().set("skip", true).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!((lab.ticks[0], lab.halts[0]), (3, 0));
        // Idle again: now it is skipped.
        assert_eq!(lab.tick(&mut tree), Err(TickError::RootSkipped));
        assert_eq!(lab.ticks, [3]);
    }
}
