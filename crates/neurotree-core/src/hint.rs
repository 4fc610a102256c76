//! Hints to the processor: start loading memory a loop will soon read.
//!
//! A runner that ticks many trees in an order the processor cannot guess (the awake members
//! of a crowd, scattered over memory) pays a trip to memory for each cache line a tick
//! touches, one after another. Asking for the lines of the next trees while this one is
//! ticked overlaps those trips with work. The hints change nothing a program computes: on a
//! processor without the instruction they do nothing.

/// Bytes of a cache line, the unit the processor loads.
pub const LINE: usize = 64;

/// The most lines one hint asks for: a larger value is more than a tick reads at once.
const MOST_LINES: usize = 8;

/// Asks the processor to load the line holding `address` into its caches.
#[inline(always)]
fn line(address: *const u8) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: SSE is part of x86-64; a prefetch reads nothing and faults on no address.
    unsafe {
        core::arch::x86_64::_mm_prefetch::<{ core::arch::x86_64::_MM_HINT_T0 }>(address.cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = address;
}

/// Asks the processor to load `value`'s bytes (its first 512 at most) into its caches.
#[inline(always)]
pub fn prefetch<T: ?Sized>(value: &T) {
    prefetch_bytes(
        (value as *const T).cast::<u8>(),
        core::mem::size_of_val(value),
    );
}

/// Asks the processor to load the `bytes` bytes from `start` (the first 512 at most) into
/// its caches: for memory no single value spans, such as a tree's node state.
#[inline(always)]
pub(crate) fn prefetch_bytes(start: *const u8, bytes: usize) {
    let bytes = bytes.min(LINE * MOST_LINES);
    let mut offset = 0;
    while offset < bytes {
        line(start.wrapping_add(offset));
        offset += LINE;
    }
    // The last byte's line, when the value straddles one more than its size suggests.
    if bytes > 0 {
        line(start.wrapping_add(bytes - 1));
    }
}
