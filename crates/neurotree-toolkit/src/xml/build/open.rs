//! Opening an element: the type it names, a mock or a substitution standing in for it, and
//! the node its registered type makes.

use neurotree_core::nodes::{self, NodeDecl};
use neurotree_core::{Arity, Category, NodeKind, Port, PortBinding, PortBindingError, PortValue};

use super::ports::{binding, conditions};
use super::{is_explicit, Expansion, Opened};
use crate::nodes::hooks::ScriptHooks;
use crate::registry::{Make, NodeType};
use crate::xml::mock;
use crate::xml::source::Element;
use crate::xml::substitute::{self, Substitute};
use crate::xml::{LoadError, LoadErrorKind};

/// A leaf standing in for an element, with the ports it keeps.
type StandIn<C> = (NodeKind<C>, Vec<Port>);

/// The type a node is made of once the substitution rules are applied.
enum Resolved<'a, C> {
    /// Its own type, or (`true`) the one a rule names; `None` when no such type is registered.
    Type(Option<&'a NodeType<C>>, bool),
    /// A test node of the rules, a leaf.
    Test(NodeKind<C>),
}

impl<'a, C: 'static> Opened<'a, C> {
    /// A leaf standing in for the node, which has no children: a mock, a test node, or an
    /// unknown leaf played as SUCCESS. It replaces what is below the node.
    fn stand_in(
        kind: NodeKind<C>,
        name: &'a str,
        type_name: &'a str,
        ports: Vec<Port>,
        hooks: Option<Box<ScriptHooks>>,
    ) -> Self {
        Self {
            kind,
            shared: None,
            name,
            type_id: Some(type_name),
            ports,
            hooks,
            descend: false,
        }
    }
}

