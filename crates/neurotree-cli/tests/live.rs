//! `neurotree run` with a tree that lives on: `--save-state`/`--stop-after`, `--resume`,
//! `--keep-states`, `--watch` and `--pace-ms`.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn neurotree(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the binary runs")
}

fn corpus(name: &str) -> String {
    format!("../../corpus/nav2/{name}")
}

fn lines(out: &Output) -> Vec<String> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(str::to_string)
        .collect()
}

/// Nav2's navigator with recovery, its leaves mocked so that the controller fails once
/// and the recovery runs: every kind of Nav2 control keeps state across the cut.
const NAV2: &str = "navigate_to_pose_w_replanning_and_recovery.xml";
const MOCKS: &[&str] = &[
    "--mock-unknown",
    "--mock",
    "FollowPath=RUNNING*3,FAILURE,RUNNING*4,SUCCESS",
    "--mock",
    "ComputePathToPose=SUCCESS",
    "--mock",
    "Spin=RUNNING*2,SUCCESS",
    "--trace",
    "--max-ticks",
    "40",
];

fn run_nav2(extra: &[&str]) -> Output {
    let file = corpus(NAV2);
    let mut args = vec!["run", file.as_str()];
    args.extend_from_slice(MOCKS);
    args.extend_from_slice(extra);
    neurotree(&args)
}

/// The lines an uninterrupted run prints after tick `n`'s line.
fn after_tick(all: &[String], n: u32) -> Vec<String> {
    let mark = format!("{{\"tick\":{n},\"status\"");
    let at = all
        .iter()
        .position(|l| l.starts_with(&mark))
        .expect("the tick's line");
    all[at + 1..].to_vec()
}

fn path_str(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn a_resumed_run_prints_what_the_uninterrupted_run_printed_after_the_cut() {
    let whole = run_nav2(&[]);
    assert_eq!(
        whole.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&whole.stderr)
    );
    let all = lines(&whole);
    // The recovery ran: the mocked Spin was ticked.
    assert!(all.iter().any(|l| l.contains("/Spin\"")), "{all:#?}");
    let dir = tempfile::tempdir().unwrap();
    for cut in [1, 4, 7] {
        let state = dir.path().join(format!("cut-{cut}.state"));
        let first = run_nav2(&[
            "--stop-after",
            &cut.to_string(),
            "--save-state",
            path_str(&state),
        ]);
        assert_eq!(first.status.code(), Some(3), "stopped while RUNNING");
        let err = String::from_utf8_lossy(&first.stderr);
        assert!(
            err.contains(&format!("state after tick {cut} saved to")),
            "{err}"
        );
        let rest = run_nav2(&["--resume", path_str(&state)]);
        assert_eq!(
            rest.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&rest.stderr)
        );
        assert_eq!(lines(&rest), after_tick(&all, cut), "cut after tick {cut}");
    }
}

#[test]
fn states_kept_every_k_ticks_resume_too() {
    let whole = lines(&run_nav2(&[]));
    let dir = tempfile::tempdir().unwrap();
    let states = dir.path().join("states");
    let kept = run_nav2(&["--keep-states", "3", "--states-dir", path_str(&states)]);
    assert_eq!(kept.status.code(), Some(0));
    assert_eq!(
        lines(&kept),
        whole,
        "keeping states changes nothing printed"
    );
    let mut names: Vec<String> = std::fs::read_dir(&states)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert!(names.contains(&"tick-3.state".to_string()), "{names:?}");
    assert!(names.contains(&"tick-6.state".to_string()), "{names:?}");
    let rest = run_nav2(&["--resume", path_str(&states.join("tick-6.state"))]);
    assert_eq!(lines(&rest), after_tick(&whole, 6));
}

