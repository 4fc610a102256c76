//! `neurotree campaign`: the same rows in any order, on any number of threads and in any
//! shard split; a run stopped by Ctrl-C resumed to exactly its variants; a replayed variant
//! matching its row; a fault landing on the call it names; a report whose figures are the
//! rows'.

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use neurotree::robotics::Pose2D;
use neurotree_cli::campaign::{Campaign, Results, VariantRow};
use neurotree_cli::demo::{DemoConfig, DemoRun};
use serde_json::Value;

fn neurotree(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .output()
        .unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A short campaign: 12 variants, some failing, within 600 ticks each.
const SMALL: &str = r#"
name = "small"
seed = 3
sample = 12
max_ticks = 600
[factors]
goal = ["20.5,6.5", "15.5,2.5"]
seed = { from = 0, to = 5 }
heading = { uniform = [-90, 90] }
faults = ["none", "ComputePathToPose=FAILURE@1#106", "FollowPath=FAILURE@2", "battery=10%@5s"]
"#;

fn write_campaign(dir: &Path, text: &str) -> PathBuf {
    let file = dir.join("small.toml");
    std::fs::write(&file, text).unwrap();
    file
}

fn rows(db: &Path) -> Vec<VariantRow> {
    Results::open(db).unwrap().rows().unwrap()
}

fn run_ok(args: &[&str]) -> Output {
    let out = neurotree(args);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    out
}

#[test]
fn the_rows_are_the_same_in_any_order_thread_count_and_shard_split() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_campaign(dir.path(), SMALL);
    let file = file.to_str().unwrap();
    let db = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    run_ok(&[
        "campaign",
        "run",
        file,
        "--db",
        &db("one.db"),
        "--threads",
        "1",
    ]);
    run_ok(&[
        "campaign",
        "run",
        file,
        "--db",
        &db("two.db"),
        "--threads",
        "2",
    ]);
    // Shards run last first, each on two threads, then merged.
    for shard in ["3/3", "1/3", "2/3"] {
        let name = format!("shard{}.db", &shard[..1]);
        run_ok(&[
            "campaign",
            "run",
            file,
            "--db",
            &db(&name),
            "--shard",
            shard,
        ]);
    }
    let merged = run_ok(&[
        "campaign",
        "merge",
        &db("shard3.db"),
        &db("shard1.db"),
        &db("shard2.db"),
        "-o",
        &db("all.db"),
    ]);
    assert_eq!(
        text(&merged.stdout),
        format!("12 rows merged into {}\n", db("all.db"))
    );
    let one = rows(Path::new(&db("one.db")));
    assert_eq!(one.len(), 12);
    assert_eq!(
        one.iter().map(|r| r.variant).collect::<Vec<_>>(),
        (1..=12).collect::<Vec<_>>()
    );
    // Not all alike: the campaign has outcomes to get wrong.
    assert!(one.iter().any(|r| r.outcome == "SUCCESS"));
    assert!(one.iter().any(|r| r.outcome == "FAILURE"));
    assert_eq!(rows(Path::new(&db("two.db"))), one);
    assert_eq!(rows(Path::new(&db("all.db"))), one);
    // A shard holds every third variant from its own.
    let shard2: Vec<u64> = rows(Path::new(&db("shard2.db")))
        .iter()
        .map(|r| r.variant)
        .collect();
    assert_eq!(shard2, [2, 5, 8, 11]);
    // And the library, variant by variant in reverse, gives the same rows.
    let campaign = Campaign::load(Path::new(file)).unwrap();
    for row in one.iter().rev().take(3) {
        assert_eq!(&campaign.run_variant(row.variant), row);
    }
}