impl<'a, C: 'static> Expansion<'a, '_, C> {
    /// Checks `el` and says what node it opens.
    #[inline(never)]
    pub(super) fn open(&mut self, el: Element<'a>) -> Result<Opened<'a, C>, LoadError> {
        let tag = el.tag();
        let explicit = is_explicit(tag);
        let type_name = if explicit {
            el.attr("ID").ok_or_else(|| {
                el.error(
                    LoadErrorKind::Structure,
                    format!("<{tag}> needs an ID attribute naming the node type"),
                )
            })?
        } else {
            tag
        };
        // Most elements have no attributes: nothing to look up.
        let (name, hooks) = if el.has_attrs() {
            let enums = self.loader.registry.enums();
            (el.attr("name").unwrap_or(type_name), conditions(el, enums)?)
        } else {
            (type_name, None)
        };
        let node_type = self.node_type(type_name);
        if let Some((kind, ports)) = self.mocked(el, name, type_name, node_type, explicit)? {
            return Ok(Opened::stand_in(kind, name, type_name, ports, hooks));
        }
        let (node_type, substituted) = match self.substituted(el, name, type_name, node_type)? {
            Resolved::Test(kind) => {
                return Ok(Opened::stand_in(kind, name, type_name, Vec::new(), hooks))
            }
            Resolved::Type(node_type, substituted) => (node_type, substituted),
        };
        let Some(node_type) = node_type else {
            let kind = self.unknown(el, type_name)?;
            return Ok(Opened::stand_in(kind, name, type_name, Vec::new(), hooks));
        };
        let ports = self.check_ports(el, node_type, explicit, substituted)?;
        self.made(el, node_type, type_name, name, ports, hooks)
    }

    /// The mock replacing the leaf `el`, and the ports it keeps; `None` when no mock does.
    ///
    /// A mock is found by the node's name first, as BehaviorTree.CPP's substitution rules
    /// match, then by its type. It keeps the node's ports, whose entries BehaviorTree.CPP
    /// creates when it builds the tree whatever the node turns out to be: a later Script
    /// may assign them.
    fn mocked(
        &mut self,
        el: Element<'a>,
        name: &'a str,
        type_name: &'a str,
        node_type: Option<&'a NodeType<C>>,
        explicit: bool,
    ) -> Result<Option<StandIn<C>>, LoadError> {
        let loader = self.loader;
        if loader.mocks.is_empty() {
            return Ok(None);
        }
        let Some((key, outcomes)) = [name, type_name]
            .into_iter()
            .find_map(|key| loader.mocks.get_key_value(key))
        else {
            return Ok(None);
        };
        let mock_name = key.as_str();
        let family = node_type.map(|t| t.category);
        if el.child_count() == 0 && !matches!(family, Some(Category::Control | Category::Decorator))
        {
            if !self.mocked.contains(&mock_name) {
                self.mocked.push(mock_name);
            }
            // A type nobody declared has no ports to keep: its attributes are not known to
            // be ports. The mock's outputs are ports of their own.
            let mut ports = match node_type {
                Some(t) => self.check_ports(el, t, explicit, false)?,
                None => Vec::new(),
            };
            let outputs = mock::output_ports(outcomes, |port| {
                el.attr(port).map(|text| binding(port, text))
            });
            for output in outputs {
                if !ports.iter().any(|p| p.name == output.name) {
                    ports.push(output);
                }
            }
            return Ok(Some((mock::mock_kind(outcomes), ports)));
        }
        // Not a leaf: it stays. A mock named after it that replaces no leaf either is a
        // mistake, found once the tree is expanded.
        if self.not_mocked.iter().all(|(n, _)| *n != mock_name) {
            let family = family.map_or("node with children", Category::as_str);
            let error = el.error(LoadErrorKind::MockNotLeaf, format!(
                "`{mock_name}` is a {family} (`{type_name}`) and no leaf is named so; a mock replaces only a leaf (an Action or a Condition)"
            ));
            self.not_mocked.push((mock_name, error));
        }
        Ok(None)
    }

    /// The type `el` is made of once the substitution rules (not applied when validating)
    /// have had their say.
    fn substituted(
        &mut self,
        el: Element<'a>,
        name: &'a str,
        type_name: &'a str,
        node_type: Option<&'a NodeType<C>>,
    ) -> Result<Resolved<'a, C>, LoadError> {
        let rule = if self.validate {
            None
        } else {
            self.substitution(name, type_name)
        };
        match rule {
            None => Ok(Resolved::Type(node_type, false)),
            // A test node is a leaf: a node with children sharing a leaf's name (Nav2's
            // RecoveryNode `ComputePathToPose` around the action of that name) stays, as
            // it does for a mock.
            Some(Substitute::Test(_)) if el.child_count() > 0 => {
                Ok(Resolved::Type(node_type, false))
            }
            Some(Substitute::Test(config)) => Ok(Resolved::Test(substitute::test_kind(
                config,
                self.loader.registry.enums(),
            ))),
            Some(Substitute::Node(other)) => match self.node_type(other) {
                Some(other_type) => Ok(Resolved::Type(Some(other_type), true)),
                None => Err(el.error(
                    LoadErrorKind::Substitution,
                    format!(
                        "a substitution rule replaces `{name}` by `{other}`, which is neither \
                         a TestNodeConfig of the rules nor a registered node type"
                    ),
                )),
            },
        }
    }

    /// The stand-in for a leaf of a type nobody registered, in a dry run that mocks unknown
    /// leaves; otherwise the error saying what to do.
    fn unknown(&self, el: Element<'_>, type_name: &str) -> Result<NodeKind<C>, LoadError> {
        if self.loader.mock_unknown && el.child_count() == 0 {
            return Ok(nodes::stand_in(Category::Action));
        }
        let hint = match self.loader.registry.closest(type_name) {
            Some(close) => format!("did you mean `{close}`? "),
            None => String::new(),
        };
        Err(el.error(
            LoadErrorKind::UnknownNode,
            format!(
                "unknown node type `{type_name}`; {hint}{}",
                self.loader.unknown_type_advice
            ),
        ))
    }

