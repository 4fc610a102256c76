//! From loaded XML elements to a blueprint: node names through the registry, ports checked,
//! subtrees expanded into blackboard scopes.

use std::sync::Arc;

use neurotree_core::nodes;

use neurotree_core::{
    Blueprint, BuildErrorKind, Builder, Category, NodeKind, Port, PortBinding, PortValue,
    SubTreeScope, DEFAULT_MAX_DEPTH,
};

use super::budget;
use super::source::Element;
use super::substitute::Substitute;
use super::{LoadError, LoadErrorKind, LoadErrors, XmlLoader};
use crate::nodes::hooks::{ScriptHooks, ATTRIBUTES};
use crate::registry::{Make, NodeType};
use crate::script::{Enums, Script};

mod open;
mod ports;
mod subtree;

pub(crate) use ports::binding;
use ports::{conditions, with_hooks, with_ports};
use subtree::Body;

/// The elements that name their type in an `ID` attribute (BehaviorTree.CPP's explicit form).
pub(super) const EXPLICIT: [&str; 4] = ["Action", "Condition", "Control", "Decorator"];

struct Expansion<'a, 'r, C> {
    loader: &'a XmlLoader<'r, C>,
    /// Validating only: model-only types become placeholders of their family.
    validate: bool,
    /// The subtree IDs being expanded, outermost first, to find cycles.
    stack: Vec<String>,
    /// Type names resolved lately, by a hash of the name: a tree names few types many times,
    /// and a registry look-up compares the name with several others.
    resolved: [Option<(&'a str, &'a NodeType<C>)>; RESOLVED],
    /// The errors met so far when collecting them ([`validate_all`]); empty otherwise.
    errors: Vec<LoadError>,
    /// How many errors to collect before giving up; 0 or 1 stops at the first.
    limit: usize,
    /// The element whose node the builder refused when it closed (a threshold above the
    /// number of children): where its error points.
    refused: Option<Element<'a>>,
    /// The names of the mocks that replaced a leaf.
    mocked: Vec<&'a str>,
    /// The names of the mocks that matched a control or decorator, which mocks do not
    /// replace, with the error to give if the mock replaced no leaf either.
    not_mocked: Vec<(&'a str, LoadError)>,
    /// Nodes opened so far, subtrees expanded: at most the loader's `max_nodes`.
    nodes: usize,
    /// No mock and no substitution rule could apply to any node: plain elements take
    /// [`open_plain`](Self::open_plain).
    plain_rules: bool,
    /// The names (else IDs) of the SubTrees being expanded, outermost first: the start of
    /// a node's path as BehaviorTree.CPP's substitution rules match it.
    subtree_names: Vec<&'a str>,
    /// The path of each subtree instance being expanded, outermost first (the main tree's
    /// is empty), as BehaviorTree.CPP makes them: the parent's path, `/`, then the SubTree's
    /// `name`, or its ID and a number unique in the tree without one.
    paths: Vec<String>,
    /// The paths of the subtree instances made so far, which must differ.
    seen: std::collections::HashSet<String>,
}

/// What an element turns into: the node to open, and whether its children follow it.
struct Opened<'a, C> {
    kind: NodeKind<C>,
    /// The registered condition it calls, opened in place of `kind`.
    shared: Option<&'a Arc<dyn neurotree_core::Condition<C>>>,
    name: &'a str,
    /// The registered type name, where the kind alone does not tell it.
    type_id: Option<&'a str>,
    ports: Vec<Port>,
    hooks: Option<Box<ScriptHooks>>,
    /// `false` for a mock, which replaces the node and what is below it.
    descend: bool,
}

