//! The library half of the `neurotree` command: the scenario that `neurotree demo` runs,
//! kept here (not in the `neurotree` library) because it is a show, not a building block.
//!
//! [`demo::DemoRun`] is Nav2's navigator, unchanged, driving the simulated robot of
//! `neurotree::sim` across a warehouse; the binary paces and draws it.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod campaign;
pub mod demo;
pub mod failure;
