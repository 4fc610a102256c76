//! Interoperability with an independent DDS implementation: Eclipse Cyclone DDS, through its
//! Python binding (`cyclonedds` on PyPI), plays a ROS 2 node on topic `chatter`
//! (`tests/cyclonedds/chatter.py`). A tree loaded from XML publishes on it with a
//! `RosTopicPubNode` and reads it with a `RosTopicSubNode`.
//!
//! The Python comes from `CYCLONEDDS_PYTHON` (`.ci/run` installs the package in a virtual
//! environment and sets it); without it the test fails under `.ci/run`
//! (`NEUROTREE_REQUIRE_REFERENCES=1`), and elsewhere prints why it skips and passes.

use crate::common;

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use common::{free_domain, node};
use neurotree_ros2::msg::std_msgs;
use neurotree_ros2::{LatestMessage, PublisherSpec, RosTopicPubNode, RosTopicSubNode};
use neurotree_toolkit::{Handle, PortSpec, Registry, Tree, XmlLoader};

/// Publishes the `text` port as a `std_msgs/String`.
struct SayText;

impl PublisherSpec<()> for SayText {
    type Message = std_msgs::String;

    fn ports() -> Vec<PortSpec> {
        vec![PortSpec::input::<String>("text")]
    }

    fn message(&mut self, h: &mut Handle<'_, ()>) -> Result<std_msgs::String, String> {
        let text: String = h.input("text").map_err(|e| e.to_string())?;
        Ok(std_msgs::String { data: text })
    }
}

const TREE: &str = r#"
<root BTCPP_format="4">
  <BehaviorTree ID="Chat">
    <Sequence>
      <SayText topic_name="chatter" text="hello from neurotree"/>
      <Chatter topic_name="chatter" message="{heard}"/>
    </Sequence>
  </BehaviorTree>
</root>"#;

/// Kills the Python side if the test ends before it does.
struct Peer(Child);

impl Drop for Peer {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// The reference this test compares with is missing. Under `.ci/run`, which installs it and
/// sets `NEUROTREE_REQUIRE_REFERENCES=1`, the test fails: a run without it proves nothing.
/// Elsewhere (a fresh checkout's `cargo test`) it says on stderr what it skipped, and passes.
fn reference_missing(why: &str) {
    if std::env::var("NEUROTREE_REQUIRE_REFERENCES").as_deref() == Ok("1") {
        panic!("{why}; `.ci/run` installs it (with NEUROTREE_ALLOW_SKIP=1 it goes without)");
    }
    use std::io::Write as _;
    // Straight to stderr, past the test harness's capture, so that the run says so.
    let _ = writeln!(
        std::io::stderr(),
        "skipped: {why} (`bash .ci/run` installs it and runs this test)"
    );
}

pub(crate) fn a_cyclone_dds_node_and_a_tree_exchange_std_msgs_string_on_chatter() {
    let Some(python) = std::env::var_os("CYCLONEDDS_PYTHON") else {
        reference_missing("CYCLONEDDS_PYTHON is not set (a Python with cyclonedds==11.0.1)");
        return;
    };
    let domain = free_domain();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/cyclonedds/chatter.py");
    let mut peer = Peer(
        Command::new(python)
            .arg(script)
            .args([domain.id.to_string(), common::HANG.as_secs().to_string()])
            .stdout(Stdio::piped())
            .spawn()
            .expect("the Python of CYCLONEDDS_PYTHON runs"),
    );

    let ros = node("tree", domain.id);
    let mut registry = Registry::<()>::new();
    RosTopicPubNode::register(&mut registry, "SayText", &ros, "chatter", || SayText).unwrap();
    RosTopicSubNode::register(&mut registry, "Chatter", &ros, "chatter", || {
        LatestMessage::<std_msgs::String>::default()
    })
    .unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(TREE, "chat.xml").unwrap();
    let mut tree = Tree::new(Arc::new(loader.build_main().unwrap()));

    // The tree publishes on every tick; the newest message it read is `heard`. Its own
    // messages come back to it too, so it waits for one from Cyclone DDS.
    let until = Instant::now() + common::HANG;
    let mut heard_cyclone = None;
    let mut peer_status = None;
    while Instant::now() < until && (heard_cyclone.is_none() || peer_status.is_none()) {
        tree.tick_once(&mut ()).unwrap();
        if let Ok(heard) = tree.blackboard().get::<std_msgs::String>("heard") {
            if heard.data.starts_with("hello from cyclonedds") {
                heard_cyclone.get_or_insert(heard.data);
            }
        }
        if peer_status.is_none() {
            peer_status = peer.0.try_wait().unwrap();
        }
        std::thread::sleep(Duration::from_millis(20));
    }

    let mut said = String::new();
    if let Some(mut out) = peer.0.stdout.take() {
        std::io::Read::read_to_string(&mut out, &mut said).unwrap();
    }
    assert!(
        heard_cyclone.is_some(),
        "the tree read nothing from Cyclone DDS"
    );
    assert!(
        peer_status.is_some_and(|s| s.success()),
        "Cyclone DDS read nothing from the tree: {said}"
    );
    assert!(said.starts_with("received: hello from neurotree"), "{said}");
}
