//! The integration tests of the `neurotree` command, one binary: each file beside this one
//! is a module of it, and what they share is a module here, declared once.

#[path = "../../neurotree-toolkit/tests/support/corpus.rs"]
mod corpus_dir;

mod campaign;
mod cli;
mod cli_bounds;
mod cli_coverage;
mod cli_files;
mod cli_lint;
mod cli_nav2;
mod cli_observe;
mod cli_show;
mod cli_testbench;
mod cli_utility;
mod demo;
mod groot;
mod live;
mod mcp_bounds;
mod resume_random;
mod ros2;
mod studio;
