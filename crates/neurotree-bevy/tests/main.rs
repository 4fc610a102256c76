//! The integration tests of `neurotree-bevy`, one binary: each file beside this one is a
//! module of it.

mod example_crowd;
mod example_village_studio;
mod plugin;
mod readme;
mod studio;
