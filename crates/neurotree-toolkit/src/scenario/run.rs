//! A scenario's run: its files loaded on a copy of the bench's registry, then ticked as
//! `neurotree run` ticks, with its values written before their ticks and its expectations
//! checked after each.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

use neurotree_core::{Blueprint, ManualClock, Status, TickError, Tree};

use super::check::Checker;
use super::{write_text, Scenario, ScenarioBench, DEFAULT_TICKS, MAX_STEP_MS};
use crate::fault::{self, FaultLog, NodeFault};
use crate::xml::{self, parse_outcomes, Substitutions};
use crate::{LoadError, LoadErrorKind, Registry, XmlLoader};

/// The most load errors a scenario reports, as `neurotree check` lists them.
const ERROR_LIMIT: usize = 20;

/// Runs `s` (read from `file`) on `bench`; the problems found.
pub(super) fn run<C: 'static>(
    bench: &mut ScenarioBench<'_, C>,
    s: &Scenario,
    file: &Path,
) -> Vec<String> {
    let shown = file.display();
    if let Err(e) = check_numbers(s) {
        return vec![format!("{shown}: {e}")];
    }
    let dir = file.parent().unwrap_or(Path::new(""));
    let (blueprint, registry) = match load(bench, s, dir) {
        Ok((blueprint, registry)) => (Arc::new(blueprint), registry),
        Err(e) => return vec![format!("the tree did not load:\n{}", e.trim_end())],
    };
    let mut ctx = (bench.context)(&blueprint);
    let mut checker = Checker::new(s);
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(Arc::clone(&blueprint), clock.clone());
    crate::runtime::attach(&mut tree);
    tree.set_observer(checker.attach(&tree, &registry));
    let limit = s.ticks.unwrap_or(DEFAULT_TICKS);
    let step = Duration::from_millis(s.step_ms.unwrap_or(100));
    let mut ticks: u32 = 0;
    while ticks < limit {
        // The values of the ticks after the last one run up to the coming one: a tick of
        // several passes may have gone past some.
        for set in &s.set {
            if set.tick > ticks && set.tick <= ticks + 1 {
                // Checked by `check_numbers`.
                if let Ok(text) = value_text(&set.value) {
                    write_text(tree.blackboard_mut(), &set.key, &text);
                }
            }
        }
        let left = limit - ticks;
        tree.set_max_passes(left);
        clock.advance(step);
        let result = tree.tick_once(&mut ctx);
        // A pass that failed with an error is not in `last_passes`, but it was made.
        ticks = ticks.saturating_add(tree.last_passes().max(1)).min(limit);
        // Out of passes because the ticks ran out: stopped, as a run still RUNNING is.
        let stopped =
            matches!(&result, Err(TickError::TooManyPasses { passes, .. }) if *passes >= left);
        let status = match &result {
            _ if stopped => "RUNNING",
            Ok(s) => s.as_str(),
            Err(TickError::RootSkipped) => "SKIPPED",
            Err(_) => "ERROR",
        };
        let error = match &result {
            Err(e) if !stopped && !matches!(e, TickError::RootSkipped) => Some(e.to_string()),
            _ => None,
        };
        checker.after_tick(ticks, status, error.as_deref(), &tree);
        if matches!(result, Ok(Status::Success | Status::Failure) | Err(_)) {
            break;
        }
    }
    checker.finish(s)
}

/// Refuses the numbers a run cannot go by.
fn check_numbers(s: &Scenario) -> Result<(), String> {
    if let Some(c) = s.coverage
        && !(0.0..=1.0).contains(&c)
    {
        return Err(format!(
            "coverage = {c}: the share of outcomes covered is from 0 to 1"
        ));
    }
    if let Some(step) = s.step_ms.filter(|&step| step > MAX_STEP_MS) {
        return Err(format!(
            "step_ms = {step}: at most a day ({MAX_STEP_MS}), so that the clock cannot run out"
        ));
    }
    for set in &s.set {
        if set.tick == 0 {
            return Err(format!(
                "[[set]] {}: tick 0: ticks are counted from 1",
                set.key
            ));
        }
        value_text(&set.value).map_err(|e| format!("[[set]] {}: {e}", set.key))?;
    }
    Ok(())
}

/// The text [`write_text`] reads for a TOML value.
fn value_text(value: &toml::Value) -> Result<String, String> {
    match value {
        toml::Value::String(s) => Ok(s.clone()),
        toml::Value::Integer(i) => Ok(i.to_string()),
        toml::Value::Float(f) => Ok(f.to_string()),
        toml::Value::Boolean(b) => Ok(b.to_string()),
        other => Err(format!(
            "a {} cannot be written to the blackboard; use a string, number or boolean",
            other.type_str()
        )),
    }
}

