//! The tools `neurotree mcp` serves, each on the code of the command it stands for: a
//! tree's XML text in `xml`, a JSON result out (or a message saying what to fix).
//!
//! `check_tree` and `lint_tree` load the text itself; `show_tree`, `run_tree` and
//! `run_scenario` write it into the call's scratch folder and run `neurotree show`, `run`
//! and `test` on it, parsed from the same command line as the binary's;
//! `simulate_nav2` runs the demo's simulated robot with it.

use std::path::{Path, PathBuf};

use clap::Parser;
use neurotree::lint::LintOptions;
use neurotree::nav2::Nav2Release;
use neurotree::{PortDirection, Registry};
use serde_json::{json, Map, Value};

use crate::registry::Nav2Args;
use crate::{check, lint, Cli, Command, Outcome};

/// The longest tree text a tool takes, in bytes.
pub const MAX_XML_BYTES: usize = 1 << 20;
/// The most ticks `run_tree` and `run_scenario` run.
pub const MAX_RUN_TICKS: u32 = 10_000;
/// The most ticks (of 100 ms) `simulate_nav2` runs: ten simulated minutes.
pub const MAX_SIM_TICKS: u32 = 6_000;

/// What one tool is: its name, what it does, and its arguments' JSON Schema.
struct Tool {
    name: &'static str,
    description: &'static str,
    properties: fn() -> Value,
    required: &'static [&'static str],
}

fn xml_property() -> Value {
    json!({ "type": "string", "description": "The tree file's text: BehaviorTree.CPP 4 XML (<root BTCPP_format=\"4\">...)." })
}

fn nav2_property() -> Value {
    json!({ "type": "boolean", "description": "Know Nav2's 81 node types (and, for lint, the entries its navigators write and read)." })
}

fn model_property() -> Value {
    json!({ "type": "string", "description": "A TreeNodesModel XML text declaring node types the tree uses." })
}

fn tree_property() -> Value {
    json!({ "type": "string", "description": "The tree ID to work on (default: main_tree_to_execute, else the only tree)." })
}

const TOOLS: &[Tool] = &[
    Tool {
        name: "list_node_types",
        description: "List the node types NeuroTree knows: the built-ins, Nav2's (nav2: true), and a model's: category, description, and ports (direction, type, default, description).",
        properties: || json!({ "nav2": nav2_property(), "model_xml": model_property() }),
        required: &[],
    },
    Tool {
        name: "check_tree",
        description: "Check a tree as BehaviorTree.CPP loads it (structure, node types, ports, literals): each error with line, column and what to change.",
        properties: || json!({ "xml": xml_property(), "nav2": nav2_property(), "model_xml": model_property() }),
        required: &["xml"],
    },
    Tool {
        name: "lint_tree",
        description: "Check a tree, then find what it does wrong without running it: entries read before written, type mismatches, unreachable children, loops that never end. Each finding has a code (NT0101), a severity, a line and a column.",
        properties: || json!({
            "xml": xml_property(), "nav2": nav2_property(), "model_xml": model_property(), "tree": tree_property(),
            "entries": { "type": "array", "items": { "type": "string" }, "description": "Entries the application writes before the first tick." },
        }),
        required: &["xml"],
    },
    Tool {
        name: "show_tree",
        description: "Draw a tree as indented text, Mermaid (for Markdown) or SVG.",
        properties: || json!({
            "xml": xml_property(), "tree": tree_property(), "nav2": nav2_property(),
            "format": { "type": "string", "enum": ["text", "ascii", "mermaid", "svg", "dot"], "description": "text (default), ascii, mermaid, svg or dot." },
        }),
        required: &["xml"],
    },
    Tool {
        name: "run_tree",
        description: "Run a tree with mock leaves on a manual clock (100 ms a tick): each tick's status, the final status, the chain of nodes that failed, per-node ticks and halts, coverage. Leaves without an implementation succeed unless mocked.",
        properties: || json!({
            "xml": xml_property(), "tree": tree_property(), "nav2": nav2_property(),
            "mocks": { "type": "object", "additionalProperties": { "type": "string" }, "description": "Leaf name (or type) -> outcomes, one per tick, the last repeated: \"RUNNING*2,SUCCESS\"; outputs after `;`: \"SUCCESS;pose=1;2\"." },
            "inputs": { "type": "object", "description": "Root blackboard entries written before the first tick: key -> value." },
            "max_ticks": { "type": "integer", "minimum": 1, "maximum": MAX_RUN_TICKS, "description": "Stop after this many ticks (default 100)." },
        }),
        required: &["xml"],
    },
    Tool {
        name: "run_scenario",
        description: "Run a scenario (TOML, as `neurotree test` reads it: mocks, inputs and expected statuses per tick) against the tree: passed or failed, and why. The scenario's `tree` is this tree.",
        properties: || json!({
            "xml": xml_property(),
            "scenario": { "type": "string", "description": "The scenario file's TOML text; its `tree` names the tree file, which is `xml`." },
        }),
        required: &["xml", "scenario"],
    },
    Tool {
        name: "simulate_nav2",
        description: "Run a Nav2 navigator tree (default: Nav2's navigate_to_pose_w_replanning_and_recovery) on the demo's simulated robot in a warehouse: arrived or Nav2's error codes, ticks, distance, recoveries.",
        properties: || json!({
            "xml": { "type": "string", "description": "A navigator tree's XML; it may use Nav2's control nodes and the simulated leaves (ComputePathToPose, FollowPath, Spin, ...)." },
            "goal": { "type": "array", "items": { "type": "number" }, "minItems": 2, "maxItems": 2, "description": "Where to send the robot: [x, y] in metres (default [36.5, 1.5])." },
            "seed": { "type": "integer", "minimum": 0, "description": "Picks the obstacle that steps onto the path (default 0)." },
            "max_ticks": { "type": "integer", "minimum": 1, "maximum": MAX_SIM_TICKS, "description": "Stop after this many ticks of 100 ms (default 3000)." },
        }),
        required: &[],
    },
];

