use super::*;
use alloc::string::ToString;
use alloc::vec;
use alloc::vec::Vec;

const T1: Duration = Duration::from_millis(1);
const T2: Duration = Duration::from_millis(2);

#[test]
fn typed_get_and_set() {
    let mut bb = Blackboard::new();
    bb.set("n", 3_i64).unwrap();
    bb.set("name", String::from("ada")).unwrap();
    assert_eq!(bb.get::<i64>("n"), Ok(3));
    assert_eq!(bb.get_ref::<String>("name").map(String::as_str), Ok("ada"));
    assert_eq!(
        bb.get::<i64>("missing"),
        Err(BlackboardError::NotFound {
            key: "missing".into()
        })
    );
}

#[test]
fn wrong_type_reads_and_writes_are_errors() {
    let mut bb = Blackboard::new();
    bb.set("n", 3_i64).unwrap();
    let e = bb.get_exact::<f64>("n").unwrap_err();
    assert_eq!(
        e,
        BlackboardError::WrongType {
            key: "n".into(),
            expected: "f64",
            found: "i64"
        }
    );
    assert_eq!(
        e.to_string(),
        "blackboard entry `n` holds a `i64`, not a `f64`: an entry's type is fixed by its \
         first write, so use `i64`, or unset the entry before writing another type"
    );
    assert!(matches!(
        bb.set("n", 1.5_f64),
        Err(BlackboardError::WrongType {
            expected: "f64",
            found: "i64",
            ..
        })
    ));
    // The failed write changed nothing.
    assert_eq!(bb.get::<i64>("n"), Ok(3));
    assert_eq!(bb.info("n").unwrap().sequence, 1);
    // replace_in changes the type on purpose.
    bb.replace_in(ScopeId::ROOT, "n", 1.5_f64, T1);
    assert_eq!(bb.get::<f64>("n"), Ok(1.5));
    assert_eq!(bb.info("n").unwrap().sequence, 2);
    // The same type again is a plain write: sequence and stamp move, the type stays.
    let later = Duration::from_secs(9);
    bb.replace_in(ScopeId::ROOT, "n", 2.5_f64, later);
    let info = bb.info("n").unwrap();
    assert_eq!(
        (bb.get::<f64>("n"), info.sequence, info.stamp),
        (Ok(2.5), 3, later)
    );
    assert_eq!(info.type_name, "f64");
    // An untyped entry holding the same type becomes typed, as with any other type.
    bb.set_untyped_in(ScopeId::ROOT, "s", 1_i64, T1).unwrap();
    assert!(bb.is_untyped_in(ScopeId::ROOT, "s"));
    bb.replace_in(ScopeId::ROOT, "s", 2_i64, T1);
    assert!(!bb.is_untyped_in(ScopeId::ROOT, "s"));
    assert_eq!(
        (bb.get::<i64>("s"), bb.info("s").unwrap().sequence),
        (Ok(2), 2)
    );
}

#[test]
fn reads_convert_numbers_as_ports_do() {
    let mut bb = Blackboard::new();
    // What a script writes: i64 and f64.
    bb.set("laps", 3_i64).unwrap();
    bb.set("big", 3_000_000_000_i64).unwrap();
    bb.set("whole", 4.0_f64).unwrap();
    bb.set("half", 4.5_f64).unwrap();
    bb.set("flag", true).unwrap();
    assert_eq!(bb.get::<i32>("laps"), Ok(3));
    assert_eq!(bb.get::<u8>("laps"), Ok(3));
    assert_eq!(bb.get::<f64>("laps"), Ok(3.0));
    assert_eq!(bb.get::<i32>("whole"), Ok(4));
    assert_eq!(bb.get::<i32>("flag"), Ok(1));
    assert_eq!(bb.get::<bool>("laps").ok(), None);
    assert_eq!(bb.get::<String>("half"), Ok("4.5".to_string()));
    // Out of range, or a fraction where an integer is asked: an error, never a wrap.
    assert_eq!(
        bb.get::<i32>("big"),
        Err(BlackboardError::NotConvertible {
            key: "big".into(),
            value: "3000000000".into(),
            expected: "i32",
            found: "i64",
        })
    );
    assert_eq!(bb.get::<u32>("big"), Ok(3_000_000_000));
    assert!(matches!(
        bb.get::<i32>("half"),
        Err(BlackboardError::NotConvertible {
            expected: "i32",
            found: "f64",
            ..
        })
    ));
    // The same in a scope, as nodes read.
    let sub = bb.add_scope(ScopeId::ROOT, true);
    assert_eq!(bb.get_in::<i16>(sub, "laps"), Ok(3));
}

