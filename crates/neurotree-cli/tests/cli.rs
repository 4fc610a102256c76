//! The `neurotree` binary, run as a user runs it.

use std::process::{Command, Output};

fn neurotree(args: &[&str]) -> Output {
    let output = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .output()
        .expect("the neurotree binary runs");
    assert!(
        output.status.success(),
        "neurotree {args:?} failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn stdout(output: &Output) -> String {
    String::from_utf8(output.stdout.clone()).expect("the output is UTF-8")
}

#[test]
fn demo_completes_the_patrol_deterministically() {
    let first = stdout(&neurotree(&["demo", "--no-animation"]));
    let summary = first
        .split("Summary\n")
        .nth(1)
        .expect("the demo ends with a summary");
    assert_eq!(
        summary,
        "  ticks      41\n\
         \x20 outcome    SUCCESS\n\
         \x20 waypoints  3 of 3\n\
         \x20 distance   27 cells\n\
         \x20 charges    1\n\
         \x20 halts      3\n"
    );
    // Every tick drew a frame with the tree, and nothing tried to move the cursor.
    assert_eq!(first.matches("\ntick ").count() + 1, 41);
    assert!(first.contains("└── [R] leg (Sequence)"));
    assert!(!first.contains('\x1b'));

    let second = stdout(&neurotree(&["demo", "--no-animation"]));
    assert_eq!(first, second);
}

#[test]
fn piped_demo_does_not_animate_and_can_stop_early() {
    // The output is a pipe, so even without --no-animation nothing is redrawn.
    let out = stdout(&neurotree(&["demo", "--ticks", "3", "--ascii"]));
    assert!(!out.contains('\x1b'));
    assert!(out.contains("\\-- [R] leg (Sequence)"));
    assert!(out.contains("  ticks      3\n  outcome    RUNNING\n"));
}

/// The value of `"key":` in a one-line JSON object of numbers and strings.
fn field<'a>(line: &'a str, key: &str) -> &'a str {
    let start = line
        .find(&format!("\"{key}\":"))
        .unwrap_or_else(|| panic!("no {key} in {line}"))
        + key.len()
        + 3;
    let rest = &line[start..];
    let end = rest.find([',', '}']).expect("the value ends");
    &rest[..end]
}

fn positive(line: &str, key: &str) -> f64 {
    let value: f64 = field(line, key)
        .parse()
        .unwrap_or_else(|e| panic!("{key} in {line}: {e}"));
    assert!(value > 0.0, "{key} is not positive in {line}");
    value
}

#[test]
fn bench_json_prints_one_line_per_benchmark() {
    let out = stdout(&neurotree(&[
        "bench", "--json", "--quick", "--agents", "1000",
    ]));
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 2, "{out}");
    for line in &lines {
        assert!(line.starts_with('{') && line.ends_with('}'), "{line}");
    }

    let tree = lines[0];
    assert_eq!(field(tree, "name"), "\"tree1111\"");
    assert_eq!(field(tree, "nodes_per_tick"), "1111");
    for key in ["ticks", "ns_per_tick", "ns_per_node", "state_bytes"] {
        positive(tree, key);
    }
    let per_node = positive(tree, "ns_per_tick") / 1111.0;
    assert!((positive(tree, "ns_per_node") - per_node).abs() <= per_node * 0.01);

    let agents = lines[1];
    assert_eq!(field(agents, "name"), "\"many_agents\"");
    assert_eq!(field(agents, "agents"), "1000");
    for key in ["frames", "ms_per_frame", "bytes_per_instance"] {
        positive(agents, key);
    }
}

#[test]
fn bench_table_names_every_measure() {
    let out = stdout(&neurotree(&["bench", "--quick", "--agents", "500"]));
    for measure in [
        "ns per tick",
        "ns per node",
        "state bytes",
        "ms per frame",
        "bytes per instance",
    ] {
        assert!(out.contains(measure), "{measure} missing from\n{out}");
    }
}

fn shared() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared")
}

