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

/// Simulated seconds per wall second for the tests' servers: a simulated step of 100 ms
/// lasts 8 ms of wall time, about one of the tests' 10 ms ticks, so a run of a minute of
/// simulated time is over in seconds while every step's result still reaches the tree.
pub const TIME_SCALE: f64 = 12.0;

/// A hang catch: far longer than any wait in these tests takes on a loaded machine.
pub const HANG: Duration = Duration::from_secs(180);

/// Waits until the servers behind `stats` have taken `steps` more steps than now, and
/// gives what they saw then: everything asked of them before the call is counted.
pub fn after_steps(
    stats: &neurotree_ros2::nav2::SimStatsHandle,
    steps: u64,
) -> neurotree_ros2::nav2::SimStats {
    let until = stats.get().steps + steps;
    let deadline = Instant::now() + HANG;
    loop {
        let seen = stats.get();
        if seen.steps >= until {
            return seen;
        }
        assert!(
            Instant::now() < deadline,
            "the servers stopped stepping: {seen:?}"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
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

/// [`SimServers`](neurotree_ros2::nav2::SimServers) serving a world in a thread of its
/// own until dropped.
pub struct Served {
    stop: Arc<std::sync::atomic::AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
    /// What the servers saw.
    pub stats: neurotree_ros2::nav2::SimStatsHandle,
}

impl Served {
    /// Serves `sim` in `domain`, `time_scale` times as fast as real time.
    pub fn start(domain: u16, sim: neurotree_sim::nav2::Nav2Sim, time_scale: f64) -> Self {
        use neurotree_ros2::nav2::{SimOptions, SimServers};
        let stop = Arc::new(std::sync::atomic::AtomicBool::new(false));
        let stopped = Arc::clone(&stop);
        let (tx, rx) = std::sync::mpsc::channel();
        let thread = std::thread::spawn(move || {
            let ros = node("nav2_sim", domain);
            let options = SimOptions {
                time_scale,
                ..SimOptions::default()
            };
            let mut servers = SimServers::new(&ros, sim, options).unwrap();
            tx.send(servers.stats()).unwrap();
            servers.run(&stopped).unwrap();
        });
        let stats = rx.recv_timeout(Duration::from_secs(10)).unwrap();
        Self {
            stop,
            thread: Some(thread),
            stats,
        }
    }
}

impl Drop for Served {
    fn drop(&mut self) {
        self.stop.store(true, std::sync::atomic::Ordering::SeqCst);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// A tree of `body` (the main tree's XML inside `<BehaviorTree>`) with the Nav2 ROS 2
/// leaves on a node of its own in `domain`, on the wall clock.
pub fn nav2_tree(domain: u16, body: &str) -> Tree<()> {
    let ros = node("bt_navigator", domain);
    let mut registry = neurotree_toolkit::Registry::<()>::new();
    neurotree_ros2::nav2::register_nav2_ros_leaves(&mut registry, &ros).unwrap();
    let mut loader = neurotree_toolkit::XmlLoader::new(&registry);
    let file =
        format!(r#"<root BTCPP_format="4"><BehaviorTree ID="T">{body}</BehaviorTree></root>"#);
    loader.load_str(&file, "tree.xml").unwrap();
    Tree::new(Arc::new(loader.build_main().unwrap()))
}
