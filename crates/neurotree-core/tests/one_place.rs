//! A built-in node is said in one place: outside comments, docs and prose, its name appears
//! in its own module and in the one list of built-ins (`nodes/mod.rs`), and in no other
//! source file of the workspace's crates (their tests aside).

use std::fs;
use std::path::{Path, PathBuf};

use neurotree_core::nodes::BUILT_INS;

/// Every `.rs` file under `dir`.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            // A module of tests of its own (`#[cfg(test)] mod tests;`) is tests.
            let stem = path
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or_default();
            if stem != "tests" && !stem.starts_with("tests_") {
                out.push(path);
            }
        }
    }
}

/// The code of a source file: up to its tests, without comments and without string
/// literals that hold prose (a message or a help text naming a node is not a mention).
fn code(text: &str) -> String {
    let text = match text.find("#[cfg(test)]\nmod tests") {
        Some(end) => &text[..end],
        None => text,
    };
    let mut out = String::new();
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '/' if chars.peek() == Some(&'/') => {
                for d in chars.by_ref() {
                    if d == '\n' {
                        out.push('\n');
                        break;
                    }
                }
            }
            '"' => {
                let mut literal = String::new();
                let mut escaped = false;
                for d in chars.by_ref() {
                    if d == '"' && !escaped {
                        break;
                    }
                    escaped = d == '\\' && !escaped;
                    literal.push(d);
                }
                if !literal.contains(char::is_whitespace) {
                    out.push('"');
                    out.push_str(&literal);
                    out.push('"');
                }
            }
            // A char literal of a quote is not a string.
            '\'' if chars.peek() == Some(&'"') => {
                out.push(c);
                out.push(chars.next().unwrap_or_default());
            }
            _ => out.push(c),
        }
    }
    out
}

/// `true` if `name` occurs in `code` as a whole word.
fn mentions(code: &str, name: &str) -> bool {
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    code.match_indices(name).any(|(at, _)| {
        let before = code[..at].chars().next_back();
        let after = code[at + name.len()..].chars().next();
        !before.is_some_and(ident) && !after.is_some_and(ident)
    })
}

#[test]
fn a_built_in_is_named_in_its_module_and_the_list_only() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for entry in fs::read_dir(&crates).unwrap().flatten() {
        sources(&entry.path().join("src"), &mut files);
    }
    assert!(files.len() > 50, "found only {} source files", files.len());
    let list = Path::new("neurotree-core/src/nodes/mod.rs");
    let mut stray = Vec::new();
    for decl in BUILT_INS {
        let own = format!("pub struct {}", decl.name);
        let mut homes = 0;
        for file in &files {
            let text = fs::read_to_string(file).unwrap();
            let relative = file.strip_prefix(&crates).unwrap();
            if relative == list {
                continue;
            }
            if text.contains(&format!("{own};")) || text.contains(&format!("{own} {{")) {
                homes += 1;
                continue;
            }
            // ROS 2 has services of its own (`Kind::Service`, `type Service`): not the node.
            let ros_word = decl.name == "Service" && relative.starts_with("neurotree-ros2");
            if !ros_word && mentions(&code(&text), decl.name) {
                stray.push(format!("{} in {}", decl.name, relative.display()));
            }
        }
        assert_eq!(homes, 1, "{} is defined in {homes} modules", decl.name);
    }
    assert!(
        stray.is_empty(),
        "built-ins named outside their module and the list: {stray:#?}"
    );
}

#[test]
fn the_scan_sees_code_and_skips_comments_and_prose() {
    let text = "let k = Kind::Delay(d); // a Delay\nlet s = \"a Delay of 1 s\";\nlet n = \"Delay\";\n#[cfg(test)]\nmod tests {\nDelay";
    let kept = code(text);
    assert!(kept.contains("Kind::Delay(d)"));
    assert!(!kept.contains("a Delay"));
    assert!(kept.contains("\"Delay\""));
    assert!(!kept.contains("#[cfg(test)]"));
    assert!(mentions("x(Delay)", "Delay"));
    assert!(!mentions("DelayMore", "Delay"));
    assert!(!mentions("AsyncDelay", "Delay"));
}
