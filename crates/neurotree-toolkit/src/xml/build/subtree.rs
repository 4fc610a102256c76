//! Expanding a `<SubTree>`: its node with the child's scope, the tree below it, and the
//! path of the instance it makes, which must be unique in the tree.

use super::*;

impl<'a, C: 'static> Expansion<'a, '_, C> {
    /// Checks a `<SubTree>`: its node, with the child's scope, and the tree to expand below
    /// it; the caller pops `stack` when done.
    #[inline(never)]
    pub(super) fn open_subtree(
        &mut self,
        el: Element<'a>,
    ) -> Result<(Opened<'a, C>, Body<'a, C>), LoadError> {
        let id = el.attr("ID").ok_or_else(|| {
            el.error(
                LoadErrorKind::Structure,
                "<SubTree> needs an ID attribute naming the tree",
            )
        })?;
        let body = match self.loader.tree(id) {
            Some(tree) => Body::Xml(tree),
            None => match self.loader.registry.subtree(id) {
                Some(add) => Body::Built(add),
                None => {
                    let known: Vec<&str> = self
                        .loader
                        .tree_ids()
                        .chain(self.loader.registry.subtree_ids())
                        .collect();
                    let meant = crate::registry::suggest::did_you_mean(id, known.iter().copied());
                    return Err(el.error(
                        LoadErrorKind::UnknownTree,
                        format!(
                            "no tree with ID `{id}` is loaded or registered{meant}; known \
                             trees: {}",
                            known.join(", ")
                        ),
                    ));
                }
            },
        };
        if let Some(at) = self.stack.iter().position(|s| s == id) {
            let mut cycle = self.stack[at..].to_vec();
            cycle.push(id.to_string());
            return Err(el.error(
                LoadErrorKind::SubtreeCycle,
                format!(
                    "subtree cycle: {}; a tree cannot contain itself",
                    cycle.join(" -> ")
                ),
            ));
        }
        let mut scope = SubTreeScope::default();
        for (key, text) in el.attrs() {
            match key {
                "ID" | "name" => {}
                "_autoremap" => {
                    scope.autoremap = match text.trim() {
                        "true" | "TRUE" | "True" | "1" => true,
                        "false" | "FALSE" | "False" | "0" => false,
                        other => {
                            return Err(el.error(
                                LoadErrorKind::BadValue,
                                format!("_autoremap must be true or false, not `{other}`"),
                            ))
                        }
                    }
                }
                k if ATTRIBUTES.contains(&k) => {}
                k if k.starts_with('_') => {
                    return Err(el.error(
                        LoadErrorKind::ReservedAttribute,
                        format!(
                        "unknown attribute `{k}` on <SubTree>; names starting with `_` are reserved"
                    ),
                    ))
                }
                _ => match binding(key, text) {
                    PortValue::Entry(parent_key) => scope.remap.push((key.to_string(), parent_key)),
                    PortValue::Literal(text) => scope.values.push((key.to_string(), text)),
                },
            }
        }
        // As BehaviorTree.CPP: a port the model declares and the SubTree leaves out takes
        // the model's default, or is an error if it has none (unless autoremapping).
        if let Some(ports) = self.loader.subtree_model(id).filter(|_| !scope.autoremap) {
            for (port, default) in ports {
                if el.attr(port).is_some() {
                    continue;
                }
                let Some(default) = default else {
                    // An attribute the model does not declare, close to the missing port,
                    // is the remapping meant.
                    let undeclared = el
                        .attrs()
                        .map(|(k, _)| k)
                        .filter(|k| !k.starts_with('_') && *k != "ID" && *k != "name")
                        .filter(|k| !ports.iter().any(|(p, _)| p == k))
                        .collect::<Vec<_>>();
                    let meant = match crate::registry::suggest::nearest(port, undeclared) {
                        Some(typed) => {
                            format!(" (`{typed}` is no port of it: did you mean `{port}`?)")
                        }
                        None => String::new(),
                    };
                    return Err(el.error(
                        LoadErrorKind::MissingPort,
                        format!(
                            "the TreeNodesModel declares port `{port}` of SubTree `{id}` with no \
                         default, so it is mandatory{meant}; remap it here ({port}=\"{{key}}\") \
                         or give it a value"
                        ),
                    ));
                };
                match binding(port, default) {
                    PortValue::Entry(parent_key) => scope.remap.push((port.clone(), parent_key)),
                    PortValue::Literal(text) => scope.values.push((port.clone(), text)),
                }
            }
        }
        let name = el.attr("name").unwrap_or(id);
        let hooks = conditions(el, self.loader.registry.enums())?;
        let path = self.subtree_path(el, id)?;
        self.stack.push(id.to_string());
        self.subtree_names.push(name);
        self.paths.push(path);
        let opened = Opened {
            type_id: Some(id),
            hooks,
            ..Opened::plain(NodeKind::SubTree(Box::new(scope)), name)
        };
        Ok((opened, body))
    }
}

impl<C: 'static> Expansion<'_, '_, C> {
    /// The path of the subtree instance the SubTree `el` (of tree `id`) makes; refused, as
    /// BehaviorTree.CPP refuses it, if another instance of the tree built has it.
    pub(super) fn subtree_path(&mut self, el: Element<'_>, id: &str) -> Result<String, LoadError> {
        let parent = self.paths.last().map_or("", String::as_str);
        let own = match el.attr("name") {
            Some(name) => name.to_string(),
            // `nodes` numbers the nodes opened: unique, as BehaviorTree.CPP's UID is.
            None => format!("{id}::{}", self.nodes),
        };
        let path = if parent.is_empty() {
            own
        } else {
            format!("{parent}/{own}")
        };
        if !self.seen.insert(path.clone()) {
            return Err(el.error(
                LoadErrorKind::DuplicateSubTreePath,
                format!(
                    "another SubTree of this tree is already named `{}`, so both would have \
                     the path `{path}` (BehaviorTree.CPP refuses this: Groot2 could not tell \
                     them apart); give them different names, or leave `name` out",
                    el.attr("name").unwrap_or_default()
                ),
            ));
        }
        Ok(path)
    }
}

/// What a SubTree expands into: a loaded `<BehaviorTree>`, or a subtree made with the builder.
pub(super) enum Body<'a, C> {
    Xml(Element<'a>),
    Built(&'a crate::registry::SubtreeMaker<C>),
}
