//! Static analysis of loaded trees: what a tree does wrong that loading cannot see.
//!
//! The loader refuses what BehaviorTree.CPP refuses when it reads a file (unknown nodes and
//! ports, bad literals, cycles). Many mistakes pass that check and show only when the tree
//! runs: a port reads an entry nothing wrote ("missing entry" at that tick), a child comes
//! after one that always ends its Sequence, a retry loop waits for a success that cannot
//! come. [`lint`] finds them over the trees an [`XmlLoader`] holds, without running them.
//!
//! The rules come in three families, one module each:
//! - [`dataflow`]: the blackboard's entries, followed through SubTree remapping: read before
//!   anything can have written them, written as one type and read as another, written and
//!   never read.
//! - [`reachability`]: children no tick can reach, Switch cases no value matches, trees
//!   nothing uses.
//! - [`liveness`]: loops that cannot end, roots that never finish.
//!
//! Reachability and liveness rest on which statuses each node can return ([`outcomes`]):
//! a node whose statuses are not known for sure (an action, a control of another library, a
//! node with a precondition attribute) is taken to return any, so that a finding is only
//! ever made from what the tree itself says.
//!
//! Each finding is a [`Diagnostic`] with a stable code (`NT0101`), a rule name, a
//! [`Severity`] and a place; [`RULES`] lists them all with their explanations.
//!
//! ```
//! use neurotree::lint::{lint, LintOptions, Severity};
//! use neurotree::{Registry, XmlLoader};
//!
//! let registry = Registry::<()>::new();
//! let mut loader = XmlLoader::new(&registry);
//! loader.load_str(r#"
//!     <root BTCPP_format="4">
//!       <BehaviorTree ID="Main">
//!         <Fallback>
//!           <AlwaysSuccess/>
//!           <AlwaysFailure/>
//!         </Fallback>
//!       </BehaviorTree>
//!     </root>"#, "main.xml").unwrap();
//! let found = lint(&loader, &LintOptions::default());
//! assert_eq!(found[0].code, "NT0201");
//! assert_eq!(found[0].severity, Severity::Warning);
//! assert_eq!(found[0].to_string(),
//!     "main.xml:6:11: warning[NT0201]: this child is never ticked: the Fallback's child \
//!      `AlwaysSuccess` at line 5 never fails");
//! ```

pub mod dataflow;
pub mod liveness;
mod node;
pub mod outcomes;
pub mod reachability;
mod rules;
pub(crate) mod types;

use std::collections::BTreeSet;
use std::fmt;

use serde::Serialize;

use crate::xml::{Element, XmlLoader};

pub use rules::{rule, Rule, RULES};

/// The guide's examples (`docs/guide/lint.md`), compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../guide/lint.md")]
pub struct Guide;

/// How much a finding matters: an error fails `neurotree lint`, a warning does when denied.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// Worth knowing; the tree works as written.
    Note,
    /// The tree will likely not do what was meant.
    Warning,
    /// The tree fails when it reaches this.
    Error,
}

impl fmt::Display for Severity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(match self {
            Severity::Note => "note",
            Severity::Warning => "warning",
            Severity::Error => "error",
        })
    }
}

/// One finding: which rule, where, and what to do.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Diagnostic {
    /// The rule's stable code, `NT0101`.
    pub code: &'static str,
    /// The rule's name, `read-before-write`.
    pub rule: &'static str,
    /// How much it matters.
    pub severity: Severity,
    /// What is wrong, for people.
    pub message: String,
    /// The file (as given to the loader).
    pub file: String,
    /// 1-based line.
    pub line: u32,
    /// 1-based column.
    pub col: u32,
    /// The `<BehaviorTree>` the node is in.
    pub tree: String,
    /// The node's place in its tree: element names from the tree's root down, each with
    /// its index among its siblings, `Sequence[0]/Fallback[1]`.
    pub path: String,
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}[{}]: {}",
            self.file, self.line, self.col, self.severity, self.code, self.message
        )
    }
}

/// What the trees' surroundings do to the blackboard, which the files cannot say.
#[derive(Clone, Debug, Default)]
pub struct LintOptions {
    /// Entries of the root blackboard the application writes before the first tick (Nav2's
    /// navigators write `goal` or `goals`). A name may start or end with `*`, matching any
    /// name that ends or starts with the rest.
    pub written: Vec<String>,
    /// Entries the application reads after or while the tree runs (Nav2's navigators
    /// read the error codes), written as [`written`](Self::written)'s names.
    pub read: Vec<String>,
    /// Lint only this tree and the trees it uses (all the trees loaded when `None`).
    pub tree: Option<String>,
}

impl LintOptions {
    /// The entries Nav2's navigators write before the first tick and read from the tree
    /// (`bt_navigator`'s NavigateToPose, NavigateThroughPoses and route navigators).
    pub fn nav2() -> Self {
        let names = |list: &[&str]| list.iter().map(|s| s.to_string()).collect();
        Self {
            tree: None,
            written: names(&[
                "goal",
                "goals",
                "route_goals",
                "waypoint_statuses",
                "number_recoveries",
                "server_timeout",
                "bt_loop_duration",
                "wait_for_service_timeout",
                "initial_pose_received",
            ]),
            read: names(&[
                "*_error_code",
                "*_error_msg",
                "path",
                "tracking_feedback",
                "waypoint_statuses",
            ]),
        }
    }
}

