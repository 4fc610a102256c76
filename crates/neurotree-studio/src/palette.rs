//! The node types the editor offers (PROTOCOL.md, "NodeType").

use neurotree_core::blackboard::short_type_name;
use neurotree_toolkit::{PortDirection, Registry};
use serde_json::{json, Value};

use crate::view::category_name;

/// Every type `registry` knows, sorted by name, with its ports.
pub fn palette<C: 'static>(registry: &Registry<C>) -> Vec<Value> {
    let mut types: Vec<Value> = registry
        .types()
        .map(|t| {
            let ports: Vec<Value> = t
                .ports
                .iter()
                .map(|p| {
                    json!({
                        "name": p.name,
                        "direction": match p.direction {
                            PortDirection::Input => "input",
                            PortDirection::Output => "output",
                            PortDirection::InOut => "inout",
                        },
                        "type": short_type_name(p.type_name),
                        "default": p.default,
                        "description": p.description,
                    })
                })
                .collect();
            json!({
                "type": t.name,
                "category": category_name(t.category),
                "builtin": t.is_builtin(),
                "description": t.description,
                "ports": ports,
            })
        })
        .collect();
    types.sort_by(|a, b| a["type"].as_str().cmp(&b["type"].as_str()));
    types
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn built_ins_are_listed_with_their_ports() {
        let types = palette(&Registry::<()>::new());
        let repeat = types.iter().find(|t| t["type"] == "Repeat").unwrap();
        assert_eq!(repeat["category"], "decorator");
        assert_eq!(repeat["builtin"], true);
        assert_eq!(repeat["ports"][0]["name"], "num_cycles");
        assert_eq!(repeat["ports"][0]["direction"], "input");
        let service = types.iter().find(|t| t["type"] == "Service").unwrap();
        assert_eq!(service["category"], "control");
        assert_eq!(service["ports"][0]["name"], "interval_msec");
        let names: Vec<&str> = types.iter().filter_map(|t| t["type"].as_str()).collect();
        let mut sorted = names.clone();
        sorted.sort_unstable();
        assert_eq!(names, sorted);
    }
}