#[test]
fn reads_parse_text_as_ports_do() {
    let mut bb = Blackboard::new();
    bb.set("n", String::from(" 42 ")).unwrap();
    bb.set("word", String::from("fast")).unwrap();
    bb.set("yes", String::from("TRUE")).unwrap();
    assert_eq!(bb.get::<i32>("n"), Ok(42));
    assert_eq!(bb.get::<bool>("yes"), Ok(true));
    let e = bb.get::<f64>("word").unwrap_err();
    assert_eq!(
        e,
        BlackboardError::NotConvertible {
            key: "word".into(),
            value: "\"fast\"".into(),
            expected: "f64",
            found: "alloc::string::String",
        }
    );
    assert!(e
        .to_string()
        .contains("\"fast\", which does not fit a `f64`"));
}

#[test]
fn exact_reads_and_other_types_do_not_convert() {
    let mut bb = Blackboard::new();
    bb.set("laps", 3_i64).unwrap();
    assert_eq!(
        bb.get_exact::<i32>("laps"),
        Err(BlackboardError::WrongType {
            key: "laps".into(),
            expected: "i32",
            found: "i64",
        })
    );
    assert_eq!(bb.get_exact::<i64>("laps"), Ok(3));
    assert!(bb.get_ref::<i32>("laps").is_err());
    // A type no port rule covers is read exactly, whatever the entry holds.
    assert!(matches!(
        bb.get::<Vec<i64>>("laps"),
        Err(BlackboardError::WrongType { found: "i64", .. })
    ));
    bb.set("list", vec![1_i64]).unwrap();
    assert!(matches!(
        bb.get::<i64>("list"),
        Err(BlackboardError::WrongType {
            expected: "i64",
            ..
        })
    ));
}

#[test]
fn sequence_and_stamp_follow_writes() {
    let mut bb = Blackboard::new();
    bb.set_in(ScopeId::ROOT, "k", 1_u8, T1).unwrap();
    assert_eq!(
        bb.info("k"),
        Some(EntryInfo {
            sequence: 1,
            stamp: T1,
            type_name: "u8"
        })
    );
    bb.set_in(ScopeId::ROOT, "k", 2_u8, T2).unwrap();
    bb.set_in(ScopeId::ROOT, "k", 2_u8, T2).unwrap();
    let info = bb.info("k").unwrap();
    assert_eq!((info.sequence, info.stamp), (3, T2));
    // Overwrites keep a single entry.
    assert_eq!(bb.keys().count(), 1);
}

#[test]
fn remapped_keys_read_and_write_the_parent() {
    let mut bb = Blackboard::new();
    bb.set("target", 10_i32).unwrap();
    let sub = bb.add_scope(ScopeId::ROOT, false);
    bb.remap(sub, "goal", "target");
    assert_eq!(bb.get_in::<i32>(sub, "goal"), Ok(10));
    bb.set_in(sub, "goal", 11_i32, T1).unwrap();
    assert_eq!(bb.get::<i32>("target"), Ok(11));
    // Unremapped keys stay in the child.
    bb.set_in(sub, "local", 1_i32, T1).unwrap();
    assert!(!bb.contains("local"));
    assert!(bb.contains_in(sub, "local"));
    assert!(!bb.contains_in(sub, "target"));
}

#[test]
fn remaps_chain_over_two_levels_and_to_the_root() {
    let mut bb = Blackboard::new();
    let mid = bb.add_scope(ScopeId::ROOT, false);
    let leaf = bb.add_scope(mid, false);
    bb.remap(mid, "b", "a");
    bb.remap(leaf, "c", "b");
    bb.remap(leaf, "d", "@top");
    bb.set_in(leaf, "c", 5_u32, T1).unwrap();
    bb.set_in(leaf, "d", 6_u32, T1).unwrap();
    assert_eq!(bb.get::<u32>("a"), Ok(5));
    assert_eq!(bb.get::<u32>("top"), Ok(6));
    assert_eq!(bb.parent(leaf), Some(mid));
    assert_eq!(bb.scope_count(), 3);
}

