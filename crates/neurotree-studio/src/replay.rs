//! Recorded runs as the page scrubs them (PROTOCOL.md, "Replay"): NeuroTree's `--jsonl`
//! trace, BehaviorTree.CPP's `.btlog` and its SQLite log, each read by the library's own
//! readers or formats and turned into steps of status changes.

use std::collections::HashMap;

use neurotree_core::Blueprint;
use neurotree_toolkit::observe::read_btlog;
use serde::Serialize;

use crate::view::{status_name, status_of_byte, TreeView};

/// The most status changes a replay holds: a log is a file the page chose.
pub const MAX_CHANGES: usize = 5_000_000;

/// A recorded run.
#[derive(Clone, Debug, Serialize)]
pub struct Replay {
    /// `jsonl`, `btlog` or `sqlite`.
    pub source: &'static str,
    /// The tree the run ticked.
    pub tree: TreeView,
    /// Its steps, in order.
    pub steps: Vec<Step>,
}

/// A tick of a trace, or the changes of one timestamp of a log.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Step {
    /// The tick, numbered as `run` and the trace number it; `None` for a log that does not
    /// record ticks (`.btlog`, SQLite): a tick that changed nothing leaves no record there,
    /// so counting its steps would not give the run's tick.
    pub tick: Option<u64>,
    /// Microseconds of the run's clock.
    pub time_us: u64,
    /// Node id and new status, in order.
    pub changes: Vec<(u32, &'static str)>,
}

/// Why a log could not be replayed.
#[derive(thiserror::Error)]
#[non_exhaustive]
pub enum ReplayError {
    /// The log is not in the format its name says.
    #[error("{0}")]
    Format(String),
    /// A trace's events name nodes the tree file does not have.
    #[error("the trace does not match the tree: {0}")]
    Mismatch(String),
}

neurotree_core::debug_shows_message!(
    enum ReplayError {
        Format(source),
        Mismatch(source),
    }
);

/// The run a `--jsonl` trace recorded, on `blueprint` (the tree it was run from).
pub fn from_jsonl<C>(
    text: &str,
    blueprint: &Blueprint<C>,
    root: &str,
) -> Result<Replay, ReplayError> {
    let tree = TreeView::of_blueprint(blueprint, root);
    let mut steps: Vec<Step> = Vec::new();
    let mut total = 0usize;
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let v: serde_json::Value = serde_json::from_str(line).map_err(|e| {
            ReplayError::Format(format!("line {}: not a JSON trace line: {e}", n + 1))
        })?;
        let (Some(tick), Some(id), Some(to)) = (
            v.get("tick").and_then(|t| t.as_u64()),
            v.get("id").and_then(|t| t.as_u64()),
            v.get("to").and_then(|t| t.as_str()),
        ) else {
            // Tick lines and the summary carry no change.
            continue;
        };
        let node = tree.nodes.get(id as usize).ok_or_else(|| {
            ReplayError::Mismatch(format!("line {}: node {id} is not in the tree", n + 1))
        })?;
        if let Some(path) = v.get("node").and_then(|p| p.as_str()) {
            if path != node.path {
                return Err(ReplayError::Mismatch(format!(
                    "line {}: node {id} is `{path}` in the trace and `{}` in the tree",
                    n + 1,
                    node.path
                )));
            }
        }
        let status = status_from_name(to)
            .ok_or_else(|| ReplayError::Format(format!("line {}: unknown status `{to}`", n + 1)))?;
        let time_us = v.get("time_us").and_then(|t| t.as_u64()).unwrap_or(0);
        if steps.last().is_none_or(|s| s.tick != Some(tick)) {
            steps.push(Step {
                tick: Some(tick),
                time_us,
                changes: Vec::new(),
            });
        }
        total += 1;
        if total > MAX_CHANGES {
            return Err(ReplayError::Format(format!(
                "the trace has more than {MAX_CHANGES} changes"
            )));
        }
        if let Some(step) = steps.last_mut() {
            step.changes.push((id as u32, status));
        }
    }
    Ok(Replay {
        source: "jsonl",
        tree,
        steps,
    })
}

/// The run a `.btlog` recorded.
pub fn from_btlog(bytes: &[u8]) -> Result<Replay, ReplayError> {
    let log = read_btlog(bytes).map_err(|e| ReplayError::Format(e.to_string()))?;
    let records = log
        .records
        .iter()
        .map(|r| (r.offset_us, r.uid, r.status as u8));
    from_log("btlog", &log.xml, records)
}

