//! The integration tests of `neurotree-groot`, one binary: each file beside this one is a
//! module of it, and what they share is a module here, declared once.

#[path = "support/client.rs"]
mod client;
#[path = "../../neurotree-core/tests/support/counting_alloc.rs"]
mod counting_alloc;

mod failure_reasons;
mod groot;
mod hostile_peers;
