//! Panics in user code that halts a node, contained so that the rest of the tree halts.

use crate::NodeId;
#[cfg(feature = "std")]
use crate::TickError;

use super::ticker::Ticker;

/// Runs `halt` (user code that halts node `id`); with `std`, a panic in it is caught and
/// recorded as the pass's error, so that the rest of the tree is still halted.
#[cfg(feature = "std")]
pub(crate) fn contain<'t, C>(
    t: &mut Ticker<'t, C>,
    id: NodeId,
    halt: impl FnOnce(&mut Ticker<'t, C>),
) {
    let caught = std::panic::catch_unwind(core::panic::AssertUnwindSafe(|| halt(&mut *t)));
    if let Err(payload) = caught {
        let bp = t.bp;
        t.out.fault(|| TickError::Panicked {
            node: id,
            path: bp.path(id),
            message: panic_message(&*payload),
        });
    }
}

#[cfg(not(feature = "std"))]
pub(crate) fn contain<'t, C>(
    t: &mut Ticker<'t, C>,
    _id: NodeId,
    halt: impl FnOnce(&mut Ticker<'t, C>),
) {
    halt(t);
}

/// The text a panic was raised with, if it was text.
#[cfg(feature = "std")]
pub(crate) fn panic_message(payload: &(dyn core::any::Any + Send)) -> alloc::string::String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).into()
    } else if let Some(s) = payload.downcast_ref::<alloc::string::String>() {
        s.clone()
    } else {
        "a panic without a message".into()
    }
}
