//! Port declarations: what a node type reads and writes, and how a literal is checked.

use std::fmt;

use neurotree_core::{FromPortStr, PortDecl, PortType};

/// Which way a port carries data (declared in the core, with the built-in nodes' ports).
pub use neurotree_core::PortDirection;

/// A declared port: name, direction, type, default and description.
///
/// The type checks the port's literals when a file loads, and the types the node reads and
/// writes it as when it runs (see [`PortType`]).
#[derive(Clone)]
pub struct PortSpec {
    /// The attribute name.
    pub name: String,
    /// Which way it carries data.
    pub direction: PortDirection,
    /// The Rust type it converts to.
    pub type_name: &'static str,
    /// Text used when the attribute is absent.
    pub default: Option<String>,
    /// What it is for.
    pub description: String,
    /// `true` if a literal converts to the port's type.
    pub(crate) check: Option<fn(&str) -> bool>,
    /// What the node's reads and writes are checked against.
    pub(crate) port_type: PortType,
    /// The type a `TreeNodesModel` names for the port, when it is none of the numbers,
    /// `bool` or text (`nav_msgs::msg::Path`): what lint follows through the entries.
    pub(crate) model_type: Option<std::sync::Arc<str>>,
}

impl PortSpec {
    /// An input port of type `T`.
    pub fn input<T: FromPortStr + 'static>(name: &str) -> Self {
        Self::new::<T>(name, PortDirection::Input)
    }

    /// An output port of type `T`.
    pub fn output<T: 'static>(name: &str) -> Self {
        Self {
            name: name.to_string(),
            direction: PortDirection::Output,
            type_name: std::any::type_name::<T>(),
            default: None,
            description: String::new(),
            check: None,
            port_type: PortType::of::<T>(),
            model_type: None,
        }
    }

    /// A port of no declared type (BehaviorTree.CPP's `AnyTypeAllowed`): read and written
    /// as any type, its literals unchecked.
    pub fn untyped(name: &str, direction: PortDirection) -> Self {
        Self {
            name: name.to_string(),
            direction,
            type_name: PortType::ANY.name(),
            default: None,
            description: String::new(),
            check: None,
            port_type: PortType::ANY,
            model_type: None,
        }
    }

    /// A port read and written, of type `T`.
    pub fn inout<T: FromPortStr + 'static>(name: &str) -> Self {
        Self::new::<T>(name, PortDirection::InOut)
    }

    fn new<T: FromPortStr + 'static>(name: &str, direction: PortDirection) -> Self {
        Self {
            name: name.to_string(),
            direction,
            type_name: std::any::type_name::<T>(),
            default: None,
            description: String::new(),
            check: Some(|text| T::from_port_str(text).is_ok()),
            port_type: PortType::of::<T>(),
            model_type: None,
        }
    }

    /// With a default value (as text).
    pub fn default_value(mut self, text: &str) -> Self {
        self.default = Some(text.to_string());
        self
    }

    /// With a description.
    pub fn describe(mut self, text: &str) -> Self {
        self.description = text.to_string();
        self
    }

    /// `true` if `text` converts to the port's type (always for types without a check).
    pub fn accepts(&self, text: &str) -> bool {
        self.check.is_none_or(|check| check(text))
    }

    /// The declared type the node's reads and writes of this port are checked against.
    pub fn port_type(&self) -> PortType {
        self.port_type
    }
}

impl From<&PortDecl> for PortSpec {
    /// A built-in node's declared port, its literals checked as the declared type converts.
    fn from(p: &PortDecl) -> Self {
        Self {
            name: p.name.to_string(),
            direction: p.direction,
            type_name: p.type_name,
            default: p.default.map(str::to_string),
            description: p.description.to_string(),
            // What a node writes is not read from a literal.
            check: match p.direction {
                PortDirection::Output => None,
                _ => literal_check(p.type_name),
            },
            port_type: PortType::named(p.type_name),
            model_type: None,
        }
    }
}

/// How a literal of a declared type is checked; `None` for text, read as the node needs it.
/// The types are those of [`PORT_TYPES`](neurotree_core::nodes::PORT_TYPES).
pub(crate) fn literal_check(type_name: &str) -> Option<fn(&str) -> bool> {
    fn converts<T: FromPortStr>(text: &str) -> bool {
        T::from_port_str(text).is_ok()
    }
    match type_name {
        "i32" => Some(converts::<i32>),
        "u64" => Some(converts::<u64>),
        "bool" => Some(converts::<bool>),
        "f64" => Some(converts::<f64>),
        _ => None,
    }
}

impl fmt::Debug for PortSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("PortSpec")
            .field("name", &self.name)
            .field("direction", &self.direction)
            .field("type_name", &self.type_name)
            .field("default", &self.default)
            .finish()
    }
}

