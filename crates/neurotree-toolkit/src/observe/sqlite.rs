//! A run in an SQLite database with BehaviorTree.CPP's `SqliteLogger` schema, to query with
//! SQL.
//!
//! Rows are written in batches because a commit costs far more than a row: at one commit
//! per tick the Nav2 navigator spent 120 to 280 µs per tick in SQLite, depending on the
//! disk, where it now spends about 2 (`BENCHMARKS.md`).

use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use neurotree_core::{NodeStatus, Observer, StatusChange, Tree};
use rusqlite::{params, Connection};

use super::{lock, micros, status_code};
use crate::xml::{write_xml, SaveOptions};
use crate::Registry;

/// BehaviorTree.CPP's tables, created if missing.
const SCHEMA: &str = "
CREATE TABLE IF NOT EXISTS Transitions (
    timestamp  INTEGER PRIMARY KEY NOT NULL,
    session_id INTEGER NOT NULL,
    uid        INTEGER NOT NULL,
    duration   INTEGER,
    state      INTEGER NOT NULL,
    metadata   VARCHAR );
CREATE TABLE IF NOT EXISTS Nodes (
    session_id INTEGER NOT NULL,
    fullpath   VARCHAR,
    uid        INTEGER NOT NULL );
CREATE TABLE IF NOT EXISTS Definitions (
    session_id INTEGER PRIMARY KEY AUTOINCREMENT,
    date       TEXT NOT NULL,
    xml_tree   TEXT NOT NULL);
";

/// What went wrong with the database.
#[derive(thiserror::Error)]
#[non_exhaustive]
pub enum SqliteLogError {
    /// SQLite refused an operation.
    #[error("SQLite log: {0}")]
    Sqlite(#[from] rusqlite::Error),
}

neurotree_core::debug_shows_message!(
    enum SqliteLogError {
        Sqlite(source),
    }
);

/// Logs a run into SQLite with the tables of BehaviorTree.CPP's `SqliteLogger`, so that
/// its tools, and plain SQL, read it:
///
/// | table | rows |
/// |---|---|
/// | `Definitions(session_id, date, xml_tree)` | one per logger: the tree as XML with `_uid`s |
/// | `Nodes(session_id, fullpath, uid)` | one per node: its path and uid |
/// | `Transitions(timestamp, session_id, uid, duration, state, metadata)` | one per status change |
///
/// A node's `uid` is its [`NodeId`](crate::NodeId) plus one.
///
/// As BehaviorTree.CPP does:
/// - `timestamp` is in microseconds since the Unix epoch, and is the table's key, so a
///   change at the same microsecond as the previous one is logged one microsecond later;
/// - `state` is the new status in BehaviorTree.CPP's numbering (IDLE 0, RUNNING 1,
///   SUCCESS 2, FAILURE 3); every change is logged, those to Idle included;
/// - `duration` is, on a change away from Running, the time since the change from Idle to
///   Running, in microseconds; else 0. `metadata` is NULL;
/// - without `append`, the rows of earlier sessions are deleted first (here the `Nodes`
///   rows too, which BehaviorTree.CPP keeps).
///
/// Timestamps are the wall-clock time when the logger was made plus the time since then on
/// the tree's clock, so a run on a [`ManualClock`](crate::ManualClock) logs the same times
/// relative to its start.
///
/// Rows are written in batches, each in one transaction: a batch closes at the end of the
/// tick that makes it [`DEFAULT_MAX_CHANGES`](Self::DEFAULT_MAX_CHANGES) changes long or
/// that ends [`DEFAULT_MAX_INTERVAL`](Self::DEFAULT_MAX_INTERVAL) of the tree's clock after
/// the last commit, whichever comes first (other figures with [`batch`](Self::batch)), so
/// a batch holds whole ticks and a run that is killed keeps every batch committed before.
/// The rest is written by [`flush`](Self::flush) or when the last handle is dropped;
/// changes made between ticks (by [`Tree::halt`]) wait for the next tick's end, or for
/// these.
///
/// The database is put in WAL mode with `synchronous=NORMAL`: a commit appends to the
/// write-ahead log without waiting for the disk, and is kept if the process is killed (what
/// it wrote is in the operating system's hands); only a power cut or a crash of the system
/// may lose the last batches, and neither leaves the file corrupt. For the log of a run
/// that is the right trade: `FULL` would wait for the disk at every batch. Readers may
/// query the file while the run goes on.
pub struct SqliteLogger {
    state: Arc<Mutex<Db>>,
}

impl Clone for SqliteLogger {
    fn clone(&self) -> Self {
        Self {
            state: Arc::clone(&self.state),
        }
    }
}

struct Db {
    conn: Connection,
    session_id: i64,
    /// The tree's clock when the logger was made.
    origin: Duration,
    /// The wall-clock time then, in microseconds since the Unix epoch.
    start_us: i64,
    /// The last timestamp logged, which the next one must exceed.
    last_us: i64,
    /// Per node: when it last went from Idle to Running.
    running_since: Vec<Option<i64>>,
    /// Changes not written yet.
    pending: Vec<Transition>,
    /// A batch is written once it holds this many changes...
    max_changes: usize,
    /// ...or this long after the last write, on the tree's clock.
    max_interval: Duration,
    /// The tree's clock at the last write (or when the logger was made).
    last_write: Duration,
    error: Option<rusqlite::Error>,
}

struct Transition {
    timestamp: i64,
    uid: i64,
    duration: i64,
    state: i64,
}

impl SqliteLogger {
    /// The changes after which a batch is written, unless [`batch`](Self::batch) says
    /// otherwise: some 450 ticks of Nav2's navigator, 32 KiB of rows in memory.
    pub const DEFAULT_MAX_CHANGES: usize = 1024;

