//! Control nodes: they tick their children and combine the results.
//!
//! | node | memory | re-checks earlier children | yields |
//! |---|---|---|---|
//! | [Sequence](sequence) / [Fallback](fallback) | resume at the running child | no | no |
//! | [SequenceWithMemory](sequence) | keeps its place even after a failure or a halt | no | after each child success |
//! | [AsyncSequence](sequence) / [AsyncFallback](fallback) | as Sequence / Fallback | no | after each child that completed at once |
//! | [ReactiveSequence / ReactiveFallback](reactive) | none | every tick | no |
//! | [Parallel](parallel) / [ParallelAll](parallel_all) | completed children | no | no |
//! | [IfThenElse](if_then_else) | the chosen branch | no | no |
//! | [WhileDoElse](while_do_else) | none | the condition, every tick | no |
//! | [TryCatch](try_catch) | as Sequence, then the catch child | no | no |
//!
//! Every control marks itself Running before ticking its children, resets all its children
//! to Idle when it completes, and halts Running children it stops ticking before it returns.

pub mod fallback;
pub mod if_then_else;
pub(crate) mod ordered;
pub mod parallel;
pub mod parallel_all;
pub mod reactive;
pub mod sequence;
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
