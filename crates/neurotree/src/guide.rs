//! The user guide's chapters (`docs/guide/`), their Rust examples compiled and run as
//! doctests.

/// `docs/guide/sleeping.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/sleeping.md")]
pub struct SleepingGuide;

/// `docs/guide/utility.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/utility.md")]
pub struct UtilityGuide;

/// `docs/guide/builder.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/builder.md")]
pub struct BuilderGuide;

/// `docs/guide/xml.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/xml.md")]
pub struct XmlGuide;

/// `docs/guide/command.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/command.md")]
pub struct CommandGuide;

/// `docs/guide/testing.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/testing.md")]
pub struct TestingGuide;

/// `docs/guide/live.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/live.md")]
pub struct LiveGuide;

/// `docs/guide/observing.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/observing.md")]
pub struct ObservingGuide;

/// `docs/guide/async.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/async.md")]
pub struct AsyncGuide;

/// `docs/guide/crowds.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/crowds.md")]
pub struct CrowdsGuide;

/// `docs/guide/bevy.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/bevy.md")]
pub struct BevyGuide;

/// `docs/guide/robotics.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/robotics.md")]
pub struct RoboticsGuide;

/// `docs/guide/demo.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/demo.md")]
pub struct DemoGuide;

/// `docs/guide/ros2-bridge.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/ros2-bridge.md")]
pub struct Ros2BridgeGuide;

/// `docs/guide/studio.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/studio.md")]
pub struct StudioGuide;

/// `docs/guide/examples.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/examples.md")]
pub struct ExamplesGuide;

/// `docs/guide/catalog.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/catalog.md")]
pub struct CatalogGuide;

/// `docs/guide/nav2-differences.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/nav2-differences.md")]
pub struct Nav2DifferencesGuide;

/// `docs/guide/rust.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/rust.md")]
pub struct RustGuide;

/// `docs/guide/layout.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/layout.md")]
pub struct LayoutGuide;

/// `docs/guide/benchmarks.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/benchmarks.md")]
pub struct BenchmarksGuide;

/// `docs/guide/checks.md`.
#[cfg(doctest)]
#[doc = include_str!("../guide/checks.md")]
pub struct ChecksGuide;