#[test]
fn check_accepts_a_nav2_tree_with_its_model() {
    let nav2 = shared().join("corpus/nav2");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .arg("check")
        .arg(nav2.join("navigate_to_pose_w_replanning_and_recovery.xml"))
        .arg("--model")
        .arg(nav2.join("nav2_tree_nodes.xml"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stderr.is_empty());
}

#[test]
fn check_reports_errors_with_positions_and_fails() {
    let dir = std::env::temp_dir().join(format!("neurotree-check-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("bad.xml");
    std::fs::write(
        &file,
        "<root main_tree_to_execute=\"T\">\n<BehaviorTree ID=\"T\">\n  <Sequense/>\n</BehaviorTree>\n</root>\n",
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .arg("check")
        .arg(&file)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr
            .contains("bad.xml:3:3: error: unknown node type `Sequense`; did you mean `Sequence`?"),
        "{stderr}"
    );
    // Without the model, the Nav2 tree's own nodes are unknown.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .arg("check")
        .arg(shared().join("corpus/nav2/navigate_to_pose_w_replanning_and_recovery.xml"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    std::fs::remove_dir_all(&dir).unwrap();
}

fn write_tree(name: &str, xml: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("neurotree-run-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(name);
    std::fs::write(&file, xml).unwrap();
    file
}

fn run_cli(args: &[&str]) -> (Option<i32>, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

const GUARDED_MOVE: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="count := 0"/>
      <ReactiveSequence>
        <IsReady/>
        <MoveBase name="move" goal="{goal}"/>
      </ReactiveSequence>
      <Script code="count += 1"/>
    </Sequence>
  </BehaviorTree>
</root>"#;

#[test]
fn run_prints_a_line_per_tick_and_a_summary() {
    let file = write_tree("guarded.xml", GUARDED_MOVE);
    let (code, out, err) = run_cli(&[
        "run",
        file.to_str().unwrap(),
        "--mock",
        "IsReady=SUCCESS",
        "--mock",
        "move=RUNNING*2,SUCCESS",
        "--set",
        "goal=3",
    ]);
    assert_eq!(code, Some(0), "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines[..3],
        [
            r#"{"tick":1,"status":"RUNNING"}"#,
            r#"{"tick":2,"status":"RUNNING"}"#,
            r#"{"tick":3,"status":"SUCCESS"}"#,
        ]
    );
    assert_eq!(
        lines[3],
        r#"{"summary":{"ticks":3,"status":"SUCCESS","nodes":{"IsReady":{"ticks":3,"halts":0},"ReactiveSequence":{"ticks":3,"halts":0},"Script":{"ticks":2,"halts":0},"Sequence":{"ticks":3,"halts":0},"move":{"ticks":3,"halts":0}},"blackboard":{"count":1,"goal":3}}}"#
    );
}

#[test]
fn run_counts_halts_and_traces_changes() {
    let file = write_tree("flip.xml", GUARDED_MOVE);
    let (code, out, _) = run_cli(&[
        "run",
        file.to_str().unwrap(),
        "--mock",
        "IsReady=SUCCESS,FAILURE",
        "--mock",
        "move=RUNNING",
        "--trace",
        "--tick",
        "exactly-once",
    ]);
    assert_eq!(code, Some(0));
    assert!(
        out.contains(
            r#"{"tick":2,"node":"Sequence/ReactiveSequence/move","from":"RUNNING","to":"IDLE"}"#
        ),
        "{out}"
    );
    let summary = out.lines().last().unwrap();
    assert!(
        summary.contains(r#""move":{"ticks":1,"halts":1}"#),
        "{summary}"
    );
    assert!(summary.contains(r#""status":"FAILURE""#), "{summary}");
}

#[test]
fn run_reports_load_errors_and_exits_1() {
    let file = write_tree("unknown.xml", GUARDED_MOVE);
    let (code, out, err) = run_cli(&["run", file.to_str().unwrap()]);
    assert_eq!(code, Some(1));
    assert!(out.is_empty());
    assert!(
        err.contains("unknown.xml:6:9: error: unknown node type `IsReady`"),
        "{err}"
    );
    let (code, _, err) = run_cli(&["run", file.to_str().unwrap(), "--mock", "IsReady=MAYBE"]);
    assert_eq!(code, Some(1));
    assert!(err.contains("`MAYBE` is not an outcome"), "{err}");
}

#[test]
fn run_mock_unknown_and_max_ticks() {
    let file = write_tree("unknown2.xml", GUARDED_MOVE);
    let (code, out, _) = run_cli(&[
        "run",
        file.to_str().unwrap(),
        "--mock-unknown",
        "--mock",
        "move=RUNNING",
        "--max-ticks",
        "4",
    ]);
    assert_eq!(code, Some(0));
    assert_eq!(out.lines().count(), 5);
    assert!(out
        .lines()
        .last()
        .unwrap()
        .contains(r#""ticks":4,"status":"RUNNING""#));
}

fn nav2_navigator() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../trees/nav2/navigate_to_pose_w_replanning_and_recovery.xml")
}

#[test]
fn run_knows_nav2_controls_so_nav2_files_run_with_mock_leaves() {
    let nav2 = nav2_navigator();
    let (code, out, err) = run_cli(&["run", nav2.to_str().unwrap(), "--mock-unknown"]);
    assert_eq!(code, Some(0), "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], r#"{"tick":1,"status":"SUCCESS"}"#);
    assert!(
        lines[1].contains(r#""NavigateRecovery":{"ticks":1,"halts":0}"#),
        "{}",
        lines[1]
    );
    assert!(lines[1].contains(r#""RateController":{"ticks":1,"halts":0}"#));
    // The leaves still need mocks (or the simulation of `neurotree demo`).
    let (code, _, err) = run_cli(&["run", nav2.to_str().unwrap()]);
    assert_eq!(code, Some(1));
    assert!(
        err.contains("unknown node type `ProgressCheckerSelector`"),
        "{err}"
    );
}

#[test]
fn check_and_show_know_nav2_controls() {
    let nav2 = nav2_navigator();
    let model = nav2.with_file_name("nav2_tree_nodes.xml");
    let (code, _, err) = run_cli(&[
        "check",
        nav2.to_str().unwrap(),
        "--model",
        model.to_str().unwrap(),
    ]);
    assert_eq!((code, err.as_str()), (Some(0), ""));
    let (code, out, err) = run_cli(&["show", nav2.to_str().unwrap(), "--format", "ascii"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        out.starts_with("[ ] NavigateRecovery (RecoveryNode)\n"),
        "{out}"
    );
    assert!(out.contains("[ ] RecoveryActions (RoundRobin)"), "{out}");
}
