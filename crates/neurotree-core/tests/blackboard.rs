//! The blackboard through its public API: typed entries, sequence numbers and stamps, scopes
//! and remapping, the allocation promises (a counting allocator watches), and a property
//! test against a plain map.

use std::collections::BTreeMap;
use std::time::Duration;

use neurotree_core::{Blackboard, BlackboardError, EntryInfo, ScopeId};
use proptest::prelude::*;

use crate::counting_alloc;
use counting_alloc::count as allocations;

const T1: Duration = Duration::from_millis(10);
const T2: Duration = Duration::from_millis(20);
const T3: Duration = Duration::from_millis(30);

#[test]
fn typed_values_come_back_as_written() {
    let mut bb = Blackboard::new();
    bb.set("count", 3_i64).unwrap();
    bb.set("name", String::from("ada")).unwrap();
    bb.set("pose", [1.0_f64, 2.0, 0.5]).unwrap();
    assert_eq!(bb.get::<i64>("count"), Ok(3));
    assert_eq!(bb.get::<String>("name"), Ok(String::from("ada")));
    assert_eq!(bb.get_ref::<String>("name").map(String::as_str), Ok("ada"));
    assert_eq!(bb.get::<[f64; 3]>("pose"), Ok([1.0, 2.0, 0.5]));
    assert_eq!(
        bb.get::<i64>("absent"),
        Err(BlackboardError::NotFound {
            key: String::from("absent")
        })
    );
}

#[test]
fn wrong_type_reads_and_writes_are_errors_that_change_nothing() {
    let mut bb = Blackboard::new();
    bb.set_in(ScopeId::ROOT, "speed", 1.5_f32, T1).unwrap();
    assert_eq!(
        bb.get_exact::<f64>("speed"),
        Err(BlackboardError::WrongType {
            key: String::from("speed"),
            expected: "f64",
            found: "f32",
        })
    );
    assert_eq!(
        bb.get_ref::<String>("speed"),
        Err(BlackboardError::WrongType {
            key: String::from("speed"),
            expected: "alloc::string::String",
            found: "f32",
        })
    );
    assert_eq!(
        bb.set_in(ScopeId::ROOT, "speed", 2_u8, T2),
        Err(BlackboardError::WrongType {
            key: String::from("speed"),
            expected: "u8",
            found: "f32",
        })
    );
    assert_eq!(bb.get::<f32>("speed"), Ok(1.5));
    assert_eq!(
        bb.info("speed"),
        Some(EntryInfo {
            sequence: 1,
            stamp: T1,
            type_name: "f32",
        })
    );
}

#[test]
fn the_error_messages_say_what_to_do() {
    let not_found = BlackboardError::NotFound {
        key: String::from("goal"),
    };
    assert!(not_found
        .to_string()
        .starts_with("no blackboard entry `goal`: write it before reading it"));
    let scope = BlackboardError::NoSuchScope { scope: 4 };
    assert!(scope.to_string().contains("`Blackboard::add_scope`"));
}

#[test]
fn each_write_bumps_the_sequence_by_one_and_stores_its_stamp() {
    let mut bb = Blackboard::new();
    let stamps = [T1, T2, T2, T3];
    for (i, &stamp) in stamps.iter().enumerate() {
        bb.set_in(ScopeId::ROOT, "k", i as u32, stamp).unwrap();
        let info = bb.info("k").unwrap();
        assert_eq!(info.sequence, i as u64 + 1);
        assert_eq!(info.stamp, stamp);
    }
    // The same value written again is still a write.
    bb.set_in(ScopeId::ROOT, "k", 3_u32, T1).unwrap();
    assert_eq!(
        bb.info("k"),
        Some(EntryInfo {
            sequence: 5,
            stamp: T1,
            type_name: "u32",
        })
    );
}

