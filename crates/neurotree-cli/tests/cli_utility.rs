//! `neurotree run` drives a UtilitySelector through `--set` and `--set-at`, as any
//! blackboard input.

use std::process::Command;

use serde_json::Value;

/// Three Running leaves scored by the entries `a`, `b` and `c`.
const CHOOSE: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <UtilitySelector>
      <Utility score="{a}"><Action ID="A"/></Utility>
      <Utility score="{b}"><Action ID="B"/></Utility>
      <Utility score="{c}"><Action ID="C"/></Utility>
    </UtilitySelector>
  </BehaviorTree>
</root>"#;

/// The exit status and the summary of `neurotree run CHOOSE` with the three leaves mocked
/// Running, the scores 1, 5, 2, `c` set to 9 before tick 3, for `ticks` ticks.
fn run(ticks: u32) -> (Option<i32>, Value) {
    let dir = tempfile::tempdir().unwrap();
    let tree = dir.path().join("choose.xml");
    std::fs::write(&tree, CHOOSE).unwrap();
    let bin = std::env::var("NEUROTREE_BIN")
        .unwrap_or_else(|_| env!("CARGO_BIN_EXE_neurotree").to_string());
    let max = ticks.to_string();
    let out = Command::new(bin)
        .args([
            "run",
            tree.to_str().unwrap(),
            "--mock",
            "A=RUNNING",
            "--mock",
            "B=RUNNING",
            "--mock",
            "C=RUNNING",
            "--set",
            "a=1",
            "--set",
            "b=5",
            "--set",
            "c=2",
            "--set-at",
            "3:c=9",
            "--max-ticks",
            &max,
        ])
        .output()
        .expect("the neurotree binary runs");
    let stdout = String::from_utf8(out.stdout).unwrap();
    let last = stdout.lines().last().expect("a summary line");
    let summary = serde_json::from_str::<Value>(last).unwrap()["summary"].clone();
    (out.status.code(), summary)
}

/// `(ticks, halts)` of node `name` in a summary.
fn counts(summary: &Value, name: &str) -> (u64, u64) {
    let node = &summary["nodes"][name];
    (
        node["ticks"].as_u64().unwrap(),
        node["halts"].as_u64().unwrap(),
    )
}

#[test]
fn b_runs_on_ticks_1_and_2_then_is_halted_once_and_c_runs_from_tick_3() {
    let (code, two) = run(2);
    // --max-ticks stopped the run while it was Running.
    assert_eq!(code, Some(3));
    assert_eq!(counts(&two, "A"), (0, 0));
    assert_eq!(counts(&two, "B"), (2, 0));
    assert_eq!(counts(&two, "C"), (0, 0));
    let (code, five) = run(5);
    assert_eq!(code, Some(3));
    assert_eq!(counts(&five, "A"), (0, 0));
    assert_eq!(counts(&five, "B"), (2, 1));
    assert_eq!(counts(&five, "C"), (3, 0));
    assert_eq!(five["blackboard"]["c"], 9);
}
