//! The files `run` and `show` are given: loaded together, and the tree to work on picked
//! from them.
//!
//! Several files load as BehaviorTree.CPP's `registerBehaviorTreeFromFile` loads each: every
//! tree of every file goes into one loader, so a tree can use (through `<SubTree>`) a tree
//! of another file. The tree to work on is, as BehaviorTree.CPP's `createTree` picks it,
//! `--tree`, else the `main_tree_to_execute` of the first file, else the only tree loaded;
//! where that leaves several trees, the one tree that no other tree uses is the one a
//! person means (a file of a main tree and its subtrees), and the command says so.

use std::io::{self, Write};
use std::path::{Path, PathBuf};

use neurotree::{LoadError, LoadErrorKind, Registry, XmlLoader};

/// What to add after an error of kind [`LoadErrorKind::TooManyNodes`]: the flag that
/// raises the limit.
pub const MAX_NODES_HINT: &str =
    "hint: if the tree is meant to be this big, raise the limit with --max-nodes N";

/// What the command line's error for an unknown node type advises: the registry is out of
/// reach from there, and these flags are what brings a type in.
/// (`run` adds how to mock it, unless its flags already do.)
pub const UNKNOWN_TYPE_ADVICE: &str =
    "declare it in a TreeNodesModel given with --model FILE, or use --nav2 if it is one of Nav2's";

/// The bounds on what loading a file may build, shared by `run`, `check` and `show`.
#[derive(clap::Args, Debug)]
pub struct LoadLimits {
    /// The most nodes a tree may have once its subtrees are expanded (each use of a
    /// subtree is a copy); a file past it is refused at the SubTree that crosses it.
    #[arg(long, value_name = "N", default_value_t = neurotree::xml::DEFAULT_MAX_NODES)]
    pub max_nodes: usize,
}

/// The text of the tree or model file `file`: a regular file of at most
/// [`DEFAULT_MAX_FILE_BYTES`](neurotree::xml::DEFAULT_MAX_FILE_BYTES), as the loader reads
/// them (a FIFO would block, `/dev/zero` never end).
pub fn read(file: &Path) -> Result<String, LoadError> {
    neurotree::xml::read_file(file, neurotree::xml::DEFAULT_MAX_FILE_BYTES)
}

/// Declares in `registry` the node types of the `TreeNodesModel` of every one of `files`
/// that can be read (one that cannot is reported when it is loaded).
pub fn add_models<C: 'static>(
    registry: &mut Registry<C>,
    files: &[PathBuf],
) -> Result<(), LoadError> {
    for file in files {
        if let Ok(text) = read(file) {
            registry.add_model_str(&text, &file.display().to_string())?;
        }
    }
    Ok(())
}

/// Loads `files` into `loader`, in order.
pub fn load_all<C: 'static>(
    loader: &mut XmlLoader<'_, C>,
    files: &[PathBuf],
) -> Result<(), LoadError> {
    files.iter().try_for_each(|file| loader.load_file(file))
}

/// `file` as errors show it.
pub fn shown(file: &Path) -> String {
    file.display().to_string()
}

/// The tree a command works on.
pub struct Picked {
    /// Its ID.
    pub id: String,
    /// Picked for being the only tree no other tree uses, which the command says.
    pub unreferenced: bool,
}

impl Picked {
    /// Says on `note` why the tree was picked, if that is not plain; `verb` (`running`,
    /// `drawing`) says what is done with it.
    pub fn note(&self, verb: &str, note: &mut impl Write) -> io::Result<()> {
        if self.unreferenced {
            writeln!(
                note,
                "note: {verb} tree '{}' (no main_tree_to_execute; the only tree no other tree references)",
                self.id
            )?;
        }
        Ok(())
    }
}

/// The tree to work on (see the module doc). Errors are shown at the start of `first`, the
/// file whose main tree counts.
pub fn pick_tree<C: 'static>(
    loader: &XmlLoader<'_, C>,
    requested: Option<&str>,
    first: &str,
) -> Result<Picked, LoadError> {
    let picked = |id: &str, unreferenced| Picked {
        id: id.to_string(),
        unreferenced,
    };
    let ids: Vec<&str> = loader.tree_ids().collect();
    if let Some(id) = requested {
        if ids.contains(&id) {
            return Ok(picked(id, false));
        }
        return Err(LoadError::at_file(
            LoadErrorKind::UnknownTree,
            first,
            format!(
                "--tree {id}: no tree with that ID is loaded; the trees are: {}",
                ids.join(", ")
            ),
        ));
    }
    if let Some(main) = loader.main_tree() {
        return Ok(picked(main, false));
    }
    if ids.is_empty() {
        return Err(LoadError::at_file(
            LoadErrorKind::NoMainTree,
            first,
            "no <BehaviorTree> is loaded; there is nothing to work on".to_string(),
        ));
    }
    let candidates = loader.unreferenced_trees();
    if let [only] = candidates[..] {
        return Ok(picked(only, true));
    }
    // None is left when the trees use each other in a cycle: any of them could be meant.
    let candidates = if candidates.is_empty() {
        ids
    } else {
        candidates
    };
    Err(LoadError::at_file(LoadErrorKind::AmbiguousMainTree,
        first,
        format!(
            "no main_tree_to_execute, and {} trees could be the main one: {}; pick one with --tree NAME",
            candidates.len(),
            candidates.join(", ")
        ),
    ))
}
