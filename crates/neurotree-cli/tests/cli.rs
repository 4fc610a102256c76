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

/// The lines from `Summary` on.
fn summary(out: &str) -> &str {
    let at = out
        .rfind("Summary\n")
        .expect("the demo ends with a summary");
    &out[at..]
}

#[test]
fn demo_drives_nav2s_navigator_to_the_goal_deterministically() {
    let first = stdout(&neurotree(&["demo", "--speed", "0"]));
    assert_eq!(
        summary(&first),
        "Summary\n\
         \x20 outcome     SUCCESS\n\
         \x20 ticks       430\n\
         \x20 time        42.9 s\n\
         \x20 distance    40.90 m\n\
         \x20 replans     38\n\
         \x20 recoveries  4 (FollowPath recovery 2, ClearingActions 1, Spin 1)\n\
         \x20 robot       (36.35, 1.50), 0.15 m from the goal (36.50, 1.50)\n\
         navigation succeeded\n\n"
    );
    assert!(first.starts_with("NeuroTree demo: Nav2's navigator drives a simulated robot\n"));
    // Piped: one frame per simulated second (and each tick where something happened),
    // one after another, plain text.
    assert!(!first.contains('\x1b'));
    let frames = first.matches("\ntick ").count();
    assert_eq!(frames, 49);
    assert!(first.contains("\ntick 430   t =  42.9 s   SUCCESS\n"));
    assert!(first.contains("  > recovery: Spin\n"));
    assert!(first.contains("├── [R] NavigateWithReplanning (PipelineSequence)"));
    assert_eq!(first, stdout(&neurotree(&["demo", "--speed", "0"])));
    // --fast draws the last frame only, before the same summary.
    let fast = stdout(&neurotree(&["demo", "--fast"]));
    assert_eq!(fast.matches("\ntick ").count(), 1);
    assert!(fast.contains("\ntick 430   t =  42.9 s   SUCCESS\n"));
    assert_eq!(summary(&fast), summary(&first));
}

#[test]
fn demo_options_pick_the_frames_the_seed_and_the_drawing() {
    let every = stdout(&neurotree(&[
        "demo", "--speed", "0", "--every", "100", "--ascii",
    ]));
    // Ticks 1, 101, 201, 301, 401, the last, and those where more happened than planning:
    // the obstacle, the failures and recoveries (232 to 235), the spin done (251), the
    // obstacle gone (262).
    let ticks: Vec<&str> = every
        .lines()
        .filter(|l| l.starts_with("tick "))
        .map(|l| l.split_whitespace().nth(1).unwrap_or(""))
        .collect();
    assert_eq!(
        ticks,
        ["1", "101", "201", "232", "233", "234", "235", "251", "262", "301", "401", "430"]
    );
    assert!(every.contains("+-- [S] ProgressCheckerSelector (Action)"));
    assert!(!every.contains('✓'));
    assert_eq!(
        summary(&every),
        summary(&stdout(&neurotree(&["demo", "--fast"])))
    );

    let seeded = stdout(&neurotree(&["demo", "--fast", "--seed", "2"]));
    assert!(seeded.contains("seed      2: an obstacle steps into cell (9, 10)"));
    assert!(summary(&seeded).contains("  recoveries  1 (FollowPath recovery 1)\n"));
}

#[test]
fn demo_to_an_unreachable_goal_fails_with_a_summary() {
    // Inside a wall: Nav2's navigation fails (exit 2) with the planner's error code.
    let (code, out, _) = run_cli(&["demo", "--speed", "0", "--goal", "0.5,0.5"]);
    assert_eq!(code, Some(2));
    assert_eq!(
        summary(&out),
        "Summary\n\
         \x20 outcome     FAILURE\n\
         \x20 ticks       1\n\
         \x20 time        0.0 s\n\
         \x20 distance    0.00 m\n\
         \x20 replans     0\n\
         \x20 recoveries  1 (ComputePathToPose recovery 1)\n\
         \x20 robot       (1.50, 13.50), 13.04 m from the goal (0.50, 0.50)\n\
         \x20 error code  206 (compute_path_error_code): (0.50, 0.50) is in blocked cell (0, 0)\n\
         navigation failed\n\n"
    );
    assert!(out.contains("  > ComputePathToPose failed: goal occupied (error 206)\n"));
    let (code, _, err) = run_cli(&["demo", "--fast", "--goal", "here"]);
    assert_eq!(code, Some(2));
    assert!(
        err.contains("`here` should be two numbers X,Y (metres)"),
        "{err}"
    );
}

