//! Blackboard data flow: entries read before anything can have written them (NT0101),
//! written as a text the reading port cannot convert (NT0102), written and never read
//! (NT0103).
//!
//! A tree no other tree uses is followed from its root, in tick order, into its SubTrees:
//! each SubTree opens a scope whose entries are the parent's where the SubTree remaps them
//! (`port="{key}"`, or every entry with `_autoremap`), and its own otherwise. Every read and
//! write of an entry (a port bound to `{key}` or defaulting to one, a Script's names and
//! assignments, SetBlackboard, a SubTree's literal) becomes an access with its place in
//! that order and the loops around it. A read is satisfied by a write before it, or by one
//! anywhere inside a loop that also holds the read (a Repeat, a retry, a reactive control,
//! a Parallel, a control of another library: the next round sees it).

use std::collections::{BTreeSet, HashMap};

use neurotree_core::{PortDirection, PortValue};

use super::node::{self, is, line, shown};
use super::types;
use super::{matches, Diagnostic, LintOptions, Site};
use crate::nodes::entry::SKIP_UNLESS_UPDATED;
use crate::nodes::script::PRECONDITION;
use crate::nodes::switch::{SWITCH2, SWITCH3, SWITCH4, SWITCH5, SWITCH6};
use crate::registry::PortSpec;
use crate::script::ast::{AssignOp, Expr, ExprKind};
use crate::script::Script;
use crate::xml::{binding, XmlLoader};
use neurotree_core::nodes::control::{fallback, if_then_else, sequence, try_catch};
use neurotree_core::nodes::decorator::{cooldown, delay, force, inverter, run_once, timeout};
use neurotree_core::nodes::NodeDecl;

/// An entry: the scope it lives in (0 is the root tree's) and its name there.
type Key = (usize, String);

/// A blackboard scope: the root tree's or a SubTree's.
struct Scope {
    parent: Option<usize>,
    /// The SubTree's ports bound to the parent's entries.
    remap: Vec<(String, Key)>,
    autoremap: bool,
}

/// How an entry is reached.
#[derive(Clone)]
enum Use<'r> {
    /// Read by an input port (whose type converts it) or by a script's name. A read that
    /// a missing entry does not fail is `checked: false`.
    Read {
        port: Option<&'r PortSpec>,
        checked: bool,
        script: bool,
    },
    /// Written; with the text written when it is a literal, or the port that writes it.
    /// `remap` for a SubTree's literal port, which gives the SubTree a value whether or not
    /// it reads it.
    Write {
        literal: Option<String>,
        port: Option<&'r PortSpec>,
        remap: bool,
    },
}

/// One read or write of an entry.
struct Access<'d, 'r> {
    key: Key,
    what: Use<'r>,
    /// Its place in tick order.
    order: usize,
    /// The loops around it, outermost first.
    loops: Vec<usize>,
    site: Site<'d>,
    /// The node and port, for messages: "port `message` of SaySomething".
    by: String,
    /// Named `@key`: an entry of the root blackboard, which the application shares.
    global: bool,
}

/// A write the node makes once it has run: the entry, the literal written, who writes it,
/// and whether it is named `@key`.
type Pending<'r> = (Key, Use<'r>, String, bool);

/// Ports whose text is a script, by node type.
const SCRIPT_PORTS: [(&str, &str); 3] = [
    ("Script", "code"),
    ("ScriptCondition", "code"),
    ("Precondition", "if"),
];
/// Attributes whose script runs before the node, and after it.
const BEFORE: [&str; 4] = ["_skipIf", "_successIf", "_failureIf", "_while"];
const AFTER: [&str; 4] = ["_onSuccess", "_onFailure", "_onHalted", "_post"];

/// Controls and decorators that tick each child at most once per round, in order: a
/// write after a read in them is not seen by that read. Any other node with children (a
/// loop, a reactive control, a Parallel, a node of another library) may tick a child again
/// after a later one.
const IN_ORDER: [&NodeDecl; 14] = [
    &sequence::SEQUENCE,
    &sequence::SEQUENCE_WITH_MEMORY,
    &sequence::ASYNC_SEQUENCE,
    &fallback::FALLBACK,
    &fallback::ASYNC_FALLBACK,
    &if_then_else::IF_THEN_ELSE,
    &try_catch::TRY_CATCH,
    &inverter::INVERTER,
    &force::FORCE_SUCCESS,
    &force::FORCE_FAILURE,
    &timeout::TIMEOUT,
    &delay::DELAY,
    &run_once::RUN_ONCE,
    &cooldown::COOLDOWN,
];
/// The toolkit's nodes that tick a child at most once per round.
const IN_ORDER_TOOLKIT: [&NodeDecl; 7] = [
    &SWITCH2,
    &SWITCH3,
    &SWITCH4,
    &SWITCH5,
    &SWITCH6,
    &PRECONDITION,
    &SKIP_UNLESS_UPDATED,
];

