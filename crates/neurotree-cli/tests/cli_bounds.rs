//! `neurotree run`, `check` and `show` given hostile input: every one ends, with a bounded
//! outcome (an exact error and exit status), within seconds.

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The exit status, stdout and stderr of `neurotree ARGS`; killed (and the test failed)
/// if it has not ended within a minute, so that a regression fails instead of hanging.
fn neurotree(args: &[&str]) -> (Option<i32>, String, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the neurotree binary runs");
    // Read both streams on threads, so that a full pipe does not stall the child.
    let mut stdout = child.stdout.take().unwrap();
    let mut stderr = child.stderr.take().unwrap();
    let out = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = stdout.read_to_string(&mut text);
        text
    });
    let err = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = stderr.read_to_string(&mut text);
        text
    });
    let deadline = Instant::now() + Duration::from_secs(60);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("neurotree {args:?} did not end within a minute");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    (status.code(), out.join().unwrap(), err.join().unwrap())
}

/// Writes `text` to `name` in `dir` and returns its path as text.
fn file(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

const REPEAT_FOREVER: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Repeat num_cycles="-1"><AlwaysSuccess/></Repeat>
  </BehaviorTree>
</root>"#;

#[test]
fn max_ticks_counts_every_pass_of_the_root_including_wake_ups() {
    let dir = tempfile::tempdir().unwrap();
    let tree = file(dir.path(), "forever.xml", REPEAT_FOREVER);
    // The Repeat asks for a pass at once after each cycle: one `tick_once` would spin.
    let (code, out, err) = neurotree(&["run", &tree, "--max-ticks", "3"]);
    assert_eq!(code, Some(3), "{err}");
    assert_eq!(
        out,
        concat!(
            r#"{"tick":3,"status":"RUNNING"}"#,
            "\n",
            r#"{"summary":{"ticks":3,"status":"RUNNING","nodes":{"AlwaysSuccess":{"ticks":3,"halts":0},"Repeat":{"ticks":3,"halts":1}},"paths":{"Repeat":[{"ticks":3,"halts":1}],"Repeat/AlwaysSuccess":[{"ticks":3,"halts":0}]},"blackboard":{}}}"#,
            "\n"
        )
    );
    assert_eq!(err, "");
    // Ticked exactly once each time, the same three passes are three ticks.
    let (code, out, _) = neurotree(&["run", &tree, "--max-ticks", "3", "--tick", "exactly-once"]);
    assert_eq!(code, Some(3));
    let ticks: Vec<&str> = out.lines().take(3).collect();
    assert_eq!(
        ticks,
        [
            r#"{"tick":1,"status":"RUNNING"}"#,
            r#"{"tick":2,"status":"RUNNING"}"#,
            r#"{"tick":3,"status":"RUNNING"}"#,
        ]
    );
    // The trace numbers the changes by pass.
    let (code, out, _) = neurotree(&["run", &tree, "--max-ticks", "2", "--trace"]);
    assert_eq!(code, Some(3));
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines[..6],
        [
            r#"{"tick":1,"node":"Repeat","from":"IDLE","to":"RUNNING"}"#,
            r#"{"tick":1,"node":"Repeat/AlwaysSuccess","from":"IDLE","to":"SUCCESS"}"#,
            r#"{"tick":1,"node":"Repeat/AlwaysSuccess","from":"SUCCESS","to":"IDLE"}"#,
            r#"{"tick":2,"node":"Repeat/AlwaysSuccess","from":"IDLE","to":"SUCCESS"}"#,
            r#"{"tick":2,"node":"Repeat/AlwaysSuccess","from":"SUCCESS","to":"IDLE"}"#,
            r#"{"tick":2,"node":"Repeat","from":"RUNNING","to":"IDLE"}"#,
        ]
    );
    assert_eq!(lines[6], r#"{"tick":2,"status":"RUNNING"}"#);
}

#[test]
fn a_step_past_a_day_is_refused_before_running() {
    let dir = tempfile::tempdir().unwrap();
    let tree = file(dir.path(), "forever.xml", REPEAT_FOREVER);
    let (code, out, err) = neurotree(&["run", &tree, "--step-ms", "18446744073709551615"]);
    assert_eq!(code, Some(2), "{err}");
    assert_eq!(out, "");
    assert!(
        err.starts_with(
            "error: invalid value '18446744073709551615' for '--step-ms <STEP_MS>': \
             18446744073709551615 is not in 0..=86400000"
        ),
        "{err}"
    );
    let (code, _, err) = neurotree(&["run", &tree, "--step-ms", "86400000", "--max-ticks", "1"]);
    assert_eq!(code, Some(3), "{err}");
}

const ONE_ACTION: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence><Action ID="Move"/></Sequence>
  </BehaviorTree>
</root>"#;

#[test]
fn mocks_with_huge_counts_run_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let tree = file(dir.path(), "move.xml", ONE_ACTION);
    let running = [
        r#"{"tick":1,"status":"RUNNING"}"#,
        r#"{"tick":2,"status":"RUNNING"}"#,
        r#"{"tick":3,"status":"RUNNING"}"#,
    ];
    for mock in [
        "Move=RUNNING*18446744073709551615",
        "Move=RUNNING*4000000000,SUCCESS",
    ] {
        let (code, out, err) = neurotree(&["run", &tree, "--mock", mock, "--max-ticks", "3"]);
        assert_eq!(code, Some(3), "{mock}: {err}");
        assert_eq!(out.lines().take(3).collect::<Vec<_>>(), running, "{mock}");
    }
    let (code, out, err) = neurotree(&["run", &tree, "--mock", "Move=RUNNING*2,SUCCESS"]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(out.lines().nth(2), Some(r#"{"tick":3,"status":"SUCCESS"}"#));
    for (mock, message) in [
        (
            "Move=RUNNING*0",
            "--mock Move=RUNNING*0: `RUNNING*0`: the count after `*` must be at least one\n",
        ),
        (
            "Move=RUNNING*18446744073709551616",
            "--mock Move=RUNNING*18446744073709551616: `RUNNING*18446744073709551616`: the count after `*` must be at most 18446744073709551615\n",
        ),
    ] {
        let (code, out, err) = neurotree(&["run", &tree, "--mock", mock]);
        assert_eq!(code, Some(1));
        assert_eq!(out, "");
        assert_eq!(err, message);
    }
}

/// `levels` trees, one a line after `<root>`, each using the next one twice, and a leaf.
fn doubling_subtrees(levels: usize) -> String {
    let mut xml = String::from("<root BTCPP_format=\"4\" main_tree_to_execute=\"T0\">\n");
    for i in 0..levels {
        let next = i + 1;
        xml.push_str(&format!(
            "<BehaviorTree ID=\"T{i}\"><Sequence><SubTree ID=\"T{next}\"/><SubTree ID=\"T{next}\"/></Sequence></BehaviorTree>\n"
        ));
    }
    xml.push_str(&format!(
        "<BehaviorTree ID=\"T{levels}\"><AlwaysSuccess/></BehaviorTree>\n</root>\n"
    ));
    xml
}

const HINT: &str =
    "hint: if the tree is meant to be this big, raise the limit with --max-nodes N\n";

#[test]
fn subtrees_doubling_thirty_times_are_refused_by_run_show_and_check() {
    let dir = tempfile::tempdir().unwrap();
    let tree = file(dir.path(), "doubling.xml", &doubling_subtrees(30));
    let refused = |limit: u64, before: u64, col: u32| {
        format!(
            "{tree}:2:{col}: error: the tree expands past the limit of {limit} nodes here: \
             SubTree `T1` adds 2147483645 nodes to the {before} counted so far (each use of a \
             subtree is a copy of it); raise the limit with XmlLoader::max_nodes if the tree \
             is meant to be this big\n"
        )
    };
    // `run` reports every error of the tree, as `check` does; `show` the first.
    let both = format!("{}{}", refused(2_000_000, 2, 33), refused(2_000_000, 3, 51));
    for (command, errors) in [("run", both), ("show", refused(2_000_000, 2, 33))] {
        let (code, out, err) = neurotree(&[command, &tree]);
        assert_eq!(code, Some(1), "{command}: {err}");
        assert_eq!(out, "");
        assert_eq!(err, format!("{errors}{HINT}"), "{command}");
    }
    // `check` goes on past an error; a low limit keeps it from validating the smaller
    // trees, which fit the default, at length.
    let (code, out, err) = neurotree(&["check", &tree, "--max-nodes", "100"]);
    assert_eq!(code, Some(1));
    assert_eq!(out, "");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines[0], refused(100, 2, 33).trim_end());
    assert_eq!(lines[1], refused(100, 3, 51).trim_end());
    // Twenty errors, then a note and the hint.
    assert_eq!(lines.len(), 22, "{err}");
    assert_eq!(
        lines[20],
        format!("{tree}: note: only the first 20 errors are shown")
    );
    assert_eq!(lines[21], HINT.trim_end());
}

#[test]
fn max_nodes_raises_and_lowers_the_budget_exactly() {
    let dir = tempfile::tempdir().unwrap();
    // 61 nodes: a Sequence and two SubTree nodes over two copies of 29.
    let tree = file(dir.path(), "doubling.xml", &doubling_subtrees(4));
    let (code, out, err) = neurotree(&["run", &tree, "--max-nodes", "61"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        out.contains(r#""summary":{"ticks":1,"status":"SUCCESS""#),
        "{out}"
    );
    let (code, _, err) = neurotree(&["show", &tree, "--max-nodes", "60"]);
    assert_eq!(code, Some(1));
    assert!(
        err.starts_with(&format!(
            "{tree}:2:51: error: the tree expands past the limit of 60 nodes here: SubTree `T1` adds 29 nodes to the 32 counted so far"
        )),
        "{err}"
    );
    let (code, out, err) = neurotree(&["check", &tree, "--max-nodes", "61"]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(out, format!("{tree}: ok (5 trees)\n"));
}

#[test]
fn a_device_is_refused_as_a_tree_a_model_and_an_include() {
    if !Path::new("/dev/zero").exists() {
        println!("note: no /dev/zero here; skipped");
        return;
    }
    let device = "/dev/zero: error: not a regular file but a character device; give the path of a tree file\n";
    for command in ["run", "check", "show"] {
        let (code, out, err) = neurotree(&[command, "/dev/zero"]);
        assert_eq!(code, Some(1), "{command}");
        assert_eq!(out, "", "{command}");
        assert_eq!(err, device, "{command}");
    }
    let dir = tempfile::tempdir().unwrap();
    let tree = file(dir.path(), "move.xml", ONE_ACTION);
    for command in ["check", "show"] {
        let (code, _, err) = neurotree(&[command, &tree, "--model", "/dev/zero"]);
        assert_eq!(code, Some(1), "{command}");
        assert_eq!(err, device, "{command}");
    }
}

#[test]
fn a_fifo_is_refused_as_a_tree_a_model_and_an_include_without_blocking() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.xml");
    match Command::new("mkfifo").arg(&fifo).status() {
        Ok(status) if status.success() => {}
        other => {
            println!("note: mkfifo did not make a FIFO ({other:?}); skipped");
            return;
        }
    }
    let fifo = fifo.to_str().unwrap();
    let refused =
        format!("{fifo}: error: not a regular file but a FIFO; give the path of a tree file\n");
    for command in ["run", "check", "show"] {
        let (code, out, err) = neurotree(&[command, fifo]);
        assert_eq!(code, Some(1), "{command}");
        assert_eq!(out, "", "{command}");
        assert_eq!(err, refused, "{command}");
    }
    let tree = file(dir.path(), "move.xml", ONE_ACTION);
    let (code, _, err) = neurotree(&["check", &tree, "--model", fifo]);
    assert_eq!(code, Some(1));
    assert_eq!(err, refused);
    let main = file(
        dir.path(),
        "main.xml",
        "<root>\n  <include path=\"pipe.xml\"/>\n</root>\n",
    );
    let (code, _, err) = neurotree(&["check", &main]);
    assert_eq!(code, Some(1));
    assert_eq!(
        err,
        format!(
            "{main}:2:3: error: in included file `{fifo}`: not a regular file but a FIFO; give the path of a tree file\n"
        )
    );
}
