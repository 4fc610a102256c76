//! The node catalog: one module per node, holding its semantics and its tests.
//!
//! - [`control`]: nodes with children that decide which to tick;
//! - [`decorator`]: nodes with one child that change its outcome or its timing;
//! - [`leaf`]: conditions, actions and the built-in leaves;
//! - [`custom`]: the door for user-defined controls and decorators;
//! - [`hooks`]: pre- and post-conditions around any node.

pub mod control;
pub mod custom;
pub mod decorator;
pub mod hooks;
pub mod leaf;
