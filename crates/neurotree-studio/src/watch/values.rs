//! Blackboard values between the tree and the pages: every scope as JSON, and a page's
//! edit written back in the entry's own type.

use neurotree_core::blackboard::short_type_name;
use neurotree_core::{ScopeId, Tree};
use neurotree_toolkit::blackboard_json::entry_json;
use serde_json::{json, Value};

use super::hub::{scope_paths, Edit};

/// Every scope of `tree` (PROTOCOL.md, "Scope"), root first, keys sorted.
pub(crate) fn scopes<C>(tree: &Tree<C>) -> Value {
    let bb = tree.blackboard();
    let scopes: Vec<Value> = scope_paths(tree)
        .into_iter()
        .map(|(scope, path)| {
            let mut keys: Vec<&str> = bb.keys_in(scope).collect();
            keys.sort_unstable();
            let entries: Vec<Value> = keys
                .into_iter()
                .map(|key| {
                    let type_name = bb
                        .info_in(scope, key)
                        .map_or(String::new(), |i| short_type_name(i.type_name));
                    json!({"key": key, "value": entry_json(bb, scope, key), "type": type_name})
                })
                .collect();
            json!({"scope": scope.0, "path": path, "entries": entries})
        })
        .collect();
    Value::Array(scopes)
}

/// Writes a page's edit in the entry's own type, or says why not. Text typed into a
/// number, `bool` or text entry is read as a port reads it (`"7"` into an `i64`); any other
/// value is JSON read by the entry's value codec, so a registered type (a pose, a path)
/// takes an object of its fields. An entry not written yet takes JSON's own type.
pub(crate) fn write<C>(tree: &mut Tree<C>, edit: &Edit) -> Result<(), String> {
    let scope = ScopeId(edit.scope);
    if edit.scope as usize >= tree.blackboard().scope_count() {
        return Err(format!("the tree has no blackboard scope {}", edit.scope));
    }
    let now = tree.now();
    let bb = tree.blackboard_mut();
    let held = bb
        .info_in(scope, &edit.key)
        .filter(|_| bb.get_any_in(scope, &edit.key).is_some())
        .map(|i| i.type_name);
    if let (Some(held), Value::String(text)) = (held, &edit.value) {
        macro_rules! parsed {
            ($($t:ty),*) => {$(
                if held == core::any::type_name::<$t>() {
                    let value = text.trim().parse::<$t>().map_err(|e| {
                        format!("`{}` holds a `{held}`: `{text}` is not one ({e})", edit.key)
                    })?;
                    bb.replace_in(scope, &edit.key, value, now);
                    return Ok(());
                }
            )*};
        }
        parsed!(i64, i32, i16, i8, isize, u64, u32, u16, u8, usize, f64, f32, bool, String);
    }
    // The page's field holds text: for other types it is the value's JSON.
    let json = match (held, &edit.value) {
        (Some(held), Value::String(text)) => match serde_json::from_str(text) {
            Ok(json) => json,
            Err(_) if held == core::any::type_name::<Value>() => edit.value.clone(),
            Err(e) => {
                return Err(format!(
                    "`{}` holds a `{}`: the text is not JSON ({e})",
                    edit.key,
                    short_type_name(held)
                ))
            }
        },
        _ => edit.value.clone(),
    };
    bb.set_json_in(scope, &edit.key, json, now)
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_toolkit::{Registry, XmlLoader};
    use serde_json::Value;
    use std::sync::Arc;

    fn tree() -> Tree<()> {
        let registry = Registry::<()>::new();
        let mut loader = XmlLoader::new(&registry);
        loader
            .load_str(
                r#"<root BTCPP_format="4"><BehaviorTree ID="M">
                     <Script code="n := 3; name := 'a'; ok := true"/>
                   </BehaviorTree></root>"#,
                "m.xml",
            )
            .unwrap();
        let mut tree = Tree::new(Arc::new(loader.build_main().unwrap()));
        tree.tick_once(&mut ()).unwrap();
        tree
    }

    /// Writes the edit; one refused leaves the entry as it was.
    fn edit(tree: &mut Tree<()>, key: &str, value: Value) {
        let _ = write(
            tree,
            &Edit {
                scope: 0,
                key: key.into(),
                value,
            },
        );
    }

    #[test]
    fn an_edit_keeps_the_entry_type() {
        let mut tree = tree();
        edit(&mut tree, "n", json!("7"));
        assert_eq!(tree.blackboard().get_exact::<i64>("n"), Ok(7));
        edit(&mut tree, "n", json!(8));
        assert_eq!(tree.blackboard().get_exact::<i64>("n"), Ok(8));
        // Not a whole number: the entry keeps its value.
        edit(&mut tree, "n", json!(2.5));
        assert_eq!(tree.blackboard().get_exact::<i64>("n"), Ok(8));
        edit(&mut tree, "ok", json!(false));
        assert_eq!(tree.blackboard().get_exact::<bool>("ok"), Ok(false));
        edit(&mut tree, "name", json!("b"));
        assert_eq!(
            tree.blackboard().get_exact::<String>("name").as_deref(),
            Ok("b")
        );
        edit(&mut tree, "fresh", json!(1.5));
        assert_eq!(tree.blackboard().get_exact::<f64>("fresh"), Ok(1.5));
        // A scope the tree does not have is refused.
        let why = write(
            &mut tree,
            &Edit {
                scope: 99,
                key: "n".into(),
                value: json!(1),
            },
        );
        assert_eq!(why, Err("the tree has no blackboard scope 99".into()));
        assert_eq!(tree.blackboard().get_exact::<i64>("n"), Ok(8));
    }

    #[test]
    fn registered_types_are_edited_as_json_and_refusals_say_why() {
        #[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
        struct Pose {
            x: f64,
            y: f64,
        }
        let mut registry = Registry::<()>::new();
        registry.register_value::<Pose>();
        let xml =
            r#"<root BTCPP_format="4"><BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>"#;
        let mut tree = registry
            .load_str(xml, "m.xml", neurotree_core::ManualClock::new())
            .unwrap();
        tree.blackboard_mut()
            .set("goal", Pose { x: 1.0, y: 2.0 })
            .unwrap();
        let v = scopes(&tree);
        let goal = &v[0]["entries"][0];
        assert_eq!(goal["value"], json!({"x": 1.0, "y": 2.0}));
        assert_eq!(goal["type"], "Pose");
        let mut set = |value: Value| {
            write(
                &mut tree,
                &Edit {
                    scope: 0,
                    key: "goal".into(),
                    value,
                },
            )
        };
        assert_eq!(set(json!({"x": 3, "y": 4.5})), Ok(()));
        let why = set(json!({"x": "far", "y": 0})).unwrap_err();
        assert!(
            why.starts_with("`goal` holds a `Pose`: invalid type"),
            "{why}"
        );
        let why = set(json!("{not json")).unwrap_err();
        assert!(why.starts_with("`goal` holds a `Pose`"), "{why}");
        assert_eq!(
            tree.blackboard().get::<Pose>("goal"),
            Ok(Pose { x: 3.0, y: 4.5 })
        );
    }

    #[test]
    fn scopes_list_entries_with_values_and_types() {
        let tree = tree();
        let v = scopes(&tree);
        assert_eq!(v[0]["scope"], 0);
        assert_eq!(v[0]["path"], "");
        let entries = v[0]["entries"].as_array().unwrap();
        let n = entries.iter().find(|e| e["key"] == "n").unwrap();
        assert_eq!(n["value"], 3);
        assert_eq!(n["type"], "i64");
    }
}