/// The tools, as `tools/list` lists them.
pub fn list() -> Vec<Value> {
    TOOLS
        .iter()
        .map(|t| {
            json!({
                "name": t.name,
                "description": t.description,
                "inputSchema": { "type": "object", "properties": (t.properties)(), "required": t.required },
            })
        })
        .collect()
}

/// Whether a tool is named `name`.
pub fn exists(name: &str) -> bool {
    TOOLS.iter().any(|t| t.name == name)
}

/// Runs the tool `name` with `args`, its files in `dir` (made here): its result, or what
/// is wrong with the call.
pub fn call(name: &str, args: &Value, dir: &Path) -> Result<Value, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot make the call's folder: {e}"))?;
    match name {
        "list_node_types" => list_node_types(args),
        "check_tree" => check_tree(args),
        "lint_tree" => lint_tree(args),
        "show_tree" => show_tree(args, dir),
        "run_tree" => run_tree(args, dir),
        "run_scenario" => run_scenario(args, dir),
        "simulate_nav2" => simulate_nav2(args, dir),
        other => Err(format!("no tool `{other}`")),
    }
}

/// The string argument `name`, if given; an error if it is not a string or too long.
fn text<'a>(args: &'a Value, name: &str) -> Result<Option<&'a str>, String> {
    match args.get(name) {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(s)) if s.len() <= MAX_XML_BYTES => Ok(Some(s)),
        Some(Value::String(s)) => Err(format!(
            "`{name}` is {} bytes; the most a call takes is {MAX_XML_BYTES}",
            s.len()
        )),
        Some(_) => Err(format!("`{name}` must be a string")),
    }
}

/// The tree's XML, which the tool needs.
fn xml(args: &Value) -> Result<&str, String> {
    text(args, "xml")?.ok_or_else(|| "give the tree's XML text in `xml`".to_string())
}

fn flag(args: &Value, name: &str) -> Result<bool, String> {
    match args.get(name) {
        None | Some(Value::Null) => Ok(false),
        Some(Value::Bool(b)) => Ok(*b),
        Some(_) => Err(format!("`{name}` must be true or false")),
    }
}

/// The integer argument `name`, between 1 and `most`.
fn count(args: &Value, name: &str, most: u32) -> Result<Option<u32>, String> {
    match args.get(name) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => match v.as_u64() {
            Some(n) if (1..=u64::from(most)).contains(&n) => Ok(Some(n as u32)),
            _ => Err(format!("`{name}` must be an integer from 1 to {most}")),
        },
    }
}

