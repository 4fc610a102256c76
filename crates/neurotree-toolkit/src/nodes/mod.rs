//! The node catalog: every built-in node, one module each, with its semantics, ports and
//! tests.
//!
//! Four modules come from the `no_std` engine ([`neurotree_core::nodes`]), each with its own
//! table:
//!
//! - [`control`]: Sequence, Fallback and their reactive, memory and async forms, Parallel,
//!   ParallelAll, IfThenElse, WhileDoElse, TryCatch.
//! - [`decorator`]: Inverter, ForceSuccess, ForceFailure, Repeat, RetryUntilSuccessful,
//!   KeepRunningUntilFailure, Delay, Timeout, Cooldown, RunOnce, SubTree.
//! - [`leaf`]: conditions, actions, stateful and async actions, AlwaysSuccess, AlwaysFailure,
//!   Sleep.
//! - [`custom`]: the door for your own controls and decorators.
//!
//! The others read scripts, text and blackboard entries by name, which needs `std`:
//!
//! | node | in short |
//! |---|---|
//! | [Script](script) | run a script; Success |
//! | [ScriptCondition](script) | Success if a script's value is true |
//! | [SetBlackboard](script) | write an entry; Success |
//! | [UnsetBlackboard](script) | remove an entry; Success |
//! | [Precondition](script) | tick the child only if a script is true |
//! | [Switch2 … Switch6](switch) | pick a child by the value of a variable |
//! | [LoopInt, LoopDouble, LoopString, LoopBool](loops) | run the child once per queue element |
//! | [WasEntryUpdated](entry) | Success if an entry was written since the last look |
//! | [SkipUnlessUpdated](entry) | tick the child after a write, else Skipped |
//! | [WaitValueUpdate](entry) | wait for a write, then tick the child |
//! | [UtilitySelector](utility_selector) | tick the child with the highest score |
//! | [Utility](utility) | give a UtilitySelector's child its score |
//!
//! [`hooks`] (also `std`) runs the `_skipIf`, `_successIf`, `_failureIf`, `_while`,
//! `_onSuccess`, `_onFailure`, `_post` and `_onHalted` scripts any node may carry. Every
//! built-in is registered by its BehaviorTree.CPP name in each new
//! [`Registry`](crate::Registry), as its module declares it ([`NodeDecl`]): the engine's in
//! [`neurotree_core::nodes::BUILT_INS`], these in [`STD_BUILT_INS`]; [`built_ins`] walks
//! both, and the README's node catalog is made from them.

pub use neurotree_core::nodes::{
    built_in, control, custom, decorator, kinds, leaf, semantics, NodeDecl,
};

pub mod entry;
pub mod hooks;
pub mod loops;
pub mod script;
pub mod switch;
pub mod utility;
pub mod utility_selector;

/// The built-in nodes of this crate, as declared in their modules, in catalog order.
pub const STD_BUILT_INS: &[&NodeDecl] = &[
    &script::SCRIPT,
    &script::SCRIPT_CONDITION,
    &script::SET_BLACKBOARD,
    &script::UNSET_BLACKBOARD,
    &script::PRECONDITION,
    &switch::SWITCH2,
    &switch::SWITCH3,
    &switch::SWITCH4,
    &switch::SWITCH5,
    &switch::SWITCH6,
    &loops::LOOP_INT,
    &loops::LOOP_DOUBLE,
    &loops::LOOP_STRING,
    &loops::LOOP_BOOL,
    &entry::WAS_ENTRY_UPDATED,
    &entry::SKIP_UNLESS_UPDATED,
    &entry::WAIT_VALUE_UPDATE,
    &utility_selector::UTILITY_SELECTOR,
    &utility::UTILITY,
];

/// Every built-in node a new [`Registry`](crate::Registry) holds: the engine's, then this
/// crate's.
pub fn built_ins() -> impl Iterator<Item = &'static NodeDecl> {
    let core = neurotree_core::nodes::BUILT_INS.iter();
    core.chain(STD_BUILT_INS).copied()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::registry::{Make, Registry};
    use crate::PortSpec;

    #[test]
    fn every_built_in_is_registered_as_declared_and_nothing_else() {
        let r = Registry::<()>::new();
        let mut names: Vec<&str> = built_ins().map(|d| d.name).collect();
        for d in built_ins() {
            let t = r
                .get(d.name)
                .unwrap_or_else(|| panic!("{} is not registered", d.name));
            assert!(t.builtin && !matches!(t.make, Make::Model), "{}", d.name);
            assert_eq!(t.category, d.category, "{}", d.name);
            let declared: Vec<PortSpec> = d.ports.iter().map(PortSpec::from).collect();
            assert_eq!(
                format!("{:?}", t.ports),
                format!("{declared:?}"),
                "{}",
                d.name
            );
            for p in d.ports {
                assert!(
                    neurotree_core::nodes::PORT_TYPES.contains(&p.type_name),
                    "{}.{}",
                    d.name,
                    p.name
                );
            }
        }
        let registered: Vec<&str> = r.types().map(|t| t.name.as_str()).collect();
        names.sort_unstable();
        let before = names.len();
        names.dedup();
        assert_eq!(names.len(), before, "a name is declared twice");
        assert_eq!(
            registered, names,
            "registered but not declared, or the reverse"
        );
    }
}