/// Whether `name` is one of `patterns` (see [`LintOptions::written`]).
fn matches(patterns: &[String], name: &str) -> bool {
    patterns
        .iter()
        .any(|p| match (p.strip_prefix('*'), p.strip_suffix('*')) {
            (Some(end), _) => name.ends_with(end),
            (_, Some(start)) => name.starts_with(start),
            _ => p == name,
        })
}

/// Lints every tree `loader` holds: each tree no other tree uses is followed from its root
/// into its SubTrees, and each finding is reported once, in file and position order.
/// The trees must have loaded and validated (what `neurotree check` does first).
pub fn lint<C: 'static>(loader: &XmlLoader<'_, C>, options: &LintOptions) -> Vec<Diagnostic> {
    let mut found = Vec::new();
    let (ids, roots) = match &options.tree {
        Some(tree) => (uses(loader, tree), vec![tree.as_str()]),
        None => (loader.tree_ids().collect(), loader.unreferenced_trees()),
    };
    let mut statuses = outcomes::Outcomes::new(loader);
    for id in &ids {
        if let Some(tree) = loader.tree(id) {
            reachability::check_tree(loader, &mut statuses, id, tree, &mut found);
            liveness::check_tree(&mut statuses, id, tree, &mut found);
        }
    }
    if options.tree.is_none() {
        reachability::unused_trees(loader, &mut found);
    }
    for id in roots {
        dataflow::check_root(loader, id, options, &mut found);
    }
    let mut seen = BTreeSet::new();
    found.retain(|d| seen.insert(d.to_string()));
    found.sort_by(|a, b| (&a.file, a.line, a.col, a.code).cmp(&(&b.file, b.line, b.col, b.code)));
    found
}

/// The tree `id` and every loaded tree it uses through its SubTrees, in the order met.
pub(crate) fn uses<'l, C: 'static>(loader: &'l XmlLoader<'_, C>, id: &'l str) -> Vec<&'l str> {
    let mut used = vec![id];
    let mut at = 0;
    while let Some(tree) = used.get(at).and_then(|id| loader.tree(id)) {
        for el in tree.descendants().filter(|e| e.tag() == "SubTree") {
            if let Some(sub) = el.attr("ID").filter(|s| !used.contains(s)) {
                used.push(sub);
            }
        }
        at += 1;
    }
    used
}

/// Where a finding is: a node of a tree.
#[derive(Clone, Copy)]
pub(crate) struct Site<'d> {
    /// The tree's ID.
    pub(crate) tree: &'d str,
    /// Its `<BehaviorTree>` element.
    pub(crate) root: Element<'d>,
    /// The node.
    pub(crate) el: Element<'d>,
}

impl Site<'_> {
    /// A finding of the rule `code` here.
    pub(crate) fn diagnostic(&self, code: &str, message: String) -> Diagnostic {
        let rule = rule(code).expect("every rule the lints use is in the catalog");
        let (line, col) = self.el.line_col();
        Diagnostic {
            code: rule.code,
            rule: rule.name,
            severity: rule.severity,
            message,
            file: self.el.file().to_string(),
            line,
            col,
            tree: self.tree.to_string(),
            path: node::path_in_tree(self.root, self.el),
        }
    }
}

/// Runs `f` on a loader holding `xml` (one file, `main.xml`) and validated; its leaves:
/// `Say` (input `message`), `Think` (output `text`), `Move` (input `goal` defaulting to
/// `{goal}`), `Count` (input `n`, an int), `Locate` (output `place`, a pair of floats),
/// `Check` (a condition).
#[cfg(test)]
fn lint_test_loader<T>(xml: &str, f: impl FnOnce(&XmlLoader<'_, ()>) -> T) -> T {
    use crate::{PortSpec, Registry};
    use neurotree_core::Status;
    let mut registry = Registry::<()>::new();
    let leaves = [
        ("Say", PortSpec::input::<String>("message")),
        ("Think", PortSpec::output::<String>("text")),
        (
            "Move",
            PortSpec::input::<String>("goal").default_value("{goal}"),
        ),
        ("Count", PortSpec::input::<i64>("n")),
        ("Locate", PortSpec::output::<(f64, f64)>("place")),
    ];
    for (name, port) in leaves {
        registry
            .register_action(name, vec![port], |_| Status::Success)
            .unwrap();
    }
    registry
        .register_condition("Check", vec![], |_| true)
        .unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(xml, "main.xml").unwrap();
    for id in loader.tree_ids() {
        loader.validate(id).unwrap();
    }
    f(&loader)
}

/// The findings of `xml` (see [`lint_test_loader`]), linted with `options`, as `(code, line)`.
#[cfg(test)]
pub(crate) fn findings_with(xml: &str, options: &LintOptions) -> Vec<(&'static str, u32)> {
    lint_test_loader(xml, |loader| {
        lint(loader, options)
            .iter()
            .map(|d| (d.code, d.line))
            .collect()
    })
}

/// The messages of the findings of `xml` (as [`findings`]).
#[cfg(test)]
pub(crate) fn messages(xml: &str) -> Vec<String> {
    lint_test_loader(xml, |loader| {
        lint(loader, &LintOptions::default())
            .into_iter()
            .map(|d| d.message)
            .collect()
    })
}

/// [`findings_with`] the default options.
#[cfg(test)]
pub(crate) fn findings(xml: &str) -> Vec<(&'static str, u32)> {
    findings_with(xml, &LintOptions::default())
}