impl<'a, C: 'static> Opened<'a, C> {
    /// A node of `kind` named `name` with nothing else attached.
    fn plain(kind: NodeKind<C>, name: &'a str) -> Self {
        Self {
            kind,
            shared: None,
            name,
            type_id: None,
            ports: Vec::new(),
            hooks: None,
            descend: true,
        }
    }

    /// Opens the node in `b`; the caller adds its children and closes it.
    fn add(self, b: Builder<C>) -> Builder<C> {
        let b = match self.shared {
            Some(condition) => b.open_shared_condition(condition, self.name),
            None => b.open(self.kind, self.name),
        };
        let b = match self.type_id {
            Some(type_id) => b.type_id(type_id),
            None => b,
        };
        with_hooks(with_ports(b, self.ports), self.hooks)
    }
}

/// Slots of [`Expansion::resolved`] (a power of two).
const RESOLVED: usize = 32;

pub(super) fn build<C: 'static>(
    loader: &XmlLoader<'_, C>,
    id: &str,
    tree: Element<'_>,
    validate: bool,
) -> Result<Blueprint<C>, LoadError> {
    Expansion::new(loader, id, validate, 0).expand(tree)
}

/// Builds the tree as [`build`] does, but goes on past an element in error (in its place, a
/// stand-in with its children) to report up to `limit` errors.
pub(super) fn build_all<C: 'static>(
    loader: &XmlLoader<'_, C>,
    id: &str,
    tree: Element<'_>,
    limit: usize,
) -> Result<Blueprint<C>, LoadErrors> {
    let mut x = Expansion::new(loader, id, false, limit);
    let built = x.expand(tree);
    let mut errors = std::mem::take(&mut x.errors);
    let last = match built {
        Ok(blueprint) => match errors.pop() {
            None => return Ok(blueprint),
            // Built with stand-ins for the elements in error: not the tree asked for.
            Some(last) => last,
        },
        Err(last) => last,
    };
    Err(LoadErrors::ending_with(errors, last, limit))
}

/// Checks the tree as [`build`] does when validating, going on past an element in error
/// (in its place, a stand-in with its children) to report up to `limit` errors.
pub(super) fn validate_all<C: 'static>(
    loader: &XmlLoader<'_, C>,
    id: &str,
    tree: Element<'_>,
    limit: usize,
) -> Vec<LoadError> {
    let mut x = Expansion::new(loader, id, true, limit);
    let last = x.expand(tree).err();
    let mut errors = x.errors;
    errors.extend(last);
    errors.truncate(limit.max(1));
    errors
}