/// Follows the entries of the tree `id` (one no other tree uses) and reports what is wrong
/// with them.
pub(crate) fn check_root<C: 'static>(
    loader: &XmlLoader<'_, C>,
    id: &str,
    options: &LintOptions,
    found: &mut Vec<Diagnostic>,
) {
    let Some(tree) = loader.tree(id) else { return };
    let Some(root) = tree.children().next() else {
        return;
    };
    let mut flow = Flow {
        loader,
        scopes: vec![Scope {
            parent: None,
            remap: Vec::new(),
            autoremap: false,
        }],
        accesses: Vec::new(),
        loops: Vec::new(),
        next_loop: 0,
        depth: 0,
        interface: loader
            .subtree_model(id)
            .unwrap_or_default()
            .iter()
            .map(|(port, _)| port.clone())
            .collect(),
    };
    let site = Site {
        tree: id,
        root: tree,
        el: root,
    };
    flow.walk(site, 0);
    flow.report(options, found);
}

struct Flow<'l, 'r, C> {
    loader: &'l XmlLoader<'r, C>,
    scopes: Vec<Scope>,
    accesses: Vec<Access<'l, 'r>>,
    loops: Vec<usize>,
    next_loop: usize,
    /// SubTrees open: the loader bounds it, this guards against a cycle it missed.
    depth: usize,
    /// The ports the root tree's SubTree model declares.
    interface: Vec<String>,
}

