//! Blackboard entries as JSON, for the tools that show a blackboard to a person or a program
//! (the `neurotree run` summary, the studio, the Groot2 monitor).
//!
//! Entries hold arbitrary Rust values. A value whose type has a codec — the numbers, `bool`,
//! `String`, `Duration`, `serde_json::Value`, and every type registered with
//! [`Registry::register_value`](crate::Registry::register_value) — is its JSON. Past 64
//! bits a number is written as text (JSON readers take numbers at their word), and a
//! `&'static str` as its text. Any other type shows as its short type name in angle brackets
//! (`"<Pose>"`), which tells the reader that the entry exists and what it holds; an entry that
//! a port declared but nothing wrote yet is `null`.
//!
//! ```
//! use neurotree::blackboard_json::scope_json;
//! use neurotree::{Blackboard, ScopeId};
//!
//! let mut bb = Blackboard::new();
//! bb.set("count", 3_i64).unwrap();
//! bb.set("mode", "docking".to_string()).unwrap();
//! bb.set("raw", 7_u8).unwrap();
//! bb.set("pose", (1.0_f64, 2.0_f64)).unwrap();
//! assert_eq!(
//!     serde_json::Value::Object(scope_json(&bb, ScopeId::ROOT)).to_string(),
//!     r#"{"count":3,"mode":"docking","pose":"<(f64, f64)>","raw":7}"#
//! );
//! ```

use neurotree_core::blackboard::short_type_name;
use neurotree_core::{Blackboard, ScopeId};
use serde_json::{json, Map, Value};

/// The value `key` resolves to from `scope`, as JSON (see the [module docs](self)).
pub fn entry_json(bb: &Blackboard, scope: ScopeId, key: &str) -> Value {
    let Some(any) = bb.get_any_in(scope, key) else {
        return Value::Null;
    };
    if let Some(v) = any.downcast_ref::<i128>() {
        json!(v.to_string())
    } else if let Some(v) = any.downcast_ref::<u128>() {
        json!(v.to_string())
    } else if let Some(v) = any.downcast_ref::<&'static str>() {
        json!(v)
    } else if let Some(v) = bb.json_in(scope, key) {
        v
    } else {
        let type_name = bb.info_in(scope, key).map_or("unknown", |i| i.type_name);
        json!(format!("<{}>", short_type_name(type_name)))
    }
}

/// Every entry stored in `scope` itself (not those it reaches through remapping), by key.
pub fn scope_json(bb: &Blackboard, scope: ScopeId) -> Map<String, Value> {
    bb.keys_in(scope)
        .map(|k| (k.to_string(), entry_json(bb, scope, k)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::time::Duration;

    #[test]
    fn known_types_are_values_and_others_their_type_name() {
        let mut bb = Blackboard::new();
        bb.set("i", -4_i64).unwrap();
        bb.set("f", 2.5_f64).unwrap();
        bb.set("b", true).unwrap();
        bb.set("s", "text".to_string()).unwrap();
        bb.set("u", 9_u32).unwrap();
        bb.declare_in(ScopeId::ROOT, "later");
        let root = ScopeId::ROOT;
        assert_eq!(entry_json(&bb, root, "i"), json!(-4));
        assert_eq!(entry_json(&bb, root, "f"), json!(2.5));
        assert_eq!(entry_json(&bb, root, "b"), json!(true));
        assert_eq!(entry_json(&bb, root, "s"), json!("text"));
        assert_eq!(entry_json(&bb, root, "u"), json!(9));
        bb.set("i32", -7_i32).unwrap();
        bb.set("f32", 0.5_f32).unwrap();
        bb.set("big", u128::MAX).unwrap();
        bb.set("pair", (1_u8, 2_u8)).unwrap();
        assert_eq!(entry_json(&bb, root, "i32"), json!(-7));
        assert_eq!(entry_json(&bb, root, "f32"), json!(0.5));
        assert_eq!(entry_json(&bb, root, "big"), json!(u128::MAX.to_string()));
        assert_eq!(entry_json(&bb, root, "pair"), json!("<(u8, u8)>"));
        assert_eq!(entry_json(&bb, root, "later"), Value::Null);
        assert_eq!(entry_json(&bb, root, "missing"), Value::Null);
    }

    #[test]
    fn registered_types_are_json_and_others_their_short_name() {
        #[derive(Clone, serde::Serialize, serde::Deserialize)]
        struct Pose {
            x: f64,
        }
        struct Opaque;
        let mut registry = crate::Registry::<()>::new();
        let xml =
            r#"<root BTCPP_format="4"><BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>"#;
        let unregistered = registry
            .load_str(xml, "m.xml", neurotree_core::ManualClock::new())
            .unwrap();
        registry.register_value::<Pose>();
        let registered = registry
            .load_str(xml, "m.xml", neurotree_core::ManualClock::new())
            .unwrap();
        for (mut tree, pose) in [
            (unregistered, json!("<Pose>")),
            (registered, json!({"x": 1.5})),
        ] {
            let bb = tree.blackboard_mut();
            bb.set("pose", Pose { x: 1.5 }).unwrap();
            bb.set("poses", vec![Opaque]).unwrap();
            assert_eq!(entry_json(bb, ScopeId::ROOT, "pose"), pose);
            assert_eq!(
                entry_json(bb, ScopeId::ROOT, "poses"),
                json!("<Vec<Opaque>>")
            );
        }
    }

    #[test]
    fn a_scope_lists_its_own_entries_only() {
        let mut bb = Blackboard::new();
        bb.set("goal", 1_i64).unwrap();
        let sub = bb.add_scope(ScopeId::ROOT, false);
        bb.remap(sub, "target", "goal");
        bb.set_in(sub, "local", 2_i64, Duration::ZERO).unwrap();
        let keys: Vec<String> = scope_json(&bb, sub).keys().cloned().collect();
        assert_eq!(keys, ["local"]);
        assert_eq!(scope_json(&bb, ScopeId::ROOT)["goal"], json!(1));
    }
}
