//! `lint` over every tree of the repository's corpus: each finding it makes there is
//! listed here by file, line, code and entry, and was read against the tree to be a real
//! one. A new finding, or one gone, fails the test.
//!
//! BehaviorTree.CPP's trees load with their leaves mocked (the lint then knows neither
//! their ports' directions nor their statuses, and assumes the least); Nav2's load against
//! Nav2's own `TreeNodesModel`, with the entries its navigators write and read.

use std::path::{Path, PathBuf};

use neurotree::lint::{lint, LintOptions};
use neurotree::{Arity, CustomNode, NodeCtx, NodeStatus, PortSpec, Registry, XmlLoader};

use crate::corpus_dir;
use corpus_dir::corpus;

fn xml_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            out.extend(xml_files(&path));
        } else if path.extension().is_some_and(|e| e == "xml") {
            out.push(path);
        }
    }
    out.sort();
    out
}

/// The examples' custom controls: only their children and ports matter to the lint.
struct StandIn;

impl CustomNode<()> for StandIn {
    fn tick(&mut self, _node: &mut NodeCtx<'_, '_, ()>) -> NodeStatus {
        NodeStatus::Success
    }
}

/// Every finding over the files of `dir`, each file loaded with the ones it groups with
/// (the tutorials split over several documents), as `file:line: code detail`.
fn findings(registry: &Registry<()>, dir: &Path, options: &LintOptions) -> Vec<String> {
    let mut found = Vec::new();
    let files = xml_files(dir);
    for file in &files {
        let name = file.file_name().unwrap().to_string_lossy().to_string();
        let mut loader = XmlLoader::new(registry)
            .mock_unknown(true)
            .base_dir(corpus(""));
        if loader.load_file(file).is_err() {
            continue;
        }
        // The tutorials' trees that use another document's trees (t07, t14).
        for other in files.iter().filter(|o| *o != file) {
            if !loader.unresolved_subtrees().is_empty() && name.starts_with("examples__t") {
                let _ = loader.load_file(other);
            }
        }
        let ids: Vec<String> = loader.tree_ids().map(String::from).collect();
        if ids.iter().any(|id| loader.validate(id).is_err()) {
            continue;
        }
        for d in lint(&loader, options) {
            let shown = Path::new(&d.file)
                .file_name()
                .unwrap()
                .to_string_lossy()
                .to_string();
            // The entry or node the message names first.
            let named = d.message.split('`').nth(1).unwrap_or_default();
            let line = format!("{shown}:{} {} {named}", d.line, d.code);
            if !found.contains(&line) {
                found.push(line);
            }
        }
    }
    found
}

fn btcpp_registry() -> Registry<()> {
    let mut registry = Registry::<()>::new();
    registry
        .register_custom(
            "ManualSelector",
            Arity::AtLeast(0),
            vec![PortSpec::input::<bool>("repeat_last_selection")],
            || Box::new(StandIn),
        )
        .unwrap();
    registry
        .register_custom(
            "LoopPose",
            Arity::One,
            vec![
                PortSpec::input::<String>("queue"),
                PortSpec::output::<String>("value"),
            ],
            || Box::new(StandIn),
        )
        .unwrap();
    registry
}

#[test]
fn behaviortree_cpp_corpus_findings_are_the_real_ones() {
    let found = findings(&btcpp_registry(), &corpus("btcpp"), &LintOptions::default());
    let expected = vec![
        // `door_open` is set, remapped into DoorClosed and set again there, and never read.
        "examples__t11_groot_howto__01.xml:6 NT0103 door_open",
        // The flag is for the C++ program's mock configuration, which the tree does not see.
        "examples__t15_nodes_mocking_strict_failure__01.xml:10 NT0103 mock_should_fail",
    ];
    assert_eq!(found, expected, "{found:#?}");
}

#[test]
fn nav2_corpus_findings_are_the_real_ones() {
    let mut registry = Registry::<()>::new();
    let model = std::fs::read_to_string(corpus("nav2/nav2_tree_nodes.xml")).unwrap();
    registry
        .add_model_str(&model, "nav2_tree_nodes.xml")
        .unwrap();
    let found = findings(&registry, &corpus("nav2"), &LintOptions::nav2());
    let expected = vec![
        // ComputeRoute's `route` output: the tree follows `route_path` instead.
        "navigate_on_route_graph_w_recovery.xml:31 NT0103 route",
        // No PlannerSelector or ControllerSelector in this tree: the reads fail, and Nav2's
        // nodes, which ignore the failure, use their default planner and controller.
        "navigate_to_pose_w_bounds_check.xml:9 NT0101 planner_id",
        // On the first tick of the ReactiveSequence, FollowPath (after it) has not yet
        // written its feedback: the bounds check's read fails on the first pass.
        "navigate_to_pose_w_bounds_check.xml:11 NT0101 tracking_feedback",
        "navigate_to_pose_w_bounds_check.xml:12 NT0101 controller_id",
        // Selected, and never passed on: FollowPath leaves goal_checker_id and
        // progress_checker_id out (Nav2 uses its defaults).
        "navigate_to_pose_w_replanning_and_recovery.xml:11 NT0103 selected_progress_checker",
        "navigate_to_pose_w_replanning_and_recovery.xml:12 NT0103 selected_goal_checker",
        "navigate_to_pose_w_replanning_and_recovery.xml:13 NT0103 selected_path_handler",
        // The docking example's entries, which its application must write first.
        "opennav_docking_bt__application_example.xml:25 NT0101 dock_type",
        "opennav_docking_bt__application_example.xml:28 NT0101 goal",
        "opennav_docking_bt__application_example.xml:30 NT0101 goal",
        "opennav_docking_bt__application_example.xml:35 NT0101 dock_id",
    ];
    assert_eq!(found, expected, "{found:#?}");
}

#[test]
fn benchmark_tree_has_no_finding() {
    let found = findings(&Registry::new(), &corpus("bench"), &LintOptions::default());
    assert_eq!(found, Vec::<String>::new());
}