#[test]
fn a_run_stopped_by_ctrl_c_resumes_to_exactly_its_variants() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_campaign(dir.path(), SMALL);
    let db = dir.path().join("stopped.db");
    let mut child = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(["campaign", "run", file.to_str().unwrap(), "--db"])
        .arg(&db)
        .args(["--threads", "1"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The plain progress lines say when variants are written: stop after the third.
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    for line in lines.by_ref() {
        if line.unwrap().contains(": 3/12 variants") {
            break;
        }
    }
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    // Drain what is left, so the child never blocks on a full pipe.
    lines.for_each(drop);
    let status = child.wait().unwrap();
    let kept = rows(&db);
    assert!(kept.len() >= 3, "{} rows kept", kept.len());
    if kept.len() < 12 {
        assert!(!status.success(), "a stopped run does not claim success");
    }
    // Without --resume the file is refused, not run again.
    let again = neurotree(&[
        "campaign",
        "run",
        file.to_str().unwrap(),
        "--db",
        db.to_str().unwrap(),
    ]);
    assert_eq!(again.status.code(), Some(1));
    assert!(
        text(&again.stderr).contains("--resume"),
        "{}",
        text(&again.stderr)
    );
    let resumed = run_ok(&[
        "campaign",
        "run",
        file.to_str().unwrap(),
        "--db",
        db.to_str().unwrap(),
        "--resume",
    ]);
    let out = text(&resumed.stdout);
    assert!(
        out.contains(&format!(
            "{} run ({} recorded before)",
            12 - kept.len(),
            kept.len()
        )),
        "{out}"
    );
    let all = rows(&db);
    assert_eq!(
        all.iter().map(|r| r.variant).collect::<Vec<_>>(),
        (1..=12).collect::<Vec<_>>()
    );
    // The rows kept are untouched, and every row is the variant's run.
    let campaign = Campaign::load(&file).unwrap();
    for row in &all {
        assert_eq!(&campaign.run_variant(row.variant), row);
    }
}

#[test]
fn a_replayed_variant_matches_its_row_and_a_changed_row_does_not() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_campaign(dir.path(), SMALL);
    let db = dir.path().join("replay.db");
    let db_text = db.to_str().unwrap();
    run_ok(&[
        "campaign",
        "run",
        file.to_str().unwrap(),
        "--db",
        db_text,
        "--limit",
        "4",
    ]);
    let failed = rows(&db)
        .into_iter()
        .find(|r| r.outcome == "FAILURE")
        .expect("a failing variant among the first four");
    let variant = failed.variant.to_string();
    let out = run_ok(&["campaign", "replay", db_text, &variant, "--trace"]);
    let stdout = text(&out.stdout);
    assert!(stdout.contains("matches the recorded row"), "{stdout}");
    assert!(
        stdout.contains(&format!("  ticks          {}\n", failed.ticks)),
        "{stdout}"
    );
    // One trace line per tick.
    assert_eq!(
        stdout.lines().filter(|l| l.starts_with("tick ")).count(),
        failed.ticks as usize
    );
    let conn = rusqlite::Connection::open(&db).unwrap();
    conn.execute(
        "UPDATE variants SET ticks = ticks + 1 WHERE variant = ?1",
        [failed.variant as i64],
    )
    .unwrap();
    let changed = neurotree(&["campaign", "replay", db_text, &variant]);
    assert_eq!(changed.status.code(), Some(1));
    assert!(text(&changed.stdout).contains("differs from the recorded row"));
    let missing = neurotree(&["campaign", "replay", db_text, "99"]);
    assert_eq!(missing.status.code(), Some(1));
    assert!(text(&missing.stderr).contains("no row of variant 99"));
}

#[test]
fn a_planner_fault_lands_on_the_call_it_names() {
    for call in 1..=4 {
        let config = DemoConfig {
            faults: vec![format!("ComputePathToPose=FAILURE@{call}#106")
                .parse()
                .unwrap()],
            goal: Pose2D::new(36.5, 1.5, 0.0),
            ..DemoConfig::default()
        };
        let mut demo = DemoRun::new(&config).unwrap();
        while demo.fault_hits().is_empty() && !demo.is_over() {
            demo.tick();
        }
        let hits = demo.fault_hits();
        assert_eq!(hits.len(), 1, "call {call}");
        assert_eq!(hits[0].call, call);
        // The calls before it planned; the faulted one did not.
        assert_eq!(demo.sim().plans(), call - 1, "call {call}");
        let code: u16 = demo
            .tree_mut()
            .blackboard()
            .get("compute_path_error_code")
            .unwrap();
        assert_eq!(code, 106);
    }
}

