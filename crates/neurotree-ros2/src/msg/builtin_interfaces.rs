//! `builtin_interfaces`: time stamps and durations.

include!(concat!(env!("OUT_DIR"), "/builtin_interfaces.rs"));

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
