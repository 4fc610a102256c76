//! The SQLite logger: BehaviorTree.CPP's tables, filled as its SqliteLogger fills them,
//! read back with plain SQL; rows written in batches, and a killed run keeping the batches
//! it committed.

#![cfg(feature = "sqlite")]

use crate::patrol;

use std::io::BufRead;
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, UNIX_EPOCH};

use neurotree::observe::SqliteLogger;
use neurotree::{Handle, ManualClock, Registry, StatefulAction, Status, Tree};
use rusqlite::Connection;

/// The patrol's transitions: (timestamp - start in µs, uid, duration in µs, state). Changes
/// within one microsecond are logged one microsecond apart, as the timestamp is the key.
const PATROL: [(i64, i64, i64, i64); 33] = [
    (100000, 1, 0, 1),
    (100001, 2, 0, 2),
    (100002, 3, 0, 1),
    (100003, 4, 0, 1),
    (100004, 5, 0, 2),
    (100005, 5, 0, 0),
    (100006, 4, 3, 2),
    (100007, 6, 0, 1),
    (100008, 2, 0, 0),
    (200000, 2, 0, 3),
    (200001, 2, 0, 0),
    (200002, 4, 0, 0),
    (200003, 6, 99996, 0),
    (200004, 3, 100002, 0),
    (200005, 1, 100005, 3),
    (200006, 1, 0, 0),
    (300000, 1, 0, 1),
    (300001, 2, 0, 2),
    (300002, 3, 0, 1),
    (300003, 6, 0, 1),
    (300004, 2, 0, 0),
    (400000, 2, 0, 2),
    (400001, 2, 0, 0),
    (500000, 2, 0, 2),
    (500001, 6, 199998, 2),
    (500002, 7, 0, 2),
    (500003, 6, 0, 0),
    (500004, 7, 0, 0),
    (500005, 3, 200003, 2),
    (500006, 2, 0, 0),
    (500007, 3, 0, 0),
    (500008, 1, 200008, 2),
    (500009, 1, 0, 0),
];

const START_US: i64 = 1_700_000_000_000_000;

fn transitions(db: &Connection, session: i64) -> Vec<(i64, i64, i64, i64)> {
    let mut query = db
        .prepare(
            "SELECT timestamp, uid, duration, state FROM Transitions
             WHERE session_id = ?1 ORDER BY timestamp",
        )
        .unwrap();
    query
        .query_map([session], |row| {
            Ok((row.get(0)?, row.get(1)?, row.get(2)?, row.get(3)?))
        })
        .unwrap()
        .map(Result::unwrap)
        .collect()
}

fn log_patrol(path: &std::path::Path, append: bool) -> i64 {
    let (mut tree, clock) = patrol::start();
    let start = UNIX_EPOCH + Duration::from_micros(START_US as u64);
    let conn = Connection::open(path).unwrap();
    let log = SqliteLogger::with_connection(conn, &tree, &Registry::new(), append, start).unwrap();
    tree.set_observer(log.clone());
    patrol::run(&mut tree, &clock);
    log.flush().unwrap();
    log.session_id()
}

