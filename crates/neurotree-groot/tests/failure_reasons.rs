//! Why the tree failed, as Groot2 receives it: the `@failure.*` entries of the main tree's
//! blackboard, asked for with a `B` request over a ZeroMQ REQ socket, for a tree built in
//! code and for one loaded from XML, each with a leaf that fails with
//! `fail_with(106, "blocked")` under a Fallback.

use std::net::{IpAddr, Ipv4Addr};
use std::sync::Arc;
use std::time::Duration;

use neurotree::groot::{Groot2Monitor, Groot2Server};
use neurotree::{Action, Blueprint, Handle, ManualClock, Registry, Status, Tree, XmlLoader};
use serde_json::{json, Value};

use crate::counting_alloc;
use counting_alloc::allocations;

use crate::client;

/// Long enough for a loaded machine; a reply that never comes fails the test instead of
/// hanging it.
const TIMEOUT: Duration = Duration::from_secs(20);

/// Fails with code 106, "blocked".
struct Blocked;
impl<C> Action<C> for Blocked {
    fn tick(&self, h: &mut Handle<'_, C>) -> Status {
        h.fail_with(106, "blocked")
    }
}

/// The blackboards a `B` request for `names` receives, read from its MessagePack.
fn blackboards(client: &mut client::Client, monitor: &Groot2Monitor, names: &str) -> Value {
    let request = [2, b'B', 5, 0, 0, 0];
    let reply = client.request_within(&[&request, names.as_bytes()], TIMEOUT);
    assert_eq!(reply.len(), 2);
    assert_eq!(reply[0][..6], [2, b'B', 5, 0, 0, 0]);
    assert_eq!(reply[0][6..], monitor.tree_uuid());
    rmp_serde::from_slice(&reply[1]).unwrap()
}

fn serve(monitor: &Groot2Monitor) -> (Groot2Server, client::Client) {
    let server = monitor
        .serve_on(IpAddr::V4(Ipv4Addr::LOCALHOST), 0)
        .unwrap();
    let client = client::Client::connect(server.port(), TIMEOUT);
    (server, client)
}

/// A tree built in code: `near` (the context) decides whether `follow`, which is blocked,
/// is tried.
fn built() -> Blueprint<bool> {
    Blueprint::<bool>::builder()
        .sequence("mission", |s| {
            s.always_success("start").fallback("reach", |f| {
                f.condition("near", |near: &bool| *near)
                    .action_node("follow", Blocked)
            })
        })
        .build()
        .unwrap()
}

#[test]
fn a_built_tree_shows_why_it_failed_in_the_main_blackboard() {
    let blueprint = Arc::new(built());
    let monitor = Groot2Monitor::new(&blueprint, &Registry::new(), "MainTree");
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    tree.set_observer(monitor.clone());
    let (_server, mut client) = serve(&monitor);

    monitor.publish_blackboard(&tree);
    assert_eq!(
        blackboards(&mut client, &monitor, "MainTree"),
        json!({ "MainTree": {} })
    );

    assert_eq!(tree.tick_once(&mut false), Ok(Status::Failure));
    monitor.publish_blackboard(&tree);
    assert_eq!(
        blackboards(&mut client, &monitor, "MainTree"),
        json!({ "MainTree": {
            "@failure.path": "mission/reach/follow",
            "@failure.reason": "blocked",
            "@failure.code": 106,
            "@failure.chain": "mission\n  \
                               mission/reach\n    \
                               tried mission/reach/near: no reason given\n    \
                               tried mission/reach/follow: blocked (error 106)\n    \
                               mission/reach/follow: blocked (error 106)",
        }})
    );

    // A tick that does not fail takes the entries away at the next publication.
    assert_eq!(tree.tick_once(&mut true), Ok(Status::Success));
    assert_eq!(
        blackboards(&mut client, &monitor, "MainTree")["MainTree"]["@failure.code"],
        json!(106)
    );
    monitor.publish_blackboard(&tree);
    assert_eq!(
        blackboards(&mut client, &monitor, "MainTree"),
        json!({ "MainTree": {} })
    );
}

const XML: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence name="mission">
      <Script name="init" code="count := count + 1"/>
      <SubTree ID="Probe" name="probe"/>
      <Fallback name="reach">
        <ScriptCondition name="near" code="near"/>
        <FollowPath name="follow"/>
      </Fallback>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Probe">
    <Script name="look" code="seen := 1"/>
  </BehaviorTree>
</root>"#;