#[test]
fn autoremap_reaches_the_parent_but_not_private_keys() {
    let mut bb = Blackboard::new();
    bb.set("shared", 1_i32).unwrap();
    bb.set("_secret", 2_i32).unwrap();
    let sub = bb.add_scope(ScopeId::ROOT, true);
    assert_eq!(bb.get_in::<i32>(sub, "shared"), Ok(1));
    assert!(bb.get_in::<i32>(sub, "_secret").is_err());
    // Writes of unknown keys land in the parent too; private ones stay.
    bb.set_in(sub, "fresh", 3_i32, T1).unwrap();
    bb.set_in(sub, "_mine", 4_i32, T1).unwrap();
    assert_eq!(bb.get::<i32>("fresh"), Ok(3));
    assert!(!bb.contains("_mine"));
    assert_eq!(bb.keys_in(sub).collect::<Vec<_>>(), ["_mine"]);
}

#[test]
fn at_keys_address_the_root_from_anywhere() {
    let mut bb = Blackboard::new();
    let a = bb.add_scope(ScopeId::ROOT, false);
    let b = bb.add_scope(a, false);
    bb.set_in(b, "@pose", (1.0_f64, 2.0_f64), T1).unwrap();
    assert_eq!(bb.get::<(f64, f64)>("pose"), Ok((1.0, 2.0)));
    assert_eq!(bb.get_in::<(f64, f64)>(b, "@pose"), Ok((1.0, 2.0)));
    assert!(!bb.contains_in(b, "pose"));
}

#[test]
fn unset_keys_and_clear() {
    let mut bb = Blackboard::new();
    for k in ["b", "a", "c"] {
        bb.set(k, 0_u8).unwrap();
    }
    assert_eq!(bb.keys().collect::<Vec<_>>(), ["a", "b", "c"]);
    assert!(bb.unset("b"));
    assert!(!bb.unset("b"));
    assert_eq!(bb.keys().collect::<Vec<_>>(), ["a", "c"]);
    let sub = bb.add_scope(ScopeId::ROOT, false);
    bb.remap(sub, "x", "a");
    bb.clear();
    assert_eq!(bb.keys().count(), 0);
    // Remaps survive a clear.
    bb.set_in(sub, "x", 9_u8, T1).unwrap();
    assert_eq!(bb.get::<u8>("a"), Ok(9));
}

#[test]
fn unknown_scopes_are_errors() {
    let mut bb = Blackboard::new();
    assert_eq!(
        bb.get_in::<u8>(ScopeId(7), "k"),
        Err(BlackboardError::NoSuchScope { scope: 7 })
    );
    assert!(bb.set_in(ScopeId(7), "k", 1_u8, T1).is_err());
    // With only its root scope, `@` names the root, and scope 1 is not there yet.
    bb.set("k", 3_u8).unwrap();
    assert_eq!(bb.get::<u8>("@k"), Ok(3));
    assert_eq!(
        bb.get_in::<u8>(ScopeId(1), "k"),
        Err(BlackboardError::NoSuchScope { scope: 1 })
    );
    // A scope with an unknown parent hangs off the root.
    let s = bb.add_scope(ScopeId(99), true);
    assert_eq!(bb.parent(s), Some(ScopeId::ROOT));
}

#[test]
fn new_is_empty_and_debug_lists_entries() {
    let mut bb = Blackboard::new();
    assert_eq!(bb.scope_count(), 1);
    assert_eq!(alloc::format!("{bb:?}"), "{0: {}}");
    bb.set("k", vec![1_u8]).unwrap();
    bb.set("k", vec![2_u8]).unwrap();
    let sub = bb.add_scope(ScopeId::ROOT, false);
    bb.remap(sub, "alias", "k");
    assert_eq!(
        alloc::format!("{bb:?}"),
        r#"{0: {"k": alloc::vec::Vec<u8> #2}, 1: {"alias": -> "k"}}"#
    );
}