impl<'a, 'r, C: 'static> Expansion<'a, 'r, C> {
    fn new(loader: &'a XmlLoader<'r, C>, id: &str, validate: bool, limit: usize) -> Self {
        Self {
            loader,
            validate,
            stack: vec![id.to_string()],
            resolved: [None; RESOLVED],
            errors: Vec::new(),
            limit,
            refused: None,
            mocked: Vec::new(),
            not_mocked: Vec::new(),
            nodes: 0,
            plain_rules: loader.mocks.is_empty() && loader.substitutions.is_empty(),
            subtree_names: Vec::new(),
            paths: vec![String::new()],
            seen: std::collections::HashSet::new(),
        }
    }

    /// Expands the `<BehaviorTree>` `tree` and builds its blueprint.
    fn expand(&mut self, tree: Element<'a>) -> Result<Blueprint<C>, LoadError> {
        // A tree too big is refused before anything of it is built, at the SubTrees where
        // it crosses the budget: each use of a subtree is a copy, so a few trees using the
        // next one twice each would make millions of nodes.
        let size = if self.loader.subtrees {
            budget::expanded_size(self.loader, &self.stack[0])
        } else {
            // Elements are stored in document order, each followed by what it holds.
            let root = only_child(tree);
            (root.subtree_end() - root.id()) as u64
        };
        if size > self.loader.max_nodes as u64 {
            let mut errors = budget::crossings(self.loader, tree, self.limit.max(1));
            if let Some(last) = errors.pop() {
                self.errors.extend(errors);
                return Err(last);
            }
        }
        // Room for the nodes up front, up to a bound: a tree refused early claims little.
        let room = usize::try_from(size.min(1 << 16)).unwrap_or(0);
        let registry = self.loader.registry;
        let b = Builder::with_capacity(room)
            .value_codecs(registry.value_codecs().clone())
            .port_directions(Arc::new(registry.port_directions()));
        let b = match &self.loader.wrap_hooks {
            Some(wrap) => {
                let wrap = Arc::clone(wrap);
                b.wrap_hooks(Box::new(move |id, hooks| wrap(id, hooks)))
            }
            None => b,
        };
        let b = self.node(b, only_child(tree), 1)?;
        if let Some((_, error)) = self
            .not_mocked
            .iter()
            .find(|(n, _)| !self.mocked.contains(n))
        {
            return Err(error.clone());
        }
        // A mock that replaced nothing is a mistake (a misspelt name), never ignored.
        if !self.validate
            && let Some(name) = self.loader.mocks.keys().find(|name| {
                !self.mocked.contains(&name.as_str())
                    && self.not_mocked.iter().all(|(n, _)| n != name)
            })
        {
            return Err(tree.error(
                LoadErrorKind::UnmatchedMock,
                format!(
                    "the mock `{name}` matches no node of tree `{}`: no node is named or of \
                         type `{name}`; check its spelling",
                    self.stack[0]
                ),
            ));
        }
        // Checks the loader could not make on one element (thresholds against the number
        // of children) come back from the builder; they point at the element it refused,
        // whose position names the node, so the node's path is left out.
        b.build().map_err(|e| match self.refused {
            Some(el) => el.error(build_error_kind(&e.kind), e.kind.to_string()),
            None => tree.error(build_error_kind(&e.kind), e.to_string()),
        })
    }

    /// Keeps `error` if errors are being collected and there is room; else gives it back.
    fn keep(&mut self, error: LoadError) -> Result<(), LoadError> {
        if self.errors.len() + 1 >= self.limit {
            return Err(error);
        }
        self.errors.push(error);
        Ok(())
    }

    /// Closes the node of `el`, noting `el` if the builder refuses it.
    fn close(&mut self, b: Builder<C>, el: Element<'a>) -> Builder<C> {
        self.note_refusal(b.close(), el)
    }

    /// Notes `el` as the element the builder refused if it just did.
    fn note_refusal(&mut self, b: Builder<C>, el: Element<'a>) -> Builder<C> {
        if self.refused.is_none() && b.has_error() {
            self.refused = Some(el);
        }
        b
    }
}

/// The kind of a builder's refusal, as the loader reports it.
fn build_error_kind(kind: &BuildErrorKind) -> LoadErrorKind {
    match kind {
        BuildErrorKind::ChildCount { .. } | BuildErrorKind::Threshold { .. } => {
            LoadErrorKind::ChildCount
        }
        BuildErrorKind::TooDeep { .. } => LoadErrorKind::TooDeep,
        BuildErrorKind::TooManyNodes { .. } => LoadErrorKind::TooManyNodes,
        _ => LoadErrorKind::Structure,
    }
}

/// Whether `tag` names its type in an `ID` attribute ([`EXPLICIT`]): most tags are not of
/// their lengths (6, 7 and 9), and `contains` would compare each with all four.
pub(crate) fn is_explicit(tag: &str) -> bool {
    matches!(tag.len(), 6 | 7 | 9) && EXPLICIT.contains(&tag)
}

/// `a == b`, for short names: inline, where `==` calls `memcmp`.
pub(super) fn same(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).all(|(x, y)| x == y)
}