#[test]
fn a_run_reads_back_with_sql() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.db3");
    let session = log_patrol(&path, false);
    assert_eq!(session, 1);

    let db = Connection::open(&path).unwrap();
    let rows: Vec<(i64, i64, i64, i64)> = transitions(&db, session)
        .into_iter()
        .map(|(t, uid, d, s)| (t - START_US, uid, d, s))
        .collect();
    assert_eq!(rows, PATROL);
    let metadata: i64 = db
        .query_row(
            "SELECT COUNT(*) FROM Transitions WHERE metadata IS NULL",
            [],
            |r| r.get(0),
        )
        .unwrap();
    assert_eq!(metadata, 33);

    let mut nodes = db
        .prepare("SELECT session_id, fullpath, uid FROM Nodes ORDER BY uid")
        .unwrap();
    let nodes: Vec<(i64, String, i64)> = nodes
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))
        .unwrap()
        .map(Result::unwrap)
        .collect();
    let expected: Vec<(i64, String, i64)> = [
        "patrol",
        "patrol/battery_ok",
        "patrol/route",
        "patrol/route/once",
        "patrol/route/once/wave",
        "patrol/route/move",
        "patrol/route/scan",
    ]
    .iter()
    .zip(1..)
    .map(|(p, uid)| (1, p.to_string(), uid))
    .collect();
    assert_eq!(nodes, expected);

    let (id, date, xml): (i64, String, String) = db
        .query_row(
            "SELECT session_id, date, xml_tree FROM Definitions",
            [],
            |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)),
        )
        .unwrap();
    assert_eq!(id, 1);
    assert_eq!(date.len(), "2024-01-01 12:00:00".len());
    assert!(xml.contains(r#"_uid="7""#), "{xml}");

    // Which node was halted, in SQL: a change from Running to Idle has a duration.
    let halted: String = db
        .query_row(
            "SELECT n.fullpath FROM Transitions t JOIN Nodes n USING (session_id, uid)
             WHERE t.state = 0 AND t.duration > 0 AND n.fullpath LIKE '%move'",
            [],
            |r| r.get(0),
        )
        .unwrap();
    assert_eq!(halted, "patrol/route/move");
}

#[test]
fn sessions_append_or_start_afresh() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("runs.btdb");
    assert_eq!(log_patrol(&path, false), 1);
    // Appended, at the same start time: timestamps stay unique and increasing.
    assert_eq!(log_patrol(&path, true), 2);
    let db = Connection::open(&path).unwrap();
    let first = transitions(&db, 1);
    let second = transitions(&db, 2);
    assert_eq!((first.len(), second.len()), (33, 33));
    assert!(second[0].0 > first[32].0);
    let count = |table: &str| -> i64 {
        db.query_row(&format!("SELECT COUNT(*) FROM {table}"), [], |r| r.get(0))
            .unwrap()
    };
    assert_eq!((count("Definitions"), count("Nodes")), (2, 14));
    drop(db);

    // Not appended: the earlier sessions are gone; ids go on.
    assert_eq!(log_patrol(&path, false), 3);
    let db = Connection::open(&path).unwrap();
    let count = |table: &str| -> i64 {
        db.query_row(&format!("SELECT COUNT(*) FROM {table}"), [], |r| r.get(0))
            .unwrap()
    };
    assert_eq!(
        (count("Definitions"), count("Nodes"), count("Transitions")),
        (1, 7, 33)
    );
    let rows: Vec<(i64, i64, i64, i64)> = transitions(&db, 3)
        .into_iter()
        .map(|(t, uid, d, s)| (t - START_US, uid, d, s))
        .collect();
    assert_eq!(rows, PATROL);
}

/// Running until halted.
struct Forever;

impl StatefulAction<()> for Forever {
    fn on_start(&mut self, _h: &mut Handle<'_, ()>) -> Status {
        Status::Running
    }
    fn on_running(&mut self, _h: &mut Handle<'_, ()>) -> Status {
        Status::Running
    }
}

