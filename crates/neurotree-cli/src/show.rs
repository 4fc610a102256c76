//! `neurotree show`: draw a BehaviorTree.CPP file's tree as text, Graphviz DOT, Mermaid or
//! SVG, optionally with the statuses of a run.
//!
//! Any well-formed file is drawn, never refused for its node types. Node types that a
//! `TreeNodesModel` declares (in the file itself or in a `--model` file, such as Nav2's
//! `nav2_tree_nodes.xml`) are drawn with stand-ins of their family that keep their type
//! name and ports; a type nobody declares is drawn from what the file says of it, its name
//! and attributes, marked `unknown NAME`, with a warning on stderr (with `--mock-unknown`,
//! `--trace` or `--coverage`, its leaves are drawn as `run --mock-unknown` runs them). None
//! is ever ticked.
//!
//! With `--trace`, the JSON lines that `neurotree run --trace` prints give each node the
//! last status it reached during the run (a halt sets it back to Idle); with `--tick N`,
//! the last status each reached during tick N, or, for a node that tick did not change,
//! the status it had when the tick began. (The trace numbers ticks by pass of the root, as
//! `run --max-ticks` counts them: a tick that re-ran the root at once for a node that asked
//! to be woken has one number per pass.) Nodes that share a path are told apart by their
//! statuses. When the root failed in that tick (the last one, without `--tick`), every
//! format marks the path that failed: for the last tick, the chain of `Tree::last_failure`
//! that the trace's summary carries; for another (or a trace without it), from the root,
//! each node's child that failed last in that tick, down to a node none of whose children
//! failed (a Timeout that halted its child, a leaf). The text formats note each ` -- failed`, with its
//! own reason if it gave one (` -- failed: gave up after 2 attempts`); DOT, Mermaid and SVG
//! draw them and the edges between them red and wide, each reason in its node's label
//! (see [`Format::render_failed_path`]).
//!
//! With `--coverage FILE`, the JSON that `neurotree run --coverage-json FILE` wrote marks
//! each node covered, reached with outcomes not seen, or never reached (see
//! [`render_coverage`]). Every error is printed as `path:line:col: error: message`.

use std::collections::{BTreeSet, HashMap};
use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::time::Duration;

use neurotree::observe::{CoverageReport, NodeCoverage, Outcome, OutcomeSet};
use neurotree::render::{render_coverage, FailedPath, Format, LastTickStatuses};
use neurotree::{
    Arity, Blueprint, Category, CustomNode, LoadError, LoadErrorKind, NodeCtx, NodeId, NodeStatus,
    Observer, PortDirection, PortSpec, Registry, StatusChange, XmlLoader,
};
use serde_json::{Map, Value};

use crate::files::{self, LoadLimits, Picked};

/// What `neurotree show` was asked to do.
#[derive(clap::Args, Debug)]
pub struct ShowArgs {
    /// The file to draw, then any files with trees it uses (all loaded into one loader).
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// The tree to draw (default: main_tree_to_execute of the first file, else the only
    /// tree, else the only tree no other tree uses).
    #[arg(long)]
    pub tree: Option<String>,
    /// ascii, unicode, dot, mermaid or svg (default: from the extension of --output, else
    /// unicode).
    #[arg(long, short = 'f')]
    pub format: Option<Format>,
    /// Write the picture to this file instead of standard output.
    #[arg(long, short = 'o')]
    pub output: Option<PathBuf>,
    /// A file whose `TreeNodesModel` declares node types the file uses (repeatable); they
    /// are drawn with their type names, without an implementation.
    #[arg(long = "model")]
    pub models: Vec<PathBuf>,
    /// Draw leaves without an implementation as `run --mock-unknown` runs them; else a
    /// node type nobody declared is drawn as `unknown NAME`, with a warning. Implied by
    /// --trace and --coverage: the run that wrote them had those leaves.
    #[arg(long)]
    pub mock_unknown: bool,
    /// The JSON lines of `neurotree run --trace`: colour each node with the last status it
    /// reached; if the root failed, mark the path that failed with the reasons the trace
    /// gives (text: ` -- failed: REASON`; dot, mermaid, svg: red and wide, reasons in labels).
    #[arg(long)]
    pub trace: Option<PathBuf>,
    /// With --trace: the statuses of this tick instead (the last each node reached in it).
    #[arg(long, requires = "trace")]
    pub tick: Option<u32>,
    /// The JSON that `neurotree run --coverage-json FILE` wrote: mark each node covered,
    /// reached with outcomes not seen, or never reached.
    #[arg(long, value_name = "FILE", conflicts_with = "trace")]
    pub coverage: Option<PathBuf>,
    #[command(flatten)]
    pub nav2: crate::registry::Nav2Args,
    #[command(flatten)]
    pub limits: LoadLimits,
}