/// Refuses the port names BehaviorTree.CPP's `CreatePort` refuses: a file written for the
/// node would not load there, and Groot2 could not show it.
pub(super) fn check_port_names(node: &str, ports: &[PortSpec]) -> Result<(), super::RegistryError> {
    for port in ports {
        crate::xml::check_port_name(&port.name).map_err(|reason| {
            super::RegistryError::BadPortName {
                node: node.to_string(),
                port: port.name.clone(),
                reason,
            }
        })?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::registry::Registry;
    use crate::testing::*;
    use neurotree_core::{Handle, PortError};

    /// What a read or write gave: `Ok(value)` or the error's message.
    fn show<T: fmt::Debug>(r: Result<T, PortError>) -> String {
        match r {
            Ok(v) => format!("Ok({v:?})"),
            Err(e) => e.to_string(),
        }
    }

    /// The lab's registry and `Probe(n: u8, label: String out, free: untyped, sink: untyped
    /// out)`, which reads
    /// and writes its ports as `f` says and records what it got in `said`.
    fn registry(lab: &Lab, f: fn(&mut Handle<'_, Lab>) -> Vec<String>) -> Registry<Lab> {
        let mut r = lab.registry();
        let ports = vec![
            PortSpec::input::<u8>("n"),
            PortSpec::output::<String>("label"),
            PortSpec::untyped("free", PortDirection::Input),
            PortSpec::untyped("sink", PortDirection::Output),
        ];
        r.register_action("Probe", ports, move |h| {
            let seen = f(h);
            h.ctx_mut().said.extend(seen);
            Status::Success
        })
        .unwrap();
        r
    }

    const TREE: &str = r#"<root BTCPP_format="4"><BehaviorTree ID="T">
          <Sequence><Probe n="{n}" label="{label}" free="5" sink="{sink}"/></Sequence>
        </BehaviorTree></root>"#;

    #[test]
    fn an_xml_leaf_reads_and_writes_its_ports_as_declared() {
        let mut lab = Lab::new(&[]);
        let r = registry(&lab, |h| {
            vec![
                show(h.input::<u8>("n")),
                show(h.input::<u64>("n")),
                show(h.input::<f64>("n")),
                show(h.input::<Vec<u8>>("n")),
                show(h.output("label", 7_u8)),
                show(h.output("label", String::from("seven"))),
                show(h.input::<String>("free")),
                show(h.input::<Vec<i32>>("free")),
                show(h.output("sink", 0.5_f32)),
            ]
        });
        let mut tree = lab.load_with(&r, TREE).unwrap();
        tree.blackboard_mut().set("n", 200_i64).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(
            lab.said,
            [
                "Ok(200)",
                "Ok(200)",
                "Ok(200.0)",
                "node `Sequence/Probe`: port `n` is declared as u8; it cannot be read as alloc::vec::Vec<u8>",
                "node `Sequence/Probe`: port `label` is declared as alloc::string::String; it cannot be written as u8",
                "Ok(())",
                "Ok(\"5\")",
                "Ok([5])",
                "Ok(())",
            ]
        );
        assert_eq!(tree.blackboard().get::<String>("label"), Ok("seven".into()));
        assert_eq!(tree.blackboard().get::<f32>("sink"), Ok(0.5));
    }

    #[test]
    fn the_mismatch_error_names_node_port_and_both_types() {
        let mut lab = Lab::new(&[]);
        let r = registry(&lab, |h| match h.input::<Vec<u8>>("n") {
            Err(e) => vec![format!("{e:?}")],
            Ok(_) => vec![],
        });
        let mut tree = lab.load_with(&r, TREE).unwrap();
        tree.blackboard_mut().set("n", 1_u8).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(S));
        let expected = PortError::TypeMismatch {
            node: "Sequence/Probe".into(),
            port: "n".into(),
            declared: "u8",
            requested: "alloc::vec::Vec<u8>",
            written: false,
        };
        assert_eq!(lab.said, [format!("{expected:?}")]);
    }

    #[test]
    fn a_literal_is_checked_against_the_declared_type_at_load() {
        let lab = Lab::new(&[]);
        let r = registry(&lab, |_| vec![]);
        let load = |attrs: &str| {
            let xml = format!(
                r#"<root BTCPP_format="4"><BehaviorTree ID="T"><Probe {attrs}/></BehaviorTree></root>"#
            );
            lab.load_with(&r, &xml).map(|_| ()).map_err(|e| e.message)
        };
        assert_eq!(
            load(r#"n="300""#),
            Err("port `n` of `Probe`: cannot read `300` as u8".into())
        );
        assert_eq!(
            load(r#"n="many""#),
            Err("port `n` of `Probe`: cannot read `many` as u8".into())
        );
        assert_eq!(load(r#"n="255""#), Ok(()));
        // An untyped port takes any text, as BehaviorTree.CPP's `AnyTypeAllowed` does.
        assert_eq!(load(r#"n="1" free="anything at all""#), Ok(()));
        // So does a built-in's declaration: Repeat's `num_cycles` is an i32.
        let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="T">
              <Repeat num_cycles="2.5"><AlwaysSuccess/></Repeat></BehaviorTree></root>"#;
        assert_eq!(
            lab.load(xml).map(|_| ()).map_err(|e| e.message),
            Err("port `num_cycles` of `Repeat`: cannot read `2.5` as i32".into())
        );
    }

    #[test]
    fn declarations_carry_their_port_types() {
        assert_eq!(PortSpec::input::<u8>("n").port_type(), PortType::of::<u8>());
        assert_eq!(
            PortSpec::output::<String>("s").port_type(),
            PortType::of::<String>()
        );
        let free = PortSpec::untyped("free", PortDirection::Input);
        assert!(free.port_type().is_any());
        assert_eq!(free.type_name, "AnyTypeAllowed");
        assert!(free.accepts("anything"));
        let decl = neurotree_core::PortDecl::input("num_cycles", "i32", "How many.");
        assert_eq!(PortSpec::from(&decl).port_type(), PortType::named("i32"));
    }
}