impl<'l, 'r, C: 'static> Flow<'l, 'r, C> {
    /// The entry `name` of `scope` is.
    fn key(&self, scope: usize, name: &str) -> Key {
        if let Some(global) = name.strip_prefix('@') {
            return (0, global.to_string());
        }
        let s = &self.scopes[scope];
        if let Some((_, key)) = s.remap.iter().find(|(port, _)| port == name) {
            return key.clone();
        }
        match s.parent {
            // As BehaviorTree.CPP: `_private` entries stay in the SubTree's scope.
            Some(parent) if s.autoremap && !name.starts_with('_') => self.key(parent, name),
            _ => (scope, name.to_string()),
        }
    }

    fn push(&mut self, key: Key, what: Use<'r>, site: Site<'l>, by: String) {
        self.accesses.push(Access {
            global: false,
            key,
            what,
            order: self.accesses.len(),
            loops: self.loops.clone(),
            site,
            by,
        });
    }

    /// The accesses of the node `site.el` and everything below it, in `scope`.
    fn walk(&mut self, site: Site<'l>, scope: usize) {
        let el = site.el;
        for attr in BEFORE {
            self.script(site, scope, attr, el.attr(attr));
        }
        let node = node::resolve(self.loader.registry(), el);
        let mut writes = Vec::new();
        match &node {
            Some(node) if node.name == "SubTree" => self.subtree(site, scope),
            Some(node) => {
                writes = self.ports(site, scope, node.name, node.node_type.map(|t| &t.ports[..]));
                let in_order = is(node.name, &IN_ORDER) || is(node.name, &IN_ORDER_TOOLKIT);
                let looping = el.child_count() > 0 && !in_order;
                self.children(site, scope, looping);
            }
            None => {
                writes = self.unknown_ports(site, scope);
                self.children(site, scope, true);
            }
        }
        for (key, write, by, global) in writes {
            self.push(key, write, site, by);
            if global {
                self.mark_global("@");
            }
        }
        for attr in AFTER {
            self.script(site, scope, attr, el.attr(attr));
        }
    }

    fn children(&mut self, site: Site<'l>, scope: usize, looping: bool) {
        if looping {
            self.loops.push(self.next_loop);
            self.next_loop += 1;
        }
        for child in site.el.children() {
            self.walk(Site { el: child, ..site }, scope);
        }
        if looping {
            self.loops.pop();
        }
    }

    /// Marks the access just recorded as one of the root blackboard if `name` is `@key`.
    fn mark_global(&mut self, name: &str) {
        if let (true, Some(last)) = (name.starts_with('@'), self.accesses.last_mut()) {
            last.global = true;
        }
    }

    /// Records the reads of the node's ports and returns its writes, which happen when it
    /// has run.
    fn ports(
        &mut self,
        site: Site<'l>,
        scope: usize,
        type_name: &str,
        ports: Option<&'r [PortSpec]>,
    ) -> Vec<Pending<'r>> {
        let el = site.el;
        if type_name == "SetBlackboard" {
            return self.set_blackboard(site, scope);
        }
        let mut writes = Vec::new();
        let by = |port: &str| format!("port `{port}` of {}", shown(el));
        for spec in ports.unwrap_or_default() {
            let text = el.attr(&spec.name).or(spec.default.as_deref());
            if SCRIPT_PORTS.contains(&(type_name, spec.name.as_str())) {
                self.script(site, scope, &spec.name, text);
                continue;
            }
            let Some(PortValue::Entry(name)) = text.map(|t| binding(&spec.name, t)) else {
                continue;
            };
            let key = self.key(scope, &name);
            // The entry nodes read an entry by name and take a missing one as not updated.
            let checked = !matches!(
                type_name,
                "WasEntryUpdated" | "SkipUnlessUpdated" | "WaitValueUpdate"
            );
            match spec.direction {
                PortDirection::Input => {
                    let what = Use::Read {
                        port: Some(spec),
                        checked,
                        script: false,
                    };
                    self.push(key, what, site, by(&spec.name));
                    self.mark_global(&name);
                }
                PortDirection::Output => writes.push((
                    key,
                    written(None, Some(spec)),
                    by(&spec.name),
                    name.starts_with('@'),
                )),
                PortDirection::InOut => {
                    let what = Use::Read {
                        port: Some(spec),
                        checked: false,
                        script: false,
                    };
                    self.push(key.clone(), what, site, by(&spec.name));
                    writes.push((
                        key,
                        written(None, Some(spec)),
                        by(&spec.name),
                        name.starts_with('@'),
                    ));
                }
            }
        }
        writes
    }

    /// SetBlackboard's read of `value` if it names an entry, and its write (returned): the
    /// entry `output_key` names, written as plain text (`key`) or as `{key}`.
    fn set_blackboard(&mut self, site: Site<'l>, scope: usize) -> Vec<Pending<'r>> {
        let el = site.el;
        let (Some(value), Some(target)) = (el.attr("value"), el.attr("output_key")) else {
            return Vec::new();
        };
        let by = |port: &str| format!("port `{port}` of {}", shown(el));
        let target = match binding("output_key", target) {
            PortValue::Entry(k) | PortValue::Literal(k) => k,
        };
        let literal = match binding("value", value) {
            PortValue::Literal(text) => Some(text),
            PortValue::Entry(source) => {
                let key = self.key(scope, &source);
                let what = Use::Read {
                    port: None,
                    checked: true,
                    script: false,
                };
                self.push(key, what, site, by("value"));
                None
            }
        };
        let target = target.trim();
        let write = written(literal, None);
        vec![(
            self.key(scope, target),
            write,
            by("output_key"),
            target.starts_with('@'),
        )]
    }

    /// A node of no known type (a leaf mocked for a dry run) may read and write every entry
    /// its attributes name: each is taken as read (without the check that it was
    /// written) and as written.
    fn unknown_ports(&mut self, site: Site<'l>, scope: usize) -> Vec<Pending<'r>> {
        let el = site.el;
        let mut writes = Vec::new();
        for (port, text) in el
            .attrs()
            .filter(|(k, _)| *k != "name" && *k != "ID" && !k.starts_with('_'))
        {
            if let PortValue::Entry(name) = binding(port, text) {
                let key = self.key(scope, &name);
                let by = format!("port `{port}` of {}", shown(el));
                let what = Use::Read {
                    port: None,
                    checked: false,
                    script: false,
                };
                self.push(key.clone(), what, site, by.clone());
                writes.push((key, written(None, None), by, name.starts_with('@')));
            }
        }
        writes
    }

    /// Opens the SubTree `site.el`'s scope and follows the tree it names.
    fn subtree(&mut self, site: Site<'l>, scope: usize) {
        let el = site.el;
        let Some(id) = el.attr("ID") else { return };
        let (Some(tree), true) = (self.loader.tree(id), self.depth < 64) else {
            return;
        };
        let autoremap = el
            .attr("_autoremap")
            .is_some_and(|v| matches!(v.trim(), "true" | "TRUE" | "True" | "1"));
        let inner = self.scopes.len();
        self.scopes.push(Scope {
            parent: Some(scope),
            remap: Vec::new(),
            autoremap,
        });
        let mut ports: Vec<(&str, &str)> = el
            .attrs()
            .filter(|(k, _)| *k != "ID" && *k != "name" && !k.starts_with('_'))
            .collect();
        if !autoremap {
            for (port, default) in self.loader.subtree_model(id).unwrap_or_default() {
                if let (None, Some(default)) = (el.attr(port), default) {
                    ports.push((port, default));
                }
            }
        }
        for (port, text) in ports {
            match binding(port, text) {
                PortValue::Entry(parent_key) => {
                    let key = self.key(scope, &parent_key);
                    self.scopes[inner].remap.push((port.to_string(), key));
                }
                PortValue::Literal(text) => {
                    let by = format!("port `{port}` of SubTree {}", shown(el));
                    self.push(
                        (inner, port.to_string()),
                        Use::Write {
                            literal: Some(text),
                            port: None,
                            remap: true,
                        },
                        site,
                        by,
                    );
                }
            }
        }
        if let Some(root) = tree.children().next() {
            self.depth += 1;
            self.walk(
                Site {
                    tree: id,
                    root: tree,
                    el: root,
                },
                inner,
            );
            self.depth -= 1;
        }
    }

    /// Records the reads and writes of the script `text` (of attribute or port `name`).
    fn script(&mut self, site: Site<'l>, scope: usize, name: &str, text: Option<&str>) {
        let Some(Ok(script)) = text.map(Script::parse) else {
            return;
        };
        let by = format!("the script `{name}` of {}", shown(site.el));
        let enums = self.loader.registry().enums();
        let mut uses = Vec::new();
        for expr in script.program() {
            script_uses(expr, &mut uses);
        }
        for (entry, what) in uses {
            if matches!(what, Use::Read { .. }) && enums.get(&entry).is_some() {
                continue;
            }
            let key = self.key(scope, &entry);
            self.push(key, what, site, by.clone());
            self.mark_global(&entry);
        }
    }

    fn report(&self, options: &LintOptions, found: &mut Vec<Diagnostic>) {
        // By entry, so that each read looks only at the writes of its own entry.
        let mut writes: HashMap<&Key, Vec<&Access<'_, '_>>> = HashMap::new();
        for a in self
            .accesses
            .iter()
            .filter(|a| matches!(a.what, Use::Write { .. }))
        {
            writes.entry(&a.key).or_default().push(a);
        }
        let read: BTreeSet<&Key> = self
            .accesses
            .iter()
            .filter(|a| matches!(a.what, Use::Read { .. }))
            .map(|a| &a.key)
            .collect();
        let external = |key: &Key, names: &[String]| key.0 == 0 && matches(names, &key.1);
        let mut unused = BTreeSet::new();
        for access in &self.accesses {
            match &access.what {
                Use::Read {
                    port,
                    checked,
                    script,
                } => {
                    let writers = writes.get(&access.key).map_or(&[][..], Vec::as_slice);
                    let is_written = !writers.is_empty();
                    // A name no one writes may be an enum the application registers.
                    let unknowable = *script && !is_written;
                    if *checked
                        && !unknowable
                        && !access.global
                        && !self.interface(&access.key)
                        && !external(&access.key, &options.written)
                        && !written_before(access, writers)
                    {
                        found.push(read_before_write(access, writers));
                    }
                    if let Some(spec) = port {
                        mismatches(access, spec, writers, found);
                    }
                }
                Use::Write { remap: false, .. } => {
                    if !read.contains(&access.key)
                        && !access.global
                        && !self.interface(&access.key)
                        && !external(&access.key, &options.read)
                        && unused.insert(&access.key)
                    {
                        found.push(access.site.diagnostic(
                            "NT0103",
                            format!(
                                "the entry `{}` is written by {} but never read",
                                access.key.1, access.by
                            ),
                        ));
                    }
                }
                Use::Write { remap: true, .. } => {}
            }
        }
    }

    /// Whether `key` is a port the root tree's SubTree model declares: its parent, not
    /// linted here, writes or reads it.
    fn interface(&self, key: &Key) -> bool {
        key.0 == 0 && self.interface.contains(&key.1)
    }
}

/// Whether one of `writes` (of `read`'s entry) can come before it: earlier in tick order,
/// or in a loop that holds them both.
fn written_before(read: &Access<'_, '_>, writes: &[&Access<'_, '_>]) -> bool {
    writes
        .iter()
        .any(|w| w.order < read.order || w.loops.iter().any(|l| read.loops.contains(l)))
}

/// The finding of `read`, which none of `writes` (of its entry) comes before.
fn read_before_write(read: &Access<'_, '_>, writes: &[&Access<'_, '_>]) -> Diagnostic {
    let name = &read.key.1;
    let hint = match writes.first() {
        Some(w) => format!(
            "; it is first written later, by {} at line {}",
            w.by,
            line(w.site.el)
        ),
        None => format!(
            "; nothing in the tree writes it (if the application does, say so with --entry {name})"
        ),
    };
    read.site.diagnostic(
        "NT0101",
        format!(
            "{} reads the entry `{name}`, which nothing can have written before: the read \
             fails at that tick{hint}",
            read.by
        ),
    )
}

/// Reports each literal of `writes` (into `read`'s entry) that its port cannot convert,
/// and each port of them that writes the entry as a type its port cannot read.
fn mismatches(
    read: &Access<'_, '_>,
    spec: &PortSpec,
    writes: &[&Access<'_, '_>],
    found: &mut Vec<Diagnostic>,
) {
    for w in writes {
        let why = match &w.what {
            Use::Write {
                literal: Some(text),
                ..
            } if !spec.accepts(text) => format!("writes `{text}` into it, which does not convert"),
            Use::Write {
                port: Some(port), ..
            } => match types::entry_mismatch(port, spec) {
                Some(why) => why,
                None => continue,
            },
            _ => continue,
        };
        found.push(read.site.diagnostic(
            "NT0102",
            format!(
                "{} reads the entry `{}` as {}, but {} at line {} {why}",
                read.by,
                read.key.1,
                types::read_as(spec),
                w.by,
                line(w.site.el)
            ),
        ));
    }
}

/// A write of a node's, of `literal` text or through `port`.
fn written(literal: Option<String>, port: Option<&PortSpec>) -> Use<'_> {
    Use::Write {
        literal,
        port,
        remap: false,
    }
}

