//! How the leaves read and write their ports: as Nav2's nodes do, an optional port that is
//! not given counts as absent, while one that is given but unreadable is an error.

use std::any::Any;

use neurotree_core::{BlackboardError, FromPortStr, Handle, PortError, Status};

use super::codes;

/// Reads input `port`: `Ok(None)` when the node has no such port (an optional port the
/// file leaves out) or its entry was never written.
pub(super) fn optional<T, C>(h: &Handle<'_, C>, port: &str) -> Result<Option<T>, PortError>
where
    T: FromPortStr + Any + Clone,
{
    match h.input::<T>(port) {
        Ok(value) => Ok(Some(value)),
        Err(PortError::NoSuchPort { .. })
        | Err(PortError::Blackboard {
            source: BlackboardError::NotFound { .. },
            ..
        }) => Ok(None),
        Err(e) => Err(e),
    }
}

/// Reads input `port`, or `default` when it is absent (see [`optional`]).
pub(super) fn or<T, C>(h: &Handle<'_, C>, port: &str, default: T) -> Result<T, PortError>
where
    T: FromPortStr + Any + Clone,
{
    optional(h, port).map(|v| v.unwrap_or(default))
}

/// Writes output `port` when the tree binds it. A binding that cannot take the value (a
/// literal, an entry holding another type) is a mistake in the tree, reported as an error
/// of the tick.
pub(super) fn emit<T: Any + Send + Sync, C>(h: &mut Handle<'_, C>, port: &str, value: T) {
    match h.output(port, value) {
        Ok(()) | Err(PortError::NoSuchPort { .. }) => {}
        Err(e) => h.fail(e.to_string()),
    }
}

/// Ends a run with Failure: writes `code` and `message` to the `error_code_id` and
/// `error_msg` outputs, and gives the Failure the reason `why` with the same code (a short
/// static text, so that failing allocates no reason; the detail is in `error_msg`). A
/// [`FailureNotes`](super::FailureNotes) on the tree logs it.
pub(super) fn fail<C>(
    h: &mut Handle<'_, C>,
    code: u16,
    why: &'static str,
    message: String,
) -> Status {
    emit(h, "error_code_id", code);
    emit(h, "error_msg", message);
    h.fail_with(code.into(), why)
}

/// Ends a run with Success: error code 0 and an empty message, as Nav2's nodes write.
pub(super) fn succeed<C>(h: &mut Handle<'_, C>) -> Status {
    emit(h, "error_code_id", codes::NONE);
    emit(h, "error_msg", String::new());
    Status::Success
}

/// A port read's result with "absent" as `None`, as [`optional`] gives it, for nodes that
/// read through another handle than [`Handle`] (a custom node's `NodeCtx`).
pub(super) fn absent_as_none<T>(read: Result<T, PortError>) -> Result<Option<T>, PortError> {
    match read {
        Ok(value) => Ok(Some(value)),
        Err(PortError::NoSuchPort { .. })
        | Err(PortError::Blackboard {
            source: BlackboardError::NotFound { .. },
            ..
        }) => Ok(None),
        Err(e) => Err(e),
    }
}
