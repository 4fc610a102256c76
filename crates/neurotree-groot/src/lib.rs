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
//! # Why the tree failed
//!
//! Groot2 learns why a tick failed from the blackboard panel. Its protocol has no field for
//! a reason: a status or transition record holds a status byte and no more, and the tree's
//! XML is fetched once per tree id. The blackboard reply, JSON that Groot2 asks for again
//! while it watches, is the one place text can reach it unmodified. So when the tick before
//! the latest [`Groot2Monitor::publish_blackboard`] failed ([`Tree::last_failure`]), the
//! main tree's blackboard (the one named after the main tree) holds, besides the tree's own
//! entries, these read-only ones ([`failure_entries`]):
//!
//! | entry | value | example |
//! |---|---|---|
//! | `@failure.path` | the path of the node whose failure decided the root | `"mission/reach/follow"` |
//! | `@failure.reason` | the message of the deepest reason on the chain, if any | `"blocked"` |
//! | `@failure.code` | its code, unless 0 | `106` |
//! | `@failure.chain` | the whole chain, one link per line, with what each Fallback tried | `"mission\n  mission/reach\n    tried ..."` |
//!
//! Groot2 lists them among the entries, as it lists strings and integers of a
//! BehaviorTree.CPP blackboard; a publication after a tick that did not fail takes them
//! away. Subtrees' blackboards never carry them. Every blackboard access reads a leading
//! `@` as "the root's" and strips it, so no key a tree reads or writes is stored under these
//! names; one written with two `@`s (`@@failure.path`) would be, and is replaced by the
//! monitor's in the reply.
//!
//! The chain is taken by `publish_blackboard`, between ticks, and the entries are made when
//! a `B` request asks for the main tree's blackboard: the observer callbacks, which run in
//! the tick, allocate nothing for them.
//!
//! [`Tree::last_failure`]: neurotree_core::Tree::last_failure
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

#![forbid(unsafe_code)]

mod monitor;
mod peer;
pub mod protocol;
mod requests;
mod server;
mod zmtp;

pub use monitor::{
    failure_entries, Groot2Monitor, FAILURE_CHAIN, FAILURE_CODE, FAILURE_PATH, FAILURE_REASON,
};
pub use server::{Groot2Options, Groot2Server, GrootError};
