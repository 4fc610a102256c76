//! The integration tests of `neurotree-nav2`, one binary: each file beside this one is a
//! module of it, and what they share is a module here, declared once.

#[path = "../../neurotree-toolkit/tests/support/corpus.rs"]
mod corpus_dir;
#[path = "../../neurotree-core/tests/support/counting_alloc.rs"]
mod counting_alloc;
#[path = "support/dummy.rs"]
mod support;

mod coverage;
mod distance_controller;
mod drawn;
mod goal_updated_controller;
mod goal_updater;
mod lint_nav2;
mod lint_sound;
mod nav2_controls;
mod nonblocking_sequence;
mod path_longer_on_approach;
mod pause_resume_controller;
mod persistent_sequence;
mod pipeline_sequence;
mod rate_controller;
mod recovery_node;
mod round_robin;
mod single_trigger;
mod speed_controller;
