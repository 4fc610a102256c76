//! Whatever bytes it is given, the loader answers with a tree or an error, never a panic:
//! arbitrary text, and real corpus files cut, spliced and corrupted at random.

use std::path::{Path, PathBuf};

use neurotree::{Registry, XmlLoader};
use proptest::prelude::*;

#[path = "support/corpus.rs"]
mod corpus_dir;

fn corpus_texts() -> Vec<String> {
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
    walk(&corpus_dir::corpus(""), &mut files);
    files.sort();
    assert!(files.len() >= 60, "only {} corpus files found", files.len());
    files
        .iter()
        .map(|f| std::fs::read_to_string(f).unwrap_or_else(|e| panic!("{}: {e}", f.display())))
        .collect()
}

/// Loads `text` and builds (or, for model-only types, validates) every tree in it.
fn try_load(text: &str) {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry).mock_unknown(true);
    if loader.load_str(text, "fuzz.xml").is_ok() {
        let ids: Vec<String> = loader.tree_ids().map(String::from).collect();
        for id in ids {
            let _ = loader.build(&id);
            let _ = loader.validate(&id);
        }
    }
    let mut with_model = Registry::<()>::new();
    let _ = with_model.add_model_str(text, "fuzz.xml");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_text_never_panics(text in ".{0,400}") {
        try_load(&text);
    }

    #[test]
    fn xml_like_text_never_panics(
        parts in prop::collection::vec(
            prop_oneof![
                Just("<root>".to_string()), Just("</root>".to_string()),
                Just("<BehaviorTree ID=\"T\">".to_string()), Just("</BehaviorTree>".to_string()),
                Just("<Sequence>".to_string()), Just("</Sequence>".to_string()),
                Just("<SubTree ID=\"T\"/>".to_string()), Just("<Repeat num_cycles=\"-1\">".to_string()),
                Just("</Repeat>".to_string()), Just("<Script code=\"a := (\"/>".to_string()),
                Just("<AlwaysSuccess _skipIf=\"x &&\"/>".to_string()), Just("&".to_string()),
                "[a-zA-Z_ =\"{}@<>/&;]{0,12}",
            ],
            0..40,
        )
    ) {
        try_load(&parts.concat());
    }

    #[test]
    fn mutated_corpus_files_never_panic(
        pick in any::<prop::sample::Index>(),
        cut in any::<prop::sample::Index>(),
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 0..8),
    ) {
        let texts = corpus_texts();
        let mut bytes = texts[pick.index(texts.len())].clone().into_bytes();
        for (at, byte) in edits {
            let i = at.index(bytes.len().max(1));
            if i < bytes.len() {
                bytes[i] = byte;
            }
        }
        bytes.truncate(cut.index(bytes.len() + 1));
        try_load(&String::from_utf8_lossy(&bytes));
    }
}

/// A tree of `depth` nested Inverters over one leaf.
fn chain_of_inverters(depth: usize) -> String {
    format!(
        "<root main_tree_to_execute=\"T\"><BehaviorTree ID=\"T\">{}<AlwaysSuccess/>{}</BehaviorTree></root>",
        "<Inverter>".repeat(depth),
        "</Inverter>".repeat(depth)
    )
}

#[test]
fn very_deep_nesting_is_an_error_not_a_crash() {
    std::thread::Builder::new()
        .stack_size(2 * 1024 * 1024)
        .spawn(|| {
            let text = chain_of_inverters(100_000);
            let registry = Registry::<()>::new();
            let mut loader = XmlLoader::new(&registry);
            let result = loader
                .load_str(&text, "deep.xml")
                .and_then(|()| loader.build_main().map(drop));
            let e = result.unwrap_err();
            assert!(e.message.contains("nest deeper than 1024 levels"), "{e}");
            assert_eq!(e.line, 1);
        })
        .unwrap()
        .join()
        .unwrap();
}

#[test]
fn nesting_past_the_tree_depth_limit_is_refused_when_building() {
    std::thread::Builder::new()
        .stack_size(2 * 1024 * 1024)
        .spawn(|| {
            let text = chain_of_inverters(600);
            let registry = Registry::<()>::new();
            let mut loader = XmlLoader::new(&registry);
            loader.load_str(&text, "deep.xml").unwrap();
            let e = loader.build_main().unwrap_err();
            assert!(e.message.contains("nests deeper than 256 levels"), "{e}");
        })
        .unwrap()
        .join()
        .unwrap();
}