/// The entries `expr` reads and writes, in the order it does.
fn script_uses<'r>(expr: &Expr, uses: &mut Vec<(String, Use<'r>)>) {
    let read = |script| Use::Read {
        port: None,
        checked: true,
        script,
    };
    match &expr.kind {
        ExprKind::Name(name) => uses.push((name.to_string(), read(true))),
        ExprKind::Unary(_, _, e) => script_uses(e, uses),
        ExprKind::Binary(_, _, a, b) => {
            script_uses(a, uses);
            script_uses(b, uses);
        }
        ExprKind::Compare(operands, _) => operands.iter().for_each(|e| script_uses(e, uses)),
        ExprKind::Ternary(c, a, b) => {
            script_uses(c, uses);
            script_uses(a, uses);
            script_uses(b, uses);
        }
        ExprKind::Assign(op, _, key, _, value) => {
            script_uses(value, uses);
            // `+=` reads the entry; `=` needs it to exist, which BehaviorTree.CPP's tree
            // makes sure of when a port names it, and is taken as a plain write.
            if matches!(op, AssignOp::Compound(_)) {
                uses.push((key.to_string(), read(false)));
            }
            let literal = match &value.kind {
                ExprKind::Str(text) => Some(text.to_string()),
                _ => None,
            };
            uses.push((
                key.to_string(),
                Use::Write {
                    literal,
                    port: None,
                    remap: false,
                },
            ));
        }
        ExprKind::Int(_) | ExprKind::Real(_) | ExprKind::Bool(_) | ExprKind::Str(_) => {}
    }
}

