//! `neurotree run --resume` is the run: random trees of the nodes that keep time or state
//! (Timeout, Delay, Sleep, Cooldown, RunOnce, Repeat and Retry counters, Parallel, the
//! reactive controls, Nav2's RateController, SingleTrigger, RecoveryNode, PipelineSequence,
//! RoundRobin) over mocks, resumed from the state kept after every tick, print what the
//! uninterrupted run printed after that tick: statuses, trace, summary and blackboard.

use std::path::Path;
use std::process::{Command, Output};

use proptest::prelude::*;
use proptest::test_runner::TestCaseError;

fn neurotree(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn lines(out: &Output) -> Vec<String> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(str::to_string)
        .collect()
}

/// The lines a run printed after tick `n`'s line.
fn after_tick(all: &[String], n: u32) -> Vec<String> {
    let mark = format!("{{\"tick\":{n},\"status\"");
    let at = all
        .iter()
        .position(|l| l.starts_with(&mark))
        .unwrap_or_else(|| panic!("no line of tick {n} in {all:#?}"));
    all[at + 1..].to_vec()
}

/// A tree node as XML, with the leaves it names (`L0`, `L1`, …) mocked by the caller.
#[derive(Clone, Debug)]
enum Node {
    Leaf,
    Script,
    Control(&'static str, String, Vec<Node>),
    Decorator(&'static str, String, Box<Node>),
}

fn xml(node: &Node, leaves: &mut usize, out: &mut String) {
    match node {
        Node::Leaf => {
            out.push_str(&format!("<Work name=\"L{leaves}\"/>"));
            *leaves += 1;
        }
        Node::Script => out.push_str("<Script code=\"n := n + 1\"/>"),
        Node::Control(name, attrs, kids) => {
            out.push_str(&format!("<{name}{attrs}>"));
            for k in kids {
                xml(k, leaves, out);
            }
            out.push_str(&format!("</{name}>"));
        }
        Node::Decorator(name, attrs, kid) => {
            out.push_str(&format!("<{name}{attrs}>"));
            xml(kid, leaves, out);
            out.push_str(&format!("</{name}>"));
        }
    }
}

fn millis() -> impl Strategy<Value = u32> {
    prop_oneof![Just(0), (1u32..6).prop_map(|n| n * 100), 1u32..500]
}

fn tree() -> impl Strategy<Value = Node> {
    let leaf = prop_oneof![6 => Just(Node::Leaf), 1 => Just(Node::Script)];
    leaf.prop_recursive(3, 40, 4, |inner| {
        let kids = proptest::collection::vec(inner.clone(), 1..=3);
        let controls = prop_oneof![
            Just("Sequence"),
            Just("Fallback"),
            Just("ReactiveSequence"),
            Just("ReactiveFallback"),
            Just("SequenceWithMemory"),
            Just("PipelineSequence"),
            Just("RoundRobin"),
        ];
        let decorators = prop_oneof![
            millis().prop_map(|ms| ("Timeout", format!(" msec=\"{ms}\""))),
            millis().prop_map(|ms| ("Delay", format!(" delay_msec=\"{ms}\""))),
            millis().prop_map(|ms| ("Cooldown", format!(" cooldown_msec=\"{ms}\""))),
            (1u32..4).prop_map(|n| ("Repeat", format!(" num_cycles=\"{n}\""))),
            (1u32..4).prop_map(|n| ("RetryUntilSuccessful", format!(" num_attempts=\"{n}\""))),
            Just(("RunOnce", String::new())),
            Just(("KeepRunningUntilFailure", String::new())),
            prop_oneof![Just(1.0), Just(2.5), Just(10.0)]
                .prop_map(|hz| ("RateController", format!(" hz=\"{hz}\""))),
            Just(("SingleTrigger", String::new())),
        ];
        prop_oneof![
            4 => (controls, kids.clone()).prop_map(|(c, k)| Node::Control(c, String::new(), k)),
            1 => kids.clone().prop_flat_map(|k| {
                let n = k.len() as i32;
                (Just(k), 1..=n, 1..=n).prop_map(|(k, s, f)| {
                    Node::Control("Parallel", format!(" success_count=\"{s}\" failure_count=\"{f}\""), k)
                })
            }),
            1 => (inner.clone(), inner.clone())
                .prop_map(|(a, b)| Node::Control("RecoveryNode", " number_of_retries=\"2\"".into(), vec![a, b])),
            1 => millis().prop_map(|ms| Node::Control("Sleep", format!(" msec=\"{ms}\""), vec![])),
            4 => (decorators, inner).prop_map(|((d, a), k)| Node::Decorator(d, a, Box::new(k))),
        ]
    })
}

fn outcomes() -> impl Strategy<Value = String> {
    let one = prop_oneof![
        3 => (1u32..4).prop_map(|k| format!("RUNNING*{k}")),
        2 => Just("SUCCESS".to_string()),
        2 => Just("FAILURE".to_string()),
    ];
    proptest::collection::vec(one, 1..5).prop_map(|v| v.join(","))
}

fn check(root: &Node, mocks: &[String], step_ms: u32, dir: &Path) -> Result<(), TestCaseError> {
    let mut body = String::new();
    let mut leaves = 0;
    xml(root, &mut leaves, &mut body);
    let file = dir.join("tree.xml");
    std::fs::write(
        &file,
        format!(
            "<root BTCPP_format=\"4\"><BehaviorTree ID=\"M\"><Sequence><Script code=\"n := 0\"/>{body}</Sequence></BehaviorTree></root>"
        ),
    )
    .unwrap();
    let states = dir.join("states");
    let step = step_ms.to_string();
    let mut args: Vec<String> = [
        "run",
        file.to_str().unwrap(),
        "--trace",
        "--max-ticks",
        "24",
    ]
    .into_iter()
    .map(String::from)
    .collect();
    args.extend(["--step-ms".into(), step]);
    for (i, m) in mocks.iter().take(leaves).enumerate() {
        args.extend(["--mock".into(), format!("L{i}={m}")]);
    }
    for i in mocks.len()..leaves {
        args.extend(["--mock".into(), format!("L{i}=RUNNING,SUCCESS")]);
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let whole = neurotree(&args);
    prop_assert!(
        matches!(whole.status.code(), Some(0 | 2 | 3)),
        "{}",
        String::from_utf8_lossy(&whole.stderr)
    );
    let all = lines(&whole);
    let mut kept_args = args.clone();
    let states_dir = states.to_str().unwrap();
    kept_args.extend(["--keep-states", "1", "--states-dir", states_dir]);
    let kept = neurotree(&kept_args);
    prop_assert_eq!(
        lines(&kept),
        all.clone(),
        "keeping states changes nothing printed"
    );
    // The ticks that ended with a line of their own (a pass of the root that a node asked
    // for at once shares the line of the tick it belongs to), the last one aside.
    let mut ticks: Vec<u32> = all
        .iter()
        .filter(|l| l.starts_with("{\"tick\":") && l.contains(",\"status\":"))
        .filter_map(|l| l["{\"tick\":".len()..].split(',').next()?.parse().ok())
        .collect();
    ticks.pop();
    for cut in ticks {
        let state = states.join(format!("tick-{cut}.state"));
        prop_assert!(state.exists(), "no state kept after tick {}", cut);
        let mut resumed = args.clone();
        resumed.extend(["--resume", state.to_str().unwrap()]);
        let rest = neurotree(&resumed);
        prop_assert_eq!(
            lines(&rest),
            after_tick(&all, cut),
            "resumed after tick {}:\n{}",
            cut,
            String::from_utf8_lossy(&rest.stderr)
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    #[test]
    fn a_run_resumed_after_any_tick_prints_what_the_uninterrupted_run_printed(
        root in tree(),
        mocks in proptest::collection::vec(outcomes(), 12),
        step_ms in prop_oneof![Just(100u32), Just(50), Just(250), 1u32..300],
    ) {
        let dir = tempfile::tempdir().unwrap();
        check(&root, &mocks, step_ms, dir.path())?;
    }
}

/// The two runs of a Timeout over a mock that stays RUNNING, with `--step-ms 100`: one where
/// the Timeout starts at the first tick (it fails at tick 6), one where it starts after a
/// Sequence's first child (at tick 9).
#[test]
fn a_running_timeout_resumed_fails_at_the_tick_the_uninterrupted_run_does() {
    let dir = tempfile::tempdir().unwrap();
    for (body, mocks, cut, fails_at) in [
        (
            "<Timeout msec=\"500\"><Work/></Timeout>",
            vec!["Work=RUNNING"],
            3,
            6,
        ),
        (
            "<Sequence><Step/><Timeout msec=\"500\"><Work/></Timeout></Sequence>",
            vec!["Step=RUNNING*3,SUCCESS", "Work=RUNNING"],
            6,
            9,
        ),
    ] {
        let file = dir.path().join("t.xml");
        std::fs::write(
            &file,
            format!("<root BTCPP_format=\"4\"><BehaviorTree ID=\"M\">{body}</BehaviorTree></root>"),
        )
        .unwrap();
        let mut args = vec!["run", file.to_str().unwrap(), "--step-ms", "100"];
        for m in &mocks {
            args.extend(["--mock", m]);
        }
        let whole = lines(&neurotree(&args));
        let failure = format!("{{\"tick\":{fails_at},\"status\":\"FAILURE\"}}");
        assert!(whole.contains(&failure), "{whole:#?}");
        let state = dir.path().join("cut.state");
        let cut_text = cut.to_string();
        let mut first = args.clone();
        first.extend([
            "--stop-after",
            &cut_text,
            "--save-state",
            state.to_str().unwrap(),
        ]);
        assert_eq!(neurotree(&first).status.code(), Some(3));
        let mut rest = args.clone();
        rest.extend(["--resume", state.to_str().unwrap()]);
        assert_eq!(lines(&neurotree(&rest)), after_tick(&whole, cut), "{body}");
    }
}