/// The root node of a `<BehaviorTree>`.
pub(super) fn only_child(tree: Element<'_>) -> Element<'_> {
    // The loader keeps only trees with exactly one child element.
    tree.children()
        .next()
        .expect("a loaded <BehaviorTree> has one child element")
}

impl<'a, C: 'static> Expansion<'a, '_, C> {
    /// Adds `el` and, below it, its children. Kept small: it recurses once per level, so all
    /// the per-element work is in [`open`](Self::open), which does not.
    fn node(
        &mut self,
        b: Builder<C>,
        el: Element<'a>,
        depth: u32,
    ) -> Result<Builder<C>, LoadError> {
        if depth > DEFAULT_MAX_DEPTH {
            return Err(self.too_deep(el));
        }
        // The backstop of the budget, which `expand` checked before building: subtrees
        // the registry builds count for one node there.
        if self.nodes >= self.loader.max_nodes {
            return Err(budget::too_many_nodes(el, self.loader.max_nodes));
        }
        self.nodes += 1;
        let tag = el.tag();
        if tag == "SubTree" {
            let (opened, body) = match self.open_subtree(el) {
                Ok(subtree) => subtree,
                Err(e) => {
                    self.keep(e)?;
                    let b = Opened::plain(nodes::stand_in(Category::Action), el.tag()).add(b);
                    return Ok(self.close(b, el));
                }
            };
            let b = opened.add(b);
            let b = match body {
                Body::Xml(tree) => self.node(b, only_child(tree), depth + 1),
                // The builder checks its depth and its child count itself.
                Body::Built(add) => Ok(add(b)),
            }
            .map(|b| self.close(b, el));
            self.stack.pop();
            self.subtree_names.pop();
            self.paths.pop();
            return b;
        }
        let b = match self.open_plain(b, el, tag) {
            // A leaf, closed already.
            Ok((b, true)) => return Ok(self.note_refusal(b, el)),
            Ok((mut b, false)) => {
                for child in el.children() {
                    b = self.node(b, child, depth + 1)?;
                }
                return Ok(self.close(b, el));
            }
            Err(b) => b,
        };
        let opened = match self.open(el) {
            Ok(opened) => opened,
            Err(e) => {
                self.keep(e)?;
                // Of a family that accepts its children, so that they are checked too and
                // the builder finds nothing more to say about it.
                let kind = nodes::stand_in(if el.child_count() == 0 {
                    Category::Action
                } else {
                    Category::Control
                });
                Opened::plain(kind, el.tag())
            }
        };
        let descend = opened.descend;
        let mut b = opened.add(b);
        if descend {
            for child in el.children() {
                b = self.node(b, child, depth + 1)?;
            }
        }
        Ok(self.close(b, el))
    }

    /// Opens `el` in `b` when it is a plain node (and closes it when it is a leaf, which the
    /// `bool` says): no attributes, no mock or substitution
    /// rule in play, a type without ports that is a registered condition (a leaf here) or
    /// a built-in whose arity takes its children. Such an element opens exactly as
    /// [`open`](Self::open) and [`Opened::add`] would open it, without the checks and
    /// records that only attributes, ports and rules need: most elements of a large tree
    /// are like this. Anything else (including every error) gives `b` back for the general
    /// path.
    #[inline]
    fn open_plain(
        &mut self,
        b: Builder<C>,
        el: Element<'a>,
        tag: &'a str,
    ) -> Result<(Builder<C>, bool), Builder<C>> {
        if !self.plain_rules || el.has_attrs() {
            return Err(b);
        }
        let Some(node_type) = self.node_type(tag) else {
            return Err(b);
        };
        if !node_type.ports.is_empty() || is_explicit(tag) {
            return Err(b);
        }
        match &node_type.make {
            Make::Condition(condition) if el.child_count() == 0 => {
                Ok((b.shared_condition_leaf(tag, tag, condition), true))
            }
            Make::BuiltIn(decl) => {
                match NodeKind::<C>::from_declared(decl, &|_| PortBinding::Missing) {
                    Some(Ok(kind)) if kind.arity().accepts(el.child_count() as u32) => {
                        Ok((b.open(kind, tag), false))
                    }
                    _ => Err(b),
                }
            }
            _ => Err(b),
        }
    }

    #[inline(never)]
    fn too_deep(&self, el: Element<'_>) -> LoadError {
        el.error(
            LoadErrorKind::TooDeep,
            format!(
            "the tree nests deeper than {DEFAULT_MAX_DEPTH} levels (subtrees included); flatten it"
        ),
        )
    }

    /// The substitution rule for the node `name` of type `type_name`, if one applies.
    fn substitution(&self, name: &str, type_name: &str) -> Option<&'a Substitute> {
        let rules = &self.loader.substitutions;
        if rules.is_empty() {
            return None;
        }
        let mut path = self.subtree_names.join("/");
        if !path.is_empty() {
            path.push('/');
        }
        path.push_str(name);
        rules.rule_for(name, type_name, &path)
    }

    /// The registered type named `name`.
    fn node_type(&mut self, name: &'a str) -> Option<&'a NodeType<C>> {
        let b = name.as_bytes();
        // Length, first four and last bytes, mixed by a multiplication whose top bits
        // depend on all of them (Fibonacci hashing).
        // Byte by byte: a copy of a variable length would call `memcpy`.
        let byte = |i: usize| u32::from(b.get(i).copied().unwrap_or(0));
        let head = byte(0) | byte(1) << 8 | byte(2) << 16 | byte(3) << 24;
        let key = b.len() as u64
            ^ u64::from(head) << 16
            ^ u64::from(b.last().copied().unwrap_or(0)) << 48;
        let hash = key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 59;
        let slot = &mut self.resolved[hash as usize % RESOLVED];
        match *slot {
            Some((known, node_type)) if same(known, name) => Some(node_type),
            _ => {
                let registry = self.loader.registry;
                let node_type = registry
                    .get(name)
                    .or_else(|| registry.alias(name).map(|(_, t)| t))?;
                *slot = Some((name, node_type));
                Some(node_type)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::binding;
    use neurotree_core::PortValue;

    #[test]
    fn bindings() {
        assert_eq!(
            binding("goal", "{target}"),
            PortValue::Entry("target".into())
        );
        assert_eq!(
            binding("goal", "{@target}"),
            PortValue::Entry("@target".into())
        );
        assert_eq!(binding("goal", "{=}"), PortValue::Entry("goal".into()));
        assert_eq!(binding("goal", "="), PortValue::Entry("goal".into()));
        assert_eq!(binding("goal", "1;2;3"), PortValue::Literal("1;2;3".into()));
        assert_eq!(binding("goal", "{}"), PortValue::Literal("{}".into()));
    }

    #[test]
    fn autoremap_never_writes_a_literal_port_into_the_parent() {
        use crate::testing::*;
        use neurotree_core::ScopeId;
        // BehaviorTree.CPP turns autoremapping off while it sets a SubTree's literal ports:
        // they are the subtree's own entries, whether or not the parent has the key.
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab
            .load(
                r#"<root BTCPP_format="4" main_tree_to_execute="Main">
                 <BehaviorTree ID="Main">
                   <Sequence>
                     <SubTree ID="Child" _autoremap="true" greeting="hello" mood="calm"/>
                     <Say message="{greeting}"/>
                     <Say message="{shared}"/>
                   </Sequence>
                 </BehaviorTree>
                 <BehaviorTree ID="Child">
                   <Sequence>
                     <Say message="{greeting}"/>
                     <Say message="{mood}"/>
                     <Script code="shared := 'from child'"/>
                     <L0/>
                   </Sequence>
                 </BehaviorTree>
               </root>"#,
            )
            .unwrap();
        tree.blackboard_mut()
            .set("greeting", "parent's".to_string())
            .unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(lab.ticks, [1]);
        // The child saw its literals; the parent kept its own `greeting` and got no `mood`;
        // autoremap still shares what the child creates (`shared`).
        assert_eq!(lab.said, ["hello", "calm", "parent's", "from child"]);
        let bb = tree.blackboard();
        assert!(!bb.contains("mood"));
        assert_eq!(bb.get::<String>("greeting"), Ok("parent's".to_string()));
        assert_eq!(bb.keys().collect::<Vec<_>>(), ["greeting", "shared"]);
        assert_eq!(
            bb.keys_in(ScopeId(1)).collect::<Vec<_>>(),
            ["greeting", "mood"]
        );
    }
}
