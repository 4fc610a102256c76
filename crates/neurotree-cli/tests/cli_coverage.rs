//! `neurotree run --coverage` and `--coverage-json`, and `neurotree show --coverage`, on the
//! cross-door example of the corpus run with mocks: the door is locked, the lock is picked
//! at the second attempt, and the door is never smashed.

use crate::corpus_dir;

use std::process::{Command, Output};

use corpus_dir::corpus;

const MOCKS: [&str; 5] = [
    "--mock-unknown",
    "--mock",
    "OpenDoor=FAILURE",
    "--mock",
    "PickLock=FAILURE,SUCCESS",
];

fn neurotree(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .output()
        .unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8(bytes.to_vec()).unwrap()
}

fn crossdoor() -> String {
    corpus("btcpp/examples/examples__t05_crossdoor__01.xml")
        .display()
        .to_string()
}

const NOTE: &str = "note: running tree 'MainTree' (no main_tree_to_execute; the only tree no \
                    other tree references)\n";

// What each node could have is what its type declares over its children's. The mocks
// not named (IsDoorClosed, SmashDoor, PassThroughDoor) only succeed, so: the Inverter over
// IsDoorClosed can only fail; the inner Fallback ends with SmashDoor and cannot fail, nor
// can the DoorClosed SubTree whose root it is, the outer Fallback that ends with it, or the
// Sequence of that Fallback and PassThroughDoor. Five Failures fewer than when only a
// node's own type narrowed them (33), none of them seen: 16 of 28.
const TABLE: &str = "\
coverage: 16 of 28 outcomes (57.1%), 10 of 11 nodes reached
node                                                                 type                  seen              not seen
Sequence                                                             Sequence              success, running  halted
Sequence/Fallback                                                    Fallback              success, running  halted
Sequence/Fallback/Inverter                                           Inverter              failure           -
Sequence/Fallback/Inverter/IsDoorClosed                              IsDoorClosed          success           -
Sequence/Fallback/DoorClosed                                         DoorClosed            success, running  halted
Sequence/Fallback/DoorClosed/Fallback                                Fallback              success, running  halted
Sequence/Fallback/DoorClosed/Fallback/OpenDoor                       OpenDoor              failure           success, running, halted
Sequence/Fallback/DoorClosed/Fallback/RetryUntilSuccessful           RetryUntilSuccessful  success, running  failure, halted
Sequence/Fallback/DoorClosed/Fallback/RetryUntilSuccessful/PickLock  PickLock              success, failure  running, halted
Sequence/Fallback/DoorClosed/Fallback/SmashDoor                      SmashDoor             -                 never reached
Sequence/PassThroughDoor                                             PassThroughDoor       success           -
";

#[test]
fn run_coverage_prints_the_table_on_stderr_and_keeps_stdout() {
    let file = crossdoor();
    let mut args = vec!["run", file.as_str()];
    args.extend(MOCKS);
    let plain = neurotree(&args);
    args.push("--coverage");
    let covered = neurotree(&args);
    assert_eq!(covered.status.code(), Some(0));
    assert_eq!(text(&covered.stdout), text(&plain.stdout));
    assert_eq!(text(&covered.stderr), format!("{NOTE}{TABLE}"));
}

