//! `neurotree run` with its loggers: `--log`, `--jsonl`, `--stats`, `--btlog`, `--sqlite`.
//!
//! Every test runs the same guarded move: tick 1 the guard holds and the move starts,
//! tick 2 the guard fails and the move is halted.

use std::path::Path;
use std::process::Command;

use neurotree::observe::read_btlog_file;
use neurotree::NodeStatus;

const GUARD: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <ReactiveSequence name="guard">
      <IsReady/>
      <MoveBase name="move"/>
    </ReactiveSequence>
  </BehaviorTree>
</root>"#;

/// What plain stdout shows, with or without loggers. The run ends FAILURE: exit status 2;
/// no node gave a reason, and the failure chain goes down to the condition that failed.
const STDOUT: &str = r#"{"tick":1,"status":"RUNNING"}
{"tick":2,"status":"FAILURE"}
{"summary":{"ticks":2,"status":"FAILURE","nodes":{"IsReady":{"ticks":2,"halts":0},"guard":{"ticks":2,"halts":0},"move":{"ticks":1,"halts":1}},"paths":{"guard":[{"ticks":2,"halts":0}],"guard/IsReady":[{"ticks":2,"halts":0}],"guard/move":[{"ticks":1,"halts":1}]},"blackboard":{},"failure":[{"path":"guard","tried":[]},{"path":"guard/IsReady","tried":[]}]}}
"#;

/// The run's status changes (the mock condition goes straight from Idle to its outcome, as a
/// BehaviorTree.CPP leaf does).
const CHANGES: [&str; 9] = [
    "[0.100s] guard IDLE -> RUNNING",
    "[0.100s] guard/IsReady IDLE -> SUCCESS",
    "[0.100s] guard/move IDLE -> RUNNING",
    "[0.100s] guard/IsReady SUCCESS -> IDLE",
    "[0.200s] guard/IsReady IDLE -> FAILURE",
    "[0.200s] guard/IsReady FAILURE -> IDLE",
    "[0.200s] guard/move RUNNING -> IDLE",
    "[0.200s] guard RUNNING -> FAILURE",
    "[0.200s] guard FAILURE -> IDLE",
];

struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// Runs the guarded move from a file in `dir`, with `extra` arguments and `env` set; colour
/// is otherwise left to the defaults (stderr is a pipe here, so none).
fn run(dir: &Path, extra: &[&str], env: &[(&str, &str)]) -> Run {
    let file = dir.join("guard.xml");
    std::fs::write(&file, GUARD).unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_neurotree"));
    cmd.arg("run")
        .arg(&file)
        .args([
            "--mock",
            "IsReady=SUCCESS,FAILURE",
            "--mock",
            "move=RUNNING",
        ])
        .args(extra)
        .env_remove("CLICOLOR_FORCE")
        .env_remove("NO_COLOR");
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().unwrap();
    Run {
        code: out.status.code(),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: String::from_utf8(out.stderr).unwrap(),
    }
}

#[test]
fn log_prints_plain_changes_on_stderr_and_stdout_is_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let plain = run(dir.path(), &[], &[]);
    assert_eq!((plain.code, plain.stdout.as_str()), (Some(2), STDOUT));
    assert_eq!(plain.stderr, "");

    let logged = run(dir.path(), &["--log"], &[]);
    assert_eq!((logged.code, logged.stdout.as_str()), (Some(2), STDOUT));
    assert_eq!(logged.stderr.lines().collect::<Vec<_>>(), CHANGES);
}

#[test]
fn log_is_coloured_when_forced() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(dir.path(), &["--log"], &[("CLICOLOR_FORCE", "1")]);
    assert_eq!(r.code, Some(2));
    let first = r.stderr.lines().next().unwrap();
    assert_eq!(
        first,
        "\u{1b}[2m[0.100s]\u{1b}[0m guard \u{1b}[2mIDLE\u{1b}[0m -> \u{1b}[33mRUNNING\u{1b}[0m"
    );
    assert_eq!(r.stdout, STDOUT);
}

#[test]
fn jsonl_writes_changes_and_ticks_to_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("run.jsonl");
    let r = run(dir.path(), &["--jsonl", file.to_str().unwrap()], &[]);
    assert_eq!(
        (r.code, r.stdout.as_str(), r.stderr.as_str()),
        (Some(2), STDOUT, "")
    );
    let text = std::fs::read_to_string(&file).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 11);
    assert_eq!(
        lines[0],
        r#"{"tick":1,"time_us":100000,"id":0,"node":"guard","from":"IDLE","to":"RUNNING"}"#
    );
    assert_eq!(
        lines[4],
        r#"{"tick":1,"time_us":100000,"status":"RUNNING"}"#
    );
    assert_eq!(
        lines[7],
        r#"{"tick":2,"time_us":200000,"id":2,"node":"guard/move","from":"RUNNING","to":"IDLE"}"#
    );
    assert_eq!(
        lines[10],
        r#"{"tick":2,"time_us":200000,"status":"FAILURE"}"#
    );
}

#[test]
fn stats_prints_a_table_on_stderr_at_the_end() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(dir.path(), &["--stats"], &[]);
    assert_eq!((r.code, r.stdout.as_str()), (Some(2), STDOUT));
    assert_eq!(
        r.stderr,
        "node           ticks  successes  failures  skips  halts  running\n\
         guard              2          0         1      0      0   0.100s\n\
         guard/IsReady      2          1         1      0      0   0.000s\n\
         guard/move         1          0         0      0      1   0.100s\n"
    );
}

