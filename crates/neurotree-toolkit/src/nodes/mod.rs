//! The built-in nodes that need the standard library: they read scripts, text and
//! blackboard entries by name, so they live here rather than in the `no_std` core.
//!
//! | module | nodes |
//! |---|---|
//! | [`script`] | Script, ScriptCondition, SetBlackboard, UnsetBlackboard, Precondition |
//! | [`switch`] | Switch2 … Switch6 |
//! | [`loops`] | LoopInt, LoopDouble, LoopString, LoopBool |
//! | [`entry`] | WasEntryUpdated, SkipUnlessUpdated, WaitValueUpdate |
//! | [`hooks`] | the `_skipIf`, `_successIf`, `_failureIf`, `_while`, `_onSuccess`, `_onFailure`, `_post` and `_onHalted` scripts any node may carry |
//!
//! Each is registered by name in every [`Registry`](crate::Registry); the core's built-ins
//! (Sequence, Retry, Timeout, ...) are documented in [`neurotree_core::nodes`].

pub mod entry;
pub(crate) mod hooks;
pub mod loops;
pub mod script;
pub mod switch;
