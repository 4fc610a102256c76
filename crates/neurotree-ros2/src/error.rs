//! What can go wrong when the bridge sets up its ROS 2 side.

/// An error of the ROS 2 bridge: making the node, or an endpoint on it.
#[derive(thiserror::Error)]
#[non_exhaustive]
pub enum Ros2Error {
    /// The DDS participant or the ROS 2 node could not be made.
    #[error("cannot start the ROS 2 node `{node}`: {message}")]
    Node {
        /// The node's name.
        node: String,
        /// RustDDS's or ros2-client's reason.
        message: String,
    },
    /// A topic, service or action name is not a valid ROS 2 name.
    #[error("`{name}` is not a valid ROS 2 name: {message}")]
    Name {
        /// The name given.
        name: String,
        /// Why not.
        message: String,
    },
    /// A publisher, subscription, client or server could not be made.
    #[error("cannot create the {kind} for `{name}`: {message}")]
    Endpoint {
        /// `publisher`, `subscription`, `service client`, `action client`, ...
        kind: &'static str,
        /// The topic, service or action name.
        name: String,
        /// RustDDS's reason.
        message: String,
    },
    /// A server failed to read a request or to answer it.
    #[error("the {kind} `{name}` failed: {message}")]
    Serve {
        /// `action server`, `service server`, ...
        kind: &'static str,
        /// The service or action name.
        name: String,
        /// What failed, and RustDDS's reason.
        message: String,
    },
}

neurotree_toolkit::debug_shows_message!(enum Ros2Error {
    Node { node, message },
    Name { name, message },
    Endpoint { kind, name, message },
    Serve { kind, name, message },
});