    /// The time on the tree's clock after which a batch is written, unless
    /// [`batch`](Self::batch) says otherwise: what a killed run may lose at most.
    pub const DEFAULT_MAX_INTERVAL: Duration = Duration::from_secs(1);

    /// Opens (or creates) the database at `path` and starts a session for `tree`, whose
    /// registered types `registry` describes. Without `append`, earlier sessions are
    /// deleted. BehaviorTree.CPP's tools expect the name to end in `.db3` or `.btdb`.
    pub fn open<C: 'static>(
        path: impl AsRef<Path>,
        tree: &Tree<C>,
        registry: &Registry<C>,
        append: bool,
    ) -> Result<Self, SqliteLogError> {
        let conn = Connection::open(path)?;
        Self::with_connection(conn, tree, registry, append, SystemTime::now())
    }

    /// Starts a session in `conn` (a file or an in-memory database), timestamped from
    /// `start`. A file is switched to WAL mode with `synchronous=NORMAL` (see
    /// [`SqliteLogger`]), which stays with the file.
    pub fn with_connection<C: 'static>(
        mut conn: Connection,
        tree: &Tree<C>,
        registry: &Registry<C>,
        append: bool,
        start: SystemTime,
    ) -> Result<Self, SqliteLogError> {
        let blueprint = tree.blueprint();
        let opts = SaveOptions {
            uids: true,
            builtin_models: true,
            ..SaveOptions::default()
        };
        let xml = write_xml(blueprint, registry, &opts);
        // An in-memory database answers `memory` and stays so; that is fine.
        conn.execute_batch("PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL;")?;
        let tx = conn.transaction()?;
        tx.execute_batch(SCHEMA)?;
        if !append {
            tx.execute_batch(
                "DELETE FROM Transitions; DELETE FROM Definitions; DELETE FROM Nodes;",
            )?;
        }
        tx.execute(
            "INSERT INTO Definitions (date, xml_tree) VALUES (datetime('now','localtime'), ?1)",
            params![xml],
        )?;
        let session_id = tx.last_insert_rowid();
        {
            let mut insert = tx.prepare("INSERT INTO Nodes VALUES (?1, ?2, ?3)")?;
            for (id, path) in blueprint.ids().zip(blueprint.paths()) {
                insert.execute(params![session_id, path, i64::from(id.0) + 1])?;
            }
        }
        let last_us: i64 = tx.query_row(
            "SELECT COALESCE(MAX(timestamp), 0) FROM Transitions",
            [],
            |row| row.get(0),
        )?;
        tx.commit()?;
        let start_us = match start.duration_since(UNIX_EPOCH) {
            Ok(d) => i64::try_from(d.as_micros()).unwrap_or(i64::MAX),
            Err(_) => 0,
        };
        Ok(Self {
            state: Arc::new(Mutex::new(Db {
                conn,
                session_id,
                origin: tree.now(),
                start_us,
                last_us,
                running_since: vec![None; blueprint.len()],
                pending: Vec::with_capacity(Self::DEFAULT_MAX_CHANGES),
                max_changes: Self::DEFAULT_MAX_CHANGES,
                max_interval: Self::DEFAULT_MAX_INTERVAL,
                last_write: tree.now(),
                error: None,
            })),
        })
    }

    /// Writes a batch at the end of the first tick that brings it to `max_changes` changes
    /// or that ends `max_interval` or more after the last write, on the tree's clock. A
    /// `max_changes` of 1 writes every tick; 0 is taken as 1.
    pub fn batch(self, max_changes: usize, max_interval: Duration) -> Self {
        {
            let mut db = lock(&self.state);
            db.max_changes = max_changes.max(1);
            db.max_interval = max_interval;
        }
        self
    }

    /// The session's id in `Definitions`, `Nodes` and `Transitions`.
    pub fn session_id(&self) -> i64 {
        lock(&self.state).session_id
    }

    /// Writes the changes not written yet, in one transaction, or returns the first error
    /// writing met (rows met by an error are lost; logging goes on).
    pub fn flush(&self) -> Result<(), SqliteLogError> {
        let mut db = lock(&self.state);
        db.write_pending();
        match db.error.take() {
            Some(e) => Err(e.into()),
            None => Ok(()),
        }
    }
}

