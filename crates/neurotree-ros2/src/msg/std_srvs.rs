//! `std_srvs`: the services without data.

use serde::{Deserialize, Serialize};

use crate::RosService;

/// `std_srvs/srv/Empty`: a call that carries nothing either way (AMCL's
/// `reinitialize_global_localization`).
#[derive(Clone, Copy, Debug)]
pub struct Empty;

impl RosService for Empty {
    type Request = EmptyRequest;
    type Response = EmptyResponse;
    const TYPE: (&'static str, &'static str) = ("std_srvs", "Empty");
}

/// The request of [`Empty`]: one placeholder byte on the wire.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct EmptyRequest {
    /// Always 0.
    pub structure_needs_at_least_one_member: u8,
}

/// The response of [`Empty`]: one placeholder byte on the wire.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct EmptyResponse {
    /// Always 0.
    pub structure_needs_at_least_one_member: u8,
}

impl ros2_client::Message for EmptyRequest {}
impl ros2_client::Message for EmptyResponse {}
