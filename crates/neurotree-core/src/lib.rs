//! # NeuroTree core
//!
//! The `no_std` heart of NeuroTree: behavior trees with the exact semantics of
//! Colledanchise & Ögren's *Behavior Trees in Robotics and AI* and, for every node it also
//! has, of BehaviorTree.CPP v4, tick for tick and halt for halt.
//!
//! - A [`Blueprint`] is the immutable tree, built with the [`Builder`], the [`tree!`] macro
//!   or (in the `neurotree` crate) from BehaviorTree.CPP XML. It is validated once and
//!   shared through `Arc`.
//! - A [`Tree`] is one running instance: a status byte per node and a few state slots,
//!   nothing more. Ticking it does not allocate, but for its record of failure reasons:
//!   made in the first tick in which a node gives a reason, and grown once, in the first
//!   tick that notes more than 16 words (a failure takes one, a reason two), or made whole
//!   up front with [`Tree::reserve_failure_record`]; and for an error a tick returns, of
//!   which the tree keeps a copy ([`Tree::last_error`]).
//! - Leaves are closures or traits ([`Condition`], [`Action`], [`StatefulAction`],
//!   [`AsyncAction`]) that receive the user's own context `C`, so they reach the robot or
//!   the game world directly. An async action runs a Rust future, polled once per tick and
//!   dropped on halt, with no runtime required.
//! - Time-based nodes read only the tree's [`Clock`]; with a [`ManualClock`] every run is
//!   deterministic.
//! - An [`Observer`] sees every status change; loggers and live views are built on it.
//!
//! ```
//! use std::sync::Arc;
//! use neurotree_core::{Blueprint, ManualClock, Status, Tree};
//!
//! #[derive(Default)]
//! struct Door { open: bool, knocks: u32 }
//!
//! let blueprint = Blueprint::<Door>::builder()
//!     .fallback("enter", |f| {
//!         f.condition("is_open", |d: &Door| d.open)
//!             .retry("knock_until_open", 3, |r| {
//!                 r.action("knock", |d: &mut Door| {
//!                     d.knocks += 1;
//!                     d.open = d.knocks == 2;
//!                     d.open.into()
//!                 })
//!             })
//!     })
//!     .build_shared()
//!     .unwrap();
//!
//! let mut tree = Tree::with_clock(Arc::clone(&blueprint), ManualClock::new());
//! let mut door = Door::default();
//! assert_eq!(tree.tick_once(&mut door), Ok(Status::Success));
//! assert_eq!(door.knocks, 2);
//! ```
//!
//! The node catalog, with each node's semantics, is under [`nodes`].

#![no_std]
#![warn(missing_docs)]

extern crate alloc;
#[cfg(any(feature = "std", test))]
extern crate std;

pub mod blackboard;
pub mod blueprint;
pub mod clock;
mod error_debug;
pub mod hint;
mod macros;
pub mod nodes;
pub mod observer;
pub mod state;
mod status;
pub mod tree;

#[cfg(test)]
pub(crate) mod testing;

pub use blackboard::{Blackboard, BlackboardError, EntryInfo, ScopeId};
pub use blueprint::{
    Arity, Blueprint, BuildError, BuildErrorKind, Builder, Category, CustomSpec, FromPortStr,
    HookWrapper, NodeId, NodeKind, Number, ParallelPolicy, Param, Port, PortBinding,
    PortBindingError, PortDirections, PortError, PortType, PortValue, Shared, SubTreeScope,
    DEFAULT_MAX_DEPTH,
};
#[cfg(feature = "std")]
pub use clock::SystemClock;
pub use clock::{Clock, ManualClock};
pub use nodes::custom::{CustomNode, NodeCtx};
pub use nodes::hooks::NodeHooks;
pub use nodes::leaf::{
    Action, ActionFuture, AsyncAction, Condition, HaltFuture, HaltProgress, Handle, Inputs,
    PortCondition, StatefulAction,
};
pub use nodes::{NodeDecl, PortDecl, PortDirection};
pub use observer::{Observer, StatusChange};
pub use status::{NodeStatus, Status};
pub use tree::{
    AwakeCounts, AwakeReason, Failure, FailureLink, HaltHandle, Reason, ReloadError, ReloadReport,
    TickError, Tree, Tried, WakeSignal, WhyAwake, Woken, DEFAULT_MAX_PASSES, HALT_POLL_PERIOD,
};

/// The length and room of a `thin_vec::ThinVec`, at the head of its block: two `usize`s
/// (unless `thin-vec` is built with its `gecko-ffi` feature, which nothing here asks for).
/// A tree's record of reasons and its blackboard's root scope are such vectors.
pub(crate) const THIN_HEAD: usize = 2 * core::mem::size_of::<usize>();
