//! The user guide's chapters (`docs/guide/`), their Rust examples compiled and run as
//! doctests.

/// `docs/guide/sleeping.md`.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/guide/sleeping.md")]
pub struct SleepingGuide;

/// `docs/guide/utility.md`.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/guide/utility.md")]
pub struct UtilityGuide;
