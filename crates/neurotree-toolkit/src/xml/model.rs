//! `TreeNodesModel`: the section of a BehaviorTree.CPP file that declares node types and
//! their ports (Groot2 writes one into every file it saves; Nav2 ships one for its nodes).
//! Reading one declares those types in a [`Registry`]; writing one lists the registry's.

use neurotree_core::{Category, FromPortStr};

use super::{escape, LoadErrorKind};
use crate::registry::{Make, NodeType, PortDirection, PortSpec, Registry};

impl<C: 'static> Registry<C> {
    /// Declares the node types of a `TreeNodesModel` (the section Groot2 and Nav2 ship)
    /// that are not registered yet, with their ports. Such types let a tree be validated
    /// (see [`XmlLoader::validate`](crate::XmlLoader::validate)) but not run. Returns how
    /// many types were added.
    pub fn add_model_str(&mut self, text: &str, file: &str) -> Result<usize, crate::LoadError> {
        let doc = crate::xml::parse_model(text, file)?;
        let mut added = 0;
        for model in doc
            .root()
            .children()
            .filter(|c| c.tag() == "TreeNodesModel")
        {
            for node in model.children() {
                let category = match node.tag() {
                    "Action" => Category::Action,
                    "Condition" => Category::Condition,
                    "Control" => Category::Control,
                    "Decorator" => Category::Decorator,
                    "SubTree" => continue,
                    other => {
                        return Err(node.error(LoadErrorKind::Structure, format!(
                            "unexpected <{other}> in <TreeNodesModel>; expected Action, Condition, Control, Decorator or SubTree"
                        )))
                    }
                };
                let Some(id) = node.attr("ID") else {
                    return Err(node.error(
                        LoadErrorKind::Structure,
                        format!("<{}> in a model needs an ID", node.tag()),
                    ));
                };
                if self.types.contains_key(id) {
                    continue;
                }
                let mut ports = Vec::new();
                for port in node.children() {
                    let direction = match port.tag() {
                        "input_port" => PortDirection::Input,
                        "output_port" => PortDirection::Output,
                        "inout_port" => PortDirection::InOut,
                        _ => continue,
                    };
                    let Some(name) = port.attr("name") else {
                        return Err(
                            port.error(LoadErrorKind::Structure, "a port in a model needs a name")
                        );
                    };
                    super::names::check_port_name(name).map_err(|m| {
                        port.error(LoadErrorKind::BadName, format!("node type `{id}`: {m}"))
                    })?;
                    ports.push(PortSpec {
                        name: name.to_string(),
                        direction,
                        type_name: model_type_name(port.attr("type")),
                        default: port.attr("default").map(str::to_string),
                        description: port.text().to_string(),
                        check: model_type_check(port.attr("type")),
                        // A node only a model describes does not run: nothing reads it.
                        port_type: neurotree_core::PortType::ANY,
                        model_type: port
                            .attr("type")
                            .filter(|t| model_type_name(Some(t)) == "text")
                            .map(|t| t.trim().into()),
                    });
                }
                self.types.insert(
                    id.to_string(),
                    NodeType {
                        name: id.to_string(),
                        category,
                        ports,
                        description: String::new(),
                        make: Make::Model,
                        builtin: false,
                        semantics: None,
                    },
                );
                added += 1;
            }
        }
        Ok(added)
    }

    /// The `TreeNodesModel` of the registered types that are not built in, as a BehaviorTree.CPP
    /// format-4 document: what Groot2 reads to know the user's nodes and their ports.
    pub fn tree_nodes_model(&self) -> String {
        let mut out = String::from("<root BTCPP_format=\"4\">\n");
        self.write_models(&mut out, false);
        out.push_str("</root>\n");
        out
    }

    /// Writes the `<TreeNodesModel>` element, indented one level, with the built-in types too
    /// when `builtins` is set.
    pub(crate) fn write_models(&self, out: &mut String, builtins: bool) {
        out.push_str("  <TreeNodesModel>\n");
        for t in self.types.values() {
            if t.builtin && !builtins {
                continue;
            }
            let tag = t.category.as_str();
            out.push_str(&format!("    <{tag} ID=\"{}\"", escape(&t.name)));
            if t.ports.is_empty() && t.description.is_empty() {
                out.push_str("/>\n");
                continue;
            }
            out.push_str(">\n");
            for p in &t.ports {
                out.push_str(&format!(
                    "      <{} name=\"{}\" type=\"{}\"",
                    p.direction.model_tag(),
                    escape(&p.name),
                    escape(p.type_name)
                ));
                if let Some(d) = &p.default {
                    out.push_str(&format!(" default=\"{}\"", escape(d)));
                }
                if p.description.is_empty() {
                    out.push_str("/>\n");
                } else {
                    out.push_str(&format!(
                        ">{}</{}>\n",
                        escape(&p.description),
                        p.direction.model_tag()
                    ));
                }
            }
            if !t.description.is_empty() {
                out.push_str(&format!(
                    "      <description>{}</description>\n",
                    escape(&t.description)
                ));
            }
            out.push_str(&format!("    </{tag}>\n"));
        }
        out.push_str("  </TreeNodesModel>\n");
    }
}