#[test]
fn demo_with_a_bad_tree_file_reports_where_and_exits_1() {
    let file = write_tree(
        "bad_demo.xml",
        "<root BTCPP_format=\"4\">\n<BehaviorTree ID=\"T\">\n  <FollowPth path=\"{path}\"/>\n</BehaviorTree>\n</root>\n",
    );
    let (code, out, err) = run_cli(&["demo", "--fast", "--tree", file.to_str().unwrap()]);
    assert_eq!(code, Some(1));
    assert!(out.is_empty(), "{out}");
    assert_eq!(
        err,
        format!(
            "{}:3:3: error: unknown node type `FollowPth`; did you mean `FollowPath`? the demo runs Nav2's node types, simulated\n",
            file.display()
        )
    );
    let (code, _, err) = run_cli(&["demo", "--fast", "--tree", "/nonexistent/tree.xml"]);
    assert_eq!(code, Some(1));
    assert!(
        err.starts_with("/nonexistent/tree.xml: error: cannot open the file"),
        "{err}"
    );
}

#[test]
fn demo_runs_another_tree_with_nav2_nodes() {
    let file = write_tree(
        "plan_and_go.xml",
        r#"<root BTCPP_format="4">
  <BehaviorTree ID="PlanAndGo">
    <PipelineSequence>
      <RateController hz="2.0">
        <ComputePathToPose goal="{goal}" path="{path}" error_code_id="{code}"/>
      </RateController>
      <FollowPath path="{path}"/>
    </PipelineSequence>
  </BehaviorTree>
</root>"#,
    );
    let out = stdout(&neurotree(&[
        "demo",
        "--fast",
        "--seed",
        "4",
        "--tree",
        file.to_str().unwrap(),
    ]));
    let summary = summary(&out);
    assert!(summary.contains("  outcome     SUCCESS\n"), "{summary}");
    assert!(summary.contains("  recoveries  0\n"), "{summary}");
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
        "bench",
        "--json",
        "--quick",
        "--agents",
        "1000",
        "--threads",
        "2",
    ]));
    let (cores, lines): (Vec<&str>, Vec<&str>) = out
        .lines()
        .partition(|line| line.starts_with(r#"{"name":"cores""#));
    assert_eq!(lines.len(), 11, "{out}");
    for line in out.lines() {
        assert!(line.starts_with('{') && line.ends_with('}'), "{line}");
    }
    // Two threads' round trip, before the crowd lines and after them, on a machine whose
    // two threads can run at once.
    if std::thread::available_parallelism().map_or(1, |n| n.get()) >= 2 {
        assert_eq!(cores.len(), 2, "{out}");
        let (first, last) = (out.find(cores[0]).unwrap(), out.find(cores[1]).unwrap());
        assert!(
            first < out.find(lines[3]).unwrap() && last > out.find(lines[7]).unwrap(),
            "{out}"
        );
        for (line, at) in cores.iter().zip(["\"start\"", "\"end\""]) {
            assert_eq!(field(line, "at"), at);
            positive(line, "round_trips");
            positive(line, "round_trip_ns");
            positive(line, "arithmetic_speedup");
        }
    }

    // The builder's tree, then the same loaded from tree1111.xml.
    for (tree, name) in lines[..2].iter().zip(["\"tree1111\"", "\"tree1111_xml\""]) {
        assert_eq!(field(tree, "name"), name);
        assert_eq!(field(tree, "nodes_per_tick"), "1111");
        for key in ["ticks", "ns_per_tick", "ns_per_node", "state_bytes"] {
            positive(tree, key);
        }
        let per_node = positive(tree, "ns_per_tick") / 1111.0;
        assert!((positive(tree, "ns_per_node") - per_node).abs() <= per_node * 0.01);
    }

    let agents = lines[2];
    assert_eq!(field(agents, "name"), "\"many_agents\"");
    assert_eq!(field(agents, "agents"), "1000");
    for key in ["frames", "ms_per_frame", "bytes_per_instance"] {
        positive(agents, key);
    }

    let crowd = lines[3];
    assert_eq!(field(crowd, "name"), "\"crowd\"");
    assert_eq!(field(crowd, "agents"), "1000");
    assert_eq!(field(crowd, "threads"), "2");
    for key in ["frames", "ms_per_frame", "bytes_per_member"] {
        positive(crowd, key);
    }
    // The mean over the members counts the failure records some made in their frames.
    assert!(
        positive(crowd, "bytes_per_member_mean") > positive(crowd, "bytes_per_member"),
        "{crowd}"
    );

    // 1% of the sleepy agents alerted each frame: 10 a frame, each awake until its agent
    // tree completes, a few frames.
    let sleeping = lines[4];
    assert_eq!(field(sleeping, "name"), "\"crowd_sleeping\"");
    assert_eq!(field(sleeping, "agents"), "1000");
    let awake = positive(sleeping, "awake_per_frame");
    assert!((10.0..100.0).contains(&awake), "{sleeping}");
    positive(sleeping, "ms_per_frame");
    let per_awake = positive(sleeping, "ns_per_awake");
    let expected = positive(sleeping, "ms_per_frame") * 1e6 / awake;
    assert!(
        (per_awake - expected).abs() <= expected * 0.01,
        "{sleeping}"
    );
    // Every member was woken once before the frames timed, and some made their records.
    assert!(
        positive(sleeping, "bytes_per_member_mean") > positive(sleeping, "bytes_per_member"),
        "{sleeping}"
    );

    // The sleeping crowd with about 1 %, 3.7 % and 20 % of it awake, each awake member's
    // cost beside a member's of the crowd all awake.
    let per_member = positive(crowd, "ns_per_member");
    let mut shares = Vec::new();
    for line in &lines[5..8] {
        assert_eq!(field(line, "name"), "\"crowd_awake\"");
        assert_eq!(field(line, "agents"), "1000");
        let awake = positive(line, "awake_per_frame");
        let per_awake = positive(line, "ns_per_awake");
        let expected = positive(line, "ms_per_frame") * 1e6 / awake;
        assert!((per_awake - expected).abs() <= expected * 0.01, "{line}");
        let ratio = positive(line, "awake_cost_ratio");
        assert!(
            (ratio - per_awake / per_member).abs() <= 0.01 + ratio * 0.01,
            "{line}"
        );
        shares.push(positive(line, "awake_percent"));
    }
    assert!(shares.windows(2).all(|w| w[0] < w[1]), "{shares:?}");

    // Ticks timed one by one: tree1111, the navigator, and the navigator's planning ticks
    // (some of its ticks), each with ordered percentiles.
    let trees = [
        "\"tree1111_xml\"",
        "\"nav2_navigator\"",
        "\"nav2_navigator_planning\"",
    ];
    for (line, tree) in lines[8..].iter().zip(trees) {
        assert_eq!(field(line, "name"), "\"tick_times\"");
        assert_eq!(field(line, "tree"), tree);
        let p: Vec<f64> = ["p50_ns", "p99_ns", "p999_ns", "max_ns"]
            .iter()
            .map(|key| positive(line, key))
            .collect();
        assert!(p.windows(2).all(|w| w[0] <= w[1]), "{line}");
    }
    let timed = |line: &str| positive(line, "ticks");
    assert_eq!(timed(lines[8]), 10_000.0, "--quick times 10,000 ticks");
    assert!(timed(lines[9]) >= 10_000.0 && timed(lines[10]) < timed(lines[9]));
}

#[test]
fn bench_table_names_every_measure() {
    let out = stdout(&neurotree(&["bench", "--quick", "--agents", "500"]));
    assert!(out.contains("tree1111_xml"), "{out}");
    for measure in [
        "ns per tick",
        "ns per node",
        "state bytes",
        "ms per frame",
        "bytes per instance",
        "bytes per member",
        "bytes per member, mean",
        "threads",
        "crowd_sleeping",
        "awake per frame",
        "ns per awake member",
        "tick_times",
        "p99.9 ns",
    ] {
        assert!(out.contains(measure), "{measure} missing from\n{out}");
    }
    if std::thread::available_parallelism().map_or(1, |n| n.get()) >= 2 {
        assert!(out.contains("round trip ns"), "{out}");
        assert!(out.contains("arithmetic speed-up"), "{out}");
    }
}

use crate::corpus_dir;
use corpus_dir::corpus;

#[test]
fn check_accepts_a_nav2_tree_with_its_model() {
    let nav2 = corpus("nav2");
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
        .arg(corpus(
            "nav2/navigate_to_pose_w_replanning_and_recovery.xml",
        ))
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
        concat!(
            r#"{"summary":{"ticks":3,"status":"SUCCESS","nodes":{"IsReady":{"ticks":3,"halts":0},"ReactiveSequence":{"ticks":3,"halts":0},"Script":{"ticks":2,"halts":0},"Sequence":{"ticks":3,"halts":0},"move":{"ticks":3,"halts":0}},"#,
            r#""paths":{"Sequence":[{"ticks":3,"halts":0}],"Sequence/ReactiveSequence":[{"ticks":3,"halts":0}],"Sequence/ReactiveSequence/IsReady":[{"ticks":3,"halts":0}],"Sequence/ReactiveSequence/move":[{"ticks":3,"halts":0}],"Sequence/Script":[{"ticks":1,"halts":0},{"ticks":1,"halts":0}]},"#,
            r#""blackboard":{"count":1,"goal":3}}}"#
        )
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
    // The run ended FAILURE.
    assert_eq!(code, Some(2));
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
fn run_reports_every_load_error_and_hints_only_what_was_not_given() {
    let file = write_tree("unknowns.xml", GUARDED_MOVE);
    let (code, _, err) = run_cli(&["run", file.to_str().unwrap()]);
    assert_eq!(code, Some(1));
    // Both unknown leaves, as `check` reports them, and the hint once.
    assert!(
        err.contains("unknowns.xml:6:9: error: unknown node type `IsReady`"),
        "{err}"
    );
    assert!(
        err.contains("unknowns.xml:7:9: error: unknown node type `MoveBase`"),
        "{err}"
    );
    assert_eq!(err.matches("--mock-unknown").count(), 1, "{err}");
    // With --mock-unknown given, what is left (an unknown node with children) is reported
    // without suggesting it again.
    let file = write_tree(
        "unknown_controls.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
             <Sequence>
               <Ordered><AlwaysSuccess/></Ordered>
               <Chosen><AlwaysSuccess/></Chosen>
             </Sequence>
           </BehaviorTree></root>"#,
    );
    let (code, _, err) = run_cli(&["run", file.to_str().unwrap(), "--mock-unknown"]);
    assert_eq!(code, Some(1));
    assert!(err.contains("unknown node type `Ordered`"), "{err}");
    assert!(err.contains("unknown node type `Chosen`"), "{err}");
    assert!(!err.contains("hint: mock"), "{err}");
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
    // Stopped while RUNNING.
    assert_eq!(code, Some(3));
    assert_eq!(out.lines().count(), 5);
    assert!(out
        .lines()
        .last()
        .unwrap()
        .contains(r#""ticks":4,"status":"RUNNING""#));
}

fn nav2_navigator() -> std::path::PathBuf {
    corpus("nav2/navigate_to_pose_w_replanning_and_recovery.xml")
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
    let (code, out, err) = run_cli(&[
        "show",
        nav2.to_str().unwrap(),
        "--model",
        model.to_str().unwrap(),
        "--format",
        "ascii",
    ]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        out.starts_with("[ ] NavigateRecovery (RecoveryNode)\n"),
        "{out}"
    );
    assert!(out.contains("[ ] RecoveryActions (RoundRobin)"), "{out}");
}

#[test]
fn check_and_run_print_the_loaders_warnings_on_stderr() {
    let file = write_tree(
        "old_names.xml",
        "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\">\n  <BehaviorTree ID=\"Main\">\n    <SequenceStar>\n      <inverter><AlwaysFailure/></inverter>\n    </SequenceStar>\n  </BehaviorTree>\n</root>",
    );
    let shown = file.display().to_string();
    let (code, out, err) = run_cli(&["check", &shown]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("ok (1 tree)"), "{out}");
    let warnings: Vec<&str> = err.lines().collect();
    assert_eq!(warnings.len(), 2, "{err}");
    assert!(
        warnings[0].starts_with(&format!(
            "{shown}:3:5: warning: `SequenceStar` is deprecated"
        )),
        "{err}"
    );
    assert!(
        warnings[1].starts_with(&format!(
            "{shown}:4:7: warning: `inverter` is not a BehaviorTree.CPP name"
        )),
        "{err}"
    );
    let (code, out, err) = run_cli(&["run", &shown]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains(r#""status":"SUCCESS""#), "{out}");
    assert_eq!(err.lines().count(), 2, "{err}");
    assert!(err.contains(":3:5: warning: `SequenceStar`"), "{err}");
}

const TIMEOUT_THEN_RETRY: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Fallback name="try">
      <Timeout name="limit" msec="150">
        <Drive name="drive"/>
      </Timeout>
      <RetryUntilSuccessful name="retry" num_attempts="2">
        <AlwaysFailure/>
      </RetryUntilSuccessful>
    </Fallback>
  </BehaviorTree>
</root>"#;

#[test]
fn run_summary_says_why_the_root_failed() {
    let file = write_tree("reasons.xml", TIMEOUT_THEN_RETRY);
    let (code, out, err) = run_cli(&["run", file.to_str().unwrap(), "--mock", "drive=RUNNING"]);
    assert_eq!(code, Some(2), "{err}");
    let summary = out.lines().last().unwrap();
    let failure = summary
        .split_once(r#","failure":"#)
        .map(|(_, f)| f)
        .expect(summary);
    assert_eq!(
        failure,
        concat!(
            r#"[{"path":"try","tried":[{"path":"try/limit","reason":"timed out after 150 ms","#,
            r#""chain":[{"path":"try/limit","reason":"timed out after 150 ms","tried":[]}]},"#,
            r#"{"path":"try/retry","reason":"gave up after 2 attempts","#,
            r#""chain":[{"path":"try/retry","reason":"gave up after 2 attempts","tried":[]},"#,
            r#"{"path":"try/retry/AlwaysFailure","tried":[]}]}]},"#,
            r#"{"path":"try/retry","reason":"gave up after 2 attempts","tried":[]},"#,
            r#"{"path":"try/retry/AlwaysFailure","tried":[]}]}}"#
        )
    );
}

const TWO_WAYS: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Fallback name="choose">
      <Sequence name="dock">
        <IsLow/>
        <Dock/>
      </Sequence>
      <Sequence name="patrol">
        <IsCharged/>
        <Patrol/>
      </Sequence>
    </Fallback>
  </BehaviorTree>
</root>"#;

#[test]
fn run_summary_follows_a_failure_without_reasons_down_to_each_leaf() {
    let file = write_tree("two_ways.xml", TWO_WAYS);
    let (code, out, err) = run_cli(&[
        "run",
        file.to_str().unwrap(),
        "--mock-unknown",
        "--mock",
        "IsLow=FAILURE",
        "--mock",
        "IsCharged=FAILURE",
    ]);
    assert_eq!(code, Some(2), "{err}");
    let summary = out.lines().last().unwrap();
    let failure = summary
        .split_once(r#","failure":"#)
        .map(|(_, f)| f)
        .expect(summary);
    assert_eq!(
        failure,
        concat!(
            r#"[{"path":"choose","tried":["#,
            r#"{"path":"choose/dock","chain":[{"path":"choose/dock","tried":[]},"#,
            r#"{"path":"choose/dock/IsLow","tried":[]}]},"#,
            r#"{"path":"choose/patrol","chain":[{"path":"choose/patrol","tried":[]},"#,
            r#"{"path":"choose/patrol/IsCharged","tried":[]}]}]},"#,
            r#"{"path":"choose/patrol","tried":[]},"#,
            r#"{"path":"choose/patrol/IsCharged","tried":[]}]}}"#
        )
    );
}

#[test]
fn run_summary_of_a_run_that_succeeds_has_no_failure() {
    let file = write_tree("no_reasons.xml", TIMEOUT_THEN_RETRY);
    let (code, out, err) = run_cli(&[
        "run",
        file.to_str().unwrap(),
        "--mock",
        "drive=RUNNING,SUCCESS",
    ]);
    assert_eq!(code, Some(0), "{err}");
    let summary = out.lines().last().unwrap();
    assert!(summary.ends_with(r#""blackboard":{}}}"#), "{summary}");
    assert!(!summary.contains("failure"), "{summary}");
}

#[test]
fn run_trace_carries_the_reason_on_the_change_to_failure() {
    let file = write_tree("reasons_trace.xml", TIMEOUT_THEN_RETRY);
    let (code, out, err) = run_cli(&[
        "run",
        file.to_str().unwrap(),
        "--mock",
        "drive=RUNNING",
        "--trace",
    ]);
    assert_eq!(code, Some(2), "{err}");
    let failures: Vec<&str> = out
        .lines()
        .filter(|l| l.contains(r#""to":"FAILURE""#))
        .collect();
    // The Retry's child fails without a reason; the Timeout and the Retry give theirs. (The
    // Retry's second attempt is the root's next pass: ticks count passes.)
    assert_eq!(
        failures,
        [
            r#"{"tick":3,"node":"try/limit","from":"RUNNING","to":"FAILURE","reason":"timed out after 150 ms"}"#,
            r#"{"tick":3,"node":"try/retry/AlwaysFailure","from":"IDLE","to":"FAILURE"}"#,
            r#"{"tick":4,"node":"try/retry/AlwaysFailure","from":"IDLE","to":"FAILURE"}"#,
            r#"{"tick":4,"node":"try/retry","from":"RUNNING","to":"FAILURE","reason":"gave up after 2 attempts"}"#,
            r#"{"tick":4,"node":"try","from":"RUNNING","to":"FAILURE"}"#,
        ]
    );
}

/// A Nav2 tree whose entry `p` holds a Path where a number is read.
const PATH_AS_NUMBER: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <ComputePathToPose goal="{goal}" path="{p}"/>
      <Wait wait_duration="{p}"/>
    </Sequence>
  </BehaviorTree>
</root>"#;

#[test]
fn an_entry_written_as_one_type_and_read_as_another_is_found_and_refused_when_strict() {
    let file = write_tree("path_as_number.xml", PATH_AS_NUMBER);
    let path = file.to_str().unwrap();
    let said = "5:7: error[NT0102]: port `wait_duration` of Wait reads the entry `p` as f64, \
                but port `path` of ComputePathToPose at line 4 writes a Path into it";
    let (code, out, err) = run_cli(&["lint", "--nav2", path]);
    assert_eq!(code, Some(1), "{err}");
    assert!(out.contains(said), "{out}");
    // `check` loads it, as documented; with --strict-types it refuses it there.
    let (code, out, err) = run_cli(&["check", "--nav2", path]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("ok (1 tree)"), "{out}");
    let (code, _, err) = run_cli(&["check", "--nav2", "--strict-types", path]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains(":5:7: error: port `wait_duration` of Wait reads the entry `p` as f64"),
        "{err}"
    );
}

#[test]
fn a_number_a_script_assigns_where_a_port_reads_a_whole_one_is_found_and_refused_when_strict() {
    let file = write_tree(
        "script_fraction.xml",
        r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="wait := 2.5"/>
      <Delay delay_msec="{wait}"><AlwaysSuccess/></Delay>
    </Sequence>
  </BehaviorTree>
</root>"#,
    );
    let path = file.to_str().unwrap();
    let said = "5:7: error[NT0102]: port `delay_msec` of Delay reads the entry `wait` as u64, \
                but the script `code` of Script at line 4 assigns the number 2.5 into it, \
                which does not convert without loss";
    let (code, out, err) = run_cli(&["lint", path]);
    assert_eq!(code, Some(1), "{err}");
    assert!(out.contains(said), "{out}");
    let (code, out, err) = run_cli(&["check", path]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("ok (1 tree)"), "{out}");
    let (code, _, err) = run_cli(&["check", "--strict-types", path]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains(":5:7: error: port `delay_msec` of Delay reads the entry `wait` as u64"),
        "{err}"
    );
    // A run refuses the value where lint says it does.
    let (_, out, err) = run_cli(&["run", path]);
    assert!(
        out.contains(r#""status":"ERROR","error":"Sequence/Delay (#2): port `delay_msec`"#)
            && out.contains("2.5 does not fit u64"),
        "{out}{err}"
    );
    // A whole number converts: nothing to say, strict or not, and the run succeeds.
    let whole = write_tree(
        "script_whole.xml",
        &std::fs::read_to_string(&file)
            .unwrap()
            .replace("2.5", "250"),
    );
    let (code, out, err) = run_cli(&["lint", whole.to_str().unwrap()]);
    assert!(!out.contains("NT0102"), "{out}{err}");
    assert_eq!(code, Some(0), "{out}{err}");
    let (code, _, err) = run_cli(&["check", "--strict-types", whole.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{err}");
    let (_, out, err) = run_cli(&["run", whole.to_str().unwrap()]);
    assert!(out.contains(r#""status":"SUCCESS","nodes""#), "{out}{err}");
}

#[test]
fn a_mistyped_port_gets_the_nearest_declared_name_in_check_and_lint() {
    let file = write_tree(
        "planer.xml",
        r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <ComputePathToPose goal="{goal}" path="{path}" planer_id="GridBased"/>
  </BehaviorTree>
</root>"#,
    );
    let path = file.to_str().unwrap();
    // `check` says `error:`, `lint` `error[NT0001]:`.
    let said = ": unknown port `planer_id` on `ComputePathToPose` (did you mean `planner_id`?); \
                its ports are: ";
    for command in ["check", "lint"] {
        let (code, out, err) = run_cli(&[command, "--nav2", path]);
        assert_eq!(code, Some(1), "{command}: {err}");
        let all = format!("{out}{err}");
        assert!(
            all.contains(":3:5: error") && all.contains(said),
            "{command}: {all}"
        );
    }
}

#[test]
fn run_takes_models_as_check_does_and_its_hint_names_mock_unknown() {
    let model = write_tree(
        "charge_model.xml",
        r#"<root BTCPP_format="4"><TreeNodesModel><Action ID="Charge"><input_port name="station" type="std::string"/></Action></TreeNodesModel></root>"#,
    );
    let tree = write_tree(
        "charge.xml",
        r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Charge station="A"/>
  </BehaviorTree>
</root>"#,
    );
    let (tree, model) = (tree.to_str().unwrap(), model.to_str().unwrap());
    let hint = "hint: mock the leaves without an implementation with --mock-unknown";
    // Unknown, then known from the model only: refused either way, the hint says how to run it.
    let (code, _, err) = run_cli(&["run", tree]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("unknown node type `Charge`") && err.contains(hint),
        "{err}"
    );
    let (code, _, err) = run_cli(&["run", tree, "--model", model]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("`Charge` is only described by a model") && err.contains(hint),
        "{err}"
    );
    // With the model, a mock of it checks its ports as the model declares them.
    let (code, out, err) = run_cli(&["run", tree, "--model", model, "--mock-unknown"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains(r#""status":"SUCCESS""#), "{out}");
    let bad = write_tree(
        "charge_bad.xml",
        r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Charge stacion="A"/>
  </BehaviorTree>
</root>"#,
    );
    let (code, _, err) = run_cli(&[
        "run",
        bad.to_str().unwrap(),
        "--model",
        model,
        "--mock-unknown",
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("(did you mean `station`?)"), "{err}");
}
