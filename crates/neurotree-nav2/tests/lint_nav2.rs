//! lint on Nav2's trees, with Nav2's controls and their declared semantics (what
//! `neurotree lint --nav2` uses): every finding on the trees of `corpus/nav2` is listed with
//! why it is right, and a read before its write under a RecoveryNode is found.

use neurotree::lint::{lint, LintOptions};
use neurotree::nav2::{register_release, Nav2Release};
use neurotree::{Registry, XmlLoader};

use crate::corpus_dir::corpus;

fn nav2_registry() -> Registry<()> {
    let mut registry = Registry::<()>::new();
    register_release(&mut registry, Nav2Release::Main).unwrap();
    registry
}

/// Every finding on the Nav2 corpus, as `file:line code entry-or-node`.
fn corpus_findings() -> Vec<String> {
    let registry = nav2_registry();
    let mut files: Vec<_> = std::fs::read_dir(corpus("nav2"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "xml"))
        .filter(|p| !p.ends_with("nav2_tree_nodes.xml"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 16, "{files:?}");
    let mut found = Vec::new();
    for file in &files {
        let mut loader = XmlLoader::new(&registry);
        loader.load_file(file).unwrap();
        let ids: Vec<String> = loader.tree_ids().map(String::from).collect();
        for id in &ids {
            loader.validate(id).unwrap();
        }
        for d in lint(&loader, &LintOptions::nav2()) {
            let name = file.file_name().unwrap().to_string_lossy().to_string();
            let named = d.message.split('`').nth(1).unwrap_or_default().to_string();
            found.push(format!("{name}:{} {} {named}", d.line, d.code));
        }
    }
    found
}

#[test]
fn every_finding_on_nav2s_trees_is_a_real_one() {
    let expected = [
        // ComputeRoute's `route` output: the tree follows `route_path` instead.
        "navigate_on_route_graph_w_recovery.xml:31 NT0103 route",
        // No PlannerSelector or ControllerSelector in this tree: nothing writes
        // `selected_planner` or `selected_controller`, so the reads fail and Nav2's nodes,
        // which ignore the failure, use their default planner and controller.
        "navigate_to_pose_w_bounds_check.xml:9 NT0101 planner_id",
        // The ReactiveSequence ticks the bounds check first, before FollowPath (after it)
        // has written any feedback: on the first pass the read of `tracking_feedback` fails.
        "navigate_to_pose_w_bounds_check.xml:11 NT0101 tracking_feedback",
        "navigate_to_pose_w_bounds_check.xml:12 NT0101 controller_id",
        // Selected, and never passed on: FollowPath leaves goal_checker_id,
        // progress_checker_id and path_handler_id out (Nav2 uses its defaults).
        "navigate_to_pose_w_replanning_and_recovery.xml:11 NT0103 selected_progress_checker",
        "navigate_to_pose_w_replanning_and_recovery.xml:12 NT0103 selected_goal_checker",
        "navigate_to_pose_w_replanning_and_recovery.xml:13 NT0103 selected_path_handler",
        // The docking example reads entries that only its application can write first
        // (`dock_type`, `picking_location`, `placing_location`, `dock_id`): nothing in the
        // tree writes them, and they are not among those Nav2's navigators write.
        "opennav_docking_bt__application_example.xml:25 NT0101 dock_type",
        "opennav_docking_bt__application_example.xml:28 NT0101 goal",
        "opennav_docking_bt__application_example.xml:30 NT0101 goal",
        "opennav_docking_bt__application_example.xml:35 NT0101 dock_id",
    ];
    assert_eq!(corpus_findings(), expected);
}

#[test]
fn a_read_before_its_write_under_a_recovery_node_fails_on_the_first_pass() {
    let xml = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <RecoveryNode number_of_retries="6" name="NavigateRecovery">
      <Sequence>
        <FollowPath path="{path}" controller_id="FollowPath"/>
        <ComputePathToPose goal="{goal}" path="{path}" planner_id="GridBased"/>
      </Sequence>
      <ClearEntireCostmap service_name="global_costmap/clear_entirely_global_costmap"/>
    </RecoveryNode>
  </BehaviorTree>
</root>"#;
    let registry = nav2_registry();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(xml, "nav.xml").unwrap();
    loader.validate("Main").unwrap();
    let found = lint(&loader, &LintOptions::nav2());
    let reads: Vec<String> = found
        .iter()
        .filter(|d| d.code == "NT0101")
        .map(|d| format!("{}: {}", d.line, d.message))
        .collect();
    assert_eq!(
        reads,
        [
            "5: port `path` of FollowPath reads the entry `path` on the first pass through \
             NavigateRecovery (RecoveryNode) at line 3, before anything can have written it: \
             the read fails at that tick; it is written later, by port `path` of \
             ComputePathToPose at line 6"
        ]
    );
    // In the right order, nothing is found.
    let ordered = xml.replace(
        "<FollowPath path=\"{path}\" controller_id=\"FollowPath\"/>\n        <ComputePathToPose goal=\"{goal}\" path=\"{path}\" planner_id=\"GridBased\"/>",
        "<ComputePathToPose goal=\"{goal}\" path=\"{path}\" planner_id=\"GridBased\"/>\n        <FollowPath path=\"{path}\" controller_id=\"FollowPath\"/>",
    );
    assert_ne!(ordered, xml);
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(&ordered, "nav.xml").unwrap();
    loader.validate("Main").unwrap();
    assert_eq!(lint(&loader, &LintOptions::nav2()), []);
}
