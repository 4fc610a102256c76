//! `neurotree run` as a test bench (mocks by type, outputs, substitution rules, values set
//! at a tick, enums, every value printed) and `neurotree test` with scenario files.

use std::path::Path;
use std::process::Command;

use serde_json::Value;

/// The exit status, stdout and stderr of `neurotree ARGS`: the binary cargo built, or the
/// one `NEUROTREE_BIN` names (a build of another target directory).
fn neurotree(args: &[&str]) -> (Option<i32>, String, String) {
    let bin = std::env::var("NEUROTREE_BIN")
        .unwrap_or_else(|_| env!("CARGO_BIN_EXE_neurotree").to_string());
    let out = Command::new(bin)
        .args(args)
        .output()
        .expect("the neurotree binary runs");
    (
        out.status.code(),
        String::from_utf8(out.stdout).expect("stdout is UTF-8"),
        String::from_utf8(out.stderr).expect("stderr is UTF-8"),
    )
}

/// Writes `text` to `name` in `dir` and returns its path as text.
fn file(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// The summary object of a run's output.
fn summary(out: &str) -> Value {
    let last = out.lines().last().expect("a summary line");
    serde_json::from_str::<Value>(last).unwrap()["summary"].clone()
}

/// A named battery check watched while the robot moves, then a report in a subtree.
const PATROL: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <ReactiveSequence>
      <BatteryOK name="battery"/>
      <MoveBase goal="{target}" pose="{where}"/>
      <SubTree ID="Report" _autoremap="true"/>
    </ReactiveSequence>
  </BehaviorTree>
  <BehaviorTree ID="Report">
    <Script code="reported := true; mode := DOCKING"/>
  </BehaviorTree>
</root>"#;

#[test]
fn a_mock_matches_a_named_node_by_its_type_and_an_unmatched_mock_exits_1() {
    let dir = tempfile::tempdir().unwrap();
    let tree = file(dir.path(), "patrol.xml", PATROL);
    let (code, out, err) = neurotree(&[
        "run",
        &tree,
        "--mock",
        "BatteryOK=FAILURE",
        "--mock",
        "MoveBase=SUCCESS",
        "--enum",
        "DOCKING=2",
    ]);
    assert_eq!(code, Some(2), "{err}");
    assert_eq!(summary(&out)["nodes"]["battery"]["ticks"], 1);
    assert_eq!(summary(&out)["nodes"]["MoveBase"]["ticks"], 0);

    let (code, out, err) = neurotree(&[
        "run",
        &tree,
        "--mock",
        "BatteryOK=SUCCESS",
        "--mock",
        "MoveBase=SUCCESS",
        "--mock",
        "MovBase=SUCCESS",
        "--enum",
        "DOCKING=2",
    ]);
    assert_eq!(code, Some(1));
    assert!(out.is_empty());
    assert!(
        err.contains("the mock `MovBase` matches no node of tree `Main`"),
        "{err}"
    );
}

#[test]
fn mocks_write_outputs_and_every_value_prints_with_its_type() {
    let dir = tempfile::tempdir().unwrap();
    let tree = file(dir.path(), "patrol.xml", PATROL);
    let (code, out, err) = neurotree(&[
        "run",
        &tree,
        "--mock",
        "BatteryOK=SUCCESS;level:u32=87",
        "--mock",
        "MoveBase=SUCCESS;pose=3.5;reached:bool=true",
        "--enum",
        "DOCKING=2",
        "--all-blackboards",
    ]);
    assert_eq!(code, Some(0), "{err}");
    let s = summary(&out);
    // `pose` is bound to `{where}`; `level` and `reached` have no attribute: their names.
    assert_eq!(s["blackboard"]["where"], 3.5);
    assert_eq!(s["blackboard"]["level"], 87);
    assert_eq!(s["blackboard"]["reached"], true);
    assert_eq!(s["blackboard"]["mode"], 2);
    assert_eq!(s["blackboards"]["/"], s["blackboard"]);
    assert!(
        s["blackboards"]["ReactiveSequence/Report"].is_object(),
        "{s}"
    );
}

#[test]
fn a_loop_int_value_prints_as_a_number_not_its_type() {
    let dir = tempfile::tempdir().unwrap();
    let tree = file(
        dir.path(),
        "loop.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
        <Sequence>
          <Script code="items := 1"/>
          <LoopInt queue="4;5;6" value="{item}"><AlwaysSuccess/></LoopInt>
        </Sequence></BehaviorTree></root>"#,
    );
    let (code, out, err) = neurotree(&["run", &tree]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(summary(&out)["blackboard"]["item"], 6, "{out}");
}

#[test]
fn a_value_set_at_a_tick_is_written_just_before_it() {
    let dir = tempfile::tempdir().unwrap();
    let wait = file(
        dir.path(),
        "until.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
        <RetryUntilSuccessful num_attempts="-1"><Sequence>
          <ScriptCondition code="go == true"/></Sequence>
        </RetryUntilSuccessful></BehaviorTree></root>"#,
    );
    let (code, out, err) = neurotree(&[
        "run",
        &wait,
        "--tick",
        "exactly-once",
        "--set",
        "go=false",
        "--set-at",
        "3:go=true",
    ]);
    assert_eq!(code, Some(0), "{err}");
    let ticks: Vec<&str> = out.lines().filter(|l| l.starts_with("{\"tick\"")).collect();
    assert_eq!(
        ticks,
        [
            r#"{"tick":1,"status":"RUNNING"}"#,
            r#"{"tick":2,"status":"RUNNING"}"#,
            r#"{"tick":3,"status":"SUCCESS"}"#
        ]
    );
    let (code, _, err) = neurotree(&["run", &wait, "--set-at", "0:go=true"]);
    assert_eq!(code, Some(2));
    assert!(err.contains("TICK:KEY=VALUE"), "{err}");
}

#[test]
fn an_unknown_enum_fails_the_script_and_a_given_one_runs() {
    let dir = tempfile::tempdir().unwrap();
    let tree = file(
        dir.path(),
        "enum.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
        <Script code="state := DOCKING"/></BehaviorTree></root>"#,
    );
    let (code, out, err) = neurotree(&["run", &tree, "--enum", "DOCKING=7"]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(summary(&out)["blackboard"]["state"], 7);
    let (code, _, _) = neurotree(&["run", &tree]);
    assert_ne!(code, Some(0));
    let (code, _, err) = neurotree(&["run", &tree, "--enum", "DOCKING=x"]);
    assert_eq!(code, Some(2));
    assert!(err.contains("integer"), "{err}");
}

const RULES: &str = r#"{
  "TestNodeConfigs": {
    "Slow": { "async_delay": 250, "return_status": "SUCCESS", "post_script": "arrived := true" }
  },
  "SubstitutionRules": { "Move*": "Slow", "battery": "AlwaysSuccess" }
}"#;

#[test]
fn a_substitution_file_replaces_unregistered_nodes() {
    let dir = tempfile::tempdir().unwrap();
    let tree = file(dir.path(), "patrol.xml", PATROL);
    let rules = file(dir.path(), "rules.json", RULES);
    let (code, out, err) = neurotree(&[
        "run",
        &tree,
        "--substitute",
        &rules,
        "--enum",
        "DOCKING=2",
        "--step-ms",
        "100",
    ]);
    assert_eq!(code, Some(0), "{err}");
    // Started at tick 1; 250 ms of 100 ms ticks later is past tick 3: done on tick 4.
    assert!(out.contains(r#"{"tick":3,"status":"RUNNING"}"#), "{out}");
    assert!(out.contains(r#"{"tick":4,"status":"SUCCESS"}"#), "{out}");
    assert_eq!(summary(&out)["blackboard"]["arrived"], true);

    let bad = file(
        dir.path(),
        "bad.json",
        "{\n  \"SubstitutionRules\": {\"a\": 1}\n}",
    );
    let (code, _, err) = neurotree(&["run", &tree, "--substitute", &bad]);
    assert_eq!(code, Some(1));
    assert!(err.contains("bad.json:2:"), "{err}");
}

/// A scenario of PATROL, with `head` first and `expect` appended.
fn scenario(dir: &Path, name: &str, head: &str, expect: &str) -> String {
    file(dir, "patrol.xml", PATROL);
    let text = format!(
        r#"{head}
tree = "patrol.xml"
main = "Main"
[mocks]
BatteryOK = "SUCCESS*2,FAILURE"
MoveBase = "RUNNING"
[enums]
DOCKING = 2
[[set]]
tick = 2
key = "target"
value = "dock"
{expect}"#
    );
    file(dir, name, &text)
}

#[test]
fn scenarios_pass_and_fail_as_cargo_test_reports() {
    let dir = tempfile::tempdir().unwrap();
    let good = scenario(
        dir.path(),
        "good.toml",
        "",
        r#"
[[expect]]
tick = 2
root = "RUNNING"
nodes = { battery = "SUCCESS", MoveBase = "RUNNING" }
blackboard = { target = "dock" }
[[expect]]
tick = 3
root = "FAILURE"
halted = ["MoveBase"]
failure = { node = "ReactiveSequence" }
"#,
    );
    let (code, out, err) = neurotree(&["test", &good]);
    assert_eq!(code, Some(0), "{out}{err}");
    assert!(out.contains("test good ... ok\n"), "{out}");
    assert!(out.ends_with("\n1 passed, 0 failed\n"), "{out}");

    let bad = scenario(
        dir.path(),
        "bad.toml",
        r#"name = "expects too much""#,
        r#"
[[expect]]
tick = 1
root = "SUCCESS"
blackboard = { target = "dock" }
"#,
    );
    let junit = dir.path().join("junit.xml");
    let (code, out, _) = neurotree(&["test", &good, &bad, "--junit", junit.to_str().unwrap()]);
    assert_eq!(code, Some(1));
    assert!(out.contains("test expects too much ... FAILED\n"), "{out}");
    assert!(
        out.contains("tick 1: root is RUNNING, expected SUCCESS"),
        "{out}"
    );
    assert!(
        out.contains("tick 1: blackboard `target` is not set, expected \"dock\""),
        "{out}"
    );
    assert_eq!(out.lines().last(), Some("1 passed, 1 failed"));

    let xml = std::fs::read_to_string(&junit).unwrap();
    let doc = roxmltree::Document::parse(&xml).expect("the JUnit file is XML");
    let suite = doc
        .descendants()
        .find(|n| n.has_tag_name("testsuite"))
        .unwrap();
    assert_eq!(suite.attribute("tests"), Some("2"));
    assert_eq!(suite.attribute("failures"), Some("1"));
    let cases: Vec<_> = suite
        .children()
        .filter(|n| n.has_tag_name("testcase"))
        .collect();
    assert_eq!(cases[0].attribute("name"), Some("good"));
    assert!(!cases[0].children().any(|n| n.has_tag_name("failure")));
    let failure = cases[1]
        .children()
        .find(|n| n.has_tag_name("failure"))
        .unwrap();
    assert_eq!(
        failure.attribute("message"),
        Some("tick 1: root is RUNNING, expected SUCCESS")
    );
}

#[test]
fn a_malformed_scenario_fails_naming_its_file_and_place() {
    let dir = tempfile::tempdir().unwrap();
    let broken = file(
        dir.path(),
        "broken.toml",
        "tree = \"x.xml\"\nticks = \"many\"\n",
    );
    let (code, out, _) = neurotree(&["test", &broken]);
    assert_eq!(code, Some(1));
    assert!(out.contains("broken.toml:2:9: error: "), "{out}");
    assert!(out.contains("neurotree test --help"), "{out}");
    assert_eq!(out.lines().last(), Some("0 passed, 1 failed"));

    let missing = scenario(
        dir.path(),
        "short.toml",
        "",
        "[[expect]]\ntick = 500\nroot = \"SUCCESS\"\n",
    );
    let (code, out, _) = neurotree(&["test", &missing]);
    assert_eq!(code, Some(1));
    assert!(
        out.contains("tick 500: not reached; the run ended after tick 3 with FAILURE"),
        "{out}"
    );
}

#[test]
fn the_repository_scenarios_pass() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    let mut files: Vec<String> = std::fs::read_dir(&root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| p.to_str().unwrap().to_string())
        .collect();
    files.sort();
    assert!(files.len() >= 5);
    let mut args = vec!["test"];
    args.extend(files.iter().map(String::as_str));
    let (code, out, err) = neurotree(&args);
    assert_eq!(code, Some(0), "{out}{err}");
    assert_eq!(
        out.lines().last().map(String::from),
        Some(format!("{} passed, 0 failed", files.len()))
    );
}
