//! `neurotree show` and `neurotree run --view`, run as a user runs them.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A tree with a subtree, a decorator and leaves the loader mocks.
const DOOR: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Door">
  <BehaviorTree ID="Door">
    <Sequence name="enter">
      <Fallback name="open it">
        <Inverter>
          <IsDoorClosed/>
        </Inverter>
        <SubTree ID="Force"/>
      </Fallback>
      <PassThroughDoor/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Force">
    <RetryUntilSuccessful num_attempts="3">
      <PickLock/>
    </RetryUntilSuccessful>
  </BehaviorTree>
</root>
"#;

const DOOR_NODES: usize = 8;

fn neurotree(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .output()
        .expect("the neurotree binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8(bytes.to_vec()).expect("the output is UTF-8")
}

/// A file `name` holding `contents` in a fresh directory.
fn file(dir: &tempfile::TempDir, name: &str, contents: &str) -> PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, contents).expect("the temporary file is written");
    path
}

fn arg(path: &Path) -> &str {
    path.to_str().expect("temporary paths are UTF-8")
}

/// Runs `show` with the file's unknown leaves drawn as mocks and returns its standard
/// output, asserting that it succeeded.
fn show(args: &[&str]) -> String {
    let mut all = vec!["show", "--mock-unknown"];
    all.extend_from_slice(args);
    let out = neurotree(&all);
    assert!(
        out.status.success(),
        "neurotree {all:?} failed: {}",
        text(&out.stderr)
    );
    assert!(out.stderr.is_empty(), "{}", text(&out.stderr));
    text(&out.stdout)
}

#[test]
fn show_draws_the_tree_in_each_format() {
    let dir = tempfile::tempdir().unwrap();
    let door = file(&dir, "door.xml", DOOR);
    let door = arg(&door);
    let unicode = "[ ] enter (Sequence)\n\
                   ├── [ ] open it (Fallback)\n\
                   │   ├── [ ] Inverter\n\
                   │   │   └── [ ] IsDoorClosed (AlwaysSuccess)\n\
                   │   └── [ ] Force (SubTree)\n\
                   │       └── [ ] RetryUntilSuccessful\n\
                   │           └── [ ] PickLock (AlwaysSuccess)\n\
                   └── [ ] PassThroughDoor (AlwaysSuccess)\n";
    assert_eq!(show(&[door]), unicode, "unicode is the default");
    assert_eq!(show(&[door, "--format", "unicode"]), unicode);
    assert_eq!(
        show(&[door, "-f", "ascii"]),
        "[ ] enter (Sequence)\n\
         +-- [ ] open it (Fallback)\n\
         |   +-- [ ] Inverter\n\
         |   |   \\-- [ ] IsDoorClosed (AlwaysSuccess)\n\
         |   \\-- [ ] Force (SubTree)\n\
         |       \\-- [ ] RetryUntilSuccessful\n\
         |           \\-- [ ] PickLock (AlwaysSuccess)\n\
         \\-- [ ] PassThroughDoor (AlwaysSuccess)\n"
    );

    let dot = show(&[door, "--format", "dot"]);
    assert!(dot.starts_with("digraph behavior_tree {\n"));
    assert!(dot.ends_with("}\n"));
    assert_eq!(dot.matches(" [label=").count(), DOOR_NODES);
    assert_eq!(dot.matches(" -> ").count(), DOOR_NODES - 1);
    assert!(dot.contains("n4 [label=\"Force\\nSubTree\", shape=box, peripheries=2];"));

    let mermaid = show(&[door, "--format", "mermaid"]);
    assert!(mermaid.starts_with("flowchart TD\n"));
    assert_eq!(mermaid.matches(" --> ").count(), DOOR_NODES - 1);
    assert!(mermaid.contains("    n2{{\"Inverter\"}}\n"));
    assert!(
        !mermaid.contains("classDef"),
        "no statuses, no status colours"
    );

    let svg = show(&[door, "--format", "svg"]);
    assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
    assert!(svg.ends_with("</svg>\n"));
    assert_eq!(svg.matches("<g id=\"n").count(), DOOR_NODES);
    assert!(svg.contains("<g id=\"n4\" class=\"node subtree\">"));
}