#[test]
fn a_same_typed_write_overwrites_in_place() {
    let mut bb = Blackboard::new();
    bb.set("a", 1_i64).unwrap();
    bb.set("b", String::from("first")).unwrap();
    let second = String::from("second");
    let (n, result) = allocations(|| {
        let r1 = bb.set_in(ScopeId::ROOT, "a", 2_i64, T1);
        let r2 = bb.set_in(ScopeId::ROOT, "b", second, T1);
        (r1, r2)
    });
    assert_eq!(result, (Ok(()), Ok(())));
    assert_eq!(n, 0, "an overwrite allocated");
    assert_eq!(bb.keys().collect::<Vec<_>>(), ["a", "b"]);
    assert_eq!(bb.get::<i64>("a"), Ok(2));
    assert_eq!(bb.get::<String>("b"), Ok(String::from("second")));
    assert_eq!(bb.info("a").unwrap().sequence, 2);
    assert_eq!(bb.info("b").unwrap().sequence, 2);
}

#[test]
fn the_counter_sees_allocations() {
    // Guards the guard: without this, a broken counter would make the tests above and below
    // pass whatever the blackboard does.
    let mut bb = Blackboard::new();
    let (n, _) = allocations(|| bb.set("fresh", [1_u8; 3]));
    assert!(
        n >= 2,
        "a first write of a boxed type allocates the scope's entries and the value, \
         counted {n}"
    );
    // A small plain value is held in its entry: only the scope's block of entries is new
    // (the key is short enough to sit in the entry too).
    let mut bb = Blackboard::new();
    let (n, _) = allocations(|| bb.set("fresh", 1_u8));
    assert_eq!(
        n, 1,
        "a first write of a `u8` allocates its scope's block only"
    );
    // The block holds one entry, then doubles: a second and a third key each make a new
    // one, a fourth fits in the room the third made.
    let (n, _) = allocations(|| bb.set("second", true));
    assert_eq!(n, 1, "a second key moves the scope to a block of two");
    let (n, _) = allocations(|| bb.set("third", 3_i64));
    assert_eq!(n, 1, "a third key moves the scope to a block of four");
    let (n, _) = allocations(|| bb.set("fourth", 4.0_f64));
    assert_eq!(n, 0, "a fourth key fits in the block the third made");
}

#[test]
fn new_and_reads_do_not_allocate() {
    let (n, bb) = allocations(Blackboard::new);
    assert_eq!(n, 0);
    drop(bb);

    let mut bb = Blackboard::new();
    let sub = bb.add_scope(ScopeId::ROOT, true);
    let leaf = bb.add_scope(sub, false);
    bb.remap(leaf, "goal", "target");
    bb.set("target", (3.0_f64, 4.0_f64)).unwrap();
    bb.set("name", String::from("r2")).unwrap();
    let (n, ()) = allocations(|| {
        assert_eq!(bb.get_in::<(f64, f64)>(leaf, "goal"), Ok((3.0, 4.0)));
        assert_eq!(bb.get_ref_in::<String>(sub, "name").unwrap(), "r2");
        assert_eq!(bb.get_ref_in::<String>(leaf, "@name").unwrap(), "r2");
        assert!(bb.get_any_in(leaf, "goal").is_some());
        assert!(bb.contains_in(leaf, "goal"));
        assert!(bb.info_in(sub, "target").is_some());
        // Probing for what is not there does not allocate either.
        assert!(!bb.contains_in(leaf, "name"));
        assert!(bb.info_in(leaf, "nothing").is_none());
        assert!(bb.get_any_in(ScopeId(40), "goal").is_none());
        assert_eq!(bb.keys_in(sub).count(), 0);
    });
    assert_eq!(n, 0);
}

