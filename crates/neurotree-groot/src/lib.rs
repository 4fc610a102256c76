//! A Groot2 monitor server: Groot2, and any client of its protocol, watch a NeuroTree tree
//! live, as they watch a BehaviorTree.CPP tree that runs a `Groot2Publisher`.
//!
//! Three parts, with the tree's tick path kept off the network:
//!
//! 1. a [`Groot2Monitor`] attached as the tree's [`Observer`](neurotree_core::Observer)
//!    keeps, under a mutex, every node's status byte and, while a client records, the
//!    transitions with their times. Its callbacks touch only memory allocated up front;
//! 2. the runner calls [`Groot2Monitor::publish_blackboard`] between ticks, since the
//!    blackboard cannot be read while the tree ticks: clients see the entries as of the
//!    latest call;
//! 3. [`Groot2Monitor::serve`] answers requests from a background thread, to ZeroMQ REQ
//!    clients on the given port (Groot2's default is 1667), with a PUB socket on the next
//!    port, as BehaviorTree.CPP binds them. Dropping the [`Groot2Server`] stops it.
//!
//! The server listens on `127.0.0.1` unless [`Groot2Options::bind`] says otherwise, and
//! treats its peers as untrusted: it speaks ZeroMQ's wire protocol (ZMTP 3) itself, checks
//! every frame's claimed length against [`Groot2Options::max_message_bytes`] before reading
//! it, and drops a peer that does not read its replies within
//! [`Groot2Options::send_timeout`], each peer being served apart from the others.
//!
//! The protocol is BehaviorTree.CPP's version 2 ([`protocol`]); the table of
//! [`Groot2Monitor::answer`] lists what each request receives. Breakpoints and node
//! replacement hooks are not supported: requests to set them get an error reply.
//!
//! Times: a transition is stamped with the tree's clock (so a [`ManualClock`](neurotree_toolkit::ManualClock) gives
//! reproducible recordings), relative to the latest time the monitor had seen when the
//! client started recording.
//!
//! ```no_run
//! use std::sync::Arc;
//! use neurotree::groot::Groot2Monitor;
//! use neurotree::{ManualClock, Registry, Status, Tree, XmlLoader};
//!
//! let registry = Registry::<()>::new();
//! let mut loader = XmlLoader::new(&registry);
//! loader.load_file("tree.xml").unwrap();
//! let blueprint = Arc::new(loader.build_main().unwrap());
//! let monitor = Groot2Monitor::new(&blueprint, &registry, loader.main_tree().unwrap());
//! let _server = monitor.serve(1667).unwrap();
//!
//! let mut tree = Tree::new(blueprint);
//! tree.set_observer(monitor.clone());
//! while tree.tick_once(&mut ()).unwrap() == Status::Running {
//!     monitor.publish_blackboard(&tree);
//!     std::thread::sleep(std::time::Duration::from_millis(100));
//! }
//! ```
//!
//! The same answers without a network, as a program with its own transport would get them:
//!
//! ```
//! use neurotree::groot::Groot2Monitor;
//! use neurotree::{Blueprint, ManualClock, Registry, Status, Tree};
//!
//! let blueprint = Blueprint::<()>::builder()
//!     .sequence("main", |s| s.always_success("a").always_failure("b"))
//!     .build_shared()
//!     .unwrap();
//! let monitor = Groot2Monitor::new(&blueprint, &Registry::new(), "MainTree");
//! let mut tree = Tree::with_clock(blueprint, ManualClock::new());
//! tree.set_observer(monitor.clone());
//! assert_eq!(tree.tick_once(&mut ()), Ok(Status::Failure));
//!
//! // `S`, request id 7: the reply header, then uid and status byte for each node.
//! let reply = monitor.answer(&[[2, b'S', 7, 0, 0, 0]]);
//! assert_eq!(reply[0][..6], [2, b'S', 7, 0, 0, 0]);
//! assert_eq!(reply[0][6..], monitor.tree_uuid());
//! // The sequence failed and was reset: Idle after Failure (13), and so were its children.
//! assert_eq!(reply[1], [1, 0, 13, 2, 0, 12, 3, 0, 13]);
//! ```

mod monitor;
mod peer;
pub mod protocol;
mod requests;
mod server;
mod zmtp;

pub use monitor::Groot2Monitor;
pub use server::{Groot2Options, Groot2Server, GrootError};