#[test]
fn show_picks_a_tree_and_writes_to_a_file_in_the_format_of_its_extension() {
    let dir = tempfile::tempdir().unwrap();
    let door = file(&dir, "door.xml", DOOR);
    let door = arg(&door);
    assert_eq!(
        show(&[door, "--tree", "Force"]),
        "[ ] RetryUntilSuccessful\n└── [ ] PickLock (AlwaysSuccess)\n"
    );

    let svg = dir.path().join("door.svg");
    assert_eq!(
        show(&[door, "-o", arg(&svg)]),
        "",
        "nothing on standard output"
    );
    let written = std::fs::read_to_string(&svg).unwrap();
    assert!(written.starts_with("<svg ") && written.ends_with("</svg>\n"));
    assert_eq!(written, show(&[door, "--format", "svg"]));

    let chart = dir.path().join("door.mmd");
    show(&[door, "--output", arg(&chart)]);
    assert!(std::fs::read_to_string(&chart)
        .unwrap()
        .starts_with("flowchart TD\n"));

    // An explicit format wins over the extension.
    let txt = dir.path().join("door.svg.txt");
    show(&[door, "-o", arg(&txt), "--format", "dot"]);
    assert!(std::fs::read_to_string(&txt)
        .unwrap()
        .starts_with("digraph"));
}

#[test]
fn show_colours_each_node_with_the_statuses_of_a_run_trace() {
    let dir = tempfile::tempdir().unwrap();
    let door = file(&dir, "door.xml", DOOR);
    let run = neurotree(&[
        "run",
        arg(&door),
        "--mock-unknown",
        "--mock",
        "IsDoorClosed=SUCCESS",
        "--mock",
        "PickLock=FAILURE,SUCCESS",
        "--mock",
        "PassThroughDoor=RUNNING,RUNNING,FAILURE",
        "--trace",
    ]);
    // The run ends FAILURE.
    assert_eq!(run.status.code(), Some(2), "{}", text(&run.stderr));
    let trace = file(&dir, "door.jsonl", &text(&run.stdout));
    let trace = arg(&trace);
    let door = arg(&door);

    // At the end the door would not let us through: every node shows its last status.
    // (`show` knows nothing of the run's mocks: its leaves are the loader's own.)
    // The root's failure chain (Tree::last_failure) goes from the root to the leaf that
    // failed: both are marked.
    assert_eq!(
        show(&[door, "--trace", trace]),
        "[✗] enter (Sequence) -- failed\n\
         ├── [✓] open it (Fallback)\n\
         │   ├── [✗] Inverter\n\
         │   │   └── [✓] IsDoorClosed (AlwaysSuccess)\n\
         │   └── [✓] Force (SubTree)\n\
         │       └── [✓] RetryUntilSuccessful\n\
         │           └── [✓] PickLock (AlwaysSuccess)\n\
         └── [✗] PassThroughDoor (AlwaysSuccess) -- failed\n"
    );
    // Ticks count passes of the root: the first tick made two, the retry of PickLock
    // passing again at once. In tick 3 only the door was ticked; the rest shows what the
    // sequence had kept.
    assert_eq!(
        show(&[door, "--trace", trace, "--tick", "3", "--format", "ascii"]),
        "[R] enter (Sequence)\n\
         +-- [S] open it (Fallback)\n\
         |   +-- [ ] Inverter\n\
         |   |   \\-- [ ] IsDoorClosed (AlwaysSuccess)\n\
         |   \\-- [ ] Force (SubTree)\n\
         |       \\-- [ ] RetryUntilSuccessful\n\
         |           \\-- [ ] PickLock (AlwaysSuccess)\n\
         \\-- [R] PassThroughDoor (AlwaysSuccess)\n"
    );
    let svg = show(&[door, "--trace", trace, "--format", "svg"]);
    assert!(svg.contains("<g id=\"n0\" class=\"node control failure failed-path\">"));
    assert!(svg.contains("<g id=\"n6\" class=\"node action success\">"));
    assert!(svg.contains("<g class=\"legend\">"));
    let mermaid = show(&[door, "--trace", trace, "--format", "mermaid"]);
    assert!(
        mermaid.contains("    class n0,n2,n7 failure;\n"),
        "{mermaid}"
    );
}

