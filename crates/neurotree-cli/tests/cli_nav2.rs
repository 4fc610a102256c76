//! `--nav2`: `run`, `check` and `show` know all of Nav2's node types without a model file,
//! and `run --nav2 --mock-unknown` runs every navigator tree Nav2 ships.

use std::path::PathBuf;
use std::process::Command;

use crate::corpus_dir;

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

/// Nav2's tree files (not its model), by name.
fn nav2_trees() -> Vec<(String, PathBuf)> {
    let mut files: Vec<(String, PathBuf)> = std::fs::read_dir(corpus_dir::corpus("nav2"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "xml"))
        .map(|p| (p.file_name().unwrap().to_str().unwrap().to_string(), p))
        .filter(|(name, _)| name != "nav2_tree_nodes.xml")
        .collect();
    files.sort();
    files
}

#[test]
fn run_nav2_mock_unknown_runs_every_navigator_tree_to_a_summary() {
    let trees = nav2_trees();
    assert_eq!(trees.len(), 16, "{trees:?}");
    for (name, path) in &trees {
        let (code, out, err) =
            neurotree(&["run", "--nav2", "--mock-unknown", path.to_str().unwrap()]);
        let expected = match name.as_str() {
            // Follows a point for ever: --max-ticks (100) stops it while it runs.
            "follow_point.xml" => 3,
            // No `robot_pose` entry: the DistanceController fails, as Nav2's does without a
            // pose in TF, and the navigator fails.
            "navigate_w_replanning_distance.xml" => 2,
            _ => 0,
        };
        assert_eq!(code, Some(expected), "{name}: {err}");
        let last = out.lines().last().unwrap_or("");
        assert!(
            last.starts_with(r#"{"summary":{"ticks":"#),
            "{name}: {last}"
        );
        let status = match expected {
            0 => "SUCCESS",
            2 => "FAILURE",
            _ => "RUNNING",
        };
        assert!(
            last.contains(&format!(r#""status":"{status}""#)),
            "{name}: {last}"
        );
    }
}

#[test]
fn a_robot_pose_lets_the_distance_controller_tick_its_child() {
    let path = corpus_dir::corpus("nav2").join("navigate_w_replanning_distance.xml");
    let (code, out, err) = neurotree(&[
        "run",
        "--nav2",
        "--mock-unknown",
        "--set",
        "robot_pose=0;0",
        path.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    let last = out.lines().last().unwrap_or("");
    assert!(
        last.contains(r#""ComputePathToPose":{"ticks":1,"halts":0}"#),
        "{last}"
    );
}

#[test]
fn check_and_show_know_nav2_leaves_only_with_nav2() {
    let path = corpus_dir::corpus("nav2").join("follow_point.xml");
    let file = path.to_str().unwrap();
    let (code, _, err) = neurotree(&["check", file]);
    assert_eq!(code, Some(1));
    assert!(
        err.contains("unknown node type `ControllerSelector`"),
        "{err}"
    );
    let (code, out, err) = neurotree(&["check", "--nav2", file]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("follow_point.xml: ok (1 tree)"), "{out}");
    let (code, out, err) = neurotree(&["show", "--nav2", file]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("GoalUpdater"), "{out}");
    assert!(out.contains("ComputePathToPose"), "{out}");
}

#[test]
fn run_without_nav2_does_not_know_nav2_leaves() {
    let path = corpus_dir::corpus("nav2").join("navigate_w_replanning_time.xml");
    let (code, _, err) = neurotree(&["run", path.to_str().unwrap()]);
    assert_eq!(code, Some(1));
    assert!(err.contains("unknown node type"), "{err}");
}

/// A tree written for Nav2 Kilted: its stop and path checks under their old names.
const KILTED_TREE: &str = r#"<root BTCPP_format="4" main_tree_to_execute="T">
  <BehaviorTree ID="T">
    <Sequence>
      <IsStopped duration_stopped="500"/>
      <IsPathValid path="{path}"/>
    </Sequence>
  </BehaviorTree>
</root>
"#;

#[test]
fn check_knows_each_releases_model_and_loads_old_names_on_main_with_a_warning() {
    let dir = std::env::temp_dir().join(format!("neurotree-nav2-releases-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("kilted.xml");
    std::fs::write(&file, KILTED_TREE).unwrap();
    let path = file.to_str().unwrap();
    let shown = file.display();
    // Main (the default release): loads, warning of each renamed node.
    let (code, out, err) = neurotree(&["check", "--nav2", path]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(out, format!("{shown}: ok (1 tree)\n"));
    assert_eq!(
        err,
        format!(
            "{shown}:4:7: warning: `IsStopped` is `CheckStopStatus` now (renamed in Nav2 after Kilted); it loads as `CheckStopStatus`, write that\n\
             {shown}:5:7: warning: `IsPathValid` is `ValidatePath` now (renamed in Nav2 after Kilted); it loads as `ValidatePath`, write that\n"
        )
    );
    let (code, _, err) = neurotree(&["check", "--nav2=main", path]);
    assert_eq!(code, Some(0), "{err}");
    // Kilted has both under these names: no warning.
    let (code, _, err) = neurotree(&["check", "--nav2=kilted", path]);
    assert_eq!((code, err.as_str()), (Some(0), ""));
    // Jazzy had no IsStopped yet.
    let (code, _, err) = neurotree(&["check", "--nav2=jazzy", path]);
    assert_eq!(code, Some(1));
    assert!(
        err.contains(":4:7: error: unknown node type `IsStopped`"),
        "{err}"
    );
    // Nav2 main's navigator uses nodes Jazzy does not have.
    let navigator =
        corpus_dir::corpus("nav2").join("navigate_to_pose_w_replanning_and_recovery.xml");
    let (code, _, err) = neurotree(&["check", "--nav2=jazzy", navigator.to_str().unwrap()]);
    assert_eq!(code, Some(1));
    assert!(err.contains("unknown node type `ValidatePath`"), "{err}");
    // run and show take the release too.
    let (code, _, err) = neurotree(&["run", "--nav2=kilted", "--mock-unknown", path]);
    assert_eq!(code, Some(0), "{err}");
    let (code, _, err) = neurotree(&["show", "--nav2=kilted", path]);
    assert_eq!(code, Some(0), "{err}");
    let (code, _, err) = neurotree(&["check", "--nav2=rolling", path]);
    assert_eq!(code, Some(2));
    assert!(
        err.contains("`rolling` is not a Nav2 release NeuroTree knows"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn models_nav2_writes_a_model_of_81_types_that_checks_nav2s_trees() {
    let (code, out, err) = neurotree(&["models", "--nav2"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        out.starts_with("<root BTCPP_format=\"4\">\n  <TreeNodesModel>\n"),
        "{out}"
    );
    assert_eq!(out.matches(" ID=\"").count(), 81);
    assert!(out.contains("<Control ID=\"PipelineSequence\""), "{out}");
    assert!(out.contains("<Action ID=\"DockRobot\">"), "{out}");
    // Written to a file, it stands in for --nav2: every tree Nav2 ships checks against it.
    let dir = std::env::temp_dir().join(format!("neurotree-models-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let model = dir.join("nav2_model.xml");
    let (code, _, err) = neurotree(&["models", "--nav2=main", "--output", model.to_str().unwrap()]);
    assert_eq!((code, err.as_str()), (Some(0), ""));
    for (name, path) in nav2_trees() {
        let (code, out, err) = neurotree(&[
            "check",
            "--model",
            model.to_str().unwrap(),
            path.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(0), "{name}: {out}{err}");
    }
    let (_, jazzy, _) = neurotree(&["models", "--nav2=jazzy"]);
    assert_eq!(jazzy.matches(" ID=\"").count(), 65);
    let (code, _, err) = neurotree(&["models"]);
    assert_eq!(code, Some(2));
    assert!(err.contains("--nav2"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
