//! The node catalog: every built-in node, one module each, with its semantics, ports and
//! tests.
//!
//! | module | nodes |
//! |---|---|
//! | [`control`] | Sequence, Fallback and their reactive, memory and async forms, Parallel, ParallelAll, IfThenElse, WhileDoElse, TryCatch |
//! | [`decorator`] | Inverter, ForceSuccess, ForceFailure, Repeat, RetryUntilSuccessful, KeepRunningUntilFailure, Delay, Timeout, Cooldown, RunOnce, SubTree |
//! | [`leaf`] | conditions, actions, stateful and async actions, AlwaysSuccess, AlwaysFailure, Sleep |
//! | [`custom`] | the door for your own controls and decorators |
//! | [`script`] | Script, ScriptCondition, SetBlackboard, UnsetBlackboard, Precondition |
//! | [`switch`] | Switch2 … Switch6 |
//! | [`loops`] | LoopInt, LoopDouble, LoopString, LoopBool |
//! | [`entry`] | WasEntryUpdated, SkipUnlessUpdated, WaitValueUpdate |
//! | [`hooks`] | the `_skipIf`, `_successIf`, `_failureIf`, `_while`, `_onSuccess`, `_onFailure`, `_post` and `_onHalted` scripts any node may carry |
//!
//! The first four come from the `no_std` engine ([`neurotree_core::nodes`]); the others
//! read scripts, text and blackboard entries by name, which needs `std`. Every built-in is
//! registered by its BehaviorTree.CPP name in each new [`Registry`](crate::Registry).

pub use neurotree_core::nodes::{control, custom, decorator, leaf};

pub mod entry;
pub mod hooks;
pub mod loops;
pub mod script;
pub mod switch;
