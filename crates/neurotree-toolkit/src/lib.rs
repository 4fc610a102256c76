//! # NeuroTree toolkit
//!
//! The BehaviorTree.CPP-compatible layer of NeuroTree, on top of the `no_std` engine
//! [`neurotree_core`] (re-exported here whole): the node [`Registry`] (which also loads a
//! file into a tree in one call, [`Registry::load_file`]), the XML loader and
//! writer ([`xml`]), static analysis of loaded trees ([`lint`]), the [`script`] language,
//! the built-in nodes that need `std` ([`nodes`]), observers and loggers ([`observe`]),
//! pictures ([`render`]), runners ([`runtime`]) and the scenario test bench ([`scenario`]).
//!
//! Most users depend on the `neurotree` crate, which re-exports all of this under the same
//! paths, and adds robotics, the simulator and the Groot2 monitor behind features.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub use neurotree_core::*;

pub mod blackboard_json;
pub mod fault;
mod json_port;
pub mod lint;
mod load;
pub mod nodes;
pub mod observe;
pub mod registry;
pub mod render;
pub mod runtime;
pub mod scenario;
pub mod scene;
pub mod script;
mod shared_blackboard;
#[cfg(test)]
mod testing;
pub mod xml;

pub use json_port::Json;
pub use nodes::script::ScriptBuilder;
pub use nodes::utility_selector::UtilityBuilder;
pub use registry::{PortDirection, PortSpec, Registry, RegistryError};
pub use runtime::{FixedRate, StopFlag};
pub use shared_blackboard::SharedBlackboard;
pub use xml::{LoadError, LoadErrorKind, LoadErrors, LoadWarning, XmlLoader};