impl Db {
    fn write_pending(&mut self) {
        if self.pending.is_empty() {
            return;
        }
        if let Err(e) = self.try_write_pending() {
            self.error.get_or_insert(e);
        }
        self.pending.clear();
    }

    fn try_write_pending(&mut self) -> rusqlite::Result<()> {
        let tx = self.conn.transaction()?;
        {
            // Prepared once, then taken from the connection's cache at every batch.
            let mut insert =
                tx.prepare_cached("INSERT INTO Transitions VALUES (?1, ?2, ?3, ?4, ?5, NULL)")?;
            for t in &self.pending {
                insert.execute(params![
                    t.timestamp,
                    self.session_id,
                    t.uid,
                    t.duration,
                    t.state
                ])?;
            }
        }
        tx.commit()
    }
}

impl Drop for Db {
    fn drop(&mut self) {
        self.write_pending();
        // As BehaviorTree.CPP does on closing; a failure here only loses an optimization.
        let _ = self.conn.execute_batch("PRAGMA optimize;");
    }
}

impl Observer for SqliteLogger {
    fn on_status_change(&mut self, change: StatusChange) {
        let mut db = lock(&self.state);
        let i = change.node.index();
        if i >= db.running_since.len() {
            return;
        }
        let since_start =
            i64::try_from(micros(change.at.saturating_sub(db.origin))).unwrap_or(i64::MAX);
        let now = db
            .start_us
            .saturating_add(since_start)
            .max(db.last_us.saturating_add(1));
        db.last_us = now;
        let mut duration = 0;
        match (change.from, change.to) {
            (NodeStatus::Idle, NodeStatus::Running) => db.running_since[i] = Some(now),
            (NodeStatus::Running, to) if to != NodeStatus::Running => {
                duration = db.running_since[i].map_or(0, |since| now - since);
            }
            _ => {}
        }
        db.pending.push(Transition {
            timestamp: now,
            uid: i64::from(change.node.0) + 1,
            duration,
            state: i64::from(status_code(change.to)),
        });
    }

    fn on_tick_end(&mut self, _status: NodeStatus, now: Duration) {
        let mut db = lock(&self.state);
        if db.pending.len() >= db.max_changes
            || now.saturating_sub(db.last_write) >= db.max_interval
        {
            db.write_pending();
            db.last_write = now;
        }
    }
}
