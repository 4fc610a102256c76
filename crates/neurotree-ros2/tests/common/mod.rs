//! What the ROS 2 tests share: a DDS domain of their own, a loopback node on it, and a loop
//! that ticks a tree until it completes or a deadline passes.

#![allow(dead_code)]

use std::net::UdpSocket;
use std::sync::Arc;
use std::time::{Duration, Instant};

use neurotree_ros2::{RosNode, RosOptions};
use neurotree_toolkit::{Blueprint, Status, Tree};

/// A DDS domain that this test alone uses on this machine, held while the value lives.
///
/// Holding the UDP port of the domain's participant 0 (7410 + 250 × domain) is the claim:
/// another test process probing the same domain fails to bind it and moves on, and the
/// test's own participants take the next participant ids. Domains 100 to 231 keep clear of
/// the default, 0.
pub struct Domain {
    /// The domain id.
    pub id: u16,
    _claim: UdpSocket,
}

/// Claims a free [`Domain`].
pub fn free_domain() -> Domain {
    let start = (std::process::id() * 7) % 132;
    for i in 0..132 {
        let id = 100 + ((start + i) % 132) as u16;
        if let Ok(claim) = UdpSocket::bind(("0.0.0.0", 7410 + 250 * id)) {
            return Domain { id, _claim: claim };
        }
    }
    panic!("no free DDS domain between 100 and 231");
}

/// A node on 127.0.0.1 in `domain`.
pub fn node(name: &str, domain: u16) -> RosNode {
    RosNode::new(name, &RosOptions::loopback(domain)).unwrap()
}

/// Ticks `tree` every 10 ms while it is Running, for at most `limit`; its last status.
pub fn tick_until_done<C>(tree: &mut Tree<C>, ctx: &mut C, limit: Duration) -> Status {
    let until = Instant::now() + limit;
    loop {
        let status = tree.tick_once(ctx).unwrap();
        if status != Status::Running || Instant::now() >= until {
            return status;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// A tree of `blueprint` on the wall clock.
pub fn tree<C: 'static>(blueprint: Arc<Blueprint<C>>) -> Tree<C> {
    Tree::new(blueprint)
}