#[test]
fn set_and_unset_cycles_do_not_grow_the_store() {
    let mut bb = Blackboard::new();
    let sub = bb.add_scope(ScopeId::ROOT, false);
    for i in 0..1000_u32 {
        bb.set_in(sub, "k", i, T1).unwrap();
        assert!(bb.unset_in(sub, "k"));
    }
    bb.set_in(sub, "k", 7_u32, T1).unwrap();
    let scopes = bb
        .rare
        .as_deref()
        .map_or(0, |r| r.scopes.iter().map(Entries::len).sum());
    assert_eq!(bb.root.len() + scopes, 1);
    // A key created again starts a new life: its sequence restarts at 1.
    assert_eq!(bb.info_in(sub, "k").map(|i| i.sequence), Some(1));
}

#[test]
fn unset_through_a_remap_removes_the_parent_entry() {
    let mut bb = Blackboard::new();
    bb.set("target", 1_i32).unwrap();
    let sub = bb.add_scope(ScopeId::ROOT, false);
    bb.remap(sub, "goal", "target");
    assert!(bb.unset_in(sub, "goal"));
    assert!(!bb.contains("target"));
    assert!(!bb.unset_in(sub, "goal"));
    assert!(!bb.unset_in(ScopeId(9), "goal"));
    // The remap itself stays.
    bb.set_in(sub, "goal", 2_i32, T2).unwrap();
    assert_eq!(bb.get::<i32>("target"), Ok(2));
}

#[test]
fn autoremap_creates_missing_keys_as_high_as_it_reaches() {
    let mut bb = Blackboard::new();
    let plain = bb.add_scope(ScopeId::ROOT, false);
    let auto1 = bb.add_scope(plain, true);
    let auto2 = bb.add_scope(auto1, true);
    bb.set_in(auto2, "k", 1_u8, T1).unwrap();
    // Autoremap stops at `plain`, which does not autoremap into the root.
    assert_eq!(bb.keys_in(plain).collect::<Vec<_>>(), ["k"]);
    assert_eq!(bb.keys_in(auto1).count(), 0);
    assert_eq!(bb.keys_in(auto2).count(), 0);
    assert!(!bb.contains("k"));
    // All three see the same entry.
    bb.set_in(plain, "k", 2_u8, T2).unwrap();
    assert_eq!(bb.get_in::<u8>(auto2, "k"), Ok(2));
    assert_eq!(bb.info_in(auto1, "k").map(|i| i.sequence), Some(2));
}

#[test]
fn same_named_keys_in_unlinked_scopes_are_distinct() {
    let mut bb = Blackboard::new();
    let auto = bb.add_scope(ScopeId::ROOT, true);
    let plain = bb.add_scope(ScopeId::ROOT, false);
    bb.set("k", 1_i32).unwrap();
    bb.set("_p", 1_i32).unwrap();
    bb.set_in(plain, "k", 5_i32, T1).unwrap();
    bb.set_in(auto, "_p", 6_i32, T1).unwrap();
    assert_eq!(bb.get::<i32>("k"), Ok(1));
    assert_eq!(bb.get::<i32>("_p"), Ok(1));
    assert_eq!(bb.get_in::<i32>(plain, "k"), Ok(5));
    assert_eq!(bb.get_in::<i32>(auto, "_p"), Ok(6));
    assert_eq!(bb.get_in::<i32>(auto, "k"), Ok(1));
}

#[test]
fn get_any_sees_every_type_and_nothing_else() {
    let mut bb = Blackboard::new();
    bb.set("n", 4_u16).unwrap();
    let any = bb.get_any_in(ScopeId::ROOT, "n").unwrap();
    assert_eq!(any.downcast_ref::<u16>(), Some(&4));
    assert!(bb.get_any_in(ScopeId::ROOT, "m").is_none());
    assert!(bb.get_any_in(ScopeId(3), "n").is_none());
}

#[test]
fn the_shorthand_set_reuses_the_latest_stamp() {
    let mut bb = Blackboard::new();
    bb.set("a", 1_u8).unwrap();
    assert_eq!(bb.info("a").unwrap().stamp, Duration::ZERO);
    bb.set_in(ScopeId::ROOT, "b", 1_u8, T2).unwrap();
    bb.set_in(ScopeId::ROOT, "c", 1_u8, T1).unwrap();
    bb.set("a", 2_u8).unwrap();
    assert_eq!(bb.info("a").unwrap().stamp, T2);
}

