//! Blackboard values between the tree and the pages: every scope as JSON, and a page's
//! edit written back in the entry's own type.

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
                        .map_or("", |i| short_type(i.type_name));
                    json!({"key": key, "value": entry_json(bb, scope, key), "type": type_name})
                })
                .collect();
            json!({"scope": scope.0, "path": path, "entries": entries})
        })
        .collect();
    Value::Array(scopes)
}

/// `alloc::string::String` as `String`.
fn short_type(name: &str) -> &str {
    name.rsplit("::").next().unwrap_or(name)
}

/// Writes a page's edit: converted to the type the entry holds (a number into an integer
/// entry must be whole and in range; text is parsed as a port parses it), else stored as
/// the JSON value's own type. An edit that does not convert is dropped: the page sees the
/// value unchanged.
pub(crate) fn apply<C>(tree: &mut Tree<C>, edit: &Edit) {
    let scope = ScopeId(edit.scope);
    if edit.scope as usize >= tree.blackboard().scope_count() {
        return;
    }
    let now = tree.now();
    let bb = tree.blackboard_mut();
    let held = bb
        .info_in(scope, &edit.key)
        .map(|i| short_type(i.type_name));
    let text = match &edit.value {
        Value::String(s) => s.clone(),
        other => other.to_string(),
    };
    macro_rules! typed {
        ($($name:literal => $t:ty),*) => {
            match held {
                $(Some($name) => {
                    if let Ok(v) = text.trim().parse::<$t>() {
                        bb.replace_in(scope, &edit.key, v, now);
                    }
                    return;
                })*
                _ => {}
            }
        };
    }
    typed!(
        "i64" => i64, "i32" => i32, "i16" => i16, "i8" => i8, "isize" => isize,
        "u64" => u64, "u32" => u32, "u16" => u16, "u8" => u8, "usize" => usize,
        "f64" => f64, "f32" => f32, "bool" => bool
    );
    if held == Some("String") || held.is_some_and(|h| h != "String") && edit.value.is_string() {
        bb.replace_in(scope, &edit.key, text, now);
        return;
    }
    match &edit.value {
        Value::Bool(b) => bb.replace_in(scope, &edit.key, *b, now),
        Value::Number(n) => match n.as_i64() {
            Some(i) => bb.replace_in(scope, &edit.key, i, now),
            None => bb.replace_in(scope, &edit.key, n.as_f64().unwrap_or(0.0), now),
        },
        Value::String(s) => bb.replace_in(scope, &edit.key, s.clone(), now),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_toolkit::{Registry, XmlLoader};
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

    fn edit(tree: &mut Tree<()>, key: &str, value: Value) {
        apply(
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
        // A scope the tree does not have is ignored.
        apply(
            &mut tree,
            &Edit {
                scope: 99,
                key: "n".into(),
                value: json!(1),
            },
        );
        assert_eq!(tree.blackboard().get_exact::<i64>("n"), Ok(8));
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
