//! From a blueprint back to BehaviorTree.CPP XML (format 4).
//!
//! [`write_xml`] writes the tree as a `<root BTCPP_format="4">` document that
//! [`XmlLoader`](super::XmlLoader) loads back into the same blueprint, and that Groot2 opens:
//!
//! - every node as the element its registered type names (`<MoveBase goal="{target}"/>`),
//!   with its `name`, its ports (literals as written, entries as `{key}`), a built-in's
//!   parameters (`num_cycles`, `msec`, ...) and its `_skipIf`-style scripts;
//! - every SubTree as `<SubTree ID>` with its remapping, and the tree it opens as a
//!   `<BehaviorTree>` of its own, written once per ID;
//! - a `TreeNodesModel` of the registered types, so an editor knows their ports.
//!
//! With [`SaveOptions::uids`] the file is the one BehaviorTree.CPP's loggers embed (in a
//! `.btlog`, or sent to Groot2's monitor): each element carries `_uid`, the node's id plus
//! one, and each subtree *instance* gets its own `<BehaviorTree>` with a `_fullpath`, as
//! BehaviorTree.CPP writes them, so that uids stay unique.
//!
//! Leaves made with the builder from closures or objects have no registered type; they are
//! written in the explicit form, `<Action ID="their name"/>`, which loads once a type of that
//! name is registered.

use neurotree_core::{Blueprint, NodeId, NodeKind, PortValue};

use super::escape;
use crate::registry::{built_in_ports, Registry};

/// What [`write_xml`] writes besides the tree.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SaveOptions {
    /// The `ID` of the main `<BehaviorTree>` (and `main_tree_to_execute`).
    pub tree_id: String,
    /// Adds `_uid` (and `_fullpath` on subtrees), for logs and live monitoring.
    pub uids: bool,
    /// Adds a `TreeNodesModel` of the registered types that are not built in.
    pub models: bool,
    /// Lists the built-in types in the `TreeNodesModel` too.
    pub builtin_models: bool,
}

impl Default for SaveOptions {
    /// `MainTree`, no uids, a model of the user's types.
    fn default() -> Self {
        SaveOptions {
            tree_id: "MainTree".to_string(),
            uids: false,
            models: true,
            builtin_models: false,
        }
    }
}

/// Writes `blueprint` as a format-4 document (see the [`save`](crate::xml::save) module).
///
/// ```
/// use neurotree::xml::{write_xml, SaveOptions, XmlLoader};
/// use neurotree::Registry;
///
/// let registry = Registry::<()>::new();
/// let mut loader = XmlLoader::new(&registry);
/// loader.load_str(r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
///     <RetryUntilSuccessful num_attempts="3"><AlwaysFailure name="try"/></RetryUntilSuccessful>
///   </BehaviorTree></root>"#, "a.xml").unwrap();
/// let blueprint = loader.build("Main").unwrap();
/// let xml = write_xml(&blueprint, &registry, &SaveOptions::default());
/// assert!(xml.contains(r#"<RetryUntilSuccessful name="RetryUntilSuccessful" num_attempts="3">"#));
///
/// // And back.
/// let mut again = XmlLoader::new(&registry);
/// again.load_str(&xml, "saved.xml").unwrap();
/// assert_eq!(again.build_main().unwrap().len(), 2);
/// ```
pub fn write_xml<C: 'static>(
    blueprint: &Blueprint<C>,
    registry: &Registry<C>,
    opts: &SaveOptions,
) -> String {
    let ends = blueprint.subtree_ends();
    let mut w = Writer {
        bp: blueprint,
        ends: &ends,
        opts,
        out: String::new(),
        pending: Vec::new(),
        written: Vec::new(),
    };
    w.out.push_str(&format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<root BTCPP_format=\"4\" main_tree_to_execute=\"{}\">\n",
        escape(&opts.tree_id)
    ));
    w.behavior_tree(&opts.tree_id, None, NodeId::ROOT);
    while let Some((id, subtree)) = w.pending.pop() {
        let tree_id = blueprint.type_id(subtree).to_string();
        if !opts.uids {
            // A subtree registered in Rust whose leaves have no file form is named, not
            // written; the registry supplies it again on loading.
            let from_rust = registry.subtree(&tree_id).is_some()
                && (id.0..ends[subtree.index()]).any(|n| no_file_form(blueprint, NodeId(n)));
            if w.written.contains(&tree_id) || from_rust {
                continue;
            }
            w.written.push(tree_id.clone());
        }
        let path = blueprint.path(subtree);
        w.behavior_tree(&tree_id, opts.uids.then_some(path.as_str()), id);
    }
    if opts.models {
        registry.write_models(&mut w.out, opts.builtin_models);
    }
    w.out.push_str("</root>\n");
    w.out
}

struct Writer<'a, C> {
    bp: &'a Blueprint<C>,
    ends: &'a [u32],
    opts: &'a SaveOptions,
    out: String,
    /// `(root of the tree, SubTree node that opens it)`, still to write: a stack whose top is
    /// the first subtree met in the latest tree written, so that trees come out depth-first
    /// in the order they are met, as BehaviorTree.CPP writes its subtree instances (a viewer
    /// that pairs repeated instances of one ID with successive `<BehaviorTree>`s relies on it).
    pending: Vec<(NodeId, NodeId)>,
    /// Tree IDs already written (without uids each is written once).
    written: Vec<String>,
}

