//! A node's port bindings checked against its type, as the loader makes them.

use super::*;

/// The node's pre- and post-condition scripts, parsed; `None` if it has none.
///
/// Boxed: most nodes have none, and an empty `Option<ScriptHooks>` would still be copied
/// whole at every move.
pub(super) fn conditions(
    el: Element<'_>,
    enums: &Arc<Enums>,
) -> Result<Option<Box<ScriptHooks>>, LoadError> {
    let mut hooks: Option<Box<ScriptHooks>> = None;
    for (key, code) in el.attrs() {
        if ATTRIBUTES.contains(&key) {
            let script = Script::parse(code)
                // A window of the script, not all of it: a script may be kilobytes long.
                .map_err(|e| {
                    el.error(
                        LoadErrorKind::Script,
                        format!("in `{key}` script `{}`: {e}", e.excerpt(code)),
                    )
                })?;
            hooks
                .get_or_insert_with(|| {
                    Box::new(ScriptHooks {
                        enums: Arc::clone(enums),
                        ..ScriptHooks::default()
                    })
                })
                .set(key, script);
        } else if key.starts_with('_') && key != "_autoremap" {
            return Err(el.error(
                LoadErrorKind::ReservedAttribute,
                format!(
                    "unknown attribute `{key}`; names starting with `_` are reserved for {}",
                    ATTRIBUTES.join(", ")
                ),
            ));
        }
    }
    Ok(hooks)
}

/// Binds `ports` to the node added last, if there are any.
#[inline(always)]
pub(super) fn with_ports<C>(b: Builder<C>, ports: Vec<Port>) -> Builder<C> {
    if ports.is_empty() {
        b
    } else {
        b.ports(ports)
    }
}

/// Attaches `hooks` to the node added last, if there are any.
#[inline(always)]
pub(super) fn with_hooks<C: 'static>(b: Builder<C>, hooks: Option<Box<ScriptHooks>>) -> Builder<C> {
    match hooks {
        Some(h) => b.hooks(*h),
        None => b,
    }
}

/// A port's binding from its attribute text: `{key}` (or `{@key}`) is an entry, `{=}` and
/// `=` the entry named like the port, anything else literal text.
pub(crate) fn binding(port: &str, text: &str) -> PortValue {
    let t = text.trim();
    if t == "=" || t == "{=}" {
        return PortValue::Entry(port.to_string());
    }
    match t.strip_prefix('{').and_then(|r| r.strip_suffix('}')) {
        Some(key) if !key.is_empty() && !key.contains(['{', '}']) => {
            PortValue::Entry(key.to_string())
        }
        _ => PortValue::Literal(text.to_string()),
    }
}

impl<C: 'static> Expansion<'_, '_, C> {
    /// The node's port bindings: every attribute a declared port, every literal convertible,
    /// absent ports with defaults filled in.
    pub(super) fn check_ports(
        &self,
        el: Element<'_>,
        node_type: &NodeType<C>,
        explicit: bool,
        substituted: bool,
    ) -> Result<Vec<Port>, LoadError> {
        let mut ports = Vec::new();
        for (key, text) in el.attrs() {
            if key == "name" || (explicit && key == "ID") || ATTRIBUTES.contains(&key) {
                continue;
            }
            // A node put in another's place by a substitution rule keeps the ports it
            // shares with the node it replaces; the others have no use there.
            if substituted && node_type.port(key).is_none() {
                continue;
            }
            let Some(spec) = node_type.port(key) else {
                let valid: Vec<&str> = node_type.ports.iter().map(|p| p.name.as_str()).collect();
                let listed = if valid.is_empty() {
                    "it has no ports".to_string()
                } else {
                    format!("its ports are: {}", valid.join(", "))
                };
                let meant = crate::registry::suggest::did_you_mean(key, valid.iter().copied());
                return Err(el.error(
                    LoadErrorKind::UnknownPort,
                    format!(
                        "unknown port `{key}` on `{}`{meant}; {listed}",
                        node_type.name
                    ),
                ));
            };
            let mut value = binding(key, text);
            if let PortValue::Literal(text) = &mut value {
                // A registered enum name stands for its number where a number is wanted.
                if let Some(n) = self.loader.registry.enums().get(text.trim())
                    && !spec.accepts(text)
                    && spec.accepts(&n.to_string())
                {
                    *text = n.to_string();
                }
                if !spec.accepts(text) {
                    return Err(el.error(
                        LoadErrorKind::BadValue,
                        format!(
                            "port `{key}` of `{}`: cannot read `{text}` as {}",
                            node_type.name, spec.type_name
                        ),
                    ));
                }
            }
            ports.push(Port {
                name: key.to_string(),
                value,
                declared: spec.port_type(),
            });
        }
        for spec in &node_type.ports {
            if let Some(default) = &spec.default
                && ports.iter().all(|p| p.name != spec.name)
            {
                ports.push(Port {
                    name: spec.name.clone(),
                    value: binding(&spec.name, default),
                    declared: spec.port_type(),
                });
            }
        }
        Ok(ports)
    }
}
