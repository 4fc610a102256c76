//! What a run reports besides its tick lines: why it failed, and the loggers that watch it.

use super::*;

pub use neurotree_cli::failure::failure_json;

/// The loggers that watch a run (`neurotree run --log --jsonl FILE ...`).
#[derive(clap::Args, Debug, Default)]
pub struct ObserveArgs {
    /// Print every status change on stderr (`[time] path FROM -> TO`, coloured on a
    /// terminal).
    #[arg(long)]
    pub log: bool,
    /// Write every status change and tick as a JSON line to FILE.
    #[arg(long, value_name = "FILE")]
    pub jsonl: Option<PathBuf>,
    /// Print per-node statistics (ticks, successes, failures, skips, halts, time Running)
    /// on stderr at the end.
    #[arg(long)]
    pub stats: bool,
    /// Write a BehaviorTree.CPP `.btlog` to FILE, for Groot2 to replay.
    #[arg(long, value_name = "FILE")]
    pub btlog: Option<PathBuf>,
    /// Log into the SQLite database FILE with BehaviorTree.CPP's schema, replacing the runs
    /// it held. Rows are committed every 1,024 status changes or 1 s of the run's clock, so
    /// a run that is killed keeps all but its last batch.
    // A build without it refuses the flag with what to do, and does not offer it in `--help`.
    #[arg(long, value_name = "FILE", hide = cfg!(not(feature = "sqlite")))]
    pub sqlite: Option<PathBuf>,
    /// Print on stderr at the end which outcomes each node was seen with, against those it
    /// could have, and the nodes never reached.
    #[arg(long)]
    pub coverage: bool,
    /// Write the coverage as JSON to FILE, for `neurotree show --coverage FILE`.
    #[arg(long, value_name = "FILE")]
    pub coverage_json: Option<PathBuf>,
}

impl ObserveArgs {
    /// `true` if any logger is asked for.
    pub(super) fn any(&self) -> bool {
        self.log
            || self.jsonl.is_some()
            || self.stats
            || self.btlog.is_some()
            || self.sqlite.is_some()
            || self.coverage
            || self.coverage_json.is_some()
    }
}

/// The handles of the loggers that write somewhere, to flush and report at the end.
#[derive(Default)]
pub(super) struct Outputs {
    jsonl: Option<(PathBuf, JsonlTrace<BufWriter<File>>)>,
    btlog: Option<(PathBuf, BtlogWriter<BufWriter<File>>)>,
    #[cfg(feature = "sqlite")]
    sqlite: Option<(PathBuf, neurotree::observe::SqliteLogger)>,
    stats: Option<Statistics>,
    coverage: Option<Coverage>,
    /// Print the coverage table (`--coverage`).
    coverage_table: bool,
    coverage_json: Option<PathBuf>,
}

/// Makes the loggers `args` asks for: the observers to attach, and their handles.
pub(super) fn observers(
    args: &ObserveArgs,
    tree: &Tree<()>,
    registry: &Registry<()>,
) -> Result<(Vec<Box<dyn Observer>>, Outputs), String> {
    let bp = tree.blueprint();
    let mut attached: Vec<Box<dyn Observer>> = Vec::new();
    let mut outputs = Outputs::default();
    if args.log {
        attached.push(Box::new(ConsoleLogger::stderr(bp)));
    }
    if let Some(path) = &args.jsonl {
        let file = File::create(path).map_err(|e| format!("--jsonl {}: {e}", path.display()))?;
        let trace = JsonlTrace::new(bp, BufWriter::new(file));
        attached.push(Box::new(trace.clone()));
        outputs.jsonl = Some((path.clone(), trace));
    }
    if let Some(path) = &args.btlog {
        let log = BtlogWriter::create(path, tree, registry)
            .map_err(|e| format!("--btlog {}: {e}", path.display()))?;
        attached.push(Box::new(log.clone()));
        outputs.btlog = Some((path.clone(), log));
    }
    #[cfg(feature = "sqlite")]
    if let Some(path) = &args.sqlite {
        let log = neurotree::observe::SqliteLogger::open(path, tree, registry, false)
            .map_err(|e| format!("--sqlite {}: {e}", path.display()))?;
        attached.push(Box::new(log.clone()));
        outputs.sqlite = Some((path.clone(), log));
    }
    #[cfg(not(feature = "sqlite"))]
    if args.sqlite.is_some() {
        return Err("this build has no SQLite logger; build it with `--features sqlite`".into());
    }
    if args.stats {
        let stats = Statistics::new(bp);
        attached.push(Box::new(stats.clone()));
        outputs.stats = Some(stats);
    }
    if args.coverage || args.coverage_json.is_some() {
        let coverage = Coverage::with_registry(bp, registry);
        attached.push(Box::new(coverage.clone()));
        outputs.coverage = Some(coverage);
        outputs.coverage_table = args.coverage;
        outputs.coverage_json.clone_from(&args.coverage_json);
    }
    Ok((attached, outputs))
}

impl Outputs {
    /// Flushes the files and prints the statistics and the coverage; `Ok(false)` if a file
    /// could not be written (the error is on `err`).
    pub(super) fn finish(self, bp: &Blueprint<()>, err: &mut impl Write) -> io::Result<bool> {
        let mut failures = Vec::new();
        if let Some((path, trace)) = &self.jsonl {
            if let Err(e) = trace.flush() {
                failures.push(format!("--jsonl {}: {e}", path.display()));
            }
        }
        if let Some((path, log)) = &self.btlog {
            if let Err(e) = log.flush() {
                failures.push(format!("--btlog {}: {e}", path.display()));
            }
        }
        #[cfg(feature = "sqlite")]
        if let Some((path, log)) = &self.sqlite {
            if let Err(e) = log.flush() {
                failures.push(format!("--sqlite {}: {e}", path.display()));
            }
        }
        if let Some(stats) = &self.stats {
            write!(err, "{stats}")?;
        }
        if let Some(coverage) = &self.coverage {
            let report = coverage.report(bp);
            if let Some(path) = &self.coverage_json {
                let text = format!("{}\n", coverage_json(&report));
                if let Err(e) = std::fs::write(path, text) {
                    failures.push(format!("--coverage-json {}: {e}", path.display()));
                }
            }
            if self.coverage_table {
                write!(err, "{report}")?;
            }
        }
        for failure in &failures {
            writeln!(err, "neurotree: {failure}")?;
        }
        Ok(failures.is_empty())
    }
}

/// The coverage as `neurotree run --coverage-json` writes it: the totals, then one entry
/// per node in pre-order (the order of the tree's node ids) with its path, type, whether
/// it was reached, and the outcomes seen, possible and not seen, as lower-case words.
///
/// ```json
/// {"covered":15,"possible":22,"nodes":[{"path":"root","type":"Fallback","reached":true,
///  "seen":["success","running"],"possible":["success","failure","running","halted"],
///  "not_seen":["failure","halted"]}, ...]}
/// ```
pub fn coverage_json(report: &CoverageReport) -> Value {
    let words = |set: neurotree::observe::OutcomeSet| -> Vec<&str> {
        set.iter().map(|o| o.as_str()).collect()
    };
    let nodes: Vec<Value> = report
        .nodes()
        .iter()
        .map(|n| {
            json!({
                "path": n.path,
                "type": n.type_name,
                "reached": n.reached,
                "seen": words(n.seen),
                "possible": words(n.possible),
                "not_seen": words(n.missing()),
            })
        })
        .collect();
    json!({
        "covered": report.covered_outcomes(),
        "possible": report.possible_outcomes(),
        "nodes": nodes,
    })
}
