//! The integration tests of `neurotree-core`, one binary: each file beside this one is a
//! module of it, and what they share is a module here, declared once.

mod common;
#[path = "support/counting_alloc.rs"]
mod counting_alloc;

mod blackboard;
mod depth;
mod failure;
mod failure_tree;
mod halt_handle;
mod halting;
mod one_place;
mod panics;
mod reference_model;
mod reload;
mod resume;
mod sleeping;
mod slow_halt;
mod wide_slots;
