//! A pass from the root, and what a panic in user code during it becomes.

use super::{ticker, TickError};
use crate::{NodeId, NodeStatus, Status};

/// Ticks the root; with `std`, a panic in user code is caught and becomes
/// [`TickError::Panicked`], naming the node it came from.
#[cfg(feature = "std")]
pub(super) fn tick_root<C>(t: &mut ticker::Ticker<'_, C>) -> Result<NodeStatus, TickError> {
    std::panic::catch_unwind(core::panic::AssertUnwindSafe(|| t.tick(NodeId::ROOT))).map_err(
        |payload| TickError::Panicked {
            node: t.current,
            path: t.bp.path(t.current),
            message: ticker::panic_message(&*payload),
        },
    )
}

/// Without `std` there is no catching a panic: it leaves `tick_once` as it found the tree
/// (nodes Running, counts half-updated). Call [`Tree::halt`] before ticking it again.
#[cfg(not(feature = "std"))]
pub(super) fn tick_root<C>(t: &mut ticker::Ticker<'_, C>) -> Result<NodeStatus, TickError> {
    Ok(t.tick(NodeId::ROOT))
}

/// After a panic: halt every Running node (each Running stateful action gets its one
/// `on_halted`), reset the rest, put back what the panic destroyed, and end the tick for
/// the observer, so that the next tick starts afresh.
#[cfg_attr(not(feature = "std"), allow(dead_code))]
#[cold]
pub(super) fn recover<C>(t: &mut ticker::Ticker<'_, C>, panicked: TickError) -> TickError {
    #[cfg(feature = "std")]
    t.replace_vacant_objects();
    // The halt below waits for the tree, whatever was halting when the panic came.
    t.halter.set_halter(None);
    t.halt_node(NodeId::ROOT);
    for id in t.bp.ids() {
        t.halt_node(id);
    }
    if let Some(o) = t.observer.as_deref_mut() {
        o.on_tick_end(NodeStatus::Idle, t.clock.now());
    }
    // A panic while halting is already in the halt's own error; the first panic is news.
    t.out.take_fault();
    panicked
}

pub(super) fn to_result(status: NodeStatus) -> Result<Status, TickError> {
    status.to_status().ok_or(TickError::RootSkipped)
}
