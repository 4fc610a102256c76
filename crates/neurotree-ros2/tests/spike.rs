//! Spike: two RustDDS participants in one process discover each other on 127.0.0.1 and
//! exchange a `std_msgs/String`. `SPIKE_MODE` picks the discovery set-up measured:
//! unset (loopback interface only, unicast SPDP to 127.0.0.1's well-known ports),
//! `default` (RustDDS's defaults), `multicast_only` (no unicast localhost peers),
//! `no_unicast_peers` (loopback only, no unicast localhost peers).
use ros2_client::{Context, MessageTypeName, Name, NodeName, NodeOptions, QosProfile};
use rustdds::DomainParticipantBuilder;
use std::time::{Duration, Instant};

fn ctx(domain: u16) -> Context {
    let mode = std::env::var("SPIKE_MODE").unwrap_or_default();
    let mut b = DomainParticipantBuilder::new(domain);
    if mode != "default" && mode != "multicast_only" {
        b = b.with_only_networks([std::net::IpAddr::from([127, 0, 0, 1])]);
    }
    if mode == "multicast_only" || mode == "no_unicast_peers" {
        b = b.same_host_loopback(false);
    }
    let dp = b.build().unwrap();
    Context::from_domain_participant(dp).unwrap()
}

#[test]
fn two_participants_exchange() {
    let domain = 40 + (std::process::id() % 50) as u16;
    let t0 = Instant::now();
    let a = ctx(domain);
    let b = ctx(domain);
    let mut na = a
        .new_node(NodeName::new("/", "a").unwrap(), NodeOptions::new())
        .unwrap();
    let mut nb = b
        .new_node(NodeName::new("/", "b").unwrap(), NodeOptions::new())
        .unwrap();
    let qos = QosProfile::publisher_default();
    let ta = na
        .create_topic(
            &Name::new("/", "chatter").unwrap(),
            MessageTypeName::new("std_msgs", "String"),
            &qos,
        )
        .unwrap();
    let tb = nb
        .create_topic(
            &Name::new("/", "chatter").unwrap(),
            MessageTypeName::new("std_msgs", "String"),
            &qos,
        )
        .unwrap();
    let publ = na.create_publisher::<String>(&ta, None).unwrap();
    let sub = nb.create_subscription::<String>(&tb, None).unwrap();
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        publ.publish(format!("hello {:?}", t0.elapsed())).unwrap();
        std::thread::sleep(Duration::from_millis(50));
        if let Some((m, _)) = sub.take().unwrap() {
            eprintln!("got {m} after {:?}", t0.elapsed());
            break;
        }
        assert!(Instant::now() < deadline, "no message");
    }
}
