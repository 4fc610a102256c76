//! `sensor_msgs`: the battery's state, as Nav2's battery conditions read it.

include!(concat!(env!("OUT_DIR"), "/sensor_msgs.rs"));