#[test]
fn declared_entries_exist_but_read_only_after_a_write() {
    let mut bb = Blackboard::new();
    let sub = bb.add_scope(ScopeId::ROOT, false);
    bb.remap(sub, "goal", "target");
    bb.declare_in(sub, "goal");
    assert!(bb.contains("target"));
    assert_eq!(bb.info("target").unwrap().sequence, 0);
    assert!(matches!(
        bb.get::<i32>("target"),
        Err(BlackboardError::NotFound { .. })
    ));
    assert!(bb.get_any_in(sub, "goal").is_none());
    // The first write, of any type, fixes the type.
    bb.set_in(sub, "goal", 1.5_f64, T1).unwrap();
    assert_eq!(bb.get::<f64>("target"), Ok(1.5));
    assert_eq!(bb.info("target").unwrap().sequence, 1);
    assert!(bb.set("target", 1_i32).is_err());
    // Declaring an existing entry changes nothing.
    bb.declare_in(ScopeId::ROOT, "target");
    assert_eq!(bb.get::<f64>("target"), Ok(1.5));
}

#[test]
fn a_blackboard_takes_32_bytes_and_a_plain_tree_s_no_box_of_rare_parts() {
    assert!(core::mem::size_of::<Blackboard>() <= 32);
    let mut bb = Blackboard::new();
    bb.set("alert", true).unwrap();
    bb.declare_in(ScopeId::ROOT, "goal");
    bb.set_json_in(ScopeId::ROOT, "n", serde_json::json!(3), T1)
        .unwrap();
    assert!(bb.rare.is_none(), "root entries alone made the rare box");
    bb.set_codecs(alloc::sync::Arc::new(crate::state::StateCodecs::new()));
    assert!(bb.rare.is_some() && bb.codecs().is_some());
    let mut bb = Blackboard::new();
    let sub = bb.add_scope(ScopeId::ROOT, false);
    assert!(bb.rare.is_some() && bb.codecs().is_none());
    assert_eq!(bb.scope_count(), 2);
    bb.set_in(sub, "k", 1_u8, T1).unwrap();
    assert_eq!((bb.root.len(), bb.get_in::<u8>(sub, "k")), (0, Ok(1)));
}

/// A newtype around a value, so that it is boxed where the value itself is held inline.
#[derive(Clone, Debug, PartialEq)]
struct Boxed<T>(T);

/// What a run of every kind of write and read leaves of an entry: `(value read, sequence,
/// stamp)` after each step; `wrap` puts a value in the type under test.
fn writes_and_reads<T, W>(wrap: impl Fn(T) -> W, a: T, b: T) -> Vec<(Option<W>, u64, Duration)>
where
    T: Clone,
    W: Any + Send + Sync + Clone + PartialEq + core::fmt::Debug,
{
    let mut bb = Blackboard::new();
    let mut log = Vec::new();
    let mut note = |bb: &Blackboard| {
        let info = bb.info("k").unwrap();
        log.push((bb.get_exact::<W>("k").ok(), info.sequence, info.stamp));
    };
    bb.declare_in(ScopeId::ROOT, "k");
    note(&bb);
    bb.set_in(ScopeId::ROOT, "k", wrap(a.clone()), T1).unwrap();
    note(&bb);
    assert_eq!(bb.get_ref::<W>("k"), Ok(&wrap(a.clone())));
    let any = bb.get_any_in(ScopeId::ROOT, "k").unwrap();
    assert_eq!(any.downcast_ref::<W>(), Some(&wrap(a.clone())));
    assert!(bb.set("k", 1_i128).is_err(), "the type is fixed");
    note(&bb);
    bb.set("k", wrap(b.clone())).unwrap();
    note(&bb);
    let b2 = wrap(b.clone());
    assert!(bb.modify_in::<W>(ScopeId::ROOT, "k", T2, |v| *v = b2));
    assert!(!bb.modify_in::<i128>(ScopeId::ROOT, "k", T2, |_| ()));
    note(&bb);
    bb.replace_in(ScopeId::ROOT, "k", wrap(a.clone()), T1);
    note(&bb);
    // Retyped to text and back.
    bb.replace_in(ScopeId::ROOT, "k", String::from("text"), T2);
    note(&bb);
    assert_eq!(bb.get_ref::<String>("k").map(String::as_str), Ok("text"));
    bb.replace_in(ScopeId::ROOT, "k", wrap(b.clone()), T2);
    note(&bb);
    // Out, boxed, and back in, as saving and restoring a tree's state do.
    let raw = bb.take_raw_entries();
    assert!(!bb.contains("k"));
    for (scope, key, info, untyped, value) in raw {
        let value = value.unwrap();
        assert_eq!(value.downcast_ref::<W>(), Some(&wrap(b.clone())));
        assert!(bb.put_raw_entry(scope, key, info, untyped, Some(value)));
    }
    note(&bb);
    bb.set("k", wrap(a)).unwrap();
    note(&bb);
    assert!(bb.unset("k") && !bb.contains("k"));
    log
}

