//! BehaviorTree.CPP's side of the differential test: `btcpp_run.py` runs the whole batch
//! in one Python process with behaviortreepy, and its JSON lines become [`Step`]s.

use std::collections::BTreeMap;
use std::io::Write as _;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use super::trees::Case;
use super::Step;

/// How long the BehaviorTree.CPP process may take for the whole batch.
const PYTHON_TIMEOUT: Duration = Duration::from_secs(600);

/// The Python to run BehaviorTree.CPP with, or why the test skips.
pub fn python() -> Result<String, String> {
    let python = std::env::var("BTCPP_PYTHON")
        .map_err(|_| "BTCPP_PYTHON is not set (a Python with behaviortreepy==0.1.4)".to_string())?;
    let out = Command::new(&python)
        .args([
            "-c",
            "import importlib.metadata as m, behaviortreepy; print(m.version('behaviortreepy'))",
        ])
        .output()
        .map_err(|e| format!("cannot run BTCPP_PYTHON={python}: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "BTCPP_PYTHON={python} cannot import behaviortreepy: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    let version = String::from_utf8_lossy(&out.stdout).trim().to_string();
    if version != "0.1.4" {
        return Err(format!(
            "BTCPP_PYTHON={python} has behaviortreepy {version}; this test is pinned to 0.1.4"
        ));
    }
    Ok(python)
}

/// Runs every case through BehaviorTree.CPP in one process: its record per case id.
pub fn run(python: &str, cases: &[Case]) -> BTreeMap<usize, Result<Vec<Step>, String>> {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("cases.jsonl");
    let output = dir.path().join("results.jsonl");
    let mut f = std::fs::File::create(&input).unwrap();
    for c in cases {
        let ops: String = c.ops.iter().map(|o| o.letter()).collect();
        let line = json!({ "id": c.id, "xml": c.xml, "scripts": c.scripts, "ops": ops });
        writeln!(f, "{line}").unwrap();
    }
    drop(f);
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/differential/btcpp_run.py");
    let mut child = Command::new(python)
        .arg(&script)
        .arg(&input)
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&output).unwrap())
        .stderr(std::fs::File::create(dir.path().join("stderr.txt")).unwrap())
        .spawn()
        .expect("start the BehaviorTree.CPP driver");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > PYTHON_TIMEOUT {
            child.kill().ok();
            child.wait().ok();
            panic!(
                "the BehaviorTree.CPP driver took more than {PYTHON_TIMEOUT:?} (a tick that \
                 never ends on its side?)"
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stderr = std::fs::read_to_string(dir.path().join("stderr.txt")).unwrap_or_default();
    assert!(
        status.success(),
        "the BehaviorTree.CPP driver failed ({status}):\n{stderr}"
    );
    let text = std::fs::read_to_string(&output).unwrap();
    text.lines()
        .map(|line| {
            let v: Value = serde_json::from_str(line).expect("the driver writes JSON lines");
            let id = v["id"].as_u64().unwrap() as usize;
            if let Some(e) = v.get("load_error") {
                return (id, Err(e.to_string()));
            }
            let steps = v["steps"].as_array().unwrap().iter().map(step).collect();
            (id, Ok(steps))
        })
        .collect()
}

fn step(v: &Value) -> Step {
    let triples = |key: &str| -> Vec<[String; 3]> {
        v[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| {
                let s = |i: usize| match &t[i] {
                    Value::String(s) => s.clone(),
                    other => other.to_string(),
                };
                [s(0), s(1), s(2)]
            })
            .collect()
    };
    let error = v
        .get("error")
        .map(|e| e.as_str().unwrap_or("?").to_string());
    let outcome = match (&error, &v["status"]) {
        (Some(_), _) => "error".to_string(),
        (None, Value::String(s)) => s.clone(),
        (None, _) => "halted".to_string(),
    };
    Step {
        outcome,
        changes: triples("changes"),
        calls: triples("calls"),
        ticks: v["ticks"]
            .as_object()
            .unwrap()
            .iter()
            .map(|(k, n)| (k.clone(), n.as_u64().unwrap()))
            .collect(),
        error,
        skipped: Vec::new(),
        stale_wake: v["stale_wake"].as_bool().unwrap_or(false),
    }
}