/// The Rust type a model's type name converts to, for messages.
fn model_type_name(t: Option<&str>) -> &'static str {
    match t.map(str::trim) {
        Some("double" | "float") => "f64",
        Some("bool") => "bool",
        Some("int" | "int8" | "int16" | "int32" | "int64" | "long") => "i64",
        Some("unsigned int" | "unsigned" | "uint8" | "uint16" | "uint32" | "uint64" | "size_t") => {
            "u64"
        }
        Some("std::string" | "string" | "String" | "alloc::string::String") => "String",
        Some("f64" | "f32") => "f64",
        Some("i8" | "i16" | "i32" | "i64" | "isize") => "i64",
        Some("u8" | "u16" | "u32" | "u64" | "usize") => "u64",
        _ => "text",
    }
}

/// How a model's literal is checked: numbers and booleans are, other types are taken as given.
fn model_type_check(t: Option<&str>) -> Option<fn(&str) -> bool> {
    match model_type_name(t) {
        "f64" => Some(|s| f64::from_port_str(s).is_ok()),
        "bool" => Some(|s| bool::from_port_str(s).is_ok()),
        "i64" => Some(|s| i64::from_port_str(s).is_ok()),
        "u64" => Some(|s| u64::from_port_str(s).is_ok()),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_core::Status;

    #[test]
    fn the_model_lists_user_types_and_reads_back() {
        let mut r = Registry::<()>::new();
        r.register_action(
            "MoveTo",
            vec![
                PortSpec::input::<f64>("speed")
                    .default_value("0.5")
                    .describe("metres per second, < 2"),
                PortSpec::output::<String>("result"),
            ],
            |_| Status::Success,
        )
        .unwrap();
        r.register_condition("IsReady", vec![], |_| true).unwrap();
        r.describe("IsReady", "the robot can move");
        let model = r.tree_nodes_model();
        assert!(model.contains(r#"<Action ID="MoveTo">"#), "{model}");
        assert!(model.contains(
            r#"<input_port name="speed" type="f64" default="0.5">metres per second, &lt; 2</input_port>"#
        ), "{model}");
        assert!(model.contains(r#"<Condition ID="IsReady">"#), "{model}");
        assert!(!model.contains("Sequence"), "{model}");
        assert!(!model.contains("Script"), "{model}");
        let mut back = Registry::<()>::new();
        assert_eq!(back.add_model_str(&model, "model.xml").unwrap(), 2);
        let move_to = back.get("MoveTo").unwrap();
        assert_eq!(move_to.ports.len(), 2);
        assert_eq!(move_to.ports[0].default.as_deref(), Some("0.5"));
        assert!(!move_to.ports[0].accepts("fast"));
        assert_eq!(move_to.ports[1].direction, PortDirection::Output);
    }
}
