//! The loop of a guard (a plain Sequence or Fallback whose children are all conditions
//! without hooks): one call per child, in order, until one decides.
//!
//! It is most of what tree-shaped workloads run (tree1111's 1,000 leaves are all guard
//! children), and at one call per child its speed depends on where the processor's fetch
//! windows fall: on AMD Zen 4, a loop whose stretch from its start to the call, or from the
//! return to its jump back, crosses a 64-byte line takes a cycle more per child, up to a
//! fifth of the whole tick, and where the compiler puts a loop is not up to the source. So
//! on x86-64 the loop is written out: every stretch between a return (or the loop's start)
//! and the next call fits one 16-byte-aligned block, which no 64-byte line boundary cuts,
//! and four calls share one jump back (a turn of such a loop is bound by its taken
//! branches: each call, each return and the jump back). Elsewhere it is plain Rust (also
//! under Miri, and with `--cfg neurotree_portable`, with which CI tests it).
//!
//! The entries never unwind (see [`call`](crate::blueprint::call)): a condition that
//! panicked answers `PANICKED`, which ends the loop like a deciding answer.

use crate::blueprint::call::Args;
use crate::blueprint::Child;

/// Calls each of `calls` with `args`, in order, while it answers `GO_ON`. Returns `None` if
/// all did, else the record that answered otherwise and its answer (the other outcome, or
/// `PANICKED`).
///
/// # Safety
/// Every record of `calls` is a condition's, and `args` is what their entries expect (a
/// guard's children: see [`Child::call`]).
#[inline(always)]
pub(crate) unsafe fn until<'c, A, const GO_ON: bool>(
    calls: &'c [Child],
    args: &mut Args<A>,
) -> Option<(&'c Child, u8)> {
    if calls.is_empty() {
        return None;
    }
    let args: *mut Args<A> = args;
    #[cfg(all(target_arch = "x86_64", not(miri), not(neurotree_portable)))]
    {
        let range = calls.as_ptr_range();
        // Four calls per turn of the loop; a guard of `n` children enters it at call
        // `skip = (4 - n % 4) % 4`, with `r15` that many records before the first, so that
        // `r15` reaches the end exactly.
        let skip = (4 - calls.len() % 4) % 4;
        let base = (range.start as usize).wrapping_sub(skip * core::mem::size_of::<Child>());
        let at: *const Child;
        let answer: u8;
        // SAFETY: the caller's contract; the range is not empty. The loop calls records
        // `start..end` (never one before `start`: it enters past the skipped ones) until
        // one answers otherwise, and leaves `r15` at it, or at `end`. The entries follow
        // the System V convention (`Entry`), whose registers the clobbers name, and never
        // unwind.
        unsafe {
            core::arch::asm!(
                "cmp {skip:e}, 2",
                "jb 20f",
                "je 42f",
                "jmp 43f",
                "20:",
                "test {skip:e}, {skip:e}",
                "jne 41f",
                ".p2align 4",
                "2:",
                // Each stretch from a return (or the loop's start) to the next call is one
                // 16-byte block, the call last: first a 6-byte no-op (spelt out, as an
                // assembler would drop its zero offset), then 3 + 3 + 4 bytes.
                ".byte 0x66, 0x0f, 0x1f, 0x44, 0x00, 0x00",
                "mov rdi, r15",
                "mov rsi, r12",
                "call qword ptr [r15 + 8]",
                // 1 + 2 + 2, then 4 + 3 + 4.
                "nop",
                "cmp al, {go_on}",
                "jne 30f",
                "41:",
                "lea rdi, [r15 + {size}]",
                "mov rsi, r12",
                "call qword ptr [r15 + {size} + 8]",
                "nop",
                "cmp al, {go_on}",
                "jne 31f",
                "42:",
                "lea rdi, [r15 + 2 * {size}]",
                "mov rsi, r12",
                "call qword ptr [r15 + 2 * {size} + 8]",
                "nop",
                "cmp al, {go_on}",
                "jne 32f",
                "43:",
                "lea rdi, [r15 + 3 * {size}]",
                "mov rsi, r12",
                "call qword ptr [r15 + 3 * {size} + 8]",
                // From the last return to the jump back, 13 bytes: 2 + 2 + 4 + 3 + 2.
                "cmp al, {go_on}",
                "jne 33f",
                "add r15, 4 * {size}",
                "cmp r15, r13",
                "jne 2b",
                "jmp 30f",
                "31:",
                "add r15, {size}",
                "jmp 30f",
                "32:",
                "add r15, 2 * {size}",
                "jmp 30f",
                "33:",
                "add r15, 3 * {size}",
                "30:",
                go_on = const GO_ON as u8,
                size = const core::mem::size_of::<Child>(),
                skip = in(reg) skip as u32,
                inout("r15") base => at,
                in("r13") range.end,
                in("r12") args,
                lateout("al") answer,
                clobber_abi("sysv64"),
            );
            if at == range.end {
                None
            } else {
                Some((&*at, answer))
            }
        }
    }
    #[cfg(not(all(target_arch = "x86_64", not(miri), not(neurotree_portable))))]
    {
        for call in calls {
            // SAFETY: the caller's contract.
            let answer = unsafe { call.call(&mut *args.cast::<Args<A>>()) };
            if answer != GO_ON as u8 {
                return Some((call, answer));
            }
        }
        None
    }
}

