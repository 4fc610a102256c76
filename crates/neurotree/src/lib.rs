//! # NeuroTree
//!
//! Behavior trees for robots and game AI. Nodes behave as BehaviorTree.CPP 4's do, tick for
//! tick and halt for halt, so its XML files (hand-written, saved by Groot2, shipped with
//! Nav2) run unchanged. A tree is built once as an immutable [`Blueprint`] and shared by any
//! number of [`Tree`] instances, whose ticks do not allocate (but for a tree's record of
//! failure reasons, made by the first tick in which a node gives one and grown at most
//! once, or made up front); time comes from a [`Clock`] you choose, so runs can be
//! deterministic.
//!
//! # Quick start
//!
//! `use neurotree::prelude::*` brings what a program needs. Register your leaves, with the
//! ports they read, in a [`Registry`] (the built-in nodes are already in it), then load a
//! BehaviorTree.CPP file in one call: [`Registry::load_file`] follows its `<include>`s,
//! checks every node, port and literal, and reports every error of the tree (a
//! [`LoadErrors`]), each as `file:line:col: error: ...`.
//! [`Registry::load_str`] does the same for text. Leaves receive your own context type,
//! here a `Vec<String>`, by `&mut` on every tick.
//!
//! ```
//! use neurotree::prelude::*;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let mut registry = Registry::<Vec<String>>::new();
//! registry.register_action("Say", vec![PortSpec::input::<String>("message")], |h| {
//!     let message = h.input::<String>("message").unwrap_or_default();
//!     h.ctx_mut().push(message);
//!     Status::Success
//! })?;
//!
//! // `registry.load_file("main.xml", SystemClock::new())` for a file.
//! let mut tree = registry.load_str(
//!     r#"<root BTCPP_format="4" main_tree_to_execute="Main">
//!          <BehaviorTree ID="Main">
//!            <Sequence>
//!              <Script code="laps := 2"/>
//!              <Repeat num_cycles="{laps}">
//!                <Say message="hello"/>
//!              </Repeat>
//!            </Sequence>
//!          </BehaviorTree>
//!        </root>"#,
//!     "main.xml",
//!     ManualClock::new(),
//! )?;
//!
//! // Tick until the root is no longer Running.
//! let mut said = Vec::new();
//! while tree.tick_once(&mut said)? == Status::Running {}
//! assert_eq!(said, ["hello", "hello"]);
//!
//! // The script wrote an `i64`; reads convert numbers as ports do, with a range check.
//! assert_eq!(tree.blackboard().get::<i32>("laps")?, 2);
//! # Ok(())
//! # }
//! ```
//!
//! The same tree from the builder: leaves are closures over your context type.
//!
//! ```
//! use neurotree::prelude::*;
//!
//! struct Robot { battery: u32 }
//!
//! let blueprint = Blueprint::<Robot>::builder()
//!     .fallback("root", |f| {
//!         f.condition("battery_ok", |r: &Robot| r.battery > 20)
//!             .action("charge", |r: &mut Robot| {
//!                 r.battery = 100;
//!                 Status::Success
//!             })
//!     })
//!     .build_shared()
//!     .expect("a valid tree");
//!
//! // One blueprint, any number of instances; each holds only its per-node state.
//! let mut tree = Tree::with_clock(blueprint, ManualClock::new());
//! let mut robot = Robot { battery: 10 };
//! assert_eq!(tree.tick_once(&mut robot), Ok(Status::Success));
//! assert_eq!(robot.battery, 100);
//! ```
//!
//! An [`XmlLoader`] is the lower-level way to load: several files, a tree other than the
//! main one, mocks, limits, warnings, one blueprint for many trees.
//!
//! For a robot, tick at a fixed rate with [`runtime::FixedRate`] or, with the `tokio`
//! feature, `runtime::tokio::tick_until_done`; [`Tree::tick_while_running`] ticks on the
//! tree's own clock.
//!
//! # Map
//!
//! | where | what |
//! |---|---|
//! | the root | the types you build and run trees with (below) |
//! | [`nodes`] | the node catalog: every built-in node, one module each |
//! | [`xml`] | loading and saving BehaviorTree.CPP format 4, `TreeNodesModel`s, mocks |
//! | [`script`] | BehaviorTree.CPP's script language |
//! | [`observe`] | loggers on the observer hook |
//! | [`render`] | pictures of a tree: text, Graphviz DOT, Mermaid, SVG, with statuses |
//! | [`runtime`] | runners: a fixed-rate loop, and tokio helpers |
//! | `crowd` | (feature `crowd`, on by default) many trees ticked frame by frame on all cores |
//! | `robotics`, `nav2` | (feature `nav2`) robot nodes; Nav2's control nodes |
//! | `sim` | (feature `sim`) a deterministic grid world and Nav2's leaves simulated on it |
//! | `groot` | (feature `groot`) a Groot2 monitor server |
//! | `studio` | (feature `studio`) the browser studio: edit, watch (breakpoints, stepping, blackboard edits) and replay |
//!
//! - [`prelude`] has what most programs need, for one `use neurotree::prelude::*`.
//! - The root has [`Blueprint`], [`Builder`], [`tree!`], [`Tree`], [`Status`], the leaf traits
//!   ([`Condition`], [`Action`], [`StatefulAction`], [`AsyncAction`], [`CustomNode`]),
//!   [`Clock`]s, [`Observer`], [`Blackboard`] and [`SharedBlackboard`], [`Registry`],
//!   [`XmlLoader`].
//! - [`nodes`] gives each node its semantics, ports and tests: the core's controls, decorators
//!   and leaves; [`nodes::script`], [`nodes::switch`], [`nodes::loops`], [`nodes::entry`] need
//!   `std`.
//! - [`script`] is for `Script`, `Precondition` and `_skipIf`-style attributes.
//! - [`observe`] has loggers for the console, JSON lines, statistics, `.btlog`, SQLite and
//!   `tracing`.
//! - `robotics` and `nav2` hold sensor and navigation nodes over your robot, and Nav2's control
//!   nodes.
//!
//! # Crate features
//!
//! Only `crowd` is on by default: the default build is the engine, the registry, XML,
//! scripts, observers, pictures and crowds.
//!
//! | feature | brings | dependencies it adds |
//! |---|---|---|
//! | `crowd` (default) | `neurotree::crowd` | `rayon` |
//! | `nav2` | `neurotree::robotics`, `neurotree::nav2` | none beyond the crate |
//! | `sim` | `neurotree::sim`; turns on `nav2` | `pathfinding`, `fastrand` |
//! | `groot` | `neurotree::groot` | `tokio`, `rmp-serde` |
//! | `studio` | `neurotree::studio` | `axum`, `tokio`, `rust-embed`, `roxmltree` |
//! | `tokio` | `runtime::tokio` | `tokio`, `tokio-util` |
//! | `sqlite` | `observe::SqliteLogger` | `rusqlite` (SQLite bundled) |
//! | `tracing` | `observe::TracingObserver` | `tracing` |
//!
//! The crates behind them: `neurotree-nav2` for `nav2`, `neurotree-sim` for `sim`,
//! `neurotree-groot` for `groot`, `neurotree-studio` for `studio`. `runtime::tokio` is a runner, a clock on tokio's time, and
//! tasks aborted by a halt.
//!
//! # Crates
//!
//! This crate re-exports the others; depend on it alone. [`neurotree_core`] is the `no_std`
//! engine (for a microcontroller, depend on it directly with `default-features = false`);
//! [`neurotree_toolkit`] is the BehaviorTree.CPP-compatible layer this crate puts at its
//! root; the optional crates come in through the features above.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub use neurotree_toolkit::*;

