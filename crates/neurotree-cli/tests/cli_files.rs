//! `neurotree run`, `show` and `check` given several files, or files of several trees: which
//! tree they work on, how every error is reported, and the exit status of a run.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::corpus_dir;
use corpus_dir::corpus;

/// The exit status, stdout and stderr of `neurotree ARGS`.
fn neurotree(args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .output()
        .expect("the neurotree binary runs");
    (
        out.status.code(),
        String::from_utf8(out.stdout).expect("stdout is UTF-8"),
        String::from_utf8(out.stderr).expect("stderr is UTF-8"),
    )
}

/// Writes `xml` to `name` in `dir` and returns its path as text.
fn file(dir: &Path, name: &str, xml: &str) -> String {
    let path: PathBuf = dir.join(name);
    std::fs::write(&path, xml).unwrap();
    path.to_str().unwrap().to_string()
}

/// The last line of a run: its summary.
fn summary(out: &str) -> &str {
    out.lines().last().unwrap_or("")
}

/// A main tree and the subtree it uses, without `main_tree_to_execute`; `Orphan` uses
/// `Shared` too.
const TWO_STARTS: &str = r#"<root BTCPP_format="4">
  <BehaviorTree ID="Shared"><AlwaysSuccess/></BehaviorTree>
  <BehaviorTree ID="Main"><SubTree ID="Shared"/></BehaviorTree>
  <BehaviorTree ID="Orphan"><SubTree ID="Shared"/></BehaviorTree>
</root>"#;

