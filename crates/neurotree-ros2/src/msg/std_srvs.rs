//! `std_srvs`: the services without data.

include!(concat!(env!("OUT_DIR"), "/std_srvs.rs"));
