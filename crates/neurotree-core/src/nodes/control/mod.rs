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

/// The most children an ordered node (a Sequence, a Fallback and their kin) may have and
/// keep its state, a cursor and a count of skipped children, in one 32-bit slot, 16 bits
/// each; a node with more takes two slots, 32 bits each. 0xFFFF stands for any count past
/// the children, which is all a count is compared with (it ends the node Skipped only when
/// it equals their number).
pub(crate) const NARROW_CHILDREN: u32 = 0xFFFE;

/// The state slots an ordered node of `children` children takes.
pub(crate) const fn ordered_slots(children: u32) -> u32 {
    if children <= NARROW_CHILDREN {
        1
    } else {
        2
    }
}

/// An ordered node's cursor and count of skipped children, from its slots.
#[inline(always)]
pub(crate) fn unpack(aux: &[u32], slot: usize, children: usize) -> (u32, u32) {
    if children <= NARROW_CHILDREN as usize {
        let packed = aux[slot];
        (packed & 0xFFFF, packed >> 16)
    } else {
        (aux[slot], aux[slot + 1])
    }
}

/// The inverse of [`unpack`].
#[inline(always)]
pub(crate) fn pack(aux: &mut [u32], slot: usize, children: usize, cursor: u32, skipped: u32) {
    if children <= NARROW_CHILDREN as usize {
        aux[slot] = cursor | (skipped.min(0xFFFF) << 16);
    } else {
        aux[slot] = cursor;
        aux[slot + 1] = skipped;
    }
}

/// An ordered node's state as a saved state stores it: the cursor in the low 32 bits, the
/// count in the high.
pub(crate) fn saved_ordered(value: u64, children: u32) -> u64 {
    if children <= NARROW_CHILDREN {
        (value & 0xFFFF) | ((value >> 16 & 0xFFFF) << 32)
    } else {
        value
    }
}

/// The inverse of [`saved_ordered`]; `None` for a cursor past the children.
pub(crate) fn restored_ordered(saved: u64, children: u32) -> Option<u64> {
    let (cursor, skipped) = (saved as u32, (saved >> 32) as u32);
    if cursor > children {
        return None;
    }
    Some(if children <= NARROW_CHILDREN {
        u64::from(cursor) | (u64::from(skipped.min(0xFFFF)) << 16)
    } else {
        saved
    })
}

/// The state an ordered kind keeps: [`ordered_slots`], saved through [`saved_ordered`].
macro_rules! ordered_state {
    () => {
        fn aux_slots(children: u32) -> u32 {
            super::ordered_slots(children)
        }
        fn saved_aux(value: u64, children: u32) -> u64 {
            super::saved_ordered(value, children)
        }
        fn restored_aux(saved: u64, children: u32) -> Option<u64> {
            super::restored_ordered(saved, children)
        }
    };
}
pub(crate) use ordered_state;
