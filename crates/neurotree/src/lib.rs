//! # NeuroTree
//!
//! Behavior trees for robots and game AI, with the semantics of BehaviorTree.CPP v4.
//!
//! This crate is the one to depend on. It re-exports the `no_std` engine
//! ([`neurotree_core`]) and the BehaviorTree.CPP-compatible toolkit ([`neurotree_toolkit`]:
//! registry, XML, scripts, observers, pictures, runners) at its root, and the optional
//! crates behind features, each under its own path.

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

mod readme;