#[cfg(test)]
mod tests {
    use super::super::{findings, findings_with, LintOptions};

    fn tree(body: &str) -> String {
        format!(
            "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\">\n\
             <BehaviorTree ID=\"Main\">\n{body}\n</BehaviorTree>\n</root>"
        )
    }

    #[test]
    fn a_read_before_its_write_is_found_and_one_after_is_not() {
        let xml = tree(
            "<Sequence>\n\
             <Say message=\"{text}\"/>\n\
             <Think text=\"{text}\"/>\n\
             <Say message=\"{text}\"/>\n\
             </Sequence>",
        );
        assert_eq!(findings(&xml), [("NT0101", 4)]);
    }

    #[test]
    fn a_write_later_in_the_same_loop_counts() {
        let xml = tree(
            "<Repeat num_cycles=\"3\"><Sequence>\n\
             <Say message=\"{text}\"/>\n\
             <Think text=\"{text}\"/>\n\
             </Sequence></Repeat>",
        );
        assert_eq!(findings(&xml), []);
        // The same in a Sequence that is no loop: the first round reads nothing.
        let xml = tree(
            "<Sequence><Sequence>\n\
             <Say message=\"{text}\"/>\n\
             <Think text=\"{text}\"/>\n\
             </Sequence></Sequence>",
        );
        assert_eq!(findings(&xml), [("NT0101", 4)]);
    }

