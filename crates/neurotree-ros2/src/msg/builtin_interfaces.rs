//! `builtin_interfaces`: time stamps and durations.

use serde::{Deserialize, Serialize};

use crate::interface::messages;

/// `builtin_interfaces/msg/Time`: a point in time, seconds and nanoseconds since the epoch.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Time {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds, below 1e9.
    pub nanosec: u32,
}

/// `builtin_interfaces/msg/Duration`: a span of time, seconds and nanoseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Duration {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds, below 1e9.
    pub nanosec: u32,
}

messages!("builtin_interfaces": Time, Duration);

impl From<core::time::Duration> for Duration {
    /// Saturates at `i32::MAX` seconds.
    fn from(d: core::time::Duration) -> Self {
        Self {
            sec: i32::try_from(d.as_secs()).unwrap_or(i32::MAX),
            nanosec: d.subsec_nanos(),
        }
    }
}

impl From<Duration> for core::time::Duration {
    /// A negative duration is zero.
    fn from(d: Duration) -> Self {
        match u64::try_from(d.sec) {
            Ok(sec) => core::time::Duration::new(sec, d.nanosec),
            Err(_) => core::time::Duration::ZERO,
        }
    }
}
