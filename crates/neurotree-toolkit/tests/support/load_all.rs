//! The loader's fuzz target: load a text, build and validate every tree in it with mocks,
//! and check that every error points into the text.

use std::path::{Path, PathBuf};

use neurotree::{LoadError, Registry, XmlLoader};

/// The name the fuzzed text is loaded under.
pub const FILE: &str = "fuzz.xml";

/// Every `.xml` file of `corpus/`, sorted by path.
pub fn corpus_xml_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "xml") {
                out.push(path);
            }
        }
    }
    let mut files = Vec::new();
    walk(&super::corpus_dir::corpus(""), &mut files);
    files.sort();
    assert!(files.len() >= 60, "only {} corpus files found", files.len());
    files
}

/// The text of every `.xml` file of `corpus/`.
pub fn corpus_texts() -> Vec<String> {
    corpus_xml_files()
        .iter()
        .map(|f| std::fs::read_to_string(f).unwrap_or_else(|e| panic!("{}: {e}", f.display())))
        .collect()
}

/// Panics unless `e` names [`FILE`], a line of `text` and a column of that line.
pub fn assert_points_into(e: &LoadError, text: &str) {
    assert_eq!(e.file, FILE, "an error that names another file: {e}");
    let line = usize::try_from(e.line).unwrap();
    let lines: Vec<&str> = text.split('\n').collect();
    assert!(
        (1..=lines.len()).contains(&line),
        "line {line} of {}: {e}",
        lines.len()
    );
    // Columns count characters; a line has no more characters than bytes.
    let col = usize::try_from(e.col).unwrap();
    let width = lines[line - 1].len();
    assert!(
        (1..=width + 1).contains(&col),
        "column {col} of a line of {width} bytes: {e}"
    );
}

/// Loads `text` with every unknown leaf mocked and builds and validates every tree in it;
/// then reads it as a `TreeNodesModel`. Every error must point into `text`.
pub fn load_everything(text: &str) {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry).mock_unknown(true);
    match loader.load_str(text, FILE) {
        Ok(()) => {
            let ids: Vec<String> = loader.tree_ids().map(String::from).collect();
            for id in ids {
                if let Err(e) = loader.build(&id) {
                    assert_points_into(&e, text);
                }
                if let Err(e) = loader.validate(&id) {
                    assert_points_into(&e, text);
                }
            }
        }
        Err(e) => assert_points_into(&e, text),
    }
    let mut with_model = Registry::<()>::new();
    if let Err(e) = with_model.add_model_str(text, FILE) {
        assert_points_into(&e, text);
    }
}