#[test]
fn show_draws_node_types_that_a_model_declares() {
    let dir = tempfile::tempdir().unwrap();
    let nav = file(
        &dir,
        "nav.xml",
        r#"<root BTCPP_format="4">
  <BehaviorTree ID="Nav">
    <RecoveryNode number_of_retries="2" name="navigate">
      <FollowPath path="{path}"/>
      <GoalUpdated/>
    </RecoveryNode>
  </BehaviorTree>
</root>"#,
    );
    let model = file(
        &dir,
        "model.xml",
        r#"<root BTCPP_format="4">
  <TreeNodesModel>
    <Control ID="RecoveryNode"><input_port name="number_of_retries" type="int"/></Control>
    <Action ID="FollowPath"><input_port name="path"/></Action>
    <Condition ID="GoalUpdated"/>
  </TreeNodesModel>
</root>"#,
    );
    // GoalUpdated and RecoveryNode are Nav2's own nodes, which `show` knows; FollowPath
    // is drawn from the model.
    assert_eq!(
        show(&[arg(&nav), "--model", arg(&model)]),
        "[ ] navigate (RecoveryNode)\n\
         ├── [ ] FollowPath\n\
         └── [ ] GoalUpdated\n"
    );
    // Without the model, FollowPath is an unknown leaf: drawn from what the file says,
    // marked unknown, with a warning.
    let out = neurotree(&["show", arg(&nav)]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(
        text(&out.stdout),
        "[ ] navigate (RecoveryNode)\n\
         ├── [ ] FollowPath (unknown FollowPath)\n\
         └── [ ] GoalUpdated\n"
    );
    assert_eq!(
        text(&out.stderr),
        format!(
            "{}:4:7: warning: unknown node type `FollowPath`: drawn from its name and \
             attributes; declare it with --model FILE (or --nav2 if it is one of Nav2's)\n",
            arg(&nav)
        )
    );
    // A control the registry does not know is drawn too, with or without mocks.
    let juggle = file(
        &dir,
        "juggle.xml",
        "<root BTCPP_format=\"4\">\n  <BehaviorTree ID=\"J\">\n    <Juggle balls=\"3\">\n      <FollowPath/>\n    </Juggle>\n  </BehaviorTree>\n</root>\n",
    );
    let out = neurotree(&["show", arg(&juggle)]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(
        text(&out.stdout),
        "[ ] Juggle (unknown Juggle)\n\
         └── [ ] FollowPath (unknown FollowPath)\n"
    );
    assert!(text(&out.stderr).starts_with(&format!(
        "{}:3:5: warning: unknown node type `Juggle`",
        arg(&juggle)
    )));
    let out = neurotree(&["show", arg(&juggle), "--mock-unknown"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).starts_with("[ ] Juggle (unknown Juggle)\n"),
        "{}",
        text(&out.stdout)
    );
}

#[test]
fn show_reports_bad_input_with_its_place_and_exit_code_1() {
    let dir = tempfile::tempdir().unwrap();
    let door = file(&dir, "door.xml", DOOR);
    let broken = file(&dir, "broken.xml", "<root BTCPP_format=\"4\">\n  <BehaviorTree ID=\"A\">\n    <Sequence>\n  </BehaviorTree>\n</root>\n");
    let trace = file(
        &dir,
        "bad.jsonl",
        "{\"tick\":1,\"node\":\"enter\",\"from\":\"IDLE\",\"to\":\"RUNNING\"}\n{\"tick\":1,\"node\":\"somewhere/else\",\"from\":\"IDLE\",\"to\":\"RUNNING\"}\n",
    );
    let failing = |args: &[&str]| {
        let mut args = args.to_vec();
        args.push("--mock-unknown");
        let out = neurotree(&args);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        assert!(out.stdout.is_empty());
        text(&out.stderr)
    };

    let err = failing(&["show", arg(&broken)]);
    assert!(
        err.starts_with(&format!("{}:4:", arg(&broken))) && err.contains(": error: "),
        "{err}"
    );
    let missing = dir.path().join("missing.xml");
    let err = failing(&["show", arg(&missing)]);
    assert!(
        err.starts_with(&format!("{}: error: cannot open the file", arg(&missing))),
        "{err}"
    );
    assert_eq!(
        failing(&["show", arg(&door), "--tree", "Nope"]),
        format!(
            "{}: error: --tree Nope: no tree with that ID is loaded; the trees are: Door, Force\n",
            arg(&door)
        )
    );
    assert_eq!(
        failing(&["show", arg(&door), "--trace", arg(&trace)]),
        format!(
            "{}:2:11: error: node `somewhere/else` is not in tree `Door`; was the trace made from another tree?\n",
            arg(&trace)
        )
    );
    let not_json = file(&dir, "notes.txt", "tick one\n");
    let err = failing(&["show", arg(&door), "--trace", arg(&not_json)]);
    assert!(
        err.starts_with(&format!(
            "{}:1:2: error: not a JSON trace line",
            arg(&not_json)
        )),
        "{err}"
    );
    let err = failing(&[
        "show",
        arg(&door),
        "-o",
        arg(&dir.path().join("no/such/dir.svg")),
    ]);
    assert!(err.contains(": error: cannot write the picture"), "{err}");

    // Command-line mistakes are clap's usage errors (exit code 2).
    let out = neurotree(&["show", arg(&door), "--format", "png"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("unknown picture format `png`"));
    let out = neurotree(&["show", arg(&door), "--tick", "1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("--trace"));
}

#[test]
fn run_view_draws_each_tick_on_stderr_and_keeps_stdout_json() {
    let dir = tempfile::tempdir().unwrap();
    let door = file(&dir, "door.xml", DOOR);
    let out = neurotree(&[
        "run",
        arg(&door),
        "--mock-unknown",
        "--mock",
        "PassThroughDoor=RUNNING,SUCCESS",
        "--view",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert_eq!(
        stdout.lines().count(),
        3,
        "two ticks and the summary: {stdout}"
    );
    assert!(stdout
        .lines()
        .all(|l| l.starts_with('{') && l.ends_with('}')));
    assert_eq!(
        text(&out.stderr),
        "tick 1: RUNNING\n\
         [R] enter (Sequence)\n\
         ├── [✓] open it (Fallback)\n\
         │   ├── [✗] Inverter\n\
         │   │   └── [✓] IsDoorClosed (AlwaysSuccess)\n\
         │   └── [✓] Force (SubTree)\n\
         │       └── [✓] RetryUntilSuccessful\n\
         │           └── [✓] PickLock (AlwaysSuccess)\n\
         └── [R] PassThroughDoor (Mock)\n\
         \n\
         tick 2: SUCCESS\n\
         [✓] enter (Sequence)\n\
         ├── [✓] open it (Fallback)\n\
         │   ├── [ ] Inverter\n\
         │   │   └── [ ] IsDoorClosed (AlwaysSuccess)\n\
         │   └── [ ] Force (SubTree)\n\
         │       └── [ ] RetryUntilSuccessful\n\
         │           └── [ ] PickLock (AlwaysSuccess)\n\
         └── [✓] PassThroughDoor (Mock)\n\
         \n"
    );
}

/// A Timeout that fires, then a Retry that runs out: both give their reasons.
const GIVE_UP: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence name="go">
      <Fallback name="try">
        <Timeout name="limit" msec="150">
          <Drive name="drive"/>
        </Timeout>
        <RetryUntilSuccessful name="retry" num_attempts="2">
          <AlwaysFailure/>
        </RetryUntilSuccessful>
      </Fallback>
    </Sequence>
  </BehaviorTree>
</root>
"#;

#[test]
fn show_marks_the_path_that_failed_with_the_reasons_of_the_trace() {
    let dir = tempfile::tempdir().unwrap();
    let tree = file(&dir, "give_up.xml", GIVE_UP);
    let run = neurotree(&["run", arg(&tree), "--mock", "drive=RUNNING", "--trace"]);
    assert_eq!(run.status.code(), Some(2), "{}", text(&run.stderr));
    let trace = file(&dir, "give_up.jsonl", &text(&run.stdout));
    let (tree, trace) = (arg(&tree), arg(&trace));
    // The last tick: the Retry ran out, and the root failed for it. The Timeout fired a
    // pass earlier, so it is not on the path; the path is the run's failure chain, down to
    // the Retry's child.
    assert_eq!(
        show(&[tree, "--trace", trace, "--format", "ascii"]),
        "[F] go (Sequence) -- failed\n\
         \\-- [F] try (Fallback) -- failed\n\
         \x20   +-- [F] limit (Timeout)\n\
         \x20   |   \\-- [ ] drive (Drive)\n\
         \x20   \\-- [F] retry (RetryUntilSuccessful) -- failed: gave up after 2 attempts\n\
         \x20       \\-- [F] AlwaysFailure -- failed\n"
    );
    // In a tick where the root did not fail, nothing is marked.
    assert!(
        !show(&[tree, "--trace", trace, "--tick", "3", "--format", "ascii"]).contains("failed")
    );
}

/// A Retry that gives up because the Timeout below it fired.
const TIMED_OUT: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence name="go">
      <RetryUntilSuccessful name="retry" num_attempts="1">
        <Timeout name="limit" msec="150">
          <Drive name="drive"/>
        </Timeout>
      </RetryUntilSuccessful>
    </Sequence>
  </BehaviorTree>
</root>
"#;

#[test]
fn show_marks_the_whole_failure_chain_down_to_the_timeout() {
    let dir = tempfile::tempdir().unwrap();
    let tree = file(&dir, "timed_out.xml", TIMED_OUT);
    let run = neurotree(&["run", arg(&tree), "--mock", "drive=RUNNING", "--trace"]);
    assert_eq!(run.status.code(), Some(2), "{}", text(&run.stderr));
    let trace = file(&dir, "timed_out.jsonl", &text(&run.stdout));
    let (tree, trace) = (arg(&tree), arg(&trace));
    // As Tree::last_failure chains it: the Retry gave up, because the Timeout fired (and
    // halted its child, which did not fail).
    assert_eq!(
        show(&[tree, "--trace", trace, "--format", "ascii"]),
        "[F] go (Sequence) -- failed\n\
         \\-- [F] retry (RetryUntilSuccessful) -- failed: gave up after 1 attempt\n\
         \x20   \\-- [F] limit (Timeout) -- failed: timed out after 150 ms\n\
         \x20       \\-- [ ] drive (Drive)\n"
    );
}

/// The lines of `picture` that contain `mark`.
fn marked<'a>(picture: &'a str, mark: &str) -> Vec<&'a str> {
    picture.lines().filter(|l| l.contains(mark)).collect()
}

#[test]
fn show_marks_the_path_that_failed_in_every_picture_format() {
    let dir = tempfile::tempdir().unwrap();
    let tree = file(&dir, "give_up.xml", GIVE_UP);
    let run = neurotree(&["run", arg(&tree), "--mock", "drive=RUNNING", "--trace"]);
    let trace = file(&dir, "give_up.jsonl", &text(&run.stdout));
    let (tree, trace) = (arg(&tree), arg(&trace));
    // Ids: go 0, try 1, limit 2, drive 3, retry 4, AlwaysFailure 5; the path is 0, 1, 4, 5.
    let dot = show(&[tree, "--trace", trace, "--format", "dot"]);
    assert_eq!(
        marked(&dot, "penwidth=3"),
        [
            "  n0 [label=\"→ go\\nSequence\", shape=box, fillcolor=\"#ffe3e3\", \
             color=\"#c92a2a\", tooltip=\"FAILURE: failed\", penwidth=3];",
            "  n1 [label=\"? try\\nFallback\", shape=box, fillcolor=\"#ffe3e3\", \
             color=\"#c92a2a\", tooltip=\"FAILURE: failed\", penwidth=3];",
            "  n4 [label=\"retry\\nRetryUntilSuccessful\\ngave up after 2 attempts\", \
             shape=hexagon, fillcolor=\"#ffe3e3\", color=\"#c92a2a\", \
             tooltip=\"FAILURE: failed: gave up after 2 attempts\", penwidth=3];",
            "  n5 [label=\"AlwaysFailure\", shape=box, fillcolor=\"#ffe3e3\", \
             color=\"#c92a2a\", tooltip=\"FAILURE: failed\", penwidth=3, \
             style=\"rounded,filled\"];",
            "  n0 -> n1 [color=\"#c92a2a\", penwidth=3];",
            "  n1 -> n4 [color=\"#c92a2a\", penwidth=3];",
            "  n4 -> n5 [color=\"#c92a2a\", penwidth=3];",
        ]
    );
    assert_eq!(marked(&dot, "gave up").len(), 1);
    assert_eq!(marked(&dot, "failed").len(), 4);

    let mermaid = show(&[tree, "--trace", trace, "--format", "mermaid"]);
    assert_eq!(
        marked(&mermaid, "#c92a2a,stroke-width:3px"),
        [
            "    classDef failedpath stroke:#c92a2a,stroke-width:3px;",
            "    linkStyle 0,3,4 stroke:#c92a2a,stroke-width:3px;",
        ]
    );
    assert_eq!(
        marked(&mermaid, "failedpath"),
        [
            "    classDef failedpath stroke:#c92a2a,stroke-width:3px;",
            "    class n0,n1,n4,n5 failedpath;",
        ]
    );
    assert_eq!(
        marked(&mermaid, "<b>"),
        ["    n4{{\"retry<br/><i>RetryUntilSuccessful</i><br/><b>gave up after 2 attempts</b>\"}}"]
    );
    // Links, in the order written: 0 go-try, 1 try-limit, 2 limit-drive, 3 try-retry.
    assert_eq!(
        marked(&mermaid, " --> "),
        [
            "    n0 --> n1",
            "    n1 --> n2",
            "    n2 --> n3",
            "    n1 --> n4",
            "    n4 --> n5"
        ]
    );

    let svg = show(&[tree, "--trace", trace, "--format", "svg"]);
    let groups: Vec<&str> = marked(&svg, "failed-path\">")
        .iter()
        .map(|l| &l[..l.find(" class").unwrap()])
        .collect();
    assert_eq!(
        groups,
        [
            "<g id=\"n0\"",
            "<g id=\"n1\"",
            "<g id=\"n4\"",
            "<g id=\"n5\""
        ]
    );
    assert_eq!(
        marked(&svg, "<path class=\"failed-path\""),
        [
            "<path class=\"failed-path\" d=\"M147.3 56V74H147.3V92\" stroke=\"#c92a2a\" stroke-width=\"3\"/>",
            "<path class=\"failed-path\" d=\"M147.3 132V153.5H226V168\" stroke=\"#c92a2a\" stroke-width=\"3\"/>",
            "<path class=\"failed-path\" d=\"M226 236V254H226V272\" stroke=\"#c92a2a\" stroke-width=\"3\"/>",
        ]
    );
    let reasons = marked(&svg, "class=\"reason\"");
    assert_eq!(reasons.len(), 1);
    assert!(reasons[0].starts_with(
        "<g id=\"n4\" class=\"node decorator failure failed-path\">\
         <title>go/try/retry (RetryUntilSuccessful): FAILURE -- failed: gave up after 2 attempts\
         &#10;in num_attempts: 2</title>"
    ));
    // Under the name, the type and the port, the reason.
    assert!(reasons[0].contains(
        "<text class=\"reason\" x=\"226\" y=\"227\" font-size=\"10\" font-weight=\"bold\" \
         text-anchor=\"middle\" fill=\"#c92a2a\">gave up after 2 attempts</text>"
    ));
    // Red and three pixels wide: the outlines of the four nodes on the path and the three
    // lines between them, nothing else.
    assert_eq!(
        svg.matches("stroke=\"#c92a2a\" stroke-width=\"3\"").count(),
        7
    );
}