/// Draws the tree of the files; [`Refused`](crate::Outcome::Refused) if it could not (the
/// error is on `err`).
pub fn execute(
    opts: &ShowArgs,
    out: &mut impl Write,
    err: &mut impl Write,
) -> io::Result<crate::Outcome> {
    let files = &opts.files;
    let loaded = load(files, opts, err);
    if let Ok((_, picked)) = &loaded {
        picked.note("drawing", err)?;
    }
    let picture = loaded.and_then(|(bp, picked)| {
        let tree_id = picked.id;
        if let Some(coverage) = &opts.coverage {
            let report = coverage_report(coverage, &bp, &tree_id)?;
            return Ok(render_coverage(&bp, &report, format_of(opts)));
        }
        let format = format_of(opts);
        match &opts.trace {
            Some(trace) => {
                let (statuses, failed) = trace_statuses(trace, &bp, &tree_id, opts.tick)?;
                Ok(format.render_failed_path(&bp, &statuses, &failed))
            }
            None => Ok(format.render(&bp, None)),
        }
    });
    let picture = match picture {
        Ok(picture) => picture,
        Err(e) => {
            writeln!(err, "{e}")?;
            return Ok(crate::Outcome::Refused);
        }
    };
    match &opts.output {
        Some(path) => {
            if let Err(e) = fs::write(path, picture) {
                writeln!(
                    err,
                    "{}: error: cannot write the picture: {e}",
                    path.display()
                )?;
                return Ok(crate::Outcome::Refused);
            }
        }
        None => out.write_all(picture.as_bytes())?,
    }
    Ok(crate::Outcome::Done)
}

fn format_of(opts: &ShowArgs) -> Format {
    opts.format
        .or_else(|| {
            let ext = opts.output.as_ref()?.extension()?.to_str()?;
            Format::from_extension(ext)
        })
        .unwrap_or(Format::Unicode)
}

/// The blueprint to draw and the tree it is.
fn load(
    files: &[PathBuf],
    opts: &ShowArgs,
    err: &mut impl Write,
) -> Result<(Blueprint<()>, Picked), LoadError> {
    let mut registry = registry_with_stand_ins(files, &opts.models, opts.nav2)?;
    // Leaves without an implementation are drawn as a run mocks them when asked for, or
    // when drawn with what a run wrote; every other node type nobody declared is drawn as
    // what the file says of it: its name and attributes, marked unknown. Never refused.
    let mock_unknown = opts.mock_unknown || opts.trace.is_some() || opts.coverage.is_some();
    {
        // A control or decorator of an unknown type is no leaf a mock replaces: drawn too.
        let drawn = unknown_types(files, &registry)
            .into_iter()
            .filter(|u| !mock_unknown || u.children);
        for unknown in drawn {
            let _ = writeln!(
                err,
                "{}:{}:{}: warning: unknown node type `{}`: drawn from its name and \
                 attributes; declare it with --model FILE (or --nav2 if it is one of Nav2's)",
                unknown.file, unknown.line, unknown.col, unknown.name
            );
            let ports = unknown
                .attributes
                .iter()
                .map(|a| PortSpec::untyped(a, PortDirection::Input))
                .collect();
            let (category, arity) = if unknown.children {
                (Category::Control, Arity::AtLeast(0))
            } else {
                (Category::Action, Arity::Leaf)
            };
            let stand_in = || -> Box<dyn CustomNode<()>> { Box::new(StandIn) };
            let shown_as = format!("unknown {}", unknown.name);
            // Unknown to the registry, so the name is free.
            let _ = registry.register_custom_shown_as(
                &unknown.name,
                &shown_as,
                category,
                arity,
                ports,
                stand_in,
            );
        }
    }
    let mut loader = XmlLoader::new(&registry)
        .unknown_type_advice(files::UNKNOWN_TYPE_ADVICE)
        .mock_unknown(mock_unknown)
        .max_nodes(opts.limits.max_nodes);
    files::load_all(&mut loader, files)?;
    // Clap asks for at least one file.
    let first = files.first().map(|f| files::shown(f)).unwrap_or_default();
    let picked = files::pick_tree(&loader, opts.tree.as_deref(), &first)?;
    let bp = loader.build(&picked.id).map_err(|mut e| {
        // Errors about the files as a whole (a main tree that is not there) name no file.
        if e.file.is_empty() {
            e.file.clone_from(&first);
        }
        if e.kind() == LoadErrorKind::TooManyNodes {
            e.message = format!("{}\n{}", e.message, files::MAX_NODES_HINT);
        }
        e
    })?;
    Ok((bp, picked))
}

