//! # NeuroTree
//!
//! Behavior trees for robots and game AI, with the semantics of BehaviorTree.CPP v4.
//! This crate is the `std` facade: it re-exports everything of [`neurotree_core`] and adds
//! what needs the standard library, such as the thread-safe [`SharedBlackboard`].

#![warn(missing_docs)]

pub use neurotree_core::*;

pub mod bench_trees;
mod entry_nodes;
mod json_port;
mod loop_nodes;
pub mod nav2;
mod readme;
pub mod registry;
pub mod render;
pub mod robotics;
pub mod runtime;
pub mod script;
mod script_hooks;
mod script_nodes;
mod shared_blackboard;
pub mod sim;
mod switch_node;
pub mod xml;

pub use json_port::Json;
pub use registry::{PortDirection, PortSpec, Registry, RegistryError};
pub use runtime::{FixedRate, StopFlag};
pub use shared_blackboard::SharedBlackboard;
pub use xml::{LoadError, XmlLoader};