#[test]
fn the_report_figures_are_the_rows() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_campaign(dir.path(), SMALL);
    let db = dir.path().join("report.db");
    let db_text = db.to_str().unwrap();
    run_ok(&[
        "campaign",
        "run",
        file.to_str().unwrap(),
        "--db",
        db_text,
        "--limit",
        "8",
    ]);
    let out = run_ok(&["campaign", "report", db_text, "--format", "json"]);
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    let conn = rusqlite::Connection::open(&db).unwrap();
    let count = |sql: &str| -> i64 { conn.query_row(sql, [], |r| r.get(0)).unwrap() };
    let total = count("SELECT COUNT(*) FROM variants");
    let ok = count("SELECT COUNT(*) FROM variants WHERE outcome = 'SUCCESS'");
    assert_eq!(report["variants"], total);
    assert_eq!(
        report["success_rate"].as_f64().unwrap(),
        ok as f64 / total as f64
    );
    // Per factor value, from the rows' JSON.
    let all = rows(&db);
    let mut by_fault: BTreeMap<String, (u32, u32)> = BTreeMap::new();
    for row in &all {
        let e = by_fault
            .entry(row.factors["faults"].as_str().unwrap().to_string())
            .or_default();
        e.0 += 1;
        e.1 += u32::from(row.outcome == "SUCCESS");
    }
    let faults = report["factors"]["faults"].as_array().unwrap();
    assert_eq!(faults.len(), by_fault.len());
    for entry in faults {
        let (n, ok) = by_fault[entry["value"].as_str().unwrap()];
        assert_eq!(entry["variants"], n);
        assert_eq!(
            entry["success_rate"].as_f64().unwrap(),
            f64::from(ok) / f64::from(n)
        );
    }
    let failures: u64 = report["failures"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["count"].as_u64().unwrap())
        .sum();
    assert_eq!(failures as i64, total - ok);
    let md = run_ok(&[
        "campaign",
        "report",
        db_text,
        "--svg",
        dir.path().join("r.svg").to_str().unwrap(),
    ]);
    let md = text(&md.stdout);
    let pct = format!(
        "{total} variants, {:.1} % succeeded.",
        100.0 * ok as f64 / total as f64
    );
    assert!(md.contains(&pct), "{md}");
    let svg = std::fs::read_to_string(dir.path().join("r.svg")).unwrap();
    assert_eq!(svg.matches("<rect").count(), all_values(&report));
}

/// The number of factor values the report lists.
fn all_values(report: &Value) -> usize {
    report["factors"]
        .as_object()
        .unwrap()
        .values()
        .map(|v| v.as_array().unwrap().len())
        .sum()
}