/// The blueprint of the scenario's tree; the error lists the loader's warnings, the
/// errors and what to do, one a line.
fn load<C: 'static>(
    bench: &ScenarioBench<'_, C>,
    s: &Scenario,
    dir: &Path,
) -> Result<(Blueprint<C>, Registry<C>), String> {
    let files: Vec<PathBuf> = std::iter::once(&s.tree)
        .chain(&s.files)
        .map(|f| dir.join(f))
        .collect();
    let registry = registry_for(bench.registry, s, &files)?;
    let mut loader = XmlLoader::new(&registry).mock_unknown(s.mock_unknown);
    if let Some(advice) = &bench.unknown_type_advice {
        loader = loader.unknown_type_advice(advice.clone());
    }
    for (name, outcomes) in &s.mocks {
        let parsed = parse_outcomes(outcomes)
            .map_err(|e| format!("[mocks] {name} = \"{outcomes}\": {e}"))?;
        loader = loader.mock(name, parsed);
    }
    if let Some(rules) = &s.substitute {
        let rules = Substitutions::read(dir.join(rules)).map_err(|e| e.to_string())?;
        loader = loader.substitute(rules);
    }
    let built = files
        .iter()
        .try_for_each(|file| loader.load_file(file))
        .map_err(|e| vec![e])
        .and_then(|()| pick_tree(&loader, s.main.as_deref()).map_err(|e| vec![e]))
        .and_then(|id| {
            loader.build(&id).map_err(|first_error| {
                // Every error of the tree, as `check` lists them: the builder stops at the
                // first.
                let mut errors = vec![first_error];
                for e in loader.validate_all(&id, ERROR_LIMIT) {
                    if errors.len() < ERROR_LIMIT && !errors.contains(&e) {
                        errors.push(e);
                    }
                }
                errors
            })
        });
    let built = built.map_err(|errors| {
        let warnings = loader.warnings().iter().map(|w| w.to_string());
        failure_text(warnings, &errors, &files[0], s.mock_unknown)
    })?;
    if s.faults.is_empty() {
        drop(loader);
        return Ok((built, registry));
    }
    // Built once as written, to find the nodes the faults name, then with their hooks.
    let faults = s
        .faults
        .iter()
        .map(|f| f.parse::<NodeFault>().map_err(|e| format!("faults: {e}")))
        .collect::<Result<Vec<_>, _>>()?;
    let resolved = fault::resolve(&built, &faults).map_err(|e| format!("faults: {e}"))?;
    drop(built);
    let loader = loader.wrap_hooks(fault::wrapper(resolved, FaultLog::default()));
    let id = pick_tree(&loader, s.main.as_deref()).map_err(|e| e.to_string())?;
    let built = loader.build(&id).map_err(|e| e.to_string());
    drop(loader);
    built.map(|blueprint| (blueprint, registry))
}

/// A copy of `registry` with the node types the `TreeNodesModel`s of `files` declare and
/// the scenario's enums.
fn registry_for<C: 'static>(
    registry: &Registry<C>,
    s: &Scenario,
    files: &[PathBuf],
) -> Result<Registry<C>, String> {
    let mut registry = registry.clone();
    for file in files {
        // A file that cannot be read is reported when it is loaded.
        if let Ok(text) = xml::read_file(file, xml::DEFAULT_MAX_FILE_BYTES) {
            registry
                .add_model_str(&text, &file.display().to_string())
                .map_err(|e| e.to_string())?;
        }
    }
    for (name, value) in &s.enums {
        registry
            .register_enum(name, *value)
            .map_err(|e| format!("[enums] {name} = {value}: {e}"))?;
    }
    Ok(registry)
}

/// Why the tree did not load: the loader's warnings, the errors (an error about the files
/// as a whole named at the first file), and what to do, one a line.
fn failure_text(
    warnings: impl Iterator<Item = String>,
    errors: &[LoadError],
    first: &Path,
    mock_unknown: bool,
) -> String {
    let mut text: Vec<String> = warnings.collect();
    for e in errors {
        let mut e = e.clone();
        if e.file.is_empty() {
            e.file = first.display().to_string();
        }
        text.push(e.to_string());
    }
    if !mock_unknown
        && errors
            .iter()
            .any(|e| e.kind() == LoadErrorKind::UnknownNode)
    {
        text.push(
            "hint: mock the leaves without an implementation with `mock_unknown = true`, or \
             one in [mocks]"
                .to_string(),
        );
    }
    text.join("\n")
}

/// The tree to run: `main`, else the main tree of the files, else the one tree that no
/// other tree uses.
fn pick_tree<C: 'static>(
    loader: &XmlLoader<'_, C>,
    main: Option<&str>,
) -> Result<String, LoadError> {
    let ids: Vec<&str> = loader.tree_ids().collect();
    if let Some(id) = main {
        if ids.contains(&id) {
            return Ok(id.to_string());
        }
        return Err(LoadError::at_file(
            LoadErrorKind::UnknownTree,
            "",
            format!(
                "main = \"{id}\": no tree with that ID is loaded; the trees are: {}",
                ids.join(", ")
            ),
        ));
    }
    if let Some(main) = loader.main_tree() {
        return Ok(main.to_string());
    }
    if ids.is_empty() {
        return Err(LoadError::at_file(
            LoadErrorKind::NoMainTree,
            "",
            "no <BehaviorTree> is loaded; there is nothing to run",
        ));
    }
    match loader.unreferenced_trees()[..] {
        [only] => Ok(only.to_string()),
        _ => Err(LoadError::at_file(
            LoadErrorKind::AmbiguousMainTree,
            "",
            format!(
                "no main_tree_to_execute, and several trees could be the main one: {}; \
                 name one with `main = \"ID\"`",
                ids.join(", ")
            ),
        )),
    }
}