impl<C> Writer<'_, C> {
    /// Writes `<BehaviorTree ID>` holding the nodes from `root` down, stopping at SubTrees,
    /// whose trees are queued instead. Iterative, so a deep tree needs no deep stack.
    fn behavior_tree(&mut self, id: &str, fullpath: Option<&str>, root: NodeId) {
        self.out
            .push_str(&format!("  <BehaviorTree ID=\"{}\"", escape(id)));
        if let Some(path) = fullpath {
            self.out
                .push_str(&format!(" _fullpath=\"{}\"", escape(path)));
        }
        self.out.push_str(">\n");
        let mut open: Vec<(NodeId, String)> = Vec::new();
        let mut met: Vec<(NodeId, NodeId)> = Vec::new();
        let mut at = root.0;
        let end = self.ends[root.index()];
        while at < end {
            let node = NodeId(at);
            while let Some((top, tag)) = open.last() {
                if self.ends[top.index()] > at {
                    break;
                }
                let indent = "  ".repeat(open.len() + 1);
                self.out.push_str(&format!("{indent}</{tag}>\n"));
                open.pop();
            }
            let depth = open.len() + 2;
            let tag = self.element(node, depth);
            if let NodeKind::SubTree(_) = self.bp.kind(node) {
                met.push((NodeId(at + 1), node));
                at = self.ends[node.index()];
                continue;
            }
            if let Some(tag) = tag {
                open.push((node, tag));
            }
            at += 1;
        }
        while let Some((_, tag)) = open.pop() {
            let indent = "  ".repeat(open.len() + 2);
            self.out.push_str(&format!("{indent}</{tag}>\n"));
        }
        self.out.push_str("  </BehaviorTree>\n");
        self.pending.extend(met.into_iter().rev());
    }

    /// Writes the node's start tag (self-closed when it has no children written below it)
    /// and returns the tag to close, if any.
    fn element(&mut self, id: NodeId, depth: usize) -> Option<String> {
        let bp = self.bp;
        let kind = bp.kind(id);
        let name = bp.name(id);
        let type_id = bp.type_id(id);
        let mut attrs: Vec<(String, String)> = Vec::new();
        let generic = no_file_form(bp, id);
        let tag = if let NodeKind::SubTree(scope) = kind {
            let tree_id = if type_id == kind.type_name() {
                name
            } else {
                type_id
            };
            attrs.push(("ID".into(), tree_id.into()));
            if name != tree_id {
                attrs.push(("name".into(), name.into()));
            }
            if self.opts.uids {
                attrs.push(("_fullpath".into(), bp.path(id)));
            }
            for (child, parent) in &scope.remap {
                attrs.push((child.clone(), format!("{{{parent}}}")));
            }
            for (child, text) in &scope.values {
                attrs.push((child.clone(), text.clone()));
            }
            if scope.autoremap {
                attrs.push(("_autoremap".into(), "true".into()));
            }
            "SubTree".to_string()
        } else if generic || !is_xml_name(type_id) {
            attrs.push(("ID".into(), if generic { name } else { type_id }.into()));
            if !generic {
                attrs.push(("name".into(), name.into()));
            }
            explicit_tag(kind).to_string()
        } else {
            attrs.push(("name".into(), name.into()));
            type_id.to_string()
        };
        if self.opts.uids {
            attrs.push(("_uid".into(), (id.0 + 1).to_string()));
        }
        if bp.ports(id).is_empty() && !generic && type_id == kind.type_name() {
            let children = bp.children(id).len();
            for (port, value) in built_in_ports(kind, children) {
                attrs.push((port.into(), value));
            }
        }
        for port in bp.ports(id) {
            let value = match &port.value {
                PortValue::Literal(text) => text.clone(),
                PortValue::Entry(key) => format!("{{{key}}}"),
            };
            attrs.push((port.name.clone(), value));
        }
        if let Some(hooks) = bp.node_hooks(id) {
            hooks.attributes(&mut |k, v| attrs.push((k.into(), v.into())));
        }
        let indent = "  ".repeat(depth);
        self.out.push_str(&format!("{indent}<{tag}"));
        for (k, v) in &attrs {
            self.out.push_str(&format!(" {}=\"{}\"", k, escape(v)));
        }
        let has_children = !bp.children(id).is_empty() && !matches!(kind, NodeKind::SubTree(_));
        if has_children {
            self.out.push_str(">\n");
            Some(tag)
        } else {
            self.out.push_str("/>\n");
            None
        }
    }
}

/// Whether node `id` is a leaf made from a closure or an object with the builder, which no
/// registered type names and so has no form in a file (the writer and the Groot2 model
/// write it as a plain Action or Condition).
pub fn no_file_form<C>(bp: &Blueprint<C>, id: NodeId) -> bool {
    let kind = bp.kind(id);
    matches!(
        kind,
        NodeKind::ActionFn(_)
            | NodeKind::Action(_)
            | NodeKind::ConditionFn(_)
            | NodeKind::Condition(_)
            | NodeKind::SharedCondition(_)
            | NodeKind::Stateful(_)
            | NodeKind::Async(_)
    ) && bp.type_id(id) == kind.type_name()
}

/// The explicit-form element of a node's family.
fn explicit_tag<C>(kind: &NodeKind<C>) -> &'static str {
    match kind.category() {
        neurotree_core::Category::Condition => "Condition",
        neurotree_core::Category::Control => "Control",
        neurotree_core::Category::Decorator => "Decorator",
        _ => "Action",
    }
}

/// Whether `s` can be an element name (letters, digits, `_`, `-`, `.`, not starting with a
/// digit, `-` or `.`).
fn is_xml_name(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c.is_alphabetic() || c == '_')
        && chars.all(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | '.'))
}
