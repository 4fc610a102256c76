//! Two bridge nodes, each with its own DDS participant, find each other over 127.0.0.1 (the
//! unicast SPDP of `Network::Loopback`) and exchange a message.

use crate::common;

use std::time::{Duration, Instant};

use common::{free_domain, node};
use neurotree_ros2::msg::std_msgs;

pub(crate) fn two_loopback_participants_discover_each_other_and_exchange_a_message() {
    let domain = free_domain();
    let talker = node("talker", domain.id);
    let listener = node("listener", domain.id);
    let publisher = talker.publisher::<std_msgs::String>("chatter").unwrap();
    let subscription = listener
        .subscription::<std_msgs::String>("chatter")
        .unwrap();
    let started = Instant::now();

    let mut received = None;
    // Discovery on loopback takes a fraction of a second (about 0.25 s measured); the
    // bound only ends a run that would never discover.
    while received.is_none() && started.elapsed() < Duration::from_secs(180) {
        publisher.publish("hello".into()).unwrap();
        std::thread::sleep(Duration::from_millis(20));
        received = subscription.take().unwrap().map(|(message, _)| message);
    }

    assert_eq!(received, Some(std_msgs::String::from("hello")));
}