/// The built-in nodes and Nav2's control nodes, and a stand-in for every other node type a
/// model declares: the `TreeNodesModel`s of the `files` drawn and of the `models` files.
fn registry_with_stand_ins(
    files: &[PathBuf],
    models: &[PathBuf],
    nav2: crate::registry::Nav2Args,
) -> Result<Registry<()>, LoadError> {
    let mut declared = crate::registry::with_nav2_controls::<()>(nav2);
    // The types that run as they are; those only described (Nav2's leaves with --nav2, a
    // model's) get a stand-in to draw.
    let built_in: BTreeSet<String> = declared
        .types()
        .filter(|t| !t.is_model_only())
        .map(|t| t.name.clone())
        .collect();
    for model in models {
        let shown = model.display().to_string();
        let model_text = files::read(model)?;
        declared.add_model_str(&model_text, &shown)?;
    }
    files::add_models(&mut declared, files)?;
    let mut registry = crate::registry::with_nav2_controls::<()>(nav2);
    for t in declared.types().filter(|t| !built_in.contains(&t.name)) {
        registry.remove(&t.name);
        let ports = t.ports.clone();
        let stand_in = || -> Box<dyn CustomNode<()>> { Box::new(StandIn) };
        let registered = match t.category {
            Category::Condition => registry.register_condition(&t.name, ports, |_| true),
            Category::Control => {
                registry.register_custom(&t.name, Arity::AtLeast(0), ports, stand_in)
            }
            Category::Decorator => registry.register_custom(&t.name, Arity::One, ports, stand_in),
            Category::Action | Category::SubTree => {
                registry.register_custom(&t.name, Arity::Leaf, ports, stand_in)
            }
        };
        // The names are unique (they come from one registry), none runs as it is, and a
        // description of it was removed just now, so the name is free.
        debug_assert!(registered.is_ok(), "{} registered twice", t.name);
    }
    Ok(registry)
}

/// A node type the files use that the registry does not know, as the files show it.
struct Unknown {
    name: String,
    /// Where it is first used.
    file: String,
    line: u32,
    col: u32,
    /// Every attribute its elements carry but `name` and the reserved `_` ones.
    attributes: BTreeSet<String>,
    /// Whether one of its elements has children.
    children: bool,
}

/// The node types the `<BehaviorTree>`s of `files` use that `registry` does not know, in
/// the order first met. A file that does not parse gives none: loading it says why.
fn unknown_types(files: &[PathBuf], registry: &Registry<()>) -> Vec<Unknown> {
    let mut found: Vec<Unknown> = Vec::new();
    for file in files {
        let Ok(text) = files::read(file) else {
            continue;
        };
        let Ok(doc) = roxmltree::Document::parse(&text) else {
            continue;
        };
        let in_tree = |n: &roxmltree::Node<'_, '_>| {
            n.ancestors()
                .skip(1)
                .any(|a| a.tag_name().name() == "BehaviorTree")
        };
        for el in doc.descendants().filter(|n| n.is_element() && in_tree(n)) {
            let name = el.tag_name().name();
            if name == "SubTree" || registry.knows(name) {
                continue;
            }
            let attributes = el
                .attributes()
                .map(|a| a.name().to_string())
                .filter(|a| a != "name" && !a.starts_with('_'));
            let children = el.children().any(|c| c.is_element());
            match found.iter_mut().find(|u| u.name == name) {
                Some(u) => {
                    u.attributes.extend(attributes);
                    u.children |= children;
                }
                None => {
                    let at = doc.text_pos_at(el.range().start);
                    found.push(Unknown {
                        name: name.to_string(),
                        file: files::shown(file),
                        line: at.row,
                        col: at.col,
                        attributes: attributes.collect(),
                        children,
                    });
                }
            }
        }
    }
    found
}

