//! The guide's Bevy example is this crate's doc example (which runs as a doctest): the
//! guide's doctests cannot compile it, since `neurotree` does not depend on Bevy.

fn code_after(text: &str, marker: &str, fence: &str) -> String {
    let start = text.find(marker).expect("the marker") + marker.len();
    let body = &text[start..];
    let code = body[body.find(fence).expect("a code block") + fence.len()..]
        .trim_start_matches(|c| c != '\n')
        .trim_start_matches('\n');
    code[..code.find(fence).expect("the block's end")]
        .trim_end()
        .to_string()
}

#[test]
fn the_guides_bevy_example_is_the_crates_doc_example() {
    let readme = include_str!("../../../docs/guide/bevy.md");
    let lib = include_str!("../src/lib.rs");
    let in_readme = code_after(readme, "# Bevy\n", "```");
    let doc: String = lib
        .lines()
        .filter_map(|l| l.strip_prefix("//!"))
        .map(|l| l.strip_prefix(' ').unwrap_or(l))
        .collect::<Vec<_>>()
        .join("\n");
    let in_doc = code_after(&doc, "# NeuroTree in Bevy", "```");
    assert_eq!(in_readme, in_doc);
}