#[cfg(feature = "groot")]
pub use neurotree_groot as groot;
#[cfg(feature = "nav2")]
pub use neurotree_nav2 as nav2;
#[cfg(feature = "nav2")]
pub use neurotree_nav2::robotics;
#[cfg(feature = "sim")]
pub use neurotree_sim as sim;
#[cfg(feature = "studio")]
pub use neurotree_studio as studio;

#[cfg(feature = "crowd")]
pub mod crowd;
#[cfg(all(feature = "crowd", feature = "studio"))]
pub mod crowd_studio;
mod guide;
mod readme;

/// What most programs need, in one `use neurotree::prelude::*;`: the types that load,
/// build and run a tree, the clocks and the [`Clock`] trait (whose `now` reads them), the
/// leaf traits, the blackboard and the errors that `?` meets on the way.
pub mod prelude {
    #[doc(no_inline)]
    pub use crate::{
        Action, AsyncAction, Blackboard, BlackboardError, Blueprint, BuildError, Clock, Condition,
        CustomNode, Handle, LoadError, LoadErrors, ManualClock, NodeCtx, Port, PortError, PortSpec,
        Registry, RegistryError, ScopeId, ScriptBuilder, SharedBlackboard, StatefulAction, Status,
        SystemClock, TickError, Tree, XmlLoader,
    };
}
