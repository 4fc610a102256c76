//! Saving a run's state and reloading its files under it (see [`crate::live`]).

use super::*;

/// Writes the run's state after tick `ticks` to `path`.
pub(super) fn save_run(
    tree: &Tree<()>,
    ticks: u32,
    status: &str,
    record: &Mutex<Record>,
    path: &std::path::Path,
) -> Result<(), String> {
    let r = record.lock().unwrap_or_else(|e| e.into_inner());
    SavedRun::new(tree, ticks, status, (&r.ticks, &r.halts))?.write(path)
}

/// Loads the files again and swaps the new tree in under the running one; prints the
/// reload's line, or the files' errors (the running tree then goes on). The per-node
/// counts follow their nodes by path.
pub(super) fn reload(
    tree: &mut Tree<()>,
    files: &[PathBuf],
    opts: &RunArgs,
    record: &Mutex<Record>,
    wrap: Option<&SharedHookWrapper<()>>,
    out: &mut impl Write,
    err: &mut impl Write,
) -> io::Result<Option<Arc<Blueprint<()>>>> {
    let mut warnings = Vec::new();
    let loaded = load(files, opts, &mut warnings, wrap);
    for w in &warnings {
        writeln!(err, "{w}")?;
    }
    let blueprint = match loaded {
        Ok((bp, _, _)) => Arc::new(bp),
        Err(e) => {
            writeln!(err, "{e}\nthe running tree goes on")?;
            return Ok(None);
        }
    };
    let report = match tree.reload(Arc::clone(&blueprint), &mut ()) {
        Ok(report) => report,
        Err(e) => {
            writeln!(err, "neurotree: the reload waits: {e}")?;
            return Ok(None);
        }
    };
    let mut r = record.lock().unwrap_or_else(|e| e.into_inner());
    let paths = blueprint.paths();
    let mut old: BTreeMap<(&str, usize), usize> = BTreeMap::new();
    let mut seen: BTreeMap<&str, usize> = BTreeMap::new();
    for (i, p) in r.paths.iter().enumerate() {
        let k = seen.entry(p).or_default();
        old.insert((p, *k), i);
        *k += 1;
    }
    seen.clear();
    let (mut ticks, mut halts) = (vec![0; paths.len()], vec![0; paths.len()]);
    for (i, p) in paths.iter().enumerate() {
        let k = seen.entry(p).or_default();
        if let Some(&o) = old.get(&(p.as_str(), *k)) {
            ticks[i] = r.ticks[o];
            halts[i] = r.halts[o];
        }
        *k += 1;
    }
    drop(old);
    r.ticks = ticks;
    r.halts = halts;
    r.paths = paths;
    let line = json!({ "reload": {
        "kept": report.kept,
        "restarted": report.restarted,
        "halted": report.halted,
    }});
    writeln!(out, "{line}")?;
    Ok(Some(blueprint))
}
