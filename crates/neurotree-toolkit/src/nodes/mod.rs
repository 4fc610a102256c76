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
//!
//! [`hooks`] (also `std`) runs the `_skipIf`, `_successIf`, `_failureIf`, `_while`,
//! `_onSuccess`, `_onFailure`, `_post` and `_onHalted` scripts any node may carry. Every
//! built-in is registered by its BehaviorTree.CPP name in each new
//! [`Registry`](crate::Registry).

pub use neurotree_core::nodes::{control, custom, decorator, leaf};

pub mod entry;
pub mod hooks;
pub mod loops;
pub mod script;
pub mod switch;