fn nav2(args: &Value) -> Result<Nav2Args, String> {
    Ok(Nav2Args {
        nav2: flag(args, "nav2")?.then_some(Nav2Release::Main),
    })
}

/// The registry `check` would use for `args`: built-ins, Nav2's if asked, `model_xml`'s
/// types.
fn registry(args: &Value) -> Result<Registry<()>, String> {
    let mut registry = check::registry(&[], nav2(args)?, &[]).map_err(|e| joined(&e))?;
    if let Some(model) = text(args, "model_xml")? {
        registry
            .add_model_str(model, "model.xml")
            .map_err(|e| e.to_string())?;
    }
    Ok(registry)
}

/// The tree text `xml` checked as `neurotree check` checks a file, with `registry` and
/// the text's own `TreeNodesModel` (whose error, if it has one, is the check's).
fn checked<'r>(
    registry: &'r mut Registry<()>,
    xml: &str,
) -> Result<check::Checked<'r>, neurotree::LoadError> {
    registry.add_model_str(xml, FILE)?;
    Ok(check::check_text(
        registry,
        xml,
        FILE,
        neurotree::xml::DEFAULT_MAX_NODES,
    ))
}

fn joined(errors: &[neurotree::LoadError]) -> String {
    errors
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join("\n")
}

/// The name the tree text has in messages and in the call's folder.
const FILE: &str = "tree.xml";

fn list_node_types(args: &Value) -> Result<Value, String> {
    let registry = registry(args)?;
    let types: Vec<Value> = registry
        .types()
        .map(|t| {
            let ports: Vec<Value> = t
                .ports
                .iter()
                .map(|p| {
                    json!({
                        "name": p.name,
                        "direction": match p.direction {
                            PortDirection::Input => "input",
                            PortDirection::Output => "output",
                            PortDirection::InOut => "inout",
                        },
                        "type": p.type_name,
                        "default": p.default,
                        "description": p.description,
                    })
                })
                .collect();
            json!({
                "name": t.name,
                "category": format!("{:?}", t.category),
                "description": t.description,
                "ports": ports,
            })
        })
        .collect();
    Ok(json!({ "count": types.len(), "types": types }))
}

fn check_tree(args: &Value) -> Result<Value, String> {
    let xml = xml(args)?;
    let mut registry = registry(args)?;
    let checked = match checked(&mut registry, xml) {
        Ok(checked) => checked,
        Err(e) => {
            let error = json!({ "file": e.file, "line": e.line, "col": e.col, "message": e.message, "kind": format!("{:?}", e.kind()) });
            return Ok(json!({ "ok": false, "errors": [error], "warnings": [] }));
        }
    };
    let place = |file: &str, line: u32, col: u32, message: &str| json!({ "file": file, "line": line, "col": col, "message": message });
    let warnings: Vec<Value> = checked
        .warnings
        .iter()
        .map(|w| place(&w.file, w.line, w.col, &w.message))
        .collect();
    Ok(match &checked.trees {
        Ok(trees) => json!({ "ok": true, "trees": trees, "errors": [], "warnings": warnings }),
        Err(errors) => {
            let errors: Vec<Value> = errors
                .iter()
                .map(|e| {
                    let mut v = place(&e.file, e.line, e.col, &e.message);
                    v["kind"] = json!(format!("{:?}", e.kind()));
                    v
                })
                .collect();
            json!({ "ok": false, "errors": errors, "warnings": warnings })
        }
    })
}

fn lint_tree(args: &Value) -> Result<Value, String> {
    let xml = xml(args)?;
    let mut registry = registry(args)?;
    let mut options = if flag(args, "nav2")? {
        LintOptions::nav2()
    } else {
        LintOptions::default()
    };
    options.tree = text(args, "tree")?.map(String::from);
    match args.get("entries") {
        None | Some(Value::Null) => {}
        Some(Value::Array(entries)) => {
            for e in entries {
                let e = e.as_str().ok_or("`entries` must be a list of strings")?;
                options.written.push(e.to_string());
            }
        }
        Some(_) => return Err("`entries` must be a list of strings".to_string()),
    }
    let found = match checked(&mut registry, xml) {
        Err(e) => vec![lint::load_error(&e)],
        Ok(checked) => {
            if let Some(tree) = &options.tree {
                if checked.trees.is_ok() && !checked.loader.tree_ids().any(|id| id == tree) {
                    return Err(format!("no tree `{tree}` in the XML"));
                }
            }
            lint::findings(&checked, &options)
        }
    };
    let mut doc = lint::json_document(&found);
    doc["text"] = json!(
        found
            .iter()
            .map(|d| d.to_string() + "\n")
            .collect::<String>()
            + &lint::summary(&found)
    );
    Ok(doc)
}