/// The newest session of a SQLite log written with BehaviorTree.CPP's schema.
#[cfg(feature = "sqlite")]
pub fn from_sqlite(path: &std::path::Path) -> Result<Replay, ReplayError> {
    use rusqlite::{Connection, OpenFlags};
    let format = |e: rusqlite::Error| ReplayError::Format(format!("SQLite log: {e}"));
    let db = Connection::open_with_flags(path, OpenFlags::SQLITE_OPEN_READ_ONLY).map_err(format)?;
    let (session, xml): (i64, String) = db
        .query_row(
            "SELECT session_id, xml_tree FROM Definitions ORDER BY session_id DESC LIMIT 1",
            [],
            |r| Ok((r.get(0)?, r.get(1)?)),
        )
        .map_err(format)?;
    let mut stmt = db
        .prepare(
            "SELECT timestamp, uid, state FROM Transitions WHERE session_id = ?1 \
             ORDER BY timestamp LIMIT ?2",
        )
        .map_err(format)?;
    let rows = stmt
        .query_map((session, MAX_CHANGES as i64 + 1), |r| {
            Ok((
                r.get::<_, i64>(0)?,
                r.get::<_, i64>(1)?,
                r.get::<_, i64>(2)?,
            ))
        })
        .map_err(format)?;
    let mut records = Vec::new();
    let mut first = None;
    for row in rows {
        let (t, uid, state) = row.map_err(format)?;
        let start = *first.get_or_insert(t);
        records.push((
            t.saturating_sub(start).max(0) as u64,
            u16::try_from(uid).unwrap_or(0),
            u8::try_from(state).unwrap_or(0),
        ));
    }
    from_log("sqlite", &xml, records.into_iter())
}

/// Steps from a log's tree XML and its `(microseconds, uid, status code)` records: one
/// step per timestamp.
fn from_log(
    source: &'static str,
    xml: &str,
    records: impl Iterator<Item = (u64, u16, u8)>,
) -> Result<Replay, ReplayError> {
    let (tree, uids) = TreeView::of_log_xml(xml).map_err(ReplayError::Format)?;
    let by_uid: HashMap<u16, u32> = uids
        .iter()
        .enumerate()
        .filter(|(_, uid)| **uid != 0)
        .map(|(i, uid)| (*uid, i as u32))
        .collect();
    let mut steps: Vec<Step> = Vec::new();
    for (n, (time_us, uid, code)) in records.enumerate() {
        if n >= MAX_CHANGES {
            return Err(ReplayError::Format(format!(
                "the log has more than {MAX_CHANGES} changes"
            )));
        }
        let Some(&id) = by_uid.get(&uid) else {
            return Err(ReplayError::Mismatch(format!(
                "a record names node uid {uid}, which the log's tree does not have"
            )));
        };
        if steps.last().is_none_or(|s| s.time_us != time_us) {
            steps.push(Step {
                tick: None,
                time_us,
                changes: Vec::new(),
            });
        }
        if let Some(step) = steps.last_mut() {
            step.changes.push((id, status_name(status_of_byte(code))));
        }
    }
    Ok(Replay {
        source,
        tree,
        steps,
    })
}