#[test]
fn a_tree_from_xml_shows_why_it_failed_in_the_main_blackboard_only() {
    let mut registry = Registry::<()>::new();
    registry
        .register_action("FollowPath", vec![], |h| h.fail_with(106, "blocked"))
        .unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(XML, "mission.xml").unwrap();
    let blueprint = Arc::new(loader.build_main().unwrap());
    let monitor = Groot2Monitor::new(&blueprint, &registry, "Main");
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    tree.blackboard_mut().set("count", 0_i64).unwrap();
    tree.blackboard_mut().set("near", false).unwrap();
    tree.set_observer(monitor.clone());
    let (_server, mut client) = serve(&monitor);

    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Failure));
    monitor.publish_blackboard(&tree);
    let failed = json!({
        "Main": {
            "count": 1,
            "near": false,
            "@failure.path": "mission/reach/follow",
            "@failure.reason": "blocked",
            "@failure.code": 106,
            "@failure.chain": "mission\n  \
                               mission/reach\n    \
                               tried mission/reach/near: no reason given\n    \
                               tried mission/reach/follow: blocked (error 106)\n    \
                               mission/reach/follow: blocked (error 106)",
        },
        "mission/probe": { "seen": 1 },
    });
    assert_eq!(
        blackboards(&mut client, &monitor, "Main;mission/probe"),
        failed
    );
    // A subtree's blackboard alone carries none of them.
    assert_eq!(
        blackboards(&mut client, &monitor, "mission/probe"),
        json!({ "mission/probe": { "seen": 1 } })
    );

    tree.blackboard_mut().set("near", true).unwrap();
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    monitor.publish_blackboard(&tree);
    assert_eq!(
        blackboards(&mut client, &monitor, "Main"),
        json!({ "Main": { "count": 2, "near": true } })
    );
}

#[test]
fn a_failure_without_reasons_reaches_each_leaf_that_decided_it() {
    // A Fallback of two Sequences whose first conditions fail; no node gives a reason.
    let blueprint = Arc::new(
        Blueprint::<()>::builder()
            .fallback("choose", |f| {
                f.sequence("dock", |s| {
                    s.condition("low", |_: &()| false).always_success("go_dock")
                })
                .sequence("patrol", |s| {
                    s.condition("charged", |_: &()| false).always_success("go")
                })
            })
            .build()
            .unwrap(),
    );
    let monitor = Groot2Monitor::new(&blueprint, &Registry::new(), "MainTree");
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    tree.set_observer(monitor.clone());
    let (_server, mut client) = serve(&monitor);
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Failure));
    monitor.publish_blackboard(&tree);
    assert_eq!(
        blackboards(&mut client, &monitor, "MainTree"),
        json!({ "MainTree": {
            "@failure.path": "choose/patrol/charged",
            "@failure.chain": "choose\n  \
                               tried choose/dock: no reason given\n    \
                               choose/dock/low\n  \
                               tried choose/patrol: no reason given\n  \
                               choose/patrol\n    \
                               choose/patrol/charged",
        }})
    );
}

#[test]
fn an_entry_the_tree_stored_under_a_reserved_name_gives_way() {
    let blueprint = Arc::new(built());
    let monitor = Groot2Monitor::new(&blueprint, &Registry::new(), "MainTree");
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    // Every access reads one leading `@` as "the root's": only a second one stores it.
    tree.blackboard_mut()
        .set("@failure.path", "elsewhere".to_string())
        .unwrap();
    tree.blackboard_mut()
        .set("@@failure.path", "elsewhere".to_string())
        .unwrap();
    assert_eq!(tree.tick_once(&mut false), Ok(Status::Failure));
    monitor.publish_blackboard(&tree);
    let reply = monitor.answer(&[&[2, b'B', 1, 0, 0, 0][..], b"MainTree"]);
    let got: Value = rmp_serde::from_slice(&reply[1]).unwrap();
    assert_eq!(got["MainTree"]["failure.path"], json!("elsewhere"));
    assert_eq!(
        got["MainTree"]["@failure.path"],
        json!("mission/reach/follow")
    );
    assert_eq!(got["MainTree"].as_object().unwrap().len(), 5);
}

#[test]
fn failing_with_a_reason_allocates_nothing_in_the_tick() {
    let blueprint = Arc::new(built());
    let monitor = Groot2Monitor::new(&blueprint, &Registry::new(), "MainTree");
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    tree.set_observer(monitor.clone());
    monitor.answer(&[&[2, b'r', 1, 0, 0, 0][..], b"start"]);
    assert_eq!(tree.tick_once(&mut false), Ok(Status::Failure));
    let n = allocations(|| {
        for _ in 0..200 {
            assert_eq!(tree.tick_once(&mut false), Ok(Status::Failure));
        }
    });
    assert_eq!(n, 0);
    // Nothing was published, so no client sees a failure yet.
    let reply = monitor.answer(&[&[2, b'B', 1, 0, 0, 0][..], b"MainTree"]);
    let got: Value = rmp_serde::from_slice(&reply[1]).unwrap();
    assert_eq!(got, json!({ "MainTree": {} }));
}
