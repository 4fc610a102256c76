//! How a condition child is called: through an entry, a plain function made for the
//! condition's own type, with the child's record (its data and id) and the loop's
//! arguments, so that a parent's loop (and a guard's, see [`crate::tree::calls`]) makes
//! one direct call per child with no vtable to load first.
//!
//! The entry is an `extern "sysv64"` function on x86-64 (one calling convention on every
//! x86-64 system, as the loop's assembly expects; `extern "C"` elsewhere) made for the condition's own type when the
//! condition is added (a closure through [`ConditionClosure`], an object through
//! [`Condition`]'s sealed supertrait). A panic does not unwind through it: with `std`, the
//! entry catches it, answers [`PANICKED`] and leaves the payload in the loop's [`Args`],
//! and the guard resumes it once out of the loop, blaming the child that panicked. (Without
//! `std` a panic cannot be caught, and one in a guard's condition aborts.)

use super::Child;
use crate::nodes::leaf::{Condition, Handle};

/// A condition's entry: called with its [`Child`] record and an [`Args`] (as untyped
/// pointers, so that the type stays private), it answers 1
/// (`true`), 0 (`false`) or [`PANICKED`].
#[doc(hidden)]
#[cfg(target_arch = "x86_64")]
pub type Entry = unsafe extern "sysv64" fn(*const (), *mut ()) -> u8;
/// A condition's entry (see the x86-64 one).
#[doc(hidden)]
#[cfg(not(target_arch = "x86_64"))]
pub type Entry = unsafe extern "C" fn(*const (), *mut ()) -> u8;

/// What an entry answers when the condition panicked (the payload is in [`Args`]); only
/// with `std`.
#[cfg(feature = "std")]
pub(crate) const PANICKED: u8 = 2;

/// What a guard's loop passes to every entry (as a pointer to it): the argument of its
/// conditions (a pointer to the context for closures, the handle itself for objects, so
/// that an entry reaches it with no load) and, with `std`, where a panic's payload goes.
///
/// The payload is written only with the answer [`PANICKED`], and then taken at once
/// ([`Args::take_panic`]): kept uninitialised otherwise, it costs the loop nothing to drop.
pub(crate) struct Args<A> {
    pub(crate) arg: A,
    #[cfg(feature = "std")]
    panic: core::mem::MaybeUninit<Payload>,
}

/// A panic's payload.
#[cfg(feature = "std")]
pub(crate) type Payload = alloc::boxed::Box<dyn core::any::Any + Send>;
/// A panic's payload: none without `std`, where no panic is caught.
#[cfg(not(feature = "std"))]
pub(crate) enum Payload {}

impl<A> Args<A> {
    /// The arguments for conditions called with `arg`.
    #[inline(always)]
    pub(crate) fn new(arg: A) -> Self {
        Self {
            arg,
            #[cfg(feature = "std")]
            panic: core::mem::MaybeUninit::uninit(),
        }
    }

    /// The payload of the panic, if `answer` is [`PANICKED`] (never, without `std`).
    ///
    /// # Safety
    /// `answer` is what an entry called with these arguments answered, and this is asked
    /// once for it.
    #[inline(always)]
    pub(crate) unsafe fn panicked(&mut self, answer: u8) -> Option<Payload> {
        #[cfg(feature = "std")]
        if answer == PANICKED {
            // SAFETY: the caller's contract: `answer` wrote it, and nobody took it yet.
            return Some(unsafe { self.panic.assume_init_read() });
        }
        let _ = answer;
        None
    }
}

/// A `Condition` object's data pointer, as a [`Child`] keeps it.
pub(crate) fn data_of<C>(c: &dyn Condition<C>) -> *const () {
    c as *const dyn Condition<C> as *const ()
}

/// The entry of a `Condition` object; `rechecked` when a node above it re-checks its
/// children every tick (see [`NodeKind::rechecks`](super::NodeKind::rechecks)).
///
/// Only such a node asks whether a leaf may read more than the blackboard, and only of a
/// condition whose kind does not say it reads the blackboard alone: that one gets the
/// entry that finds out whether it declared a wake in `check`. Every other condition gets
/// the plain one, which does nothing but call it, so that trees with no reactive node tick
/// as fast as if trees never slept.
pub(crate) fn entry_of<C>(c: &dyn Condition<C>, rechecked: bool) -> Entry {
    c.entry(rechecked && !c.reads_only_blackboard())
}

/// A closure condition, as [`ConditionFn`](super::ConditionFn) holds it: any
/// `Fn(&C) -> bool + Send + Sync`, callable as such.
///
/// Implemented for every such closure; it cannot be implemented otherwise (its supertrait
/// is sealed). Beside the closure it gives the plain function, made for the closure's type,
/// through which a parent's loop calls it; a panic in it ends the tick with
/// [`TickError::Panicked`](crate::TickError::Panicked), or aborts without the `std`
/// feature, where a panic cannot be caught.
///
/// ```
/// use neurotree_core::blueprint::{ConditionFn, NodeKind};
///
/// let f: ConditionFn<u32> = Box::new(|n: &u32| *n > 2);
/// assert!(f(&3));
/// assert_eq!(NodeKind::ConditionFn(f).type_name(), "Condition");
/// ```
pub trait ConditionClosure<C>: Fn(&C) -> bool + Send + Sync + sealed::ClosureEntry<C> {}

