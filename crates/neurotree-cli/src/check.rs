//! `neurotree check`: validate BehaviorTree.CPP files without running them.
//!
//! Node types come from the built-ins and Nav2's control nodes, from the `TreeNodesModel`
//! of every `--model` file and from the `TreeNodesModel` sections of the checked files
//! themselves. Each file is loaded on its own (following its includes), with the files
//! given after or before it that define trees it uses but does not have (as `run a.xml
//! b.xml` would load them), and every tree of it is checked: structure, node names, ports
//! and literal conversions.
//!
//! Every error found is reported, up to [`LIMIT`] per file, as
//! `path:line:col: error: message` on stderr; a valid file gets `path: ok (N trees)` on
//! stdout. A subtree's error is reported once, though each tree that uses it meets it.

use std::collections::BTreeSet;
use std::io::{self, Write};
use std::path::PathBuf;

use neurotree::{LoadError, LoadErrorKind, LoadWarning, Registry, XmlLoader};

use crate::files::{self, LoadLimits};
use crate::Outcome;

/// The most errors reported for one file: past that, the rest are mostly consequences.
pub const LIMIT: usize = neurotree::xml::MAX_ERRORS;

/// What `neurotree check` was asked to do.
#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    /// The files to check, each with the trees it uses from the others; every error is
    /// reported (up to 20 per file), and each valid file gets `FILE: ok (N trees)` on stdout.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// A file whose `TreeNodesModel` declares node types the files use (repeatable).
    #[arg(long = "model")]
    pub models: Vec<PathBuf>,
    #[command(flatten)]
    pub nav2: crate::registry::Nav2Args,
    #[command(flatten)]
    pub limits: LoadLimits,
    /// Refuse a file in which an entry is written as one type and read through a port as
    /// another it cannot convert to (lint's NT0102 errors), as BehaviorTree.CPP refuses it
    /// when it creates the tree.
    #[arg(long)]
    pub strict_types: bool,
}

/// The registry the files are checked against: the built-ins and Nav2's controls (or a
/// release's types with `--nav2`), the `--model` files' types and the files' own
/// `TreeNodesModel`s; or the errors of the models that could not be read.
pub(crate) fn registry(
    models: &[PathBuf],
    nav2: crate::registry::Nav2Args,
    files: &[PathBuf],
) -> Result<Registry<()>, Vec<LoadError>> {
    let mut registry = crate::registry::with_nav2_controls::<()>(nav2);
    let mut refused = Vec::new();
    for path in models {
        match files::read(path) {
            Ok(text) => {
                if let Err(e) = registry.add_model_str(&text, &files::shown(path)) {
                    refused.push(e);
                }
            }
            Err(e) => refused.push(e),
        }
    }
    if let Err(e) = files::add_models(&mut registry, files) {
        refused.push(e);
    }
    if refused.is_empty() {
        Ok(registry)
    } else {
        Err(refused)
    }
}

/// Checks the files against the built-ins and the models: [`Outcome::Done`] if all are
/// valid, else [`Outcome::Refused`] (the errors are on `err`).
pub fn execute(
    args: &CheckArgs,
    out: &mut impl Write,
    err: &mut impl Write,
) -> io::Result<Outcome> {
    let files = &args.files;
    let registry = match registry(&args.models, args.nav2, files) {
        Ok(mut registry) => {
            registry.set_strict_types(args.strict_types);
            registry
        }
        Err(refused) => {
            for e in &refused {
                writeln!(err, "{e}")?;
            }
            return Ok(Outcome::Refused);
        }
    };
    let mut reported = BTreeSet::new();
    let mut valid = true;
    let mut too_many_nodes = false;
    for at in 0..files.len() {
        let shown = files::shown(&files[at]);
        let checked = check_file(&registry, files, at, args.limits.max_nodes);
        for w in &checked.warnings {
            if reported.insert(w.to_string()) {
                writeln!(err, "{w}")?;
            }
        }
        match checked.trees {
            Ok(1) => writeln!(out, "{shown}: ok (1 tree)")?,
            Ok(trees) => writeln!(out, "{shown}: ok ({trees} trees)")?,
            Err(errors) => {
                valid = false;
                for e in &errors {
                    too_many_nodes |= e.kind() == LoadErrorKind::TooManyNodes;
                    if reported.insert(e.to_string()) {
                        writeln!(err, "{e}")?;
                    }
                }
                if errors.len() >= LIMIT {
                    writeln!(
                        err,
                        "{shown}: note: only the first {LIMIT} errors are shown"
                    )?;
                }
            }
        }
    }
    if too_many_nodes {
        writeln!(err, "{}", files::MAX_NODES_HINT)?;
    }
    Ok(Outcome::from(valid))
}