#[test]
fn a_remapped_key_reads_and_writes_the_parent_entry() {
    let mut bb = Blackboard::new();
    bb.set_in(ScopeId::ROOT, "target", 10_i32, T1).unwrap();
    let sub = bb.add_scope(ScopeId::ROOT, false);
    bb.remap(sub, "goal", "target");
    assert_eq!(bb.get_in::<i32>(sub, "goal"), Ok(10));
    bb.set_in(sub, "goal", 11_i32, T2).unwrap();
    assert_eq!(bb.get::<i32>("target"), Ok(11));
    assert_eq!(
        bb.info("target"),
        Some(EntryInfo {
            sequence: 2,
            stamp: T2,
            type_name: "i32",
        })
    );
    // The alias is not an entry of the child, and the child sees nothing else of the parent.
    assert_eq!(bb.keys_in(sub).count(), 0);
    assert_eq!(
        bb.get_in::<i32>(sub, "target"),
        Err(BlackboardError::NotFound {
            key: String::from("target")
        })
    );
    // A remapped key written first from the child creates the parent's entry.
    bb.remap(sub, "out", "result");
    bb.set_in(sub, "out", true, T3).unwrap();
    assert_eq!(bb.get::<bool>("result"), Ok(true));
    assert_eq!(bb.keys().collect::<Vec<_>>(), ["result", "target"]);
}

#[test]
fn remaps_chain_over_two_levels() {
    let mut bb = Blackboard::new();
    let mid = bb.add_scope(ScopeId::ROOT, false);
    let leaf = bb.add_scope(mid, false);
    bb.remap(mid, "waypoint", "goal");
    bb.remap(leaf, "next", "waypoint");
    bb.set_in(leaf, "next", 7_u32, T1).unwrap();
    assert_eq!(bb.get::<u32>("goal"), Ok(7));
    assert_eq!(bb.get_in::<u32>(mid, "waypoint"), Ok(7));
    assert_eq!(bb.keys().collect::<Vec<_>>(), ["goal"]);
    assert_eq!(bb.keys_in(mid).count(), 0);
    assert_eq!(bb.keys_in(leaf).count(), 0);
    bb.set("goal", 8_u32).unwrap();
    assert_eq!(bb.get_in::<u32>(leaf, "next"), Ok(8));
    assert_eq!(bb.info_in(leaf, "next").unwrap().sequence, 2);
    assert_eq!(bb.parent(leaf), Some(mid));
    assert_eq!(bb.parent(mid), Some(ScopeId::ROOT));
    assert_eq!(bb.parent(ScopeId::ROOT), None);
    assert_eq!(bb.scope_count(), 3);
}

#[test]
fn autoremap_reads_the_parent_but_not_private_keys() {
    let mut bb = Blackboard::new();
    bb.set("shared", 1_i32).unwrap();
    bb.set("_secret", 2_i32).unwrap();
    let sub = bb.add_scope(ScopeId::ROOT, true);
    let plain = bb.add_scope(ScopeId::ROOT, false);
    assert_eq!(bb.get_in::<i32>(sub, "shared"), Ok(1));
    assert_eq!(
        bb.get_in::<i32>(sub, "_secret"),
        Err(BlackboardError::NotFound {
            key: String::from("_secret")
        })
    );
    assert!(!bb.contains_in(plain, "shared"));
    // A write from the child reaches the shared entry; a private one stays in the child.
    bb.set_in(sub, "shared", 5_i32, T1).unwrap();
    bb.set_in(sub, "_secret", 6_i32, T1).unwrap();
    assert_eq!(bb.get::<i32>("shared"), Ok(5));
    assert_eq!(bb.get::<i32>("_secret"), Ok(2));
    assert_eq!(bb.get_in::<i32>(sub, "_secret"), Ok(6));
    assert_eq!(bb.keys_in(sub).collect::<Vec<_>>(), ["_secret"]);
}

#[test]
fn at_keys_hit_the_root_from_a_nested_scope() {
    let mut bb = Blackboard::new();
    let a = bb.add_scope(ScopeId::ROOT, false);
    let b = bb.add_scope(a, true);
    let c = bb.add_scope(b, false);
    bb.remap(c, "battery", "level");
    bb.set_in(c, "@battery", 0.8_f64, T1).unwrap();
    assert_eq!(bb.get::<f64>("battery"), Ok(0.8));
    assert_eq!(bb.get_in::<f64>(b, "@battery"), Ok(0.8));
    // The remap of `battery` in `c` does not apply to `@battery`.
    assert!(!bb.contains_in(c, "battery"));
    assert_eq!(bb.keys_in(a).count(), 0);
    assert_eq!(bb.keys_in(c).count(), 0);
    assert!(bb.unset_in(c, "@battery"));
    assert!(!bb.contains("battery"));
}