#[test]
fn with_a_batch_of_one_rows_are_written_at_the_end_of_each_tick() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.db3");
    let count = |db: &Connection| -> i64 {
        db.query_row("SELECT COUNT(*) FROM Transitions", [], |r| r.get(0))
            .unwrap()
    };
    // A condition that notes, while the tree ticks, how many rows are written already.
    let reader: Mutex<Option<Connection>> = Mutex::new(None);
    let seen = Arc::new(Mutex::new(Vec::new()));
    let probe = {
        let (path, seen) = (path.clone(), Arc::clone(&seen));
        move |_: &()| {
            let mut reader = reader.lock().unwrap();
            let db = reader.get_or_insert_with(|| Connection::open(&path).unwrap());
            seen.lock().unwrap().push(count(db));
            true
        }
    };
    let blueprint = neurotree::Blueprint::<()>::builder()
        .reactive_sequence("seq", |s| {
            s.condition("probe", probe).stateful("work", || Forever)
        })
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    let log = SqliteLogger::open(&path, &tree, &Registry::new(), false)
        .unwrap()
        .batch(1, Duration::MAX);
    tree.set_observer(log.clone());
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    // During tick 1 nothing was written yet; during tick 2, tick 1's four changes (seq
    // IDLE->RUNNING, probe IDLE->SUCCESS, work IDLE->RUNNING, probe SUCCESS->IDLE).
    assert_eq!(*seen.lock().unwrap(), [0, 4]);
    let db = Connection::open(&path).unwrap();
    assert_eq!(count(&db), 6);

    // A halt between ticks is written by the flush.
    tree.halt(&mut ());
    assert_eq!(count(&db), 6);
    log.flush().unwrap();
    assert_eq!(count(&db), 8);
}

/// A Sequence of ten leaves that succeed: 23 status changes per tick (the sequence Idle,
/// Running, Success, Idle; each leaf Idle, Success, Idle).
fn ten_successes(clock: &ManualClock) -> Tree<()> {
    let blueprint = neurotree::Blueprint::<()>::builder()
        .sequence("all", |mut s| {
            for i in 0..10 {
                s = s.always_success(&format!("leaf{i}"));
            }
            s
        })
        .build_shared()
        .unwrap();
    Tree::with_clock(blueprint, clock.clone())
}

const CHANGES_PER_TICK: i64 = 23;

fn count_rows(path: &Path) -> i64 {
    let db = Connection::open(path).unwrap();
    db.query_row("SELECT COUNT(*) FROM Transitions", [], |r| r.get(0))
        .unwrap()
}

/// Ticks `tree` once, its manual clock `step` further first.
fn tick_after(tree: &mut Tree<()>, clock: &ManualClock, step: Duration) {
    clock.advance(step);
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
}

#[test]
fn a_batch_is_written_at_the_end_of_the_tick_that_fills_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.db3");
    let clock = ManualClock::new();
    let mut tree = ten_successes(&clock);
    let log = SqliteLogger::open(&path, &tree, &Registry::new(), false)
        .unwrap()
        .batch(50, Duration::MAX);
    tree.set_observer(log.clone());
    // 23 and 46 changes wait; the third tick brings 69 >= 50, all written.
    let mut seen = Vec::new();
    for _ in 0..6 {
        tick_after(&mut tree, &clock, Duration::from_millis(100));
        seen.push(count_rows(&path));
    }
    assert_eq!(seen, [0, 0, 69, 69, 69, 138]);
}

#[test]
fn a_batch_is_written_at_the_end_of_the_tick_that_ends_its_interval() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.db3");
    let clock = ManualClock::new();
    let mut tree = ten_successes(&clock);
    let log = SqliteLogger::open(&path, &tree, &Registry::new(), false)
        .unwrap()
        .batch(10_000, Duration::from_millis(250));
    tree.set_observer(log.clone());
    // Ticks at 100, 200, 300 ms: the one at 300 ends 250 ms after the start and writes;
    // then the one at 600 ms, 300 ms after that write.
    let mut seen = Vec::new();
    for _ in 0..6 {
        tick_after(&mut tree, &clock, Duration::from_millis(100));
        seen.push(count_rows(&path));
    }
    assert_eq!(seen, [0, 0, 69, 69, 69, 138]);
}