/// A file checked: the loader that holds its trees (and those it uses from the other
/// files), its warnings, and how many trees it has or up to [`LIMIT`] errors, each once.
pub(crate) struct Checked<'r> {
    pub(crate) loader: XmlLoader<'r, ()>,
    pub(crate) warnings: Vec<LoadWarning>,
    pub(crate) trees: Result<usize, Vec<LoadError>>,
}

/// Checks every tree of `files[at]`.
pub(crate) fn check_file<'r>(
    registry: &'r Registry<()>,
    files: &[PathBuf],
    at: usize,
    max_nodes: usize,
) -> Checked<'r> {
    let mut loader = XmlLoader::new(registry)
        .unknown_type_advice(files::UNKNOWN_TYPE_ADVICE)
        .max_nodes(max_nodes);
    let loaded = loader.load_file(&files[at]);
    let warnings = loader.warnings().to_vec();
    let trees = match loaded {
        Err(e) => Err(vec![e]),
        Ok(()) => check_trees(registry, &mut loader, files, at),
    };
    Checked {
        loader,
        warnings,
        trees,
    }
}

/// Checks the XML `text`, named `shown` in errors, as [`check_file`] checks a file (its
/// includes are refused: a text has no folder).
pub(crate) fn check_text<'r>(
    registry: &'r Registry<()>,
    text: &str,
    shown: &str,
    max_nodes: usize,
) -> Checked<'r> {
    let mut loader = XmlLoader::new(registry)
        .unknown_type_advice(
            "declare it in a TreeNodesModel given as `model_xml`, or set `nav2` if it is one of Nav2's",
        )
        .max_nodes(max_nodes);
    loader.include_texts(Default::default());
    let loaded = loader.load_str(text, shown);
    let warnings = loader.warnings().to_vec();
    let trees = match loaded {
        Err(e) => Err(vec![e]),
        Ok(()) => check_trees(registry, &mut loader, &[], 0),
    };
    Checked {
        loader,
        warnings,
        trees,
    }
}

/// Checks the trees `loader` loaded from `files[at]`, with the other files lending the
/// subtrees they use.
fn check_trees(
    registry: &Registry<()>,
    loader: &mut XmlLoader<'_, ()>,
    files: &[PathBuf],
    at: usize,
) -> Result<usize, Vec<LoadError>> {
    let own: Vec<String> = loader.tree_ids().map(String::from).collect();
    lend(registry, loader, files, at);
    match loader.validate_trees(own.iter().map(String::as_str)) {
        Ok(()) => Ok(own.len()),
        Err(errors) => Err(errors.into_vec()),
    }
}

/// Loads into `loader` each of the other `files` that defines a tree the loaded trees use
/// but the loader does not have, as running the files together would.
fn lend(registry: &Registry<()>, loader: &mut XmlLoader<'_, ()>, files: &[PathBuf], at: usize) {
    for (other, file) in files.iter().enumerate() {
        let missing: Vec<String> = loader
            .unresolved_subtrees()
            .into_iter()
            .map(String::from)
            .collect();
        if missing.is_empty() {
            return;
        }
        if other == at {
            continue;
        }
        let mut probe = XmlLoader::new(registry);
        // A file that does not load is reported when it is checked itself.
        if probe.load_file(file).is_ok()
            && probe.tree_ids().any(|id| missing.iter().any(|m| m == id))
        {
            // Its error, if it has one (a tree ID this file also uses), is its own: the
            // trees loaded before it stay, and a tree still missing is reported where used.
            let _ = loader.load_file(file);
        }
    }
}