#[test]
fn unset_removes_one_entry() {
    let mut bb = Blackboard::new();
    bb.set("a", 1_u8).unwrap();
    bb.set("b", 2_u8).unwrap();
    assert!(bb.unset("a"));
    assert!(!bb.unset("a"));
    assert!(!bb.contains("a"));
    assert_eq!(bb.get::<u8>("b"), Ok(2));
    assert_eq!(bb.info("a"), None);
    // Once unset, the key can take another type.
    bb.set("a", 'x').unwrap();
    assert_eq!(
        bb.info("a"),
        Some(EntryInfo {
            sequence: 1,
            stamp: Duration::ZERO,
            type_name: "char",
        })
    );
}

#[test]
fn keys_are_sorted_per_scope() {
    let mut bb = Blackboard::new();
    for k in ["zeta", "alpha", "_hidden", "Mid", "beta"] {
        bb.set(k, 0_u8).unwrap();
    }
    let sub = bb.add_scope(ScopeId::ROOT, false);
    bb.set_in(sub, "local", 0_u8, T1).unwrap();
    assert_eq!(
        bb.keys().collect::<Vec<_>>(),
        ["Mid", "_hidden", "alpha", "beta", "zeta"]
    );
    assert_eq!(bb.keys_in(sub).collect::<Vec<_>>(), ["local"]);
    assert_eq!(bb.keys_in(ScopeId(5)).count(), 0);
}

#[test]
fn clear_empties_every_scope_but_keeps_the_remaps() {
    let mut bb = Blackboard::new();
    let sub = bb.add_scope(ScopeId::ROOT, true);
    bb.remap(sub, "goal", "target");
    bb.set("target", 1_i32).unwrap();
    bb.set_in(sub, "_own", 1_i32, T1).unwrap();
    bb.clear();
    assert_eq!(bb.keys().count(), 0);
    assert_eq!(bb.keys_in(sub).count(), 0);
    assert_eq!(bb.scope_count(), 2);
    bb.set_in(sub, "goal", 2_i32, T2).unwrap();
    assert_eq!(bb.get::<i32>("target"), Ok(2));
    assert_eq!(bb.info("target").unwrap().sequence, 1);
}

#[test]
fn replace_changes_the_type_and_still_counts() {
    let mut bb = Blackboard::new();
    let sub = bb.add_scope(ScopeId::ROOT, false);
    bb.remap(sub, "n", "number");
    bb.set_in(sub, "n", String::from("42"), T1).unwrap();
    bb.replace_in(sub, "n", 42_i64, T2);
    assert_eq!(bb.get::<i64>("number"), Ok(42));
    assert_eq!(
        bb.info("number"),
        Some(EntryInfo {
            sequence: 2,
            stamp: T2,
            type_name: "i64",
        })
    );
    // From now on the type is the new one.
    assert!(bb.set("number", String::from("43")).is_err());
    // Replacing a missing entry creates it.
    bb.replace_in(ScopeId::ROOT, "fresh", 1_u8, T3);
    assert_eq!(bb.info("fresh").unwrap().sequence, 1);
}

#[test]
fn unknown_scopes_are_reported_and_never_created() {
    let mut bb = Blackboard::new();
    let ghost = ScopeId(3);
    assert_eq!(
        bb.get_in::<u8>(ghost, "k"),
        Err(BlackboardError::NoSuchScope { scope: 3 })
    );
    assert_eq!(
        bb.get_ref_in::<u8>(ghost, "k"),
        Err(BlackboardError::NoSuchScope { scope: 3 })
    );
    assert_eq!(
        bb.set_in(ghost, "k", 1_u8, T1),
        Err(BlackboardError::NoSuchScope { scope: 3 })
    );
    bb.replace_in(ghost, "k", 1_u8, T1);
    bb.remap(ghost, "a", "b");
    assert!(!bb.unset_in(ghost, "k"));
    assert!(!bb.contains_in(ghost, "k"));
    assert_eq!(bb.parent(ghost), None);
    assert_eq!(bb.scope_count(), 1);
    // The scope is checked before the `@`, so a bad scope is caught even for root keys.
    assert_eq!(
        bb.get_in::<u8>(ghost, "@k"),
        Err(BlackboardError::NoSuchScope { scope: 3 })
    );
    // A scope asked to hang off an unknown parent hangs off the root instead.
    let s = bb.add_scope(ScopeId(9), false);
    assert_eq!(s, ScopeId(1));
    assert_eq!(bb.parent(s), Some(ScopeId::ROOT));
}