#[test]
fn run_coverage_json_feeds_show_coverage() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("coverage.json");
    let file = crossdoor();
    let mut args = vec!["run", file.as_str()];
    args.extend(MOCKS);
    args.extend(["--coverage-json", json.to_str().unwrap()]);
    let r = neurotree(&args);
    assert_eq!(r.status.code(), Some(0));
    // Only the file: the table is printed with --coverage alone.
    assert_eq!(text(&r.stderr), NOTE);
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(
        (&written["covered"], &written["possible"]),
        (&16.into(), &28.into())
    );
    assert_eq!(
        written["nodes"][9],
        serde_json::json!({
            "path": "Sequence/Fallback/DoorClosed/Fallback/SmashDoor",
            "type": "SmashDoor",
            "reached": false,
            "seen": [],
            "possible": ["success"],
            "not_seen": ["success"],
        })
    );

    let shown = neurotree(&[
        "show",
        &file,
        "--coverage",
        json.to_str().unwrap(),
        "-f",
        "ascii",
    ]);
    assert_eq!(shown.status.code(), Some(0), "{}", text(&shown.stderr));
    // The outcomes possible are the run's (OpenDoor was a mock that can run), not those of
    // the stand-ins `show` draws.
    assert_eq!(
        text(&shown.stdout),
        "[~] Sequence -- not seen: halted\n\
         +-- [~] Fallback -- not seen: halted\n\
         |   +-- [+] Inverter\n\
         |   |   \\-- [+] IsDoorClosed (AlwaysSuccess)\n\
         |   \\-- [~] DoorClosed (SubTree) -- not seen: halted\n\
         |       \\-- [~] Fallback -- not seen: halted\n\
         |           +-- [~] OpenDoor (AlwaysSuccess) -- not seen: success, running, halted\n\
         |           +-- [~] RetryUntilSuccessful -- not seen: failure, halted\n\
         |           |   \\-- [~] PickLock (AlwaysSuccess) -- not seen: running, halted\n\
         |           \\-- [!] SmashDoor (AlwaysSuccess) -- never reached\n\
         \\-- [+] PassThroughDoor (AlwaysSuccess)\n"
    );

    let svg = neurotree(&[
        "show",
        &file,
        "--coverage",
        json.to_str().unwrap(),
        "-f",
        "svg",
    ]);
    let svg = text(&svg.stdout);
    let classes: Vec<&str> = svg
        .split("class=\"node ")
        .skip(1)
        .map(|rest| &rest[..rest.find('"').unwrap()])
        .collect();
    // Covered as success, reached with outcomes not seen as running, never reached as
    // skipped (dashed).
    assert_eq!(classes[3], "action success");
    assert_eq!(classes[6], "action running");
    assert_eq!(classes[9], "action skipped");
    assert_eq!(classes.iter().filter(|c| c.ends_with("skipped")).count(), 1);
    assert!(svg.contains(">covered</text>"));
    assert!(svg.contains(">outcomes not seen</text>"));
    assert!(svg.contains(
        "stroke=\"#adb5bd\" stroke-dasharray=\"3 2\"/><text x=\"248.6\" y=\"453.9\" \
         font-size=\"11\" fill=\"#495057\">never reached</text>"
    ));
}

#[test]
fn show_coverage_of_another_tree_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("coverage.json");
    std::fs::write(&json, r#"{"nodes":[{"path":"elsewhere","seen":[]}]}"#).unwrap();
    let shown = neurotree(&["show", &crossdoor(), "--coverage", json.to_str().unwrap()]);
    assert_eq!(shown.status.code(), Some(1));
    assert!(text(&shown.stderr).ends_with(&format!(
        "{}: error: the coverage has 1 nodes and tree `MainTree` 11; was it made from \
         another tree?\n",
        json.display()
    )));
}

// A Nav2 control's possible outcomes are those its registry declares: the RecoveryNode's
// action can only fail, and its recovery cannot run, so the node can only fail (one
// outcome, not the four of a type that declares nothing); each leaf has its one status.
#[test]
fn run_coverage_reads_nav2_declarations() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("recover.xml");
    std::fs::write(
        &file,
        "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\"><BehaviorTree ID=\"Main\">\
         <RecoveryNode name=\"recover\" number_of_retries=\"1\">\
         <AlwaysFailure name=\"act\"/><AlwaysSuccess name=\"fix\"/>\
         </RecoveryNode></BehaviorTree></root>",
    )
    .unwrap();
    let file = file.display().to_string();
    let out = neurotree(&["run", file.as_str(), "--coverage"]);
    assert_eq!(
        text(&out.stderr),
        "coverage: 3 of 3 outcomes (100.0%), 3 of 3 nodes reached\n\
         node         type           seen     not seen\n\
         recover      RecoveryNode   failure  -\n\
         recover/act  AlwaysFailure  failure  -\n\
         recover/fix  AlwaysSuccess  success  -\n"
    );
}