/// Writes `text` as `name` in `dir` and gives its path.
fn write(dir: &Path, name: &str, text: &str) -> Result<PathBuf, String> {
    let path = dir.join(name);
    std::fs::write(&path, text).map_err(|e| format!("cannot write {name}: {e}"))?;
    Ok(path)
}

/// Runs the `neurotree` command line `argv` (show, run or test) in this process: how it
/// ended, its standard output and its standard error.
fn command(argv: &[String]) -> Result<(Outcome, String, String), String> {
    let cli =
        Cli::try_parse_from(std::iter::once("neurotree".to_string()).chain(argv.iter().cloned()))
            .map_err(|e| e.to_string())?;
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let outcome = match cli.command {
        Command::Show(args) => crate::show::execute(&args, &mut out, &mut err),
        Command::Run(args) => crate::run::execute(&args, &mut out, &mut err),
        Command::Test(args) => crate::test::execute(&args, &mut out, &mut err),
        _ => return Err("not a command the tools run".to_string()),
    }
    .map_err(|e| e.to_string())?;
    let text = |bytes: Vec<u8>| String::from_utf8_lossy(&bytes).into_owned();
    Ok((outcome, text(out), text(err)))
}

/// `--name=VALUE`: one argument, so that no value is read as a flag.
fn opt(name: &str, value: impl std::fmt::Display) -> String {
    format!("--{name}={value}")
}

fn show_tree(args: &Value, dir: &Path) -> Result<Value, String> {
    let path = write(dir, FILE, xml(args)?)?;
    let format = match text(args, "format")?.unwrap_or("text") {
        "text" => "unicode",
        f @ ("ascii" | "mermaid" | "svg" | "dot") => f,
        other => {
            return Err(format!(
                "format `{other}`: give text, ascii, mermaid, svg or dot"
            ))
        }
    };
    let mut argv = vec![
        "show".to_string(),
        path.display().to_string(),
        opt("format", format),
    ];
    argv.extend(text(args, "tree")?.map(|t| opt("tree", t)));
    if flag(args, "nav2")? {
        argv.push("--nav2".into());
    }
    match command(&argv)? {
        (Outcome::Done, out, err) => Ok(json!({ "format": format, "text": out, "notes": err })),
        (_, _, err) => Err(err),
    }
}

fn run_tree(args: &Value, dir: &Path) -> Result<Value, String> {
    let path = write(dir, FILE, xml(args)?)?;
    let coverage = dir.join("coverage.json");
    let ticks = count(args, "max_ticks", MAX_RUN_TICKS)?.unwrap_or(100);
    let mut argv = vec![
        "run".to_string(),
        path.display().to_string(),
        "--mock-unknown".into(),
        opt("max-ticks", ticks),
        opt("coverage-json", coverage.display()),
    ];
    argv.extend(text(args, "tree")?.map(|t| opt("tree", t)));
    if flag(args, "nav2")? {
        argv.push("--nav2".into());
    }
    for (name, value) in object(args, "mocks")? {
        let outcomes = value
            .as_str()
            .ok_or("each mock's outcomes must be a string")?;
        argv.push(opt("mock", format!("{name}={outcomes}")));
    }
    for (key, value) in object(args, "inputs")? {
        let value = match value {
            Value::String(s) => s.clone(),
            other => other.to_string(),
        };
        argv.push(opt("set", format!("{key}={value}")));
    }
    let (outcome, out, err) = command(&argv)?;
    if outcome == Outcome::Refused {
        return Err(err);
    }
    let lines: Vec<Value> = out
        .lines()
        .filter_map(|l| serde_json::from_str(l).ok())
        .collect();
    let (summary, ticks) = match lines.split_last() {
        Some((last, ticks)) => (
            last.get("summary").cloned().unwrap_or(Value::Null),
            ticks.to_vec(),
        ),
        None => return Err(format!("the run printed nothing: {err}")),
    };
    let coverage: Value = std::fs::read_to_string(&coverage)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .unwrap_or(Value::Null);
    Ok(json!({
        "status": summary.get("status").cloned().unwrap_or(Value::Null),
        "stopped_at_max_ticks": outcome == Outcome::Stopped,
        "ticks": ticks,
        "summary": summary,
        "coverage": coverage,
        "notes": err,
    }))
}