#[test]
fn a_state_of_another_tree_or_no_state_is_refused_with_the_file_named() {
    let dir = tempfile::tempdir().unwrap();
    let state = dir.path().join("nav.state");
    run_nav2(&["--stop-after", "2", "--save-state", path_str(&state)]);
    let other = corpus("navigate_w_replanning_time.xml");
    let out = neurotree(&[
        "run",
        &other,
        "--mock-unknown",
        "--resume",
        path_str(&state),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.starts_with(&format!(
            "{}: error: the state belongs to another tree",
            state.display()
        )),
        "{err}"
    );
    assert!(out.stdout.is_empty());

    let junk = dir.path().join("junk.state");
    std::fs::write(&junk, b"NTRUN but not really a state").unwrap();
    let out = run_nav2(&["--resume", path_str(&junk)]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.starts_with(&format!("{}: error: ", junk.display())),
        "{err}"
    );
}

const PATROL: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence name="patrol">
      <Walk name="walk"/>
      <Look name="look"/>
    </Sequence>
  </BehaviorTree>
</root>
"#;

/// Replaces `file` as editors do: a new file renamed over it.
fn replace(file: &Path, text: &str) {
    let new = file.with_extension("new");
    std::fs::write(&new, text).unwrap();
    std::fs::rename(&new, file).unwrap();
}

#[test]
fn watch_reloads_a_changed_file_between_ticks_and_survives_a_broken_one() {
    let dir = tempfile::tempdir().unwrap();
    let file: PathBuf = dir.path().join("patrol.xml");
    std::fs::write(&file, PATROL).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args([
            "run",
            path_str(&file),
            "--mock-unknown",
            "--mock",
            "walk=RUNNING",
            "--watch",
            "--pace-ms",
            "40",
            "--max-ticks",
            "400",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut out = BufReader::new(child.stdout.take().unwrap()).lines();
    let mut next = || out.next().expect("a line").unwrap();
    // Wait for a tick, then change a leaf that is not running: everything else is kept.
    assert!(next().starts_with("{\"tick\":1,"));
    replace(
        &file,
        &PATROL.replace("<Look name=\"look\"/>", "<Listen name=\"look\"/>"),
    );
    let reload = loop {
        let line = next();
        if line.starts_with("{\"reload\"") {
            break line;
        }
    };
    assert_eq!(reload, r#"{"reload":{"kept":2,"restarted":1,"halted":0}}"#);
    // A broken file: reported, the run goes on.
    replace(
        &file,
        &PATROL.replace("<Look name=\"look\"/>", "<Look name=\"look\" oops"),
    );
    let mut ticks_after = 0;
    while ticks_after < 4 {
        let line = next();
        assert!(!line.starts_with("{\"reload\""), "{line}");
        ticks_after += usize::from(line.starts_with("{\"tick\""));
    }
    // The running leaf itself changes: it is halted and starts afresh.
    let listening = PATROL.replace("<Look name=\"look\"/>", "<Listen name=\"look\"/>");
    replace(
        &file,
        &listening.replace("<Walk name=\"walk\"/>", "<Run name=\"walk\"/>"),
    );
    let reload = loop {
        let line = next();
        if line.starts_with("{\"reload\"") {
            break line;
        }
    };
    assert_eq!(reload, r#"{"reload":{"kept":2,"restarted":1,"halted":1}}"#);
    child.kill().unwrap();
    let output = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&output.stderr);
    // `file:line:col: error: …`, where the XML broke.
    let place = format!("{}:6:5: error: malformed XML", file.display());
    assert!(err.contains(&place), "{err}");
    assert!(err.contains("the running tree goes on"), "{err}");
}

#[test]
fn watch_refuses_loggers_it_cannot_keep_up_to_date() {
    let file = corpus(NAV2);
    let out = neurotree(&["run", &file, "--mock-unknown", "--watch", "--view"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--watch"));
}

const GUARDED: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <ReactiveSequence name="go">
      <ScriptCondition name="charged" code="battery > 20"/>
      <Drive name="drive"/>
    </ReactiveSequence>
  </BehaviorTree>
</root>
"#;

#[test]
fn a_resumed_run_forks_with_another_value_or_mock() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("guarded.xml");
    std::fs::write(&file, GUARDED).unwrap();
    let state = dir.path().join("go.state");
    let (tree, state_arg) = (path_str(&file), path_str(&state));
    let mock = ["--mock", "drive=RUNNING*5,SUCCESS"];
    let mut first = vec!["run", tree, "--set", "battery=50", "--stop-after", "2"];
    first.extend_from_slice(&mock);
    first.extend_from_slice(&["--save-state", state_arg]);
    assert_eq!(neurotree(&first).status.code(), Some(3));

    let mut same = vec!["run", tree, "--resume", state_arg];
    same.extend_from_slice(&mock);
    let out = neurotree(&same);
    assert_eq!(out.status.code(), Some(0));
    assert!(
        lines(&out)[3].starts_with(r#"{"tick":6,"status":"SUCCESS"}"#),
        "{:?}",
        lines(&out)
    );

    // The battery drops at the cut: the guard fails on the next tick.
    let mut drained = same.clone();
    drained.extend_from_slice(&["--set", "battery=10"]);
    let out = neurotree(&drained);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(lines(&out)[0], r#"{"tick":3,"status":"FAILURE"}"#);

    // Another mock for the drive, from where the saved one was.
    let out = neurotree(&[
        "run",
        tree,
        "--resume",
        state_arg,
        "--mock",
        "drive=RUNNING*3,FAILURE",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(lines(&out)[1], r#"{"tick":4,"status":"FAILURE"}"#);
}
