//! Whatever bytes it is given, the loader answers with a tree or an error pointing into
//! them, never a panic: arbitrary text, and real corpus files cut, spliced and corrupted at
//! random. `tests/fuzz.rs` runs the same target on many more mutated corpus files.

use neurotree::{Registry, XmlLoader};
use proptest::prelude::*;

use crate::load_all;

use load_all::{corpus_texts, load_everything as try_load};

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