#[test]
fn without_a_main_tree_the_only_tree_no_other_uses_runs_and_the_run_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let f = file(
        dir.path(),
        "one.xml",
        r#"<root BTCPP_format="4">
  <BehaviorTree ID="Sub"><Script code="sub := 1"/></BehaviorTree>
  <BehaviorTree ID="Top"><Sequence><SubTree ID="Sub" _autoremap="true"/></Sequence></BehaviorTree>
</root>"#,
    );
    let (code, out, err) = neurotree(&["run", &f]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(
        err,
        "note: running tree 'Top' (no main_tree_to_execute; the only tree no other tree references)\n"
    );
    assert!(summary(&out).contains(r#""blackboard":{"sub":1}"#), "{out}");
    let (code, out, err) = neurotree(&["show", &f, "-f", "ascii"]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(
        err,
        "note: drawing tree 'Top' (no main_tree_to_execute; the only tree no other tree references)\n"
    );
    assert_eq!(
        out,
        "[ ] Sequence\n\\-- [ ] Sub (SubTree)\n    \\-- [ ] Script (Action)\n"
    );
}

#[test]
fn an_ambiguous_main_tree_lists_the_candidates_and_a_bad_tree_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let f = file(dir.path(), "two.xml", TWO_STARTS);
    let expected = format!(
        "{f}: error: no main_tree_to_execute, and 2 trees could be the main one: Main, Orphan; pick one with --tree NAME\n"
    );
    for command in ["run", "show"] {
        let (code, out, err) = neurotree(&[command, &f]);
        assert_eq!((code, out.as_str(), err), (Some(1), "", expected.clone()));
    }
    let (code, _, err) = neurotree(&["run", &f, "--tree", "Main"]);
    assert_eq!((code, err.as_str()), (Some(0), ""));
    let (code, _, err) = neurotree(&["run", &f, "--tree", "Mian"]);
    assert_eq!(
        (code, err),
        (
            Some(1),
            format!("{f}: error: --tree Mian: no tree with that ID is loaded; the trees are: Main, Orphan, Shared\n")
        )
    );
}

#[test]
fn several_files_load_into_one_loader_like_the_load_multiple_xml_tutorial() {
    let examples = corpus("btcpp/examples");
    let part = |n| {
        examples
            .join(format!("examples__t07_load_multiple_xml__0{n}.xml"))
            .to_str()
            .unwrap()
            .to_string()
    };
    let (main, sub_a, sub_b) = (part(1), part(2), part(3));
    let (code, out, err) = neurotree(&["run", &main, &sub_a, &sub_b, "--mock-unknown"]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(
        err,
        "note: running tree 'MainTree' (no main_tree_to_execute; the only tree no other tree references)\n"
    );
    assert_eq!(
        summary(&out),
        concat!(
            r#"{"summary":{"ticks":1,"status":"SUCCESS","nodes":{"SaySomething":{"ticks":3,"halts":0},"Sequence":{"ticks":1,"halts":0},"SubA":{"ticks":1,"halts":0},"SubB":{"ticks":1,"halts":0}},"#,
            r#""paths":{"Sequence":[{"ticks":1,"halts":0}],"Sequence/SaySomething":[{"ticks":1,"halts":0}],"Sequence/SubA":[{"ticks":1,"halts":0}],"Sequence/SubA/SaySomething":[{"ticks":1,"halts":0}],"Sequence/SubB":[{"ticks":1,"halts":0}],"Sequence/SubB/SaySomething":[{"ticks":1,"halts":0}]},"#,
            r#""blackboard":{}}}"#
        )
    );
    let (code, out, _) = neurotree(&[
        "show",
        &main,
        &sub_a,
        &sub_b,
        "--mock-unknown",
        "-f",
        "ascii",
    ]);
    assert_eq!(code, Some(0));
    assert!(
        out.contains("+-- [ ] SubA (SubTree)\n|   \\-- [ ] SaySomething"),
        "{out}"
    );
    // Alone, the main file lacks its subtrees.
    let (code, _, err) = neurotree(&["run", &main, "--mock-unknown"]);
    assert_eq!(code, Some(1));
    assert!(
        err.starts_with(&format!(
            "{main}:6:13: error: no tree with ID `SubA` is loaded"
        )),
        "{err}"
    );
}

#[test]
fn check_takes_a_files_subtrees_from_the_other_files_given() {
    let dir = tempfile::tempdir().unwrap();
    let main = file(
        dir.path(),
        "main.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="Main"><SubTree ID="Sub"/></BehaviorTree></root>"#,
    );
    let sub = file(
        dir.path(),
        "sub.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="Sub"><AlwaysSuccess/></BehaviorTree><BehaviorTree ID="Spare"><AlwaysFailure/></BehaviorTree></root>"#,
    );
    let (code, out, err) = neurotree(&["check", &main, &sub]);
    assert_eq!(
        (code, out, err.as_str()),
        (
            Some(0),
            format!("{main}: ok (1 tree)\n{sub}: ok (2 trees)\n"),
            ""
        )
    );
    let (code, out, err) = neurotree(&["check", &main]);
    assert_eq!((code, out.as_str()), (Some(1), ""));
    assert_eq!(
        err,
        format!("{main}:1:48: error: no tree with ID `Sub` is loaded or registered; known trees: Main\n")
    );
}

#[test]
fn main_tree_to_execute_comes_from_the_first_file_given() {
    let dir = tempfile::tempdir().unwrap();
    let a = file(
        dir.path(),
        "a.xml",
        r#"<root BTCPP_format="4" main_tree_to_execute="A"><BehaviorTree ID="A"><Script code="ran := 'A'"/></BehaviorTree></root>"#,
    );
    let b = file(
        dir.path(),
        "b.xml",
        r#"<root BTCPP_format="4" main_tree_to_execute="B"><BehaviorTree ID="B"><Script code="ran := 'B'"/></BehaviorTree></root>"#,
    );
    let (_, out, _) = neurotree(&["run", &a, &b]);
    assert!(
        summary(&out).ends_with(r#""blackboard":{"ran":"A"}}}"#),
        "{out}"
    );
    let (_, out, _) = neurotree(&["run", &b, &a]);
    assert!(
        summary(&out).ends_with(r#""blackboard":{"ran":"B"}}}"#),
        "{out}"
    );
}

/// Two trees with errors in several nodes, and a third tree that is valid.
const MANY_ERRORS: &str = r#"<root BTCPP_format="4">
  <BehaviorTree ID="First">
    <Sequence>
      <Sequense/>
      <Repeat num_cycles="often"><AlwaysSuccess/></Repeat>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Second">
    <Fallback>
      <Inverter><AlwaysSuccess/><AlwaysFailure/></Inverter>
      <Parallel success_count="3"><AlwaysSuccess/></Parallel>
    </Fallback>
  </BehaviorTree>
  <BehaviorTree ID="Third"><AlwaysSuccess/></BehaviorTree>
</root>"#;

#[test]
fn check_reports_every_error_of_every_tree_and_ok_for_each_valid_file() {
    let dir = tempfile::tempdir().unwrap();
    let bad = file(dir.path(), "bad.xml", MANY_ERRORS);
    let good = file(
        dir.path(),
        "good.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="T"><AlwaysSuccess/></BehaviorTree></root>"#,
    );
    let (code, out, err) = neurotree(&["check", &bad, &good]);
    assert_eq!(code, Some(1));
    assert_eq!(out, format!("{good}: ok (1 tree)\n"));
    assert_eq!(
        err,
        format!(
            "{bad}:4:7: error: unknown node type `Sequense`; did you mean `Sequence`? declare it in a TreeNodesModel given with --model FILE, or use --nav2 if it is one of Nav2's\n\
             {bad}:5:7: error: port `num_cycles` of `Repeat`: cannot read `often` as i32\n\
             {bad}:10:7: error: `Inverter` takes exactly 1 child, found 2\n\
             {bad}:11:7: error: Parallel: success threshold 3 needs at least 3 children, found 1\n"
        )
    );
}

#[test]
fn check_stops_at_twenty_errors_per_file() {
    let dir = tempfile::tempdir().unwrap();
    let leaves = "<Nope/>".repeat(25);
    let many = file(
        dir.path(),
        "many.xml",
        &format!(
            r#"<root><BehaviorTree ID="T"><Sequence>{leaves}</Sequence></BehaviorTree></root>"#
        ),
    );
    let (code, _, err) = neurotree(&["check", &many]);
    assert_eq!(code, Some(1));
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 21, "{err}");
    assert!(lines[19].starts_with(&format!("{many}:1:171: error: unknown node type `Nope`")));
    assert_eq!(
        lines[20],
        format!("{many}: note: only the first 20 errors are shown")
    );
}

/// A file as Groot2 saves it: its leaves are described in its own `TreeNodesModel`.
const GROOT2_SAVED: &str = r#"<root BTCPP_format="4">
  <BehaviorTree ID="Dock">
    <Sequence>
      <IsCharged/>
      <DockRobot station="3"/>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel>
    <Condition ID="IsCharged"/>
    <Action ID="DockRobot"><input_port name="station"/></Action>
    <Control ID="Ordered"/>
  </TreeNodesModel>
</root>"#;

#[test]
fn mock_unknown_mocks_leaves_a_tree_nodes_model_describes() {
    let dir = tempfile::tempdir().unwrap();
    let f = file(dir.path(), "dock.xml", GROOT2_SAVED);
    let (code, _, err) = neurotree(&["run", &f]);
    assert_eq!(code, Some(1));
    assert_eq!(
        err.lines().next().unwrap_or(""),
        format!("{f}:4:7: error: `IsCharged` is only described by a model; register an implementation to run it, or mock it (XmlLoader::mock_unknown)")
    );
    let (code, out, err) = neurotree(&["run", &f, "--mock-unknown", "--mock", "IsCharged=FAILURE"]);
    assert_eq!(code, Some(2), "{err}");
    assert_eq!(out.lines().next(), Some(r#"{"tick":1,"status":"FAILURE"}"#));
    let (code, out, err) = neurotree(&["run", &f, "--mock-unknown"]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(out.lines().next(), Some(r#"{"tick":1,"status":"SUCCESS"}"#));
}

#[test]
fn mocking_a_control_or_a_decorator_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let f = file(dir.path(), "dock.xml", GROOT2_SAVED);
    let (code, out, err) = neurotree(&["run", &f, "--mock-unknown", "--mock", "Sequence=SUCCESS"]);
    assert_eq!(
        (code, out.as_str(), err),
        (
            Some(1),
            "",
            format!("{f}:3:5: error: `Sequence` is a Control (`Sequence`) and no leaf is named so; a mock replaces only a leaf (an Action or a Condition)\n")
        )
    );
    let f = file(
        dir.path(),
        "ordered.xml",
        &GROOT2_SAVED.replace("Sequence>", "Ordered>"),
    );
    let (code, _, err) = neurotree(&["run", &f, "--mock-unknown", "--mock", "Ordered=SUCCESS"]);
    assert_eq!(
        (code, err),
        (
            Some(1),
            format!("{f}:3:5: error: `Ordered` is a Control (`Ordered`) and no leaf is named so; a mock replaces only a leaf (an Action or a Condition)\n")
        )
    );
}

#[test]
fn a_threshold_error_points_at_the_parallel_itself() {
    let dir = tempfile::tempdir().unwrap();
    let f = file(
        dir.path(),
        "par.xml",
        "<root BTCPP_format=\"4\">\n  <BehaviorTree ID=\"T\">\n    <Parallel success_count=\"3\">\n      <AlwaysSuccess/>\n      <AlwaysSuccess/>\n    </Parallel>\n  </BehaviorTree>\n</root>\n",
    );
    let expected = format!(
        "{f}:3:5: error: Parallel: success threshold 3 needs at least 3 children, found 2\n"
    );
    let (code, _, err) = neurotree(&["run", &f]);
    assert_eq!((code, err), (Some(1), expected.clone()));
    let (code, _, err) = neurotree(&["check", &f]);
    assert_eq!((code, err), (Some(1), expected));
}

#[test]
fn unknown_nodes_in_a_run_get_a_hint_to_mock_them() {
    let dir = tempfile::tempdir().unwrap();
    let f = file(
        dir.path(),
        "unknown.xml",
        r#"<root><BehaviorTree ID="T"><Sequence><OpenDoor/></Sequence></BehaviorTree></root>"#,
    );
    let (code, _, err) = neurotree(&["run", &f]);
    assert_eq!(
        (code, err),
        (
            Some(1),
            format!(
                "{f}:1:38: error: unknown node type `OpenDoor`; declare it in a TreeNodesModel given with --model FILE, or use --nav2 if it is one of Nav2's\n\
                 hint: mock the leaves without an implementation with --mock-unknown, or one with --mock NAME=OUTCOMES\n"
            )
        )
    );
}

#[test]
fn run_exit_status_says_how_the_run_ended() {
    let dir = tempfile::tempdir().unwrap();
    let f = file(
        dir.path(),
        "step.xml",
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T"><Sequence><Step/></Sequence></BehaviorTree></root>"#,
    );
    let status = |mock: &str, extra: &[&str]| {
        let mut args = vec!["run", f.as_str(), "--mock", mock];
        args.extend_from_slice(extra);
        let (code, out, _) = neurotree(&args);
        (code, summary(&out).to_string())
    };
    assert_eq!(status("Step=SUCCESS", &[]).0, Some(0));
    assert_eq!(status("Step=FAILURE", &[]).0, Some(2));
    let (code, line) = status("Step=RUNNING", &["--max-ticks", "3"]);
    assert_eq!(code, Some(3));
    assert!(line.contains(r#""ticks":3,"status":"RUNNING""#), "{line}");
    // A tick that fails with an error ends the run too.
    let script = file(
        dir.path(),
        "error.xml",
        r#"<root><BehaviorTree ID="T"><Script code="x = unknown + 1"/></BehaviorTree></root>"#,
    );
    let (code, out, _) = neurotree(&["run", &script]);
    assert_eq!(code, Some(2));
    assert!(out.starts_with(r#"{"tick":1,"status":"ERROR","#), "{out}");
    // And the codes are in the help.
    let (code, help, _) = neurotree(&["run", "--help"]);
    assert_eq!(code, Some(0));
    assert!(
        help.contains(
            "Exit status:\n  0  the root ended SUCCESS\n  1  the files did not load (or a log could not be written)\n  2  the root ended FAILURE or SKIPPED, or a tick failed with an error\n  3  --max-ticks stopped the run while it was RUNNING"
        ),
        "{help}"
    );
}

#[test]
fn the_summary_keeps_nodes_that_share_a_name_apart_by_path() {
    let dir = tempfile::tempdir().unwrap();
    let f = file(
        dir.path(),
        "twins.xml",
        r#"<root><BehaviorTree ID="T">
  <Sequence>
    <Fallback name="left"><AlwaysFailure name="try"/><AlwaysSuccess name="try"/></Fallback>
    <Fallback name="right"><AlwaysSuccess name="try"/></Fallback>
  </Sequence>
</BehaviorTree></root>"#,
    );
    let (code, out, _) = neurotree(&["run", &f]);
    assert_eq!(code, Some(0));
    assert_eq!(
        summary(&out),
        concat!(
            r#"{"summary":{"ticks":1,"status":"SUCCESS","nodes":{"Sequence":{"ticks":1,"halts":0},"left":{"ticks":1,"halts":0},"right":{"ticks":1,"halts":0},"try":{"ticks":3,"halts":0}},"#,
            r#""paths":{"Sequence":[{"ticks":1,"halts":0}],"Sequence/left":[{"ticks":1,"halts":0}],"Sequence/left/try":[{"ticks":1,"halts":0},{"ticks":1,"halts":0}],"#,
            r#""Sequence/right":[{"ticks":1,"halts":0}],"Sequence/right/try":[{"ticks":1,"halts":0}]},"blackboard":{}}}"#
        )
    );
}

#[test]
fn a_mock_named_like_a_control_and_a_leaf_mocks_the_leaf() {
    // Nav2's navigator: a RecoveryNode named FollowPath around the action FollowPath.
    let nav2 = corpus("nav2/navigate_to_pose_w_replanning_and_recovery.xml");
    let (code, out, err) = neurotree(&[
        "run",
        nav2.to_str().unwrap(),
        "--mock-unknown",
        "--mock",
        "FollowPath=RUNNING",
        "--max-ticks",
        "2",
    ]);
    assert_eq!(code, Some(3), "{err}");
    let line = summary(&out);
    assert!(
        line.contains(r#""NavigateRecovery/NavigateWithReplanning/FollowPath":[{"ticks":2,"halts":0}],"NavigateRecovery/NavigateWithReplanning/FollowPath/FollowPath":[{"ticks":2,"halts":0}]"#),
        "{line}"
    );
}
