//! The integration tests of `neurotree-toolkit`, one binary: each file beside this one is a
//! module of it, and what they share is a module here, declared once.

#[path = "support/corpus.rs"]
mod corpus_dir;
#[path = "../../neurotree-core/tests/support/counting_alloc.rs"]
mod counting_alloc;
#[path = "support/load_all.rs"]
mod load_all;
#[path = "support/mutate.rs"]
mod mutate;
#[path = "support/patrol.rs"]
mod patrol;
#[path = "support/xml.rs"]
mod shared;
#[path = "support/signature.rs"]
mod signature;

mod async_actions;
mod btcpp_refusals;
mod catalog;
mod corpus;
mod declared_ports;
mod differential;
mod failure_reasons;
mod faults;
mod fuzz;
mod halt_handle_xml;
mod lint_corpus;
mod load_error_kinds;
mod loader_no_panic;
mod observe_btlog;
mod observe_coverage;
mod observe_sqlite;
mod observe_stats;
mod observe_text;
mod observe_tracing;
mod plain_path;
mod reload_edits;
mod render_formats;
mod render_layout;
mod render_plan;
mod render_snapshots;
mod script_no_alloc;
mod slow_halt_xml;
mod std_nodes_no_alloc;
mod substitutions;
mod xml_conditions;
mod xml_errors;
mod xml_limits;
mod xml_load;
mod xml_models;
mod xml_ports;
mod xml_save;
mod xml_scripts;
mod xml_std_nodes;