#[test]
fn debug_lists_keys_and_types_but_not_values() {
    let mut bb = Blackboard::new();
    bb.set("pin", 1234_u16).unwrap();
    let text = format!("{bb:?}");
    assert_eq!(text, r#"{0: {"pin": u16 #1}}"#);
    assert!(!text.contains("1234"));
}

/// One step of the property test.
#[derive(Clone, Debug)]
enum Op {
    Set(u8, i64),
    SetText(u8),
    Get(u8),
    Unset(u8),
    Clear,
}

fn op() -> impl Strategy<Value = Op> {
    // Few keys, so that steps meet the same entries often.
    let key = 0_u8..6;
    prop_oneof![
        4 => (key.clone(), any::<i64>()).prop_map(|(k, v)| Op::Set(k, v)),
        1 => key.clone().prop_map(Op::SetText),
        3 => key.clone().prop_map(Op::Get),
        2 => key.prop_map(Op::Unset),
        1 => Just(Op::Clear),
    ]
}

fn name(k: u8) -> String {
    format!("key{k}")
}

proptest! {
    /// The root scope behaves as a map from keys to `i64`, plus the sequence number of each
    /// key's current life, plus the type rule (a text write to an `i64` key is refused).
    #[test]
    fn the_root_scope_behaves_like_a_map(ops in proptest::collection::vec(op(), 0..80)) {
        let mut bb = Blackboard::new();
        let mut model: BTreeMap<String, i64> = BTreeMap::new();
        let mut writes: BTreeMap<String, u64> = BTreeMap::new();
        for (step, op) in ops.into_iter().enumerate() {
            let stamp = Duration::from_millis(step as u64);
            match op {
                Op::Set(k, v) => {
                    let key = name(k);
                    prop_assert_eq!(bb.set_in(ScopeId::ROOT, &key, v, stamp), Ok(()));
                    model.insert(key.clone(), v);
                    *writes.entry(key.clone()).or_insert(0) += 1;
                    prop_assert_eq!(bb.info(&key).map(|i| i.stamp), Some(stamp));
                }
                Op::SetText(k) => {
                    let key = name(k);
                    let result = bb.set_in(ScopeId::ROOT, &key, String::from("text"), stamp);
                    if model.contains_key(&key) {
                        prop_assert_eq!(result, Err(BlackboardError::WrongType {
                            key: key.clone(),
                            expected: "alloc::string::String",
                            found: "i64",
                        }));
                    } else {
                        // Created as text; take it out again so the model stays all-`i64`.
                        prop_assert_eq!(result, Ok(()));
                        prop_assert!(bb.unset(&key));
                    }
                }
                Op::Get(k) => {
                    let key = name(k);
                    let expected = model.get(&key).copied().ok_or(BlackboardError::NotFound {
                        key: key.clone(),
                    });
                    prop_assert_eq!(bb.get::<i64>(&key), expected);
                }
                Op::Unset(k) => {
                    let key = name(k);
                    prop_assert_eq!(bb.unset(&key), model.remove(&key).is_some());
                    writes.remove(&key);
                }
                Op::Clear => {
                    bb.clear();
                    model.clear();
                    writes.clear();
                }
            }
            prop_assert!(bb.keys().eq(model.keys().map(String::as_str)));
            for (key, &n) in &writes {
                prop_assert_eq!(bb.info(key).map(|i| i.sequence), Some(n));
            }
        }
    }
}