fn status_from_name(name: &str) -> Option<&'static str> {
    ["IDLE", "RUNNING", "SUCCESS", "FAILURE", "SKIPPED"]
        .into_iter()
        .find(|s| *s == name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_toolkit::observe::{BtlogWriter, JsonlTrace};
    use neurotree_toolkit::{ManualClock, Registry, Status, Tree, XmlLoader};
    use std::sync::Arc;
    use std::time::Duration;

    const XML: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence name="s">
      <Delay delay_msec="150"><AlwaysSuccess name="a"/></Delay>
      <AlwaysFailure name="f"/>
    </Sequence>
  </BehaviorTree>
</root>"#;

    fn blueprint() -> Arc<Blueprint<()>> {
        let registry = Registry::<()>::new();
        let mut loader = XmlLoader::new(&registry);
        loader.load_str(XML, "t.xml").unwrap();
        Arc::new(loader.build_main().unwrap())
    }

    fn run<O: neurotree_core::Observer + 'static>(make: impl FnOnce(&Tree<()>) -> O) -> Status {
        let clock = ManualClock::new();
        let mut tree = Tree::with_clock(blueprint(), clock.clone());
        let observer = make(&tree);
        tree.set_observer(observer);
        let mut status = Status::Running;
        while status == Status::Running {
            clock.advance(Duration::from_millis(100));
            status = tree.tick_once(&mut ()).unwrap();
        }
        status
    }

    #[test]
    fn a_jsonl_trace_replays_tick_by_tick() {
        let bp = blueprint();
        let trace = JsonlTrace::new(&bp, Vec::new());
        assert_eq!(run(|_| trace.clone()), Status::Failure);
        let text = trace.with_writer(|w| String::from_utf8(w.clone()).unwrap());
        let replay = from_jsonl(&text, &bp, "Main").unwrap();
        // Tick 1: the Delay waits; tick 2: it runs its child, and the Sequence fails.
        assert_eq!(replay.steps.len(), 2);
        assert_eq!(replay.steps[0].tick, Some(1));
        assert_eq!(replay.steps[0].changes, [(0, "RUNNING"), (1, "RUNNING")]);
        let last = &replay.steps[1].changes;
        assert!(last.contains(&(3, "FAILURE")), "{last:?}");
        assert_eq!(last.last(), Some(&(0, "IDLE")));
    }

    #[test]
    fn a_trace_of_another_tree_is_refused() {
        let bp = blueprint();
        let line =
            r#"{"tick":1,"time_us":0,"id":1,"node":"s/elsewhere","from":"IDLE","to":"RUNNING"}"#;
        assert!(matches!(
            from_jsonl(line, &bp, "Main"),
            Err(ReplayError::Mismatch(_))
        ));
        assert!(matches!(
            from_jsonl("not json", &bp, "Main"),
            Err(ReplayError::Format(_))
        ));
    }

    #[test]
    fn a_btlog_replays_by_timestamp() {
        let registry = Registry::<()>::new();
        let mut log = None;
        let status = run(|tree| {
            let writer = BtlogWriter::new(Vec::new(), tree, &registry).unwrap();
            log = Some(writer.clone());
            writer
        });
        assert_eq!(status, Status::Failure);
        let bytes = log.unwrap().with_writer(|w| w.clone());
        let replay = from_btlog(&bytes).unwrap();
        assert_eq!(replay.source, "btlog");
        let paths: Vec<&str> = replay.tree.nodes.iter().map(|n| n.path.as_str()).collect();
        assert_eq!(paths, ["s", "s/Delay", "s/Delay/a", "s/f"]);
        assert_eq!(replay.steps.len(), 2);
        assert_eq!(replay.steps[0].changes, [(0, "RUNNING"), (1, "RUNNING")]);
        assert!(replay.steps[1].changes.contains(&(3, "FAILURE")));
        assert!(from_btlog(b"not a log").is_err());
    }

    #[test]
    fn a_trace_numbers_ticks_as_run_does_and_a_btlog_of_the_same_run_numbers_none() {
        // The Delay waits through tick 2, which changes nothing: the trace's second step
        // is tick 3, at 0.3 s, and the btlog's second record is at the same time.
        let registry = Registry::<()>::new();
        let bp = blueprint();
        let trace = JsonlTrace::new(&bp, Vec::new());
        let mut log = None;
        let status = run(|tree| {
            let writer = BtlogWriter::new(Vec::new(), tree, &registry).unwrap();
            log = Some(writer.clone());
            (trace.clone(), writer)
        });
        assert_eq!(status, Status::Failure);
        let text = trace.with_writer(|w| String::from_utf8(w.clone()).unwrap());
        let from_trace = from_jsonl(&text, &bp, "Main").unwrap();
        let ticks: Vec<Option<u64>> = from_trace.steps.iter().map(|s| s.tick).collect();
        assert_eq!(ticks, [Some(1), Some(3)]);
        assert!(
            text.contains(r#"{"tick":3,"time_us":300000,"status":"FAILURE"}"#),
            "{text}"
        );
        let bytes = log.unwrap().with_writer(|w| w.clone());
        let from_log = from_btlog(&bytes).unwrap();
        let ticks: Vec<Option<u64>> = from_log.steps.iter().map(|s| s.tick).collect();
        assert_eq!(ticks, [None, None]);
        let times: Vec<u64> = from_log.steps.iter().map(|s| s.time_us).collect();
        let trace_times: Vec<u64> = from_trace.steps.iter().map(|s| s.time_us).collect();
        assert_eq!(times, trace_times);
    }

    #[cfg(feature = "sqlite")]
    #[test]
    fn a_sqlite_log_replays_its_newest_session() {
        use neurotree_toolkit::observe::SqliteLogger;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("run.db3");
        let registry = Registry::<()>::new();
        let mut log = None;
        let status = run(|tree| {
            let logger = SqliteLogger::open(&path, tree, &registry, false).unwrap();
            log = Some(logger.clone());
            logger
        });
        assert_eq!(status, Status::Failure);
        log.unwrap().flush().unwrap();
        let replay = from_sqlite(&path).unwrap();
        assert_eq!(replay.source, "sqlite");
        assert_eq!(replay.tree.nodes.len(), 4);
        let changes: Vec<(u32, &str)> = replay
            .steps
            .iter()
            .flat_map(|s| s.changes.iter().copied())
            .collect();
        assert_eq!(&changes[..2], &[(0, "RUNNING"), (1, "RUNNING")]);
        assert!(changes.contains(&(3, "FAILURE")));
        assert!(from_sqlite(&dir.path().join("missing.db3")).is_err());
    }
}
