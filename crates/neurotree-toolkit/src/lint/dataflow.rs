//! Blackboard data flow: entries read before anything can have written them (NT0101),
//! written as a value the reading port cannot convert (NT0102), written and never read
//! (NT0103).
//!
//! A tree no other tree uses is followed from its root, in tick order, into its SubTrees:
//! each SubTree opens a scope whose entries are the parent's where the SubTree remaps them
//! (`port="{key}"`, or every entry with `_autoremap`), and its own otherwise. Every read and
//! write of an entry (a port bound to `{key}` or defaulting to one, a Script's names and
//! assignments, SetBlackboard, a SubTree's literal) becomes an access with its place in
//! that order, following each control's declared [`Order`]. A write satisfies a read if it
//! can come first on the first pass: earlier in that order, or under a node that holds both
//! and ticks its children all at once (Parallel, Switch, a control of another library). A
//! later write in a loop (Repeat, a reactive control, RecoveryNode) comes only on the next
//! pass: a read the first pass surely reaches is reported as failing on the first pass.

use std::collections::{BTreeSet, HashMap};

use neurotree_core::{PortDirection, PortValue};

use super::node::{self, line, shown};
use super::outcomes;
use super::types;
use super::{matches, Diagnostic, LintOptions, Site};
use crate::registry::PortSpec;
use crate::script::ast::{AssignOp, Expr, ExprKind};
use crate::script::Script;
use crate::xml::{binding, Element, XmlLoader};
use neurotree_core::nodes::{Order, Statuses};

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
    /// Written; with the text written when it is a literal, the number a script assigns,
    /// or the port that writes it. `remap` for a SubTree's literal port, which gives the
    /// SubTree a value whether or not it reads it.
    Write {
        literal: Option<String>,
        number: Option<f64>,
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
    /// The nodes around it whose children run all at once or in no declared order.
    concurrent: Vec<usize>,
    /// The loops around it from which the first pass surely reaches it ([`Flow::sure`]).
    sure_in: Vec<usize>,
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
        loop_sites: Vec::new(),
        sure: Vec::new(),
        statuses: super::outcomes::Outcomes::new(loader),
        concurrent: Vec::new(),
        next_group: 0,
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
    /// Each loop's node, and where its children start in `sure`, by number.
    loop_sites: Vec<(Element<'l>, usize)>,
    /// From the root down to the node walked: whether each is ticked whenever its parent is
    /// (no precondition; an only child, or one after children that always let it go on).
    sure: Vec<bool>,
    statuses: super::outcomes::Outcomes<'l, 'r, C>,
    concurrent: Vec<usize>,
    next_group: usize,
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
            concurrent: self.concurrent.clone(),
            sure_in: (self.loops.iter().copied())
                .filter(|&l| self.sure[self.loop_sites[l].1..].iter().all(|&s| s))
                .collect(),
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
                let order = outcomes::semantics(self.loader, el).order;
                self.children(site, scope, order);
            }
            None => {
                writes = self.unknown_ports(site, scope);
                self.children(site, scope, Order::AllAtOnce);
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

    /// The accesses of `site.el`'s children, ticked in `order`.
    fn children(&mut self, site: Site<'l>, scope: usize, order: Order) {
        let looping = order.loops();
        let concurrent = order == Order::AllAtOnce && site.el.child_count() > 1;
        if looping {
            self.loops.push(self.loop_sites.len());
            self.loop_sites.push((site.el, self.sure.len()));
        }
        if concurrent {
            self.concurrent.push(self.next_group);
            self.next_group += 1;
        }
        let next_after = order.next_after();
        let single = site.el.child_count() == 1;
        let mut goes_on = next_after != Statuses::ANY;
        for child in site.el.children() {
            self.sure
                .push(outcomes::unguarded(child) && (single || goes_on));
            self.walk(Site { el: child, ..site }, scope);
            self.sure.pop();
            goes_on = goes_on && next_after.contains(self.statuses.of(child));
        }
        if looping {
            self.loops.pop();
        }
        if concurrent {
            self.concurrent.pop();
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
                            number: None,
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
            self.sure.push(outcomes::unguarded(root));
            self.walk(
                Site {
                    tree: id,
                    root: tree,
                    el: root,
                },
                inner,
            );
            self.sure.pop();
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
                        // A later write in a loop may reach it on a pass after a first
                        // one that need not reach it (a condition may end the branch).
                        && outer_shared_loop(access, writers)
                            .is_none_or(|l| access.sure_in.contains(&l))
                    {
                        found.push(read_before_write(access, writers, &self.loop_sites));
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

/// Whether one of `writes` (of `read`'s entry) can come before it on the first pass:
/// earlier in tick order, or under a node that holds them both and ticks its children all
/// at once.
fn written_before(read: &Access<'_, '_>, writes: &[&Access<'_, '_>]) -> bool {
    writes
        .iter()
        .any(|w| w.order < read.order || w.concurrent.iter().any(|g| read.concurrent.contains(g)))
}

/// The outermost loop holding `read` and one of `writes` after it: its next pass sees the
/// write.
fn outer_shared_loop(read: &Access<'_, '_>, writes: &[&Access<'_, '_>]) -> Option<usize> {
    read.loops
        .iter()
        .find(|l| {
            writes
                .iter()
                .any(|w| w.order > read.order && w.loops.contains(l))
        })
        .copied()
}

/// The finding of `read`, which none of `writes` (of its entry) comes before; `loops`
/// holds each loop's node, to say which one a later write comes round through.
fn read_before_write(
    read: &Access<'_, '_>,
    writes: &[&Access<'_, '_>],
    loops: &[(Element<'_>, usize)],
) -> Diagnostic {
    let name = &read.key.1;
    let through = outer_shared_loop(read, writes).map(|l| loops[l].0);
    if let (Some(lp), Some(w)) = (through, writes.iter().find(|w| w.order > read.order)) {
        return read.site.diagnostic(
            "NT0101",
            format!(
                "{} reads the entry `{name}` on the first pass through {} at line {}, before \
                 anything can have written it: the read fails at that tick; it is written \
                 later, by {} at line {}",
                read.by,
                shown(lp),
                line(lp),
                w.by,
                line(w.site.el)
            ),
        );
    }
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
        let Use::Write {
            literal,
            number,
            port,
            ..
        } = &w.what
        else {
            continue;
        };
        let Some(why) = types::write_mismatch(literal.as_deref(), *number, *port, spec) else {
            continue;
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
        number: None,
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
            // `+=` assigns what the entry held and the value make.
            let number = Some(&**value).filter(|_| !matches!(op, AssignOp::Compound(_)));
            uses.push((
                key.to_string(),
                Use::Write {
                    literal,
                    number: number.and_then(types::assigned_number),
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
    fn a_write_later_in_a_loop_is_too_late_for_the_first_pass() {
        let xml = tree(
            "<Repeat num_cycles=\"3\"><Sequence>\n\
             <Say message=\"{text}\"/>\n\
             <Think text=\"{text}\"/>\n\
             </Sequence></Repeat>",
        );
        assert_eq!(findings(&xml), [("NT0101", 4)]);
        let message = &super::super::messages(&xml)[0];
        assert!(
            message.contains("on the first pass through Repeat at line 3")
                && message.contains("written later, by port `text` of Think at line 5"),
            "{message}"
        );
        // Children ticked all at once: the write may come first.
        let parallel = xml.replace("Sequence", "Parallel");
        assert_eq!(findings(&parallel), []);
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
