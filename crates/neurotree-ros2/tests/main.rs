//! The integration tests of `neurotree-ros2`, one binary: each file beside this one is a
//! module of it, and what they share is a module here, declared once.

mod common;

mod action;
mod battery;
mod behaviors;
mod clearing;
mod costs;
mod cyclonedds;
mod discovery;
mod navigator;
mod odometry;
mod planning;
mod releases;
mod robot;
mod servers;
mod service;
mod subscriber;