#[test]
fn values_held_inline_read_and_write_as_boxed_ones_do() {
    fn unwrap<T: Clone>(
        log: Vec<(Option<Boxed<T>>, u64, Duration)>,
    ) -> Vec<(Option<T>, u64, Duration)> {
        log.into_iter()
            .map(|(v, s, t)| (v.map(|b| b.0), s, t))
            .collect()
    }
    let inline = writes_and_reads(|v| v, true, false);
    assert_eq!(inline, unwrap(writes_and_reads(Boxed, true, false)));
    assert_eq!(
        inline.iter().map(|e| e.1).collect::<Vec<_>>(),
        [0, 1, 1, 2, 3, 4, 5, 6, 6, 7]
    );
    assert_eq!(inline[4], (Some(false), 3, T2));
    assert_eq!(inline[6], (None, 5, T2), "text read as a `bool`");
    let inline = writes_and_reads(|v| v, -7_i64, 1 << 40);
    assert_eq!(inline, unwrap(writes_and_reads(Boxed, -7_i64, 1 << 40)));
    let inline = writes_and_reads(|v| v, 0.25_f32, -1.5);
    assert_eq!(inline, unwrap(writes_and_reads(Boxed, 0.25_f32, -1.5)));
    let inline = writes_and_reads(|v| v, T1, Duration::from_secs(3));
    assert_eq!(
        inline,
        unwrap(writes_and_reads(Boxed, T1, Duration::from_secs(3)))
    );
}

#[test]
fn an_untyped_entry_held_inline_takes_any_type_as_a_boxed_one_does() {
    let mut bb = Blackboard::new();
    bb.set_untyped_in(ScopeId::ROOT, "x", 1_i64, T1).unwrap();
    bb.set_untyped_in(ScopeId::ROOT, "x", 2_i64, T1).unwrap();
    assert_eq!(bb.get_exact::<i64>("x"), Ok(2));
    bb.set_untyped_in(ScopeId::ROOT, "x", String::from("two"), T2)
        .unwrap();
    assert_eq!(bb.get_exact::<String>("x"), Ok(String::from("two")));
    bb.set_untyped_in(ScopeId::ROOT, "x", 2.5_f64, T2).unwrap();
    assert_eq!(bb.get_exact::<f64>("x"), Ok(2.5));
    let info = bb.info("x").unwrap();
    assert_eq!((info.sequence, info.type_name), (4, "f64"));
    assert!(bb.is_untyped_in(ScopeId::ROOT, "x"));
    // Reads convert an inline number as they convert a boxed one.
    assert_eq!(bb.get::<String>("x"), Ok(String::from("2.5")));
    assert!(matches!(
        bb.get::<i32>("x"),
        Err(BlackboardError::NotConvertible { .. })
    ));
    // JSON sees and edits it, and a value from JSON is held as a write holds it.
    assert_eq!(bb.json_in(ScopeId::ROOT, "x"), Some(serde_json::json!(2.5)));
    bb.set_json_in(ScopeId::ROOT, "x", serde_json::json!(-1), T2)
        .unwrap();
    assert_eq!(bb.get_exact::<f64>("x"), Ok(-1.0));
    let entry = bb.root.get("x").unwrap();
    assert!(matches!(entry.value, entry::Stored::F64(_)));
}