#[test]
fn flush_and_the_last_drop_write_the_rest() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.db3");
    let clock = ManualClock::new();
    let mut tree = ten_successes(&clock);
    let log = SqliteLogger::open(&path, &tree, &Registry::new(), false)
        .unwrap()
        .batch(10_000, Duration::MAX);
    tree.set_observer(log.clone());
    for _ in 0..5 {
        tick_after(&mut tree, &clock, Duration::from_millis(100));
    }
    assert_eq!(count_rows(&path), 0);
    log.flush().unwrap();
    assert_eq!(count_rows(&path), 5 * CHANGES_PER_TICK);
    for _ in 0..2 {
        tick_after(&mut tree, &clock, Duration::from_millis(100));
    }
    assert_eq!(count_rows(&path), 5 * CHANGES_PER_TICK);
    // The tree holds one handle: dropping ours writes nothing yet, dropping the last does.
    drop(log);
    assert_eq!(count_rows(&path), 5 * CHANGES_PER_TICK);
    drop(tree);
    assert_eq!(count_rows(&path), 7 * CHANGES_PER_TICK);

    let db = Connection::open(&path).unwrap();
    let mode: String = db
        .query_row("PRAGMA journal_mode", [], |r| r.get(0))
        .unwrap();
    assert_eq!(mode, "wal");
}

/// The environment variable that makes [`killed_writer`] write to the database it names.
const CHILD_DB: &str = "NEUROTREE_TEST_SQLITE_CHILD_DB";

/// Logs `ticks` ticks of a [`ten_successes`] tree, 1 ms apart, into `path` in batches of ten
/// ticks; returns the tree, which holds the logger.
fn log_ticks(path: &Path, ticks: usize) -> Tree<()> {
    let clock = ManualClock::new();
    let mut tree = ten_successes(&clock);
    let start = UNIX_EPOCH + Duration::from_micros(START_US as u64);
    let conn = Connection::open(path).unwrap();
    let log = SqliteLogger::with_connection(conn, &tree, &Registry::new(), false, start)
        .unwrap()
        .batch(10 * CHANGES_PER_TICK as usize, Duration::MAX);
    tree.set_observer(log);
    for _ in 0..ticks {
        tick_after(&mut tree, &clock, Duration::from_millis(1));
    }
    tree
}

/// Run by [`a_killed_run_keeps_its_committed_batches`] in a child process: 35 ticks in
/// batches of 10, so 3 batches committed and 5 ticks waiting, then "ready" and a wait to
/// be killed.
#[test]
#[ignore = "the child process of a_killed_run_keeps_its_committed_batches"]
fn killed_writer() {
    let Some(path) = std::env::var_os(CHILD_DB) else {
        return;
    };
    let _tree = log_ticks(Path::new(&path), 35);
    println!("ready");
    // Killed long before; a bound so that a child whose parent died goes away too.
    std::thread::sleep(Duration::from_secs(60));
}

#[test]
fn a_killed_run_keeps_its_committed_batches() {
    use std::os::unix::process::ExitStatusExt;

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("killed.db3");
    let mut child = Command::new(std::env::current_exe().unwrap())
        .args([
            "--ignored",
            "--exact",
            "observe_sqlite::killed_writer",
            "--nocapture",
        ])
        .env(CHILD_DB, &path)
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let stdout = std::io::BufReader::new(child.stdout.take().unwrap());
    let ready = stdout
        .lines()
        .map(Result::unwrap)
        .any(|line| line == "ready");
    assert!(ready, "the child ended without logging its ticks");
    child.kill().unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(9), "{status}");

    // The same 30 ticks logged to the end, to compare with.
    let reference = dir.path().join("reference.db3");
    drop(log_ticks(&reference, 30));
    let expected = transitions(&Connection::open(&reference).unwrap(), 1);
    assert_eq!(expected.len(), 30 * CHANGES_PER_TICK as usize);

    let db = Connection::open(&path).unwrap();
    assert_eq!(transitions(&db, 1), expected);
    let nodes: i64 = db
        .query_row("SELECT COUNT(*) FROM Nodes WHERE session_id = 1", [], |r| {
            r.get(0)
        })
        .unwrap();
    assert_eq!(nodes, 11);
    let check: String = db
        .query_row("PRAGMA integrity_check", [], |r| r.get(0))
        .unwrap();
    assert_eq!(check, "ok");
}
