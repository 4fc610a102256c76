//! `nav_msgs`: paths, lists of goals and odometry.

include!(concat!(env!("OUT_DIR"), "/nav_msgs.rs"));