    /// The node `node_type` makes for `el`, whose ports are checked.
    fn made(
        &self,
        el: Element<'a>,
        node_type: &'a NodeType<C>,
        type_name: &'a str,
        name: &'a str,
        ports: Vec<Port>,
        hooks: Option<Box<ScriptHooks>>,
    ) -> Result<Opened<'a, C>, LoadError> {
        let children = el.child_count();
        let kind = match &node_type.make {
            Make::BuiltIn(decl) => {
                let (kind, ports) = built_in(el, decl, type_name, ports)?;
                return Ok(Opened {
                    hooks,
                    ports,
                    ..Opened::plain(kind, name)
                });
            }
            // A dry run: a leaf only a model describes plays SUCCESS like an unknown one.
            Make::Model
                if !self.validate
                    && self.loader.mock_unknown
                    && children == 0
                    && matches!(node_type.category, Category::Action | Category::Condition) =>
            {
                let kind = nodes::stand_in(Category::Action);
                return Ok(Opened::stand_in(kind, name, type_name, ports, hooks));
            }
            Make::Model if !self.validate => {
                return Err(self.model_only(el, node_type, type_name, name))
            }
            Make::Model => {
                // A placeholder of the same family, so that the structure is checked.
                let kind = nodes::stand_in(node_type.category);
                if !kind.arity().accepts(children as u32) {
                    return Err(el.error(
                        LoadErrorKind::ChildCount,
                        format!("`{type_name}` takes {}, found {children}", kind.arity()),
                    ));
                }
                kind
            }
            Make::Leaf(make) => {
                let kind = make(&ports, self.loader.registry.enums()).map_err(|e| {
                    let (kind, message) = e.into_parts();
                    el.error(kind, message)
                })?;
                let arity = kind.arity();
                if !arity.accepts(children as u32) {
                    let what = if arity == Arity::Leaf {
                        "is a leaf and takes no children".to_string()
                    } else {
                        format!("takes {arity}")
                    };
                    return Err(el.error(
                        LoadErrorKind::ChildCount,
                        format!("`{type_name}` {what}, found {children}"),
                    ));
                }
                kind
            }
            Make::Condition(condition) => {
                if children != 0 {
                    return Err(el.error(
                        LoadErrorKind::ChildCount,
                        format!("`{type_name}` is a leaf and takes no children, found {children}"),
                    ));
                }
                return Ok(Opened {
                    // Made from `shared` when the node is added.
                    kind: nodes::stand_in(Category::Condition),
                    shared: Some(condition),
                    name,
                    type_id: Some(type_name),
                    ports,
                    hooks,
                    descend: true,
                });
            }
        };
        Ok(Opened {
            kind,
            shared: None,
            name,
            type_id: Some(type_name),
            ports,
            hooks,
            descend: true,
        })
    }

    /// Why a type only a model describes cannot run: asked to mock it, why that cannot be
    /// (the closer mistake); else that it needs an implementation.
    fn model_only(
        &self,
        el: Element<'_>,
        node_type: &NodeType<C>,
        type_name: &str,
        name: &str,
    ) -> LoadError {
        if let Some((_, e)) = self.not_mocked.iter().find(|(n, _)| *n == name)
            && !self.mocked.contains(&name)
        {
            return e.clone();
        }
        let leaf = matches!(node_type.category, Category::Action | Category::Condition);
        let mocked = if leaf {
            ", or mock it (XmlLoader::mock_unknown)"
        } else {
            "; mocks replace only leaves"
        };
        el.error(LoadErrorKind::ModelOnly, format!(
            "`{type_name}` is only described by a model; register an implementation to run it{mocked}"
        ))
    }
}

/// An engine built-in made from its declaration, with the bindings it keeps: a node that
/// reads a port when it runs keeps them; the others are known by their kind alone.
fn built_in<C: 'static>(
    el: Element<'_>,
    decl: &NodeDecl,
    type_name: &str,
    ports: Vec<Port>,
) -> Result<StandIn<C>, LoadError> {
    let binding = |port: &str| match ports.iter().find(|p| p.name == port) {
        Some(Port {
            value: PortValue::Literal(text),
            ..
        }) => PortBinding::Literal(text.clone()),
        Some(_) => PortBinding::Entry,
        None => PortBinding::Missing,
    };
    let kind = match NodeKind::<C>::from_declared(decl, &binding) {
        Some(Ok(kind)) => kind,
        Some(Err(e)) => {
            let kind = match e {
                PortBindingError::Missing { .. } => LoadErrorKind::MissingPort,
                _ => LoadErrorKind::BadValue,
            };
            return Err(el.error(kind, e.to_string()));
        }
        None => {
            let message = format!("`{type_name}` is no built-in of the engine");
            return Err(el.error(LoadErrorKind::UnknownNode, message));
        }
    };
    let arity = kind.arity();
    if !arity.accepts(el.child_count() as u32) {
        return Err(el.error(
            LoadErrorKind::ChildCount,
            format!("`{type_name}` takes {arity}, found {}", el.child_count()),
        ));
    }
    let reads_entries = ports.iter().any(|p| matches!(p.value, PortValue::Entry(_)));
    Ok((kind, if reads_entries { ports } else { Vec::new() }))
}
