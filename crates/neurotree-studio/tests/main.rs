//! The integration tests of `neurotree-studio` without a browser, one binary: each file
//! beside this one is a module of it, and what they share is a module here, declared once.
//! The browser tests are a binary of their own, `tests/browser.rs` (`--test browser`).

mod common;

mod agents;
mod api;
mod watch;