#[test]
fn a_bad_campaign_file_is_refused_with_its_place() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_campaign(dir.path(), "grid = true\n[factors]\nbattery = [50, 150]\n");
    let out = neurotree(&[
        "campaign",
        "run",
        file.to_str().unwrap(),
        "--db",
        dir.path().join("x.db").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.contains("small.toml:3:11: error: a battery level is 0 to 100 percent, not 150"),
        "{err}"
    );
    let file = write_campaign(dir.path(), "grid = true\n[factors]\nwind = [1]\n");
    let out = neurotree(&[
        "campaign",
        "run",
        file.to_str().unwrap(),
        "--db",
        dir.path().join("x.db").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("small.toml:3:1: error: unknown factor `wind`"));
}

mod random_trees {
    //! Over random trees of Nav2's simulated leaves and random faults: a campaign's rows
    //! are the same whatever the order and the threads they are run in.

    use super::*;
    use proptest::prelude::*;

    const LEAVES: [&str; 6] = [
        r#"<ComputePathToPose goal="{goal}" path="{path}" error_code_id="{cp_code}"/>"#,
        r#"<FollowPath path="{path}" error_code_id="{fp_code}"/>"#,
        r#"<Spin spin_dist="1.57"/>"#,
        r#"<Wait wait_duration="0.5"/>"#,
        r#"<BackUp backup_dist="0.3" backup_speed="0.1"/>"#,
        r#"<ClearEntireCostmap service_name="local_costmap/clear_entirely_local_costmap"/>"#,
    ];

    /// A tree of Sequences, Fallbacks and RecoveryNodes over the leaves.
    fn tree() -> impl Strategy<Value = String> {
        let leaf = (0..LEAVES.len()).prop_map(|i| LEAVES[i].to_string());
        leaf.prop_recursive(3, 12, 3, |inner| {
            (0..3usize, prop::collection::vec(inner, 2..=3)).prop_map(|(kind, children)| {
                let body = children.concat();
                match kind {
                    0 => format!("<Sequence>{body}</Sequence>"),
                    1 => format!("<Fallback>{body}</Fallback>"),
                    _ => format!(
                        r#"<RecoveryNode number_of_retries="2">{}{}</RecoveryNode>"#,
                        children[0], children[1]
                    ),
                }
            })
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(12))]
        #[test]
        fn rows_do_not_depend_on_order_or_threads(
            body in tree(),
            seed in 0u64..1000,
            fault_calls in prop::collection::vec(1u32..4, 2),
        ) {
            let dir = tempfile::tempdir().unwrap();
            std::fs::write(
                dir.path().join("tree.xml"),
                format!(r#"<root BTCPP_format="4"><BehaviorTree ID="T">{body}</BehaviorTree></root>"#),
            )
            .unwrap();
            let faults = [
                "\"none\"".to_string(),
                format!("\"Wait=FAILURE@{}\"", fault_calls[0]),
                format!("\"ComputePathToPose=FAILURE@{}#208\"", fault_calls[1]),
                "\"FollowPath*2\"".to_string(),
            ];
            let text = format!(
                "tree = \"tree.xml\"\nseed = {seed}\nsample = 6\nmax_ticks = 300\n\
                 [factors]\nseed = {{ from = 0, to = 9 }}\nheading = {{ uniform = [-180, 180] }}\n\
                 faults = [{}]\n",
                faults.join(", ")
            );
            let file = dir.path().join("random.toml");
            std::fs::write(&file, &text).unwrap();
            let campaign = Campaign::load(&file).unwrap();
            let forward: Vec<u64> = (1..=6).collect();
            let backward: Vec<u64> = forward.iter().rev().copied().collect();
            let one = Results::open(&dir.path().join("one.db")).unwrap();
            one.claim(&campaign).unwrap();
            campaign.run_into(&one, &forward, 1, &mut |_| {}).unwrap();
            let two = Results::open(&dir.path().join("two.db")).unwrap();
            two.claim(&campaign).unwrap();
            campaign.run_into(&two, &backward, 2, &mut |_| {}).unwrap();
            let rows = one.rows().unwrap();
            prop_assert_eq!(rows.len(), 6);
            // The only error: a fault of a type the random tree does not have.
            prop_assert!(
                rows.iter()
                    .all(|r| !r.outcome.starts_with("error") || r.outcome.contains("names no node")),
                "{:?}",
                rows
            );
            prop_assert_eq!(&rows, &two.rows().unwrap());
            // And one variant alone, outside any pool, gives its row.
            prop_assert_eq!(&campaign.run_variant(4), &rows[3]);
        }
    }
}

#[test]
fn a_variant_that_panics_is_a_row_and_every_other_row_is_kept() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_campaign(
        dir.path(),
        r#"
name = "panics"
grid = true
max_ticks = 600
[factors]
goal = ["20.5,6.5", "15.5,2.5"]
faults = ["none", "FollowPath=PANIC@1", "ComputePathToPose=FAILURE@1"]
"#,
    );
    let file = file.to_str().unwrap();
    let db = dir.path().join("panics.db");
    let db = db.to_str().unwrap();
    let out = run_ok(&["campaign", "run", file, "--db", db, "--threads", "2"]);
    // The panics are the rows' outcomes, not messages on stderr.
    let stderr = text(&out.stderr);
    assert!(
        !stderr.contains("panicked") && !stderr.contains("injected fault"),
        "{stderr}"
    );
    let all = rows(Path::new(db));
    assert_eq!(
        all.iter().map(|r| r.variant).collect::<Vec<_>>(),
        (1..=6).collect::<Vec<_>>(),
        "{}",
        text(&out.stderr)
    );
    let faults_of = |row: &VariantRow| row.factors["faults"].as_str().unwrap().to_string();
    for row in &all {
        match faults_of(row).as_str() {
            "FollowPath=PANIC@1" => assert!(
                row.outcome.starts_with("error: ")
                    && row.outcome.contains("injected fault: ")
                    && row.outcome.contains("FollowPath panics on its call 1"),
                "{}",
                row.outcome
            ),
            "none" => assert_eq!(row.outcome, "SUCCESS"),
            _ => assert_eq!(row.outcome, "FAILURE"),
        }
    }
    assert_eq!(
        all.iter()
            .filter(|r| faults_of(r) == "FollowPath=PANIC@1")
            .count(),
        2
    );
    // Resuming finds nothing missing and adds nothing.
    let resumed = run_ok(&["campaign", "run", file, "--db", db, "--resume"]);
    assert!(
        text(&resumed.stdout).contains("0 run (6 recorded before)"),
        "{}",
        text(&resumed.stdout)
    );
    assert_eq!(rows(Path::new(db)), all);
}

#[test]
fn a_panic_outside_the_tree_is_the_rows_outcome_too() {
    // A panic the tick does not catch (here in what watches the run) still ends as the
    // variant's row, not the caller's panic.
    let dir = tempfile::tempdir().unwrap();
    let campaign = Campaign::load(&write_campaign(dir.path(), SMALL)).unwrap();
    let mut ticks = 0;
    let row = campaign.run_variant_watched(4, &mut |_| {
        ticks += 1;
        if ticks == 3 {
            panic!("the watcher broke at tick {ticks}");
        }
    });
    assert_eq!(row.variant, 4);
    assert_eq!(row.outcome, "error: panicked: the watcher broke at tick 3");
    assert_eq!(row.factors, campaign.run_variant(4).factors);
}

/// Three variants: no fault, a controller fault, and two planner faults after which
/// the navigator's two `WouldAPlannerRecoveryHelp` answer differently (a scenario says
/// them by path); then one whose fault panics.
const REPLAYED: &str = r#"
name = "replayed"
grid = true
max_ticks = 600
[factors]
faults = ["none", "FollowPath=FAILURE@2",
          "ComputePathToPose=FAILURE@1#208 + ComputePathToPose=FAILURE@2#201",
          "ComputePathToPose=PANIC@1"]
"#;

#[test]
fn a_variant_written_as_a_scenario_passes_neurotree_test_and_an_edited_outcome_fails() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("replayed.toml");
    std::fs::write(&file, REPLAYED).unwrap();
    let db = dir.path().join("replayed.db");
    let db_text = db.to_str().unwrap();
    run_ok(&["campaign", "run", file.to_str().unwrap(), "--db", db_text]);
    let rows = rows(&db);
    for row in &rows[..3] {
        let scenario = dir.path().join(format!("variant{}.toml", row.variant));
        let scenario_text = scenario.to_str().unwrap();
        let n = row.variant.to_string();
        let out = run_ok(&[
            "campaign",
            "replay",
            db_text,
            &n,
            "--scenario",
            scenario_text,
        ]);
        assert!(
            text(&out.stdout).contains(&format!("scenario written to {scenario_text}")),
            "{}",
            text(&out.stdout)
        );
        let written = std::fs::read_to_string(&scenario).unwrap();
        assert!(
            written.contains(&format!("tick = {}\nroot = \"{}\"", row.ticks, row.outcome)),
            "{written}"
        );
        // The navigator is written beside it.
        assert!(dir.path().join(format!("variant{n}.xml")).exists());
        let tested = run_ok(&["test", scenario_text]);
        assert!(
            text(&tested.stdout).ends_with("1 passed, 0 failed\n"),
            "{}",
            text(&tested.stdout)
        );
        // Another outcome expected: the scenario fails.
        let other = if row.outcome == "SUCCESS" {
            "FAILURE"
        } else {
            "SUCCESS"
        };
        std::fs::write(
            &scenario,
            written.replace(
                &format!("root = \"{}\"", row.outcome),
                &format!("root = \"{other}\""),
            ),
        )
        .unwrap();
        let failed = neurotree(&["test", scenario_text]);
        assert_eq!(failed.status.code(), Some(1), "{}", text(&failed.stdout));
        assert!(
            text(&failed.stdout).contains(&format!(
                "tick {}: root is {}, expected {other}",
                row.ticks, row.outcome
            )),
            "{}",
            text(&failed.stdout)
        );
        if row.variant == 3 {
            // The two leaves of one name that answered differently, by path.
            for fault in [
                "\"NavigateRecovery/NavigateWithReplanning/RateController/ComputePathToPose/Sequence/WouldAPlannerRecoveryHelp=SUCCESS@1\"",
                "\"NavigateRecovery/Sequence/Fallback/WouldAPlannerRecoveryHelp=FAILURE@1\"",
            ] {
                assert!(written.contains(fault), "{written}");
            }
            assert!(
                !written.contains("\"WouldAPlannerRecoveryHelp\" ="),
                "{written}"
            );
        }
    }
    // A variant that ended in a panic has no status to expect.
    assert!(
        rows[3].outcome.starts_with("error: ") && rows[3].outcome.contains("panicked"),
        "{:?}",
        rows[3]
    );
    let scenario = dir.path().join("variant4.toml");
    let out = neurotree(&[
        "campaign",
        "replay",
        db_text,
        "4",
        "--scenario",
        scenario.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("variant 4 ended in an error"),
        "{}",
        text(&out.stderr)
    );
    assert!(!scenario.exists());

    // Beside a file of its own of the navigator's name, no scenario is written over it.
    let mine = dir.path().join("mine.xml");
    std::fs::write(&mine, "<root/>").unwrap();
    let out = neurotree(&[
        "campaign",
        "replay",
        db_text,
        "1",
        "--scenario",
        dir.path().join("mine.toml").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("mine.xml is another file; give the scenario another name"),
        "{}",
        text(&out.stderr)
    );
    assert_eq!(std::fs::read_to_string(&mine).unwrap(), "<root/>");
    assert!(!dir.path().join("mine.toml").exists());
}
