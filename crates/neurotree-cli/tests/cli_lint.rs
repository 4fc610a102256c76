//! `neurotree lint`: the findings printed as text, JSON and SARIF, the exit status, the
//! rule catalog, and Nav2's default trees under `--nav2`.

use std::path::PathBuf;
use std::process::Command;

use serde_json::Value;

use crate::corpus_dir;

/// The exit status, stdout and stderr of `neurotree ARGS`.
fn neurotree(args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .output()
        .expect("the neurotree binary runs");
    (
        out.status.code(),
        String::from_utf8(out.stdout).expect("stdout is UTF-8"),
        String::from_utf8(out.stderr).expect("stderr is UTF-8"),
    )
}

/// A tree with a warning (a child after AlwaysFailure) and a note (an entry never read).
const WARNED: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="unused := 1"/>
      <AlwaysFailure/>
      <AlwaysSuccess/>
    </Sequence>
  </BehaviorTree>
</root>
"#;

/// A tree with an error: a text written where a number is read.
const MISTYPED: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="n := 'three'"/>
      <Repeat num_cycles="{n}"><AlwaysSuccess/></Repeat>
    </Sequence>
  </BehaviorTree>
</root>
"#;

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> String {
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn text_findings_and_exit_status() {
    let dir = tempfile::tempdir().unwrap();
    let warned = write(&dir, "warned.xml", WARNED);
    let (code, out, err) = neurotree(&["lint", &warned]);
    assert_eq!(code, Some(0), "{out}{err}");
    assert_eq!(
        out,
        format!(
            "{warned}:4:7: note[NT0103]: the entry `unused` is written by the script `code` of \
             Script but never read\n\
             {warned}:6:7: warning[NT0201]: this child is never ticked: the Sequence's child \
             `AlwaysFailure` at line 5 never succeeds\n"
        )
    );
    assert_eq!(err, "0 errors, 1 warning, 1 note\n");
    let (code, _, _) = neurotree(&["lint", "--deny", "warnings", &warned]);
    assert_eq!(code, Some(1));
    let mistyped = write(&dir, "mistyped.xml", MISTYPED);
    let (code, out, _) = neurotree(&["lint", &mistyped]);
    assert_eq!(code, Some(1));
    assert!(
        out.contains(":5:7: error[NT0102]: port `num_cycles` of Repeat reads the entry `n` as"),
        "{out}"
    );
}

#[test]
fn a_file_that_does_not_load_is_an_error_of_its_own_rule() {
    let dir = tempfile::tempdir().unwrap();
    let bad = write(
        &dir,
        "bad.xml",
        "<root BTCPP_format=\"4\"><BehaviorTree ID=\"M\"><Nope/></BehaviorTree></root>",
    );
    let (code, out, err) = neurotree(&["lint", &bad]);
    // The advice is in the finding itself, not in a hint after it.
    assert!(!err.contains("hint:"), "{err}");

    assert_eq!(code, Some(1));
    assert!(
        out.starts_with(&format!(
            "{bad}:1:45: error[NT0001]: unknown node type `Nope`"
        )),
        "{out}"
    );
    let (code, _, err) = neurotree(&["lint", "missing.xml"]);
    assert_eq!(code, Some(1), "{err}");
}

#[test]
fn json_is_one_document_with_every_field() {
    let dir = tempfile::tempdir().unwrap();
    let warned = write(&dir, "warned.xml", WARNED);
    let (code, out, _) = neurotree(&["lint", "--format", "json", &warned]);
    assert_eq!(code, Some(0));
    let doc: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(doc["warnings"], 1);
    assert_eq!(doc["notes"], 1);
    assert_eq!(doc["errors"], 0);
    let first = &doc["diagnostics"][1];
    assert_eq!(first["code"], "NT0201");
    assert_eq!(first["rule"], "unreachable-child");
    assert_eq!(first["severity"], "warning");
    assert_eq!(first["line"], 6);
    assert_eq!(first["col"], 7);
    assert_eq!(first["tree"], "Main");
    assert_eq!(first["path"], "Sequence[0]/AlwaysSuccess[2]");
}

#[test]
fn sarif_names_each_rule_and_result() {
    let dir = tempfile::tempdir().unwrap();
    let mistyped = write(&dir, "mistyped.xml", MISTYPED);
    let (code, out, _) = neurotree(&["lint", "--format", "sarif", &mistyped]);
    assert_eq!(code, Some(1));
    let doc: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(doc["version"], "2.1.0");
    let run = &doc["runs"][0];
    let rules = run["tool"]["driver"]["rules"].as_array().unwrap();
    assert!(rules
        .iter()
        .any(|r| r["id"] == "NT0101" && r["name"] == "read-before-write"));
    let result = &run["results"][0];
    assert_eq!(result["ruleId"], "NT0102");
    assert_eq!(result["level"], "error");
    let place = &result["locations"][0]["physicalLocation"];
    assert_eq!(place["region"]["startLine"], 5);
    assert!(place["artifactLocation"]["uri"]
        .as_str()
        .unwrap()
        .ends_with("mistyped.xml"));
}

#[test]
fn list_and_explain_show_the_catalog() {
    let (code, out, _) = neurotree(&["lint", "--list"]);
    assert_eq!(code, Some(0));
    for code in [
        "NT0001", "NT0101", "NT0102", "NT0103", "NT0201", "NT0202", "NT0203", "NT0301", "NT0302",
        "NT0303",
    ] {
        assert!(out.contains(code), "{code}: {out}");
    }
    let (code, out, _) = neurotree(&["lint", "--explain", "nt0101"]);
    assert_eq!(code, Some(0));
    assert!(
        out.starts_with("NT0101 read-before-write (warning)"),
        "{out}"
    );
    let (code, _, err) = neurotree(&["lint", "--explain", "NT0999"]);
    assert_eq!(code, Some(1));
    assert!(err.contains("no rule `NT0999`"), "{err}");
}

#[test]
fn entries_the_application_writes_are_given_with_entry() {
    let dir = tempfile::tempdir().unwrap();
    let tree = write(
        &dir,
        "reads.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
             <Repeat num_cycles="{count}"><AlwaysSuccess/></Repeat>
           </BehaviorTree></root>"#,
    );
    let (_, out, _) = neurotree(&["lint", &tree]);
    assert!(out.contains("warning[NT0101]"), "{out}");
    let (code, out, _) = neurotree(&["lint", "--deny", "warnings", "--entry", "count", &tree]);
    assert_eq!((code, out.as_str()), (Some(0), ""));
}

#[test]
fn tree_lints_one_tree_and_what_it_uses() {
    let dir = tempfile::tempdir().unwrap();
    let two = write(
        &dir,
        "two.xml",
        r#"<root BTCPP_format="4">
  <BehaviorTree ID="A"><Fallback><AlwaysSuccess/><AlwaysFailure/></Fallback></BehaviorTree>
  <BehaviorTree ID="B"><Sequence><AlwaysFailure/><AlwaysSuccess/></Sequence></BehaviorTree>
</root>
"#,
    );
    let (_, all, _) = neurotree(&["lint", &two]);
    assert_eq!(all.matches("[NT0201]").count(), 2, "{all}");
    let (_, b, _) = neurotree(&["lint", "--tree", "B", &two]);
    assert_eq!(b.matches("[NT0201]").count(), 1, "{b}");
    assert!(b.contains(":3:"), "{b}");
}

/// Nav2's default trees: no error under `--nav2`, which knows the entries its navigators
/// write (goal, goals, ...); the warnings are the corpus test's (`lint_corpus.rs`).
#[test]
fn nav2_default_trees_lint_with_exit_zero() {
    let dir = corpus_dir::corpus("nav2");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "xml"))
        .filter(|p| !p.ends_with("nav2_tree_nodes.xml"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 16);
    for file in &files {
        let (code, out, err) = neurotree(&["lint", "--nav2", file.to_str().unwrap()]);
        assert_eq!(code, Some(0), "{}: {out}{err}", file.display());
        assert!(!out.contains("error["), "{out}");
        assert!(
            !out.contains("[NT0201]") && !out.contains("[NT0303]"),
            "{out}"
        );
    }
}
