//! Control nodes: they tick their children and combine the results.
//!
//! | node | in short |
//! |---|---|
//! | [Sequence](sequence) | all children in order, until one fails |
//! | [SequenceWithMemory](sequence) | a Sequence that keeps its place |
//! | [AsyncSequence](sequence) | a Sequence that yields between children |
//! | [Fallback](fallback) | children in order, until one succeeds |
//! | [AsyncFallback](fallback) | a Fallback that yields between children |
//! | [ReactiveSequence](reactive) | a Sequence re-checked from the first child |
//! | [ReactiveFallback](reactive) | a Fallback re-checked from the first child |
//! | [Parallel](parallel) | every child; decide by thresholds |
//! | [ParallelAll](parallel_all) | every child to completion; count failures |
//! | [IfThenElse](if_then_else) | pick a branch by a condition |
//! | [WhileDoElse](while_do_else) | a branch by a condition re-checked every tick |
//! | [TryCatch](try_catch) | a Sequence with a catch child |
//! | [Service](service) | a child at an interval while the other runs |
//!
//! They differ in what they remember between ticks, whether they re-check earlier children,
//! and whether they yield:
//!
//! - Sequence / Fallback resume at the running child.
//! - SequenceWithMemory keeps its place even after a failure or a halt, and yields after each
//!   child success.
//! - AsyncSequence / AsyncFallback remember as Sequence / Fallback, and yield after each child
//!   that completed at once.
//! - ReactiveSequence / ReactiveFallback remember nothing and re-check every child every tick.
//! - Parallel / ParallelAll remember the completed children.
//! - IfThenElse remembers the chosen branch.
//! - WhileDoElse remembers nothing and re-checks the condition every tick.
//! - TryCatch remembers as Sequence, then the catch child.
//! - Service remembers when it last ticked its service child.
//!
//! No other control yields, and no other re-checks earlier children.
//!
//! Every control marks itself Running before ticking its children, resets all its children
//! to Idle when it completes, and halts Running children it stops ticking before it returns.
//! When such a halt takes ticks, ReactiveSequence, ReactiveFallback, WhileDoElse and
//! Parallel wait for it, returning Running; see [`slow_halt`](crate::tree::slow_halt).

pub mod fallback;
pub mod if_then_else;
pub(crate) mod ordered;
pub mod parallel;
pub mod parallel_all;
pub mod reactive;
pub mod sequence;
pub mod service;
pub mod try_catch;
pub mod while_do_else;

/// A cursor and a count of skipped children, packed in one state slot.
#[inline(always)]
pub(crate) fn unpack(slot: u64) -> (u32, u32) {
    (slot as u32, (slot >> 32) as u32)
}

/// The inverse of [`unpack`].
#[inline(always)]
pub(crate) fn pack(cursor: u32, skipped: u32) -> u64 {
    u64::from(cursor) | (u64::from(skipped) << 32)
}