    #[test]
    fn an_entry_written_by_a_script_or_the_application_is_provided() {
        let xml = tree(
            "<Sequence>\n\
             <Script code=\"text := 'hi'\"/>\n\
             <Say message=\"{text}\"/>\n\
             <Say message=\"{greeting}\"/>\n\
             </Sequence>",
        );
        assert_eq!(findings(&xml), [("NT0101", 6)]);
        let options = LintOptions {
            written: vec!["greet*".into()],
            ..LintOptions::default()
        };
        assert_eq!(findings_with(&xml, &options), []);
    }

    #[test]
    fn a_port_default_naming_an_entry_reads_it() {
        let xml = tree("<Move/>");
        assert_eq!(findings(&xml), [("NT0101", 3)]);
        assert_eq!(findings_with(&xml, &LintOptions::nav2()), []);
    }

    #[test]
    fn entries_follow_subtree_remapping() {
        let remapped = "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\">\n\
             <BehaviorTree ID=\"Main\"><Sequence>\n\
             <Think text=\"{said}\"/>\n\
             <SubTree ID=\"Speak\" words=\"{said}\"/>\n\
             </Sequence></BehaviorTree>\n\
             <BehaviorTree ID=\"Speak\">\n\
             <Say message=\"{words}\"/>\n\
             </BehaviorTree></root>";
        assert_eq!(findings(remapped), []);
        // Not remapped: the SubTree's own `words` is never written, and `said` never read.
        let plain = remapped.replace(" words=\"{said}\"", "");
        assert_eq!(findings(&plain), [("NT0103", 3), ("NT0101", 7)]);
        // A literal gives the SubTree its entry.
        let literal = remapped.replace("words=\"{said}\"", "words=\"hello\"");
        assert_eq!(findings(&literal), [("NT0103", 3)]);
        let autoremap = plain.replace("ID=\"Speak\"/>", "ID=\"Speak\" _autoremap=\"true\"/>");
        assert_eq!(findings(&autoremap), [("NT0103", 3), ("NT0101", 7)]);
    }

    #[test]
    fn a_text_written_where_a_number_is_read_is_an_error() {
        let xml = tree(
            "<Sequence>\n\
             <Script code=\"n := 'three'\"/>\n\
             <Count n=\"{n}\"/>\n\
             </Sequence>",
        );
        assert_eq!(findings(&xml), [("NT0102", 5)]);
        assert_eq!(findings(&xml.replace("'three'", "'3'")), []);
        let set = xml.replace(
            "<Script code=\"n := 'three'\"/>",
            "<SetBlackboard value=\"many\" output_key=\"n\"/>",
        );
        assert_eq!(findings(&set), [("NT0102", 5)]);
        // A port of another type writes it.
        let located = xml.replace("<Script code=\"n := 'three'\"/>", "<Locate place=\"{n}\"/>");
        assert_eq!(findings(&located), [("NT0102", 5)]);
        // Text converts.
        let thought = xml.replace("<Script code=\"n := 'three'\"/>", "<Think text=\"{n}\"/>");
        assert_eq!(findings(&thought), []);
    }

    #[test]
    fn an_entry_written_and_never_read_is_noted() {
        let xml = tree(
            "<Sequence>\n\
             <Script code=\"x := 1; y := x + 1\"/>\n\
             <Think text=\"{thought}\" _onSuccess=\"@shared := 2\"/>\n\
             </Sequence>",
        );
        // `y` and `thought`; `x` is read by the script, `@shared` by the application.
        assert_eq!(findings(&xml), [("NT0103", 4), ("NT0103", 5)]);
        let options = LintOptions {
            read: vec!["thought".into(), "y".into()],
            ..LintOptions::default()
        };
        assert_eq!(findings_with(&xml, &options), []);
    }
}