/// Stands in for a node type known only from a model: `show` draws it and never ticks it.
struct StandIn;

impl CustomNode<()> for StandIn {
    fn tick(&mut self, _node: &mut NodeCtx<'_, '_, ()>) -> NodeStatus {
        NodeStatus::Failure
    }
}

/// The coverage that `neurotree run --coverage-json` wrote to `path`, for `bp`: its
/// `nodes` must be `bp`'s, in order and by path.
fn coverage_report(
    path: &Path,
    bp: &Blueprint<()>,
    tree_id: &str,
) -> Result<CoverageReport, LoadError> {
    let shown = path.display().to_string();
    let text = read_text(path, "coverage")?;
    coverage_from_json(&text, bp, tree_id)
        .map_err(|e| LoadError::at_file(LoadErrorKind::BadValue, &shown, e))
}

/// See [`coverage_report`].
fn coverage_from_json(
    text: &str,
    bp: &Blueprint<()>,
    tree_id: &str,
) -> Result<CoverageReport, String> {
    let json: Value = serde_json::from_str(text)
        .map_err(|e| format!("not the JSON of `neurotree run --coverage-json`: {e}"))?;
    let nodes = json
        .get("nodes")
        .and_then(Value::as_array)
        .ok_or("no `nodes` list; expected the JSON of `neurotree run --coverage-json`")?;
    if nodes.len() != bp.len() {
        return Err(format!(
            "the coverage has {} nodes and tree `{tree_id}` {}; was it made from another tree?",
            nodes.len(),
            bp.len()
        ));
    }
    let outcomes = |node: &Value, key: &str| -> Result<OutcomeSet, String> {
        let mut set = OutcomeSet::NONE;
        for word in node
            .get(key)
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
        {
            let outcome = word
                .as_str()
                .and_then(Outcome::from_name)
                .ok_or_else(|| format!("unknown outcome {word} in `{key}`"))?;
            set = set.with(outcome);
        }
        Ok(set)
    };
    let mut read = Vec::with_capacity(nodes.len());
    for (id, node) in bp.ids().zip(nodes) {
        let path = node.get("path").and_then(Value::as_str).unwrap_or_default();
        if path != bp.path(id) {
            return Err(format!(
                "node {} of the coverage is `{path}`, not `{}`; was it made from another tree?",
                id.index(),
                bp.path(id)
            ));
        }
        // The possible outcomes are the run's: its mocks may be of other kinds than the
        // stand-ins `show` draws.
        read.push(NodeCoverage {
            path: path.to_string(),
            type_name: bp.type_id(id).to_string(),
            reached: node
                .get("reached")
                .and_then(Value::as_bool)
                .unwrap_or(false),
            seen: outcomes(node, "seen").map_err(|e| format!("node `{path}`: {e}"))?,
            possible: outcomes(node, "possible").map_err(|e| format!("node `{path}`: {e}"))?,
        });
    }
    Ok(CoverageReport::from_nodes(read))
}

/// One status change read from a trace line.
struct Change {
    line: u32,
    col: u32,
    tick: u64,
    path: String,
    from: NodeStatus,
    to: NodeStatus,
    /// The reason the line gives for a change to FAILURE, in words (`blocked (error 106)`).
    reason: Option<String>,
}

/// What a trace shows of a run: each node's status, by node id, and the path that failed.
type Shown = (Vec<NodeStatus>, FailedPath);

/// The statuses the trace at `path` shows; see [`statuses_from_trace`].
fn trace_statuses(
    path: &Path,
    bp: &Blueprint<()>,
    tree_id: &str,
    tick: Option<u32>,
) -> Result<Shown, LoadError> {
    let shown = path.display().to_string();
    let text = read_text(path, "trace")?;
    statuses_from_trace(&text, &shown, bp, tree_id, tick)
}

