//! `neurotree check`: validate BehaviorTree.CPP files without running them.
//!
//! Node types come from the built-ins and Nav2's control nodes, from the `TreeNodesModel`
//! of every `--model` file and from the `TreeNodesModel` sections of the checked files
//! themselves. Each file is
//! loaded (following its includes) and every tree in it is checked: structure, node names,
//! ports and literal conversions. Errors are printed as `path:line:col: error: message`.

use std::io::{self, Write};
use std::path::PathBuf;

use neurotree::{LoadError, XmlLoader};

/// Checks `files` against the built-ins and the `models`; returns `true` if all are valid.
pub fn run(files: &[PathBuf], models: &[PathBuf], err: &mut impl Write) -> io::Result<bool> {
    let mut registry = crate::registry::with_nav2_controls::<()>();
    let mut errors = Vec::new();
    for path in models.iter().chain(files) {
        match std::fs::read_to_string(path) {
            Ok(text) => {
                if let Err(e) = registry.add_model_str(&text, &path.display().to_string()) {
                    errors.push(e);
                }
            }
            Err(e) => errors.push(LoadError {
                file: path.display().to_string(),
                line: 1,
                col: 1,
                message: format!("cannot read the file: {e}"),
            }),
        }
    }
    if errors.is_empty() {
        for file in files {
            let mut loader = XmlLoader::new(&registry);
            if let Err(e) = loader.load_file(file) {
                errors.push(e);
                continue;
            }
            let ids: Vec<String> = loader.tree_ids().map(String::from).collect();
            errors.extend(ids.iter().filter_map(|id| loader.validate(id).err()));
        }
    }
    for e in &errors {
        writeln!(err, "{e}")?;
    }
    Ok(errors.is_empty())
}
