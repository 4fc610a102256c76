//! The results file: SQLite, table `variants` (one row per variant, written as it
//! finishes), table `campaign` (the campaign's text and where it was, to replay a variant
//! and to resume).
//!
//! Each row is its own transaction, in SQLite's write-ahead log: a run stopped by Ctrl-C, a
//! kill or a crash keeps every row written; `variant` is the primary key, so no variant is recorded twice.

use std::collections::BTreeSet;
use std::path::Path;

use rusqlite::{params, Connection, OptionalExtension};
use serde_json::Value;

use super::{Campaign, VariantRow};

const SCHEMA: &str = "
CREATE TABLE IF NOT EXISTS campaign (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS variants (
    variant INTEGER PRIMARY KEY,
    factors TEXT NOT NULL,
    outcome TEXT NOT NULL,
    ticks INTEGER NOT NULL,
    sim_seconds REAL NOT NULL,
    distance REAL NOT NULL,
    recoveries INTEGER NOT NULL,
    failure_chain TEXT,
    nav2_error_code INTEGER,
    nodes_covered INTEGER NOT NULL
);";

/// A results file, open.
pub struct Results {
    conn: Connection,
}

fn sql(path: &Path, e: rusqlite::Error) -> String {
    format!("{}: {e}", path.display())
}

impl Results {
    /// Opens (or creates) the results file at `path`.
    pub fn open(path: &Path) -> Result<Results, String> {
        let conn = Connection::open(path).map_err(|e| sql(path, e))?;
        // Another process may be writing the file (a shard): wait for it rather than fail.
        conn.busy_timeout(std::time::Duration::from_secs(30))
            .map_err(|e| sql(path, e))?;
        // Write-ahead logging: a committed row survives the process being killed, and a
        // commit costs no sync of the whole file (only a power cut may lose the last rows).
        conn.execute_batch("PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL;")
            .map_err(|e| sql(path, e))?;
        conn.execute_batch(SCHEMA).map_err(|e| {
            format!(
                "{}: not a campaign's results file ({e}); give another --db",
                path.display()
            )
        })?;
        Ok(Results { conn })
    }

    /// The campaign's text and file the results were made with, if any yet.
    pub fn campaign(&self) -> Result<Option<(String, String)>, String> {
        let get = |key: &str| -> rusqlite::Result<Option<String>> {
            self.conn
                .query_row("SELECT value FROM campaign WHERE key = ?1", [key], |r| {
                    r.get(0)
                })
                .optional()
        };
        let text = get("text").map_err(|e| e.to_string())?;
        let file = get("file").map_err(|e| e.to_string())?;
        Ok(text.zip(file))
    }

    /// Records the campaign the rows are of; refuses rows of another campaign.
    pub fn claim(&self, campaign: &Campaign) -> Result<(), String> {
        match self.campaign()? {
            Some((text, _)) if text != campaign.text => Err(format!(
                "the results hold another campaign's variants (its text differs from {}); \
                 give another --db",
                campaign.file.display()
            )),
            Some(_) => Ok(()),
            None => {
                let file =
                    std::fs::canonicalize(&campaign.file).unwrap_or_else(|_| campaign.file.clone());
                self.conn
                    .execute(
                        "INSERT INTO campaign (key, value) VALUES ('text', ?1), ('file', ?2)",
                        params![campaign.text, file.display().to_string()],
                    )
                    .map(drop)
                    .map_err(|e| e.to_string())
            }
        }
    }

    /// The variants recorded.
    pub fn done(&self) -> Result<BTreeSet<u64>, String> {
        let mut stmt = self
            .conn
            .prepare("SELECT variant FROM variants")
            .map_err(|e| e.to_string())?;
        let rows = stmt
            .query_map([], |r| r.get::<_, i64>(0))
            .map_err(|e| e.to_string())?;
        rows.map(|r| r.map(|v| v as u64).map_err(|e| e.to_string()))
            .collect()
    }

    /// Writes one row, at once.
    pub fn insert(&self, row: &VariantRow) -> Result<(), String> {
        let json = |v: &Option<Value>| v.as_ref().map(Value::to_string);
        self.conn
            .execute(
                "INSERT INTO variants (variant, factors, outcome, ticks, sim_seconds, distance, \
                 recoveries, failure_chain, nav2_error_code, nodes_covered) \
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)",
                params![
                    row.variant as i64,
                    row.factors.to_string(),
                    row.outcome,
                    row.ticks,
                    row.seconds,
                    row.distance,
                    row.recoveries,
                    json(&row.failure_chain),
                    row.error_code,
                    row.nodes_covered,
                ],
            )
            .map(drop)
            .map_err(|e| format!("variant {}: {e}", row.variant))
    }

    /// Every row, by variant number.
    pub fn rows(&self) -> Result<Vec<VariantRow>, String> {
        let mut stmt = self
            .conn
            .prepare(
                "SELECT variant, factors, outcome, ticks, sim_seconds, distance, recoveries, \
                 failure_chain, nav2_error_code, nodes_covered FROM variants ORDER BY variant",
            )
            .map_err(|e| e.to_string())?;
        let parse = |text: String| serde_json::from_str(&text).unwrap_or(Value::String(text));
        let rows = stmt
            .query_map([], |r| {
                Ok(VariantRow {
                    variant: r.get::<_, i64>(0)? as u64,
                    factors: parse(r.get(1)?),
                    outcome: r.get(2)?,
                    ticks: r.get(3)?,
                    seconds: r.get(4)?,
                    distance: r.get(5)?,
                    recoveries: r.get(6)?,
                    failure_chain: r.get::<_, Option<String>>(7)?.map(parse),
                    error_code: r.get(8)?,
                    nodes_covered: r.get(9)?,
                })
            })
            .map_err(|e| e.to_string())?;
        rows.map(|r| r.map_err(|e| e.to_string())).collect()
    }

    /// The row of `variant`.
    pub fn row(&self, variant: u64) -> Result<Option<VariantRow>, String> {
        Ok(self.rows()?.into_iter().find(|r| r.variant == variant))
    }
}

/// Writes into `out` the rows of every file of `sources`, all of one campaign; a variant
/// in two files is an error unless both rows are the same.
pub fn merge(sources: &[&Path], out: &Path) -> Result<usize, String> {
    let target = Results::open(out)?;
    let mut written = target.done()?;
    let mut count = 0;
    for source in sources {
        let from = Results::open(source)?;
        let Some((text, file)) = from.campaign()? else {
            continue;
        };
        let campaign = Campaign {
            file: file.clone().into(),
            ..Campaign::parse(&text, Path::new(&file))
                .map_err(|e| format!("{}: {e}", source.display()))?
        };
        target
            .claim(&campaign)
            .map_err(|e| format!("{}: {e}", source.display()))?;
        for row in from.rows()? {
            if written.contains(&row.variant) {
                if target.row(row.variant)?.as_ref() != Some(&row) {
                    return Err(format!(
                        "{}: variant {} differs from the row already merged",
                        source.display(),
                        row.variant
                    ));
                }
                continue;
            }
            target.insert(&row)?;
            written.insert(row.variant);
            count += 1;
        }
    }
    Ok(count)
}
