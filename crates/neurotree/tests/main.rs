//! The integration tests of `neurotree`, one binary: each file beside this one is a module
//! of it.

mod crowd;
mod crowd_held;
mod crowd_sleeping;
mod example_drone_mission;
mod example_navigation_recovery;
mod example_needs;
mod example_patrol;
mod example_pick_and_place;
mod example_sensor_fusion;