#[cfg(all(target_arch = "x86_64", not(miri), not(neurotree_portable)))]
const _: () = {
    // The record as the loop reads it: the entry at 8, 24 bytes in all (see `Child`).
    assert!(core::mem::size_of::<Child>() == 24);
    assert!(core::mem::size_of::<crate::blueprint::call::Entry>() == 8);
};

#[cfg(test)]
mod tests {
    use alloc::vec::Vec;
    use core::cell::RefCell;

    use super::until;
    use crate::blueprint::call::Args;
    use crate::blueprint::Child;
    use crate::NodeId;

    /// The context: which children were called, in order.
    #[derive(Default)]
    struct Calls(RefCell<Vec<u32>>);

    /// A child that notes its call and answers `holds` (or panics, with `panics`).
    fn child(i: u32, holds: bool, panics: bool) -> impl Fn(&Calls) -> bool {
        move |calls: &Calls| {
            calls.0.borrow_mut().push(i);
            if panics {
                panic!("child {i}");
            }
            holds
        }
    }

    fn record<F: Fn(&Calls) -> bool + Send + Sync>(f: &F, id: u32) -> Child {
        Child::of_closure(f, NodeId(id))
    }

    /// Every length the loop's four ways in meet, each child deciding in turn (and none),
    /// both ways round: exactly the children up to the deciding one are called, in order,
    /// and the loop names that one and its answer.
    #[test]
    fn calls_each_child_in_order_until_one_decides() {
        for n in 1..=13u32 {
            for go_on in [true, false] {
                for decides in (0..n).map(Some).chain([None]) {
                    let children: Vec<_> = (0..n)
                        .map(|i| child(i, (Some(i) == decides) != go_on, false))
                        .collect();
                    let calls: Vec<Child> = children
                        .iter()
                        .zip(10..)
                        .map(|(f, id)| record(f, id))
                        .collect();
                    let ctx = Calls::default();
                    let mut args = Args::new(&raw const ctx);
                    // SAFETY: the records hold closures of `Calls`, called with one.
                    let got = unsafe {
                        if go_on {
                            until::<_, true>(&calls, &mut args)
                        } else {
                            until::<_, false>(&calls, &mut args)
                        }
                    };
                    let got = got.map(|(call, answer)| (call.id.0, answer));
                    let want = decides.map(|i| (10 + i, u8::from(!go_on)));
                    assert_eq!(
                        got, want,
                        "{n} children, go_on {go_on}, {decides:?} decides"
                    );
                    let last = decides.unwrap_or(n - 1);
                    assert_eq!(*ctx.0.borrow(), (0..=last).collect::<Vec<_>>());
                }
            }
        }
    }

    /// A child that panics ends the loop at once with `PANICKED`, its payload kept; the
    /// children after it are not called.
    #[cfg(feature = "std")]
    #[test]
    fn a_panicking_child_ends_the_loop_with_its_payload() {
        use crate::blueprint::call::PANICKED;
        for n in 1..=9u32 {
            for at in 0..n {
                let children: Vec<_> = (0..n).map(|i| child(i, true, i == at)).collect();
                let calls: Vec<Child> = children
                    .iter()
                    .zip(0..)
                    .map(|(f, id)| record(f, id))
                    .collect();
                let ctx = Calls::default();
                let mut args = Args::new(&raw const ctx);
                let hook = std::panic::take_hook();
                std::panic::set_hook(alloc::boxed::Box::new(|_| {}));
                // SAFETY: as above.
                let got = unsafe { until::<_, true>(&calls, &mut args) };
                std::panic::set_hook(hook);
                let (call, answer) = got.expect("the panic ends the loop");
                assert_eq!((call.id.0, answer), (at, PANICKED));
                // SAFETY: the entry's answer, asked about once.
                let payload = unsafe { args.panicked(answer) }.expect("a payload is kept");
                assert_eq!(
                    payload.downcast_ref::<alloc::string::String>().unwrap(),
                    &alloc::format!("child {at}")
                );
                assert_eq!(*ctx.0.borrow(), (0..=at).collect::<Vec<_>>());
            }
        }
    }
}
