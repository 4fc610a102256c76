//! `std_msgs`: the header and the plain messages.

include!(concat!(env!("OUT_DIR"), "/std_msgs.rs"));

impl From<&str> for String {
    fn from(text: &str) -> Self {
        Self {
            data: text.to_owned(),
        }
    }
}
