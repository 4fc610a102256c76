//! `.btlog` files: what the writer writes reads back exactly, uids match the XML, and the
//! file is laid out byte for byte as BehaviorTree.CPP's FileLogger2 lays it out.

use crate::patrol;

use std::time::{Duration, UNIX_EPOCH};

use neurotree::observe::{read_btlog, read_btlog_file, BtlogRecord, BtlogWriter, BTLOG_MAGIC};
use neurotree::{ManualClock, NodeId, NodeStatus, Registry, Status, Tree, XmlLoader};

const I: NodeStatus = NodeStatus::Idle;
const R: NodeStatus = NodeStatus::Running;
const S: NodeStatus = NodeStatus::Success;
const F: NodeStatus = NodeStatus::Failure;

/// The patrol's status changes: (milliseconds since the log started, uid, new status).
const PATROL: [(u64, u16, NodeStatus); 33] = [
    (100, 1, R),
    (100, 2, S),
    (100, 3, R),
    (100, 4, R),
    (100, 5, S),
    (100, 5, I),
    (100, 4, S),
    (100, 6, R),
    (100, 2, I),
    (200, 2, F),
    (200, 2, I),
    (200, 4, I),
    (200, 6, I),
    (200, 3, I),
    (200, 1, F),
    (200, 1, I),
    (300, 1, R),
    (300, 2, S),
    (300, 3, R),
    (300, 6, R),
    (300, 2, I),
    (400, 2, S),
    (400, 2, I),
    (500, 2, S),
    (500, 6, S),
    (500, 7, S),
    (500, 6, I),
    (500, 7, I),
    (500, 3, S),
    (500, 2, I),
    (500, 3, I),
    (500, 1, S),
    (500, 1, I),
];

#[test]
fn round_trip_gives_back_every_transition() {
    let (mut tree, clock) = patrol::start();
    // Offsets count from the writer's creation, not from the clock's origin.
    clock.advance(Duration::from_secs(1));
    let start = UNIX_EPOCH + Duration::from_micros(1_700_000_000_123_456);
    let log = BtlogWriter::with_start(Vec::new(), &tree, &Registry::new(), start).unwrap();
    tree.set_observer(log.clone());
    patrol::run(&mut tree, &clock);
    log.flush().unwrap();
    let bytes = log.with_writer(|out| out.clone());

    let read = read_btlog(&bytes[..]).unwrap();
    assert_eq!(read.first_timestamp_us, 1_700_000_000_123_456);
    let expected: Vec<BtlogRecord> = PATROL
        .iter()
        .map(|&(ms, uid, status)| BtlogRecord {
            offset_us: ms * 1000,
            uid,
            status,
        })
        .collect();
    assert_eq!(read.records, expected);
    assert_eq!(read.records[5].node(), Some(NodeId(4)));

    // The header is exactly: magic, protocol 1, the XML's length, the XML, the timestamp.
    let xml_len = read.xml.len();
    assert_eq!(&bytes[..18], BTLOG_MAGIC);
    assert_eq!(bytes[18], 1);
    assert_eq!(bytes[19..23], (xml_len as i32).to_le_bytes());
    assert_eq!(&bytes[23..23 + xml_len], read.xml.as_bytes());
    assert_eq!(
        bytes[23 + xml_len..31 + xml_len],
        1_700_000_000_123_456i64.to_le_bytes()
    );
    assert_eq!(bytes.len(), 31 + xml_len + 9 * PATROL.len());
    // The first record, byte for byte: 100 ms (48 bits), uid 1, RUNNING.
    assert_eq!(
        bytes[31 + xml_len..40 + xml_len],
        [0xa0, 0x86, 0x01, 0, 0, 0, 1, 0, 1]
    );

    // The XML names every node with its uid (leaves made from closures have no registered
    // type, so they are written `<Action ID="their name"/>`).
    let doc = roxmltree::Document::parse(&read.xml).unwrap();
    let uids: Vec<(u16, String)> = doc
        .descendants()
        .filter_map(|e| {
            let uid = e.attribute("_uid")?.parse().ok()?;
            Some((uid, e.attribute("name").or(e.attribute("ID"))?.into()))
        })
        .collect();
    let names: Vec<(u16, String)> = tree
        .blueprint()
        .ids()
        .map(|id| (id.0 as u16 + 1, tree.blueprint().name(id).to_string()))
        .collect();
    assert_eq!(uids, names);
    assert!(doc.descendants().any(|e| e.has_tag_name("TreeNodesModel")));
}