/// The object argument `name` (empty if not given).
fn object(args: &Value, name: &str) -> Result<Map<String, Value>, String> {
    match args.get(name) {
        None | Some(Value::Null) => Ok(Map::new()),
        Some(Value::Object(map)) => Ok(map.clone()),
        Some(_) => Err(format!("`{name}` must be an object")),
    }
}

fn run_scenario(args: &Value, dir: &Path) -> Result<Value, String> {
    let xml = xml(args)?;
    let scenario = text(args, "scenario")?.ok_or("give the scenario's TOML text in `scenario`")?;
    let mut table: toml::Table = scenario.parse().map_err(|e| format!("scenario: {e}"))?;
    // Every file the scenario reads is the call's: the tree, and nothing else.
    for field in ["files", "substitute"] {
        if table.contains_key(field) {
            return Err(format!("scenario: `{field}` names files, which a call cannot give; put everything in `xml`"));
        }
    }
    // Capped as `run_tree`'s `max_ticks` is (the scenario's own default is 100).
    match table.get("ticks") {
        None => {}
        Some(toml::Value::Integer(n)) if (1..=i64::from(MAX_RUN_TICKS)).contains(n) => {}
        Some(other) => {
            return Err(format!(
                "scenario: `ticks` is {other}; a call runs from 1 to {MAX_RUN_TICKS} ticks"
            ))
        }
    }
    table.insert("tree".into(), toml::Value::String(FILE.into()));
    write(dir, FILE, xml)?;
    let path = write(dir, "scenario.toml", &table.to_string())?;
    let (outcome, out, err) = command(&["test".to_string(), path.display().to_string()])?;
    Ok(json!({ "passed": outcome == Outcome::Done, "text": out + &err }))
}

fn simulate_nav2(args: &Value, dir: &Path) -> Result<Value, String> {
    use neurotree::robotics::Pose2D;
    use neurotree_cli::demo::{DemoConfig, DemoRun};
    let mut config = DemoConfig::default();
    if let Some(xml) = text(args, "xml")? {
        config.tree = Some(write(dir, FILE, xml)?);
    }
    if let Some(goal) = args.get("goal").filter(|g| !g.is_null()) {
        match goal
            .as_array()
            .map(|g| g.iter().map(Value::as_f64).collect::<Vec<_>>())
            .as_deref()
        {
            Some([Some(x), Some(y)]) if x.is_finite() && y.is_finite() => {
                config.goal = Pose2D::new(*x, *y, 0.0)
            }
            _ => return Err("`goal` must be [x, y] in metres".to_string()),
        }
    }
    if let Some(seed) = args.get("seed").filter(|s| !s.is_null()) {
        config.seed = seed
            .as_u64()
            .ok_or("`seed` must be an integer of 0 or more")?;
    }
    config.max_ticks = count(args, "max_ticks", MAX_SIM_TICKS)?.unwrap_or(3000);
    let mut demo = DemoRun::new(&config).map_err(|e| e.to_string())?;
    let s = demo.run_to_end();
    let codes: Vec<Value> = s
        .error_codes
        .iter()
        .map(|(entry, code, message)| json!({ "entry": entry, "code": code, "message": message }))
        .collect();
    Ok(json!({
        "arrived": s.succeeded(),
        "status": format!("{:?}", s.outcome).to_uppercase(),
        "ticks": s.ticks,
        "seconds": s.time.as_secs_f64(),
        "distance_m": s.distance,
        "replans": s.replans,
        "recoveries": s.recoveries,
        "recovery_runs": s.recovery_runs,
        "error": s.error,
        "error_codes": codes,
        "pose": [s.pose.x, s.pose.y],
        "text": s.to_string(),
    }))
}