#[test]
fn btlog_writes_a_log_that_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("run.btlog");
    let r = run(dir.path(), &["--btlog", file.to_str().unwrap()], &[]);
    assert_eq!(
        (r.code, r.stdout.as_str(), r.stderr.as_str()),
        (Some(2), STDOUT, "")
    );
    let log = read_btlog_file(&file).unwrap();
    let records: Vec<(u64, u16, NodeStatus)> = log
        .records
        .iter()
        .map(|r| (r.offset_us, r.uid, r.status))
        .collect();
    use NodeStatus::{Failure as F, Idle as I, Running as R, Success as S};
    assert_eq!(
        records,
        [
            (100_000, 1, R),
            (100_000, 2, S),
            (100_000, 3, R),
            (100_000, 2, I),
            (200_000, 2, F),
            (200_000, 2, I),
            (200_000, 3, I),
            (200_000, 1, F),
            (200_000, 1, I),
        ]
    );
    assert!(log.xml.contains(r#"name="move" _uid="3""#), "{}", log.xml);
}

#[test]
fn sqlite_writes_bt_cpps_tables() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("run.db3");
    for _ in 0..2 {
        // A second run replaces the first.
        let r = run(dir.path(), &["--sqlite", file.to_str().unwrap()], &[]);
        assert_eq!(
            (r.code, r.stdout.as_str(), r.stderr.as_str()),
            (Some(2), STDOUT, "")
        );
    }
    let db = rusqlite::Connection::open(&file).unwrap();
    let mut query = db
        .prepare(
            "SELECT n.fullpath, t.state FROM Transitions t JOIN Nodes n USING (session_id, uid)
             ORDER BY t.timestamp",
        )
        .unwrap();
    let rows: Vec<(String, i64)> = query
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?)))
        .unwrap()
        .map(Result::unwrap)
        .collect();
    let expected: Vec<(String, i64)> = CHANGES
        .iter()
        .map(|line| {
            let words: Vec<&str> = line.split(' ').collect();
            let state = match words[4] {
                "IDLE" => 0,
                "RUNNING" => 1,
                "SUCCESS" => 2,
                _ => 3,
            };
            (words[1].to_string(), state)
        })
        .collect();
    assert_eq!(rows, expected);
    let sessions: i64 = db
        .query_row("SELECT COUNT(*) FROM Definitions", [], |r| r.get(0))
        .unwrap();
    assert_eq!(sessions, 1);
}

#[test]
fn an_output_that_cannot_be_created_is_an_error_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("missing").join("run.jsonl");
    let r = run(dir.path(), &["--jsonl", file.to_str().unwrap()], &[]);
    assert_eq!(r.code, Some(1));
    assert_eq!(r.stdout, "");
    assert!(r.stderr.starts_with("neurotree: --jsonl "), "{}", r.stderr);
    assert!(r.stderr.contains("run.jsonl"), "{}", r.stderr);
}

#[test]
fn a_killed_sqlite_run_keeps_the_batches_it_committed() {
    use std::os::unix::process::ExitStatusExt;
    use std::time::{Duration, Instant};

    let dir = tempfile::tempdir().unwrap();
    let tree = dir.path().join("guard.xml");
    std::fs::write(&tree, GUARD).unwrap();
    let file = dir.path().join("killed.db3");
    let mut child = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .arg("run")
        .arg(&tree)
        .args(["--mock", "IsReady=SUCCESS", "--mock", "move=RUNNING"])
        .args(["--max-ticks", "4000000000", "--sqlite"])
        .arg(&file)
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let count = |db: &rusqlite::Connection| -> i64 {
        db.query_row("SELECT COUNT(*) FROM Transitions", [], |r| r.get(0))
            .unwrap_or(0)
    };
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        assert!(Instant::now() < deadline, "the run wrote too little");
        std::thread::sleep(Duration::from_millis(20));
        if let Ok(db) = rusqlite::Connection::open(&file) {
            if count(&db) >= 3_000 {
                break;
            }
        }
    }
    child.kill().unwrap();
    assert_eq!(child.wait().unwrap().signal(), Some(9));

    // Batches close at tick ends, every 1 s of the clock: 10 ticks of 100 ms. The first
    // tick makes 4 changes (guard and move start, IsReady succeeds and is reset), each
    // other 2 (a mocked leaf goes Idle -> Success with no Running mark, as in
    // BehaviorTree.CPP).
    let db = rusqlite::Connection::open(&file).unwrap();
    let rows = count(&db);
    assert_eq!((rows - 22) % 20, 0, "{rows} rows: not whole batches");
    let mut query = db
        .prepare(
            "SELECT t.timestamp, n.fullpath, t.state FROM Transitions t
             JOIN Nodes n USING (session_id, uid) ORDER BY t.timestamp",
        )
        .unwrap();
    let all: Vec<(i64, String, i64)> = query
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))
        .unwrap()
        .map(Result::unwrap)
        .collect();
    assert_eq!(all.len() as i64, rows, "every row names a node");
    for (tick, rows) in all[4..].chunks(2).enumerate() {
        let states: Vec<(&str, i64)> = rows.iter().map(|r| (r.1.as_str(), r.2)).collect();
        assert_eq!(
            states,
            [("guard/IsReady", 2), ("guard/IsReady", 0)],
            "tick {}",
            tick + 2
        );
        // 100 ms after the tick before (plus the microsecond that keeps keys apart).
        let since_first = rows[0].0 - all[0].0;
        assert!(
            (since_first - (tick as i64 + 1) * 100_000).abs() < 10,
            "tick {}",
            tick + 2
        );
    }
}