#[test]
fn subtree_nodes_are_numbered_in_place_as_bt_cpp_does() {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            r#"<root BTCPP_format="4" main_tree_to_execute="Main">
                 <BehaviorTree ID="Main">
                   <Sequence name="main">
                     <SubTree ID="Step" name="first"/>
                     <AlwaysSuccess name="between"/>
                     <SubTree ID="Step" name="second"/>
                   </Sequence>
                 </BehaviorTree>
                 <BehaviorTree ID="Step">
                   <Inverter name="not"><AlwaysFailure name="fail"/></Inverter>
                 </BehaviorTree>
               </root>"#,
            "subtrees.xml",
        )
        .unwrap();
    let blueprint = std::sync::Arc::new(loader.build_main().unwrap());
    let mut tree = Tree::with_clock(blueprint.clone(), ManualClock::new());
    let log = BtlogWriter::new(Vec::new(), &tree, &registry).unwrap();
    tree.set_observer(log.clone());
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    let read = read_btlog(&log.with_writer(|out| out.clone())[..]).unwrap();

    // Depth-first creation order: each SubTree, then the nodes of its tree.
    let doc = roxmltree::Document::parse(&read.xml).unwrap();
    let mut by_uid: Vec<(u16, String)> = doc
        .descendants()
        .filter_map(|e| {
            let uid = e.attribute("_uid")?.parse().ok()?;
            let label = e.attribute("name").or(e.attribute("ID"))?;
            Some((uid, format!("{}:{label}", e.tag_name().name())))
        })
        .collect();
    by_uid.sort();
    assert_eq!(
        by_uid,
        [
            (1, "Sequence:main".to_string()),
            (2, "SubTree:first".to_string()),
            (3, "Inverter:not".to_string()),
            (4, "AlwaysFailure:fail".to_string()),
            (5, "AlwaysSuccess:between".to_string()),
            (6, "SubTree:second".to_string()),
            (7, "Inverter:not".to_string()),
            (8, "AlwaysFailure:fail".to_string()),
        ]
    );
    // Each subtree instance is its own <BehaviorTree> with its path.
    let fullpaths: Vec<&str> = doc
        .descendants()
        .filter(|e| e.has_tag_name("BehaviorTree"))
        .filter_map(|e| e.attribute("_fullpath"))
        .collect();
    assert_eq!(fullpaths, ["main/first", "main/second"]);
    // The second subtree's leaf failed: uid 8 is node 7, inside "second".
    let fail = read
        .records
        .iter()
        .find(|r| r.uid == 8 && r.status == NodeStatus::Failure)
        .unwrap();
    assert_eq!(blueprint.path(fail.node().unwrap()), "main/second/not/fail");
}

#[test]
fn create_writes_a_file_that_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.btlog");
    let (mut tree, clock) = patrol::start();
    let log = BtlogWriter::create(&path, &tree, &Registry::new()).unwrap();
    tree.set_observer(log.clone());
    patrol::run(&mut tree, &clock);
    // Dropping the tree and the handle flushes the file.
    drop(tree);
    drop(log);
    let read = read_btlog_file(&path).unwrap();
    assert_eq!(read.records.len(), PATROL.len());
    assert!(
        read.first_timestamp_us > 1_600_000_000_000_000,
        "a wall-clock time"
    );
    // A file cut inside a record is an error, not a shorter log.
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..bytes.len() - 4]).unwrap();
    let err = read_btlog_file(&path).unwrap_err();
    assert!(err.to_string().contains("the last record"), "{err}");
}