impl<C, F: Fn(&C) -> bool + Send + Sync> ConditionClosure<C> for F {}

/// The entries, made for each type that has them: sealed, so that no condition can be
/// given an entry that does not call it.
pub(crate) mod sealed {
    use super::{Args, Child, Condition, Entry, Handle};

    /// The context of a guard of closures.
    type Ctx<C> = *const C;

    /// A closure's entry.
    pub trait ClosureEntry<C> {
        /// The entry of this closure's type (see [`Entry`]).
        #[doc(hidden)]
        fn entry(&self) -> Entry;
    }

    impl<C, F: Fn(&C) -> bool> ClosureEntry<C> for F {
        fn entry(&self) -> Entry {
            closure::<C, F>
        }
    }

    /// A `Condition` object's entry.
    pub trait ConditionEntry<C> {
        /// The entry of this object's type (see [`Entry`]); `tracked`: the one that notes
        /// whether the condition declared a wake (see [`entry_of`](super::entry_of)).
        #[doc(hidden)]
        fn entry(&self, tracked: bool) -> Entry;
    }

    impl<C, T: Condition<C>> ConditionEntry<C> for T {
        fn entry(&self, tracked: bool) -> Entry {
            if tracked {
                tracked_object::<C, T>
            } else {
                object::<C, T>
            }
        }
    }

    /// Makes the two entries in the calling convention `$abi` (that of [`Entry`]).
    macro_rules! entries {
        ($abi:literal) => {
        /// Calls the closure of type `F` of record `call` with the context in `args`.
        ///
        /// # Safety
        /// The record's data points at an `F`, and `args` at an `Args<*const C>` whose
        /// context is alive.
        unsafe extern $abi fn closure<C, F: Fn(&C) -> bool>(call: *const (), args: *mut ()) -> u8 {
            // SAFETY: the caller's contract.
            unsafe {
                let (call, args) = (call.cast::<Child>(), args.cast::<Args<Ctx<C>>>());
                let f = &*(*call).data.cast::<F>();
                let ctx = &*(*args).arg;
                answer(args, || f(ctx))
            }
        }

        /// Checks the `Condition` object of type `T` of record `call` with the handle in
        /// `args`, set to the record's node.
        ///
        /// # Safety
        /// The record's data points at a `T`, and `args` at an `Args<Handle<'_, C>>` that
        /// nothing else borrows during the call.
        unsafe extern $abi fn object<C, T: Condition<C>>(call: *const (), args: *mut ()) -> u8 {
            // SAFETY: the caller's contract.
            unsafe {
                let (call, args) = (call.cast::<Child>(), args.cast::<Args<Handle<'_, C>>>());
                let c = &*(*call).data.cast::<T>();
                (*args).arg.node = (*call).id;
                let h = &(*args).arg;
                answer(args, || c.check(h))
            }
        }

        /// As `object`, for a condition that may read more than the blackboard under a
        /// node that re-checks it: unless it declares a wake in `check`, the caller's
        /// `Reads::take_opaque` says so.
        ///
        /// # Safety
        /// As for `object`.
        unsafe extern $abi fn tracked_object<C, T: Condition<C>>(call: *const (), args: *mut ()) -> u8 {
            // SAFETY: the caller's contract.
            unsafe {
                let (call, args) = (call.cast::<Child>(), args.cast::<Args<Handle<'_, C>>>());
                let c = &*(*call).data.cast::<T>();
                (*args).arg.node = (*call).id;
                let h = &(*args).arg;
                h.out.reads.declare(false);
                let answered = answer(args, || c.check(h));
                (*args).arg.out.reads.settle();
                answered
            }
        }
        };
    }
    #[cfg(target_arch = "x86_64")]
    entries!("sysv64");
    #[cfg(not(target_arch = "x86_64"))]
    entries!("C");

    /// What `check` answers, as an entry answers it: a panic's payload is kept in `args`.
    #[inline(always)]
    fn answer<A>(args: *mut Args<A>, check: impl FnOnce() -> bool) -> u8 {
        #[cfg(feature = "std")]
        {
            match std::panic::catch_unwind(core::panic::AssertUnwindSafe(check)) {
                Ok(holds) => holds as u8,
                Err(payload) => {
                    // SAFETY: `args` is the loop's, alive for the call (see the callers).
                    unsafe { (*args).panic.write(payload) };
                    super::PANICKED
                }
            }
        }
        #[cfg(not(feature = "std"))]
        {
            let _ = args;
            check() as u8
        }
    }
}