/// The largest trace read: a long run with `--trace` writes a few megabytes.
const MAX_TRACE_BYTES: u64 = 256 << 20;

/// The text of the trace (or other input, `what`) at `path`, read up to
/// [`MAX_TRACE_BYTES`]. A pipe is welcome (`show --trace <(neurotree run --trace ...)`), so
/// the kind of file is not checked.
fn read_text(path: &Path, what: &str) -> Result<String, LoadError> {
    use std::io::Read;
    let shown = path.display().to_string();
    let io_error = |message: String| LoadError::at_file(LoadErrorKind::Io, &shown, message);
    let file =
        fs::File::open(path).map_err(|e| io_error(format!("cannot read the {what}: {e}")))?;
    let mut bytes = Vec::new();
    file.take(MAX_TRACE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| io_error(format!("cannot read the {what}: {e}")))?;
    if bytes.len() as u64 > MAX_TRACE_BYTES {
        return Err(LoadError::at_file(
            LoadErrorKind::TooLarge,
            &shown,
            format!(
                "the {what} is more than {MAX_TRACE_BYTES} bytes; give the {what} of a shorter run"
            ),
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        io_error(format!(
            "cannot read the {what}: it is not UTF-8 text (at byte {})",
            e.utf8_error().valid_up_to()
        ))
    })
}

/// The status of every node of `bp` that a trace (`text`, read from `file`) shows: the last
/// each reached or, with `tick`, the last each reached in that tick (the one stored when it
/// began, for a node the tick did not change); and the path that failed in that tick (see
/// [`failed_path`]).
fn statuses_from_trace(
    text: &str,
    file: &str,
    bp: &Blueprint<()>,
    tree_id: &str,
    tick: Option<u32>,
) -> Result<Shown, LoadError> {
    let shown = file.to_string();
    let (changes, last_tick, chain) = parse_trace(text, &shown)?;
    let mut by_path: HashMap<String, Vec<NodeId>> = HashMap::new();
    for id in bp.ids() {
        by_path.entry(bp.path(id)).or_default().push(id);
    }
    // A mirror of the stored statuses, to tell apart nodes that share a path.
    let mut stored = vec![NodeStatus::Idle; bp.len()];
    let mut record = LastTickStatuses::new();
    let mut current = None;
    // The changes to FAILURE of the tick shown, by node, with their reasons.
    let shown_tick = tick.map_or(last_tick, u64::from);
    let mut failed: Vec<(NodeId, Option<&str>)> = Vec::new();
    for change in &changes {
        if tick.is_some_and(|n| change.tick > u64::from(n)) {
            break;
        }
        let Some(candidates) = by_path.get(&change.path) else {
            return Err(LoadError::new(
                LoadErrorKind::BadValue,
                shown,
                change.line,
                change.col,
                format!(
                    "node `{}` is not in tree `{tree_id}`; was the trace made from another tree?",
                    change.path
                ),
            ));
        };
        // Siblings may share a name; the one that changes is the first whose status is
        // the change's `from` (BehaviorTree.CPP ticks, resets and halts in child order).
        let node = candidates
            .iter()
            .copied()
            .find(|id| stored[id.index()] == change.from)
            .unwrap_or(candidates[0]);
        stored[node.index()] = change.to;
        if change.tick == shown_tick && change.to == NodeStatus::Failure {
            failed.push((node, change.reason.as_deref()));
        }
        if tick.is_some() && current != Some(change.tick) {
            record.on_tick_start(Duration::ZERO);
            current = Some(change.tick);
        }
        record.on_status_change(StatusChange {
            node,
            from: change.from,
            to: change.to,
            at: Duration::ZERO,
        });
    }
    if let Some(n) = tick {
        if u64::from(n) > last_tick || n == 0 {
            return Err(LoadError::at_file(
                LoadErrorKind::BadValue,
                &shown,
                format!("--tick {n} is not a tick of this trace, which has ticks 1 to {last_tick}"),
            ));
        }
        // Tick N changed nothing: the view then showed what was stored when it started.
        if current != Some(u64::from(n)) {
            record.on_tick_start(Duration::ZERO);
        }
    }
    let mut statuses = record.statuses();
    statuses.resize(bp.len(), NodeStatus::Idle);
    // The run's own chain, when the tick shown is the one it is of.
    let path = match chain.filter(|_| shown_tick == last_tick) {
        Some(chain) if !chain.is_empty() => chain_path(&by_path, bp, &chain),
        _ => failed_path(bp, &failed),
    };
    Ok((statuses, path))
}

/// The path of a summary's failure chain: each link's node (among those of its path, the
/// child of the link before) with its reason. A link not in the tree ends it.
fn chain_path(
    by_path: &HashMap<String, Vec<NodeId>>,
    bp: &Blueprint<()>,
    chain: &[(String, Option<String>)],
) -> FailedPath {
    let mut path = FailedPath::new();
    let mut parent = None;
    for (link, reason) in chain {
        let node = by_path
            .get(link)
            .and_then(|nodes| nodes.iter().copied().find(|n| bp.parent(*n) == parent));
        let Some(node) = node else { break };
        path.mark(node, reason.clone());
        parent = Some(node);
    }
    path
}

/// The path that failed, from the changes to FAILURE of one tick (in order, with their
/// reasons): empty unless the root failed in it. From the root, the path goes down to the
/// child that failed last in the tick (the one that decided its parent: a Sequence's
/// failing child, a Fallback's last), until a node none of whose children failed: a
/// Timeout that halted its child ends it, with its own reason. Each node on it carries the
/// last reason it gave in the tick, if any.
fn failed_path(bp: &Blueprint<()>, failed: &[(NodeId, Option<&str>)]) -> FailedPath {
    let mut path = FailedPath::new();
    if !failed.iter().any(|(node, _)| *node == NodeId::ROOT) {
        return path;
    }
    let mut on_path = Some(NodeId::ROOT);
    while let Some(node) = on_path {
        let reason = failed
            .iter()
            .rev()
            .find_map(|(n, reason)| reason.filter(|_| *n == node));
        path.mark(node, reason.map(str::to_string));
        on_path = failed
            .iter()
            .rev()
            .map(|(n, _)| *n)
            .find(|n| bp.parent(*n) == Some(node));
    }
    path
}

/// What a trace holds: its status changes, in order; the last tick it mentions; and, from
/// its summary, the chain of `Tree::last_failure` after that tick (each link's path and
/// reason in words), if the root failed.
type Parsed = (Vec<Change>, u64, Option<Vec<(String, Option<String>)>>);

/// A reason of a trace line or of a summary's failure link in words:
/// `blocked (error 106)`.
fn reason_text(object: &Map<String, Value>) -> Option<String> {
    let message = object.get("reason").and_then(Value::as_str)?;
    Some(match object.get("code").and_then(Value::as_u64) {
        Some(code) if code != 0 => format!("{message} (error {code})"),
        _ => message.to_string(),
    })
}

/// The status changes of a trace, in order, the last tick it mentions and the failure
/// chain of its summary.
fn parse_trace(text: &str, file: &str) -> Result<Parsed, LoadError> {
    let mut changes = Vec::new();
    let mut last_tick = 0;
    let mut chain = None;
    for (i, line) in text.lines().enumerate() {
        let line_no = u32::try_from(i + 1).unwrap_or(u32::MAX);
        if line.trim().is_empty() {
            continue;
        }
        let at = |col: usize, kind: LoadErrorKind, message: String| {
            LoadError::new(
                kind,
                file,
                line_no,
                u32::try_from(col).unwrap_or(u32::MAX),
                message,
            )
        };
        // Past the JSON, every check is of a value the line holds.
        let error = |col: usize, message: String| at(col, LoadErrorKind::BadValue, message);
        let key_col = |key: &str| line.find(&format!("\"{key}\"")).map_or(1, |at| at + 1);
        let value: Value = serde_json::from_str(line).map_err(|e| {
            at(
                e.column().max(1),
                LoadErrorKind::Syntax,
                format!("not a JSON trace line: {e}"),
            )
        })?;
        let Some(object) = value.as_object() else {
            return Err(error(1, "a trace line is a JSON object".into()));
        };
        if let Some(summary) = object.get("summary") {
            chain = summary["failure"].as_array().map(|links| {
                links
                    .iter()
                    .filter_map(Value::as_object)
                    .filter_map(|link| {
                        let path = link.get("path")?.as_str()?.to_string();
                        Some((path, reason_text(link)))
                    })
                    .collect()
            });
            continue;
        }
        let Some(tick) = object.get("tick").and_then(Value::as_u64) else {
            return Err(error(
                key_col("tick"),
                "a trace line needs a `tick` number; is this the output of `neurotree run --trace`?"
                    .into(),
            ));
        };
        last_tick = last_tick.max(tick);
        let Some(node) = object.get("node") else {
            // A tick's own line, `{"tick":N,"status":..}`.
            continue;
        };
        let Some(path) = node.as_str() else {
            return Err(error(key_col("node"), "`node` must be a string".into()));
        };
        let status = |key: &str| -> Result<NodeStatus, LoadError> {
            let text = object.get(key).and_then(Value::as_str).unwrap_or("");
            text.parse().map_err(|()| {
                error(
                    key_col(key),
                    format!(
                        "`{key}` must be IDLE, RUNNING, SUCCESS, FAILURE or SKIPPED, not `{text}`"
                    ),
                )
            })
        };
        let reason = reason_text(object);
        changes.push(Change {
            line: line_no,
            col: u32::try_from(key_col("node")).unwrap_or(u32::MAX),
            tick,
            path: path.to_string(),
            from: status("from")?,
            to: status("to")?,
            reason,
        });
    }
    Ok((changes, last_tick, chain))
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree::Status;

    fn blueprint() -> Blueprint<()> {
        Blueprint::<()>::builder()
            .sequence("root", |s| {
                s.action("step", |_: &mut ()| Status::Success)
                    .action("step", |_: &mut ()| Status::Success)
                    .action("last", |_: &mut ()| Status::Success)
            })
            .build()
            .unwrap()
    }

    fn statuses(trace: &str, tick: Option<u32>) -> Result<Vec<NodeStatus>, LoadError> {
        statuses_from_trace(trace, "trace", &blueprint(), "Main", tick).map(|(s, _)| s)
    }

    const TRACE: &str = r#"{"tick":1,"node":"root","from":"IDLE","to":"RUNNING"}
{"tick":1,"node":"root/step","from":"IDLE","to":"SUCCESS"}
{"tick":1,"node":"root/step","from":"IDLE","to":"SUCCESS"}
{"tick":1,"node":"root/last","from":"IDLE","to":"RUNNING"}
{"tick":1,"status":"RUNNING"}
{"tick":2,"status":"RUNNING"}
{"tick":3,"node":"root/last","from":"RUNNING","to":"FAILURE"}
{"tick":3,"node":"root/step","from":"SUCCESS","to":"IDLE"}
{"tick":3,"node":"root/step","from":"SUCCESS","to":"IDLE"}
{"tick":3,"node":"root/last","from":"FAILURE","to":"IDLE"}
{"tick":3,"node":"root","from":"RUNNING","to":"FAILURE"}
{"tick":3,"node":"root","from":"FAILURE","to":"IDLE"}
{"tick":3,"status":"FAILURE"}
{"summary":{"ticks":3,"status":"FAILURE"}}
"#;

    #[test]
    fn the_whole_trace_gives_the_last_status_each_node_reached() {
        use NodeStatus::*;
        // Both nodes named `step` are found, one per change, though they share a path.
        assert_eq!(
            statuses(TRACE, None),
            Ok(vec![Failure, Success, Success, Failure])
        );
    }

    #[test]
    fn the_path_that_failed_ends_at_the_last_reason_with_its_code() {
        let trace = r#"{"tick":1,"node":"root","from":"IDLE","to":"RUNNING"}
{"tick":1,"node":"root/step","from":"IDLE","to":"SUCCESS"}
{"tick":1,"node":"root/step","from":"IDLE","to":"SUCCESS"}
{"tick":1,"node":"root/last","from":"IDLE","to":"FAILURE","reason":"blocked","code":106}
{"tick":1,"node":"root","from":"RUNNING","to":"FAILURE"}
{"tick":1,"status":"FAILURE"}"#;
        let (_, path) = statuses_from_trace(trace, "trace", &blueprint(), "Main", None).unwrap();
        let mut expected = FailedPath::new();
        expected.mark(NodeId(0), None);
        expected.mark(NodeId(3), Some("blocked (error 106)".into()));
        assert_eq!(path, expected);
    }

    #[test]
    fn the_path_that_failed_goes_down_to_the_timeout_below_a_retry() {
        // A Timeout halts its child and fails with its reason; the Retry above gives up with
        // its own: both are on the path, as in Tree::last_failure.
        let bp = Blueprint::<()>::builder()
            .sequence("Sequence", |s| {
                s.retry("Retry", 1, |r| {
                    r.timeout("Timeout", Duration::from_secs(3), |t| {
                        t.action("Work", |_: &mut ()| Status::Running)
                    })
                })
            })
            .build()
            .unwrap();
        let trace = r#"{"tick":1,"node":"Sequence","from":"IDLE","to":"RUNNING"}
{"tick":1,"node":"Sequence/Retry","from":"IDLE","to":"RUNNING"}
{"tick":1,"node":"Sequence/Retry/Timeout","from":"IDLE","to":"RUNNING"}
{"tick":1,"node":"Sequence/Retry/Timeout/Work","from":"IDLE","to":"RUNNING"}
{"tick":1,"status":"RUNNING"}
{"tick":2,"node":"Sequence/Retry/Timeout/Work","from":"RUNNING","to":"IDLE"}
{"tick":2,"node":"Sequence/Retry/Timeout","from":"RUNNING","to":"FAILURE","reason":"timed out after 3 s"}
{"tick":2,"node":"Sequence/Retry/Timeout","from":"FAILURE","to":"IDLE"}
{"tick":2,"node":"Sequence/Retry","from":"RUNNING","to":"FAILURE","reason":"gave up after 1 attempt"}
{"tick":2,"node":"Sequence/Retry","from":"FAILURE","to":"IDLE"}
{"tick":2,"node":"Sequence","from":"RUNNING","to":"FAILURE"}
{"tick":2,"status":"FAILURE"}"#;
        let (_, path) = statuses_from_trace(trace, "trace", &bp, "Main", None).unwrap();
        let mut expected = FailedPath::new();
        expected.mark(NodeId(0), None);
        expected.mark(NodeId(1), Some("gave up after 1 attempt".into()));
        expected.mark(NodeId(2), Some("timed out after 3 s".into()));
        assert_eq!(path, expected);
    }

    #[test]
    fn a_tick_gives_the_last_status_each_node_reached_in_it() {
        use NodeStatus::*;
        assert_eq!(
            statuses(TRACE, Some(1)),
            Ok(vec![Running, Success, Success, Running])
        );
        // Nothing changed in tick 2: what was stored when it started.
        assert_eq!(
            statuses(TRACE, Some(2)),
            Ok(vec![Running, Success, Success, Running])
        );
        assert_eq!(
            statuses(TRACE, Some(3)),
            Ok(vec![Failure, Success, Success, Failure])
        );
        let past = statuses(TRACE, Some(4)).unwrap_err();
        assert_eq!(
            past.to_string(),
            "trace: error: --tick 4 is not a tick of this trace, which has ticks 1 to 3"
        );
    }

    #[test]
    fn bad_lines_are_errors_with_their_place() {
        let err = statuses(
            "{\"tick\":1,\"node\":\"root\",\"from\":\"IDLE\",\"to\":\"RUNNING\"}\n{\"tick\":",
            None,
        )
        .unwrap_err();
        assert_eq!((err.line, err.col), (2, 8));
        assert!(err.message.starts_with("not a JSON trace line"), "{err}");

        let err = statuses(
            r#"{"tick":1,"node":"root/elsewhere","from":"IDLE","to":"RUNNING"}"#,
            None,
        )
        .unwrap_err();
        assert_eq!(
            err.to_string(),
            "trace:1:11: error: node `root/elsewhere` is not in tree `Main`; was the trace made from another tree?"
        );

        let err = statuses(
            r#"{"tick":1,"node":"root","from":"IDLE","to":"DONE"}"#,
            None,
        )
        .unwrap_err();
        assert_eq!((err.line, err.col), (1, 39));
        assert!(err.message.contains("not `DONE`"), "{err}");

        let err = statuses("[1, 2]", None).unwrap_err();
        assert_eq!(err.message, "a trace line is a JSON object");
        let err = statuses(r#"{"node":"root"}"#, None).unwrap_err();
        assert!(err.message.contains("needs a `tick` number"), "{err}");
    }
}
