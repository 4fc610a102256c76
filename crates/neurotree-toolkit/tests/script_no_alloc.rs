//! Evaluating a parsed script allocates nothing when it computes with numbers and booleans
//! on entries that already exist: a counting allocator watches the evaluations.

use std::time::Duration;

use neurotree::script::{Enums, Script, ScriptEnv, Value};
use neurotree::{Blackboard, ScopeId};

use crate::counting_alloc;
use counting_alloc::allocations;

#[test]
fn counting_works() {
    assert_eq!(allocations(|| drop(std::hint::black_box(vec![1_u8]))), 1);
    assert_eq!(
        allocations(|| drop(std::hint::black_box(String::from("s")))),
        1
    );
}

#[test]
fn numeric_scripts_do_not_allocate() {
    let mut bb = Blackboard::new();
    bb.set("counter", 0_i64).unwrap();
    bb.set("ok", false).unwrap();
    bb.set("x", 0.5_f64).unwrap();
    bb.set("y", 3_i64).unwrap();
    let script =
        Script::parse("counter += 1; ok := counter < 10 && (x * 2.5 > 1 || y == 3)").unwrap();
    let enums = Enums::new();
    let mut results = [Value::Empty, Value::Empty];
    let n = allocations(|| {
        for i in 0..20 {
            let mut env = ScriptEnv {
                blackboard: &mut bb,
                scope: ScopeId::ROOT,
                enums: &enums,
                stamp: Duration::from_millis(i),
                max_string_len: neurotree::script::DEFAULT_MAX_STRING_LEN,
            };
            let v = script.eval(&mut env).unwrap();
            results[usize::from(i >= 10)] = v;
        }
    });
    assert_eq!(n, 0);
    // The first ten runs count to 10; then `counter < 10` is false.
    assert_eq!(results, [Value::Bool(false), Value::Bool(false)]);
    assert_eq!(bb.get::<i64>("counter"), Ok(20));
    assert_eq!(bb.get::<bool>("ok"), Ok(false));
    assert_eq!(bb.info("counter").unwrap().sequence, 21);
    assert_eq!(bb.info("ok").unwrap().stamp, Duration::from_millis(19));

    // While the count was below 10, `ok` was true (`y == 3`).
    bb.set("counter", 0_i64).unwrap();
    let mut env = ScriptEnv::new(&mut bb);
    assert_eq!(script.eval(&mut env), Ok(Value::Bool(true)));
}

#[test]
fn every_numeric_operator_is_allocation_free() {
    let mut bb = Blackboard::new();
    bb.set("i", 7_i32).unwrap();
    bb.set("u", 200_u8).unwrap();
    bb.set("f", 1.5_f32).unwrap();
    bb.set("flag", true).unwrap();
    bb.set("label", String::from("idle")).unwrap();
    bb.set("out", 0.0_f64).unwrap();
    let child = bb.add_scope(ScopeId::ROOT, false);
    bb.set_in(child, "local", 1_i64, Duration::ZERO).unwrap();
    let enums: Enums = [("DOCKING", 2_i64)].into_iter().collect();
    let script = Script::parse(
        "local := local * 2 - 1; @i -= 1; @u = (@u + 1) & 0xFF ^ 1 | 2; @f /= 2; \
         @flag = !@flag || ~local == -2; \
         @out := (1 < 2 <= 2 != 3 ? DOCKING * 1.5 : -@i / 4) + ('a' == 'a') + ('7' > 6); \
         'lit' ? 1 : 2",
    )
    .unwrap();
    let n = allocations(|| {
        for _ in 0..5 {
            let mut env = ScriptEnv {
                blackboard: &mut bb,
                scope: child,
                enums: &enums,
                stamp: Duration::ZERO,
                max_string_len: neurotree::script::DEFAULT_MAX_STRING_LEN,
            };
            assert_eq!(script.eval(&mut env), Ok(Value::Int(1)));
        }
    });
    assert_eq!(n, 0);
    assert_eq!(bb.get_in::<i64>(child, "local"), Ok(1));
    assert_eq!(bb.get::<i32>("i"), Ok(2));
    assert_eq!(bb.get::<f32>("f"), Ok(1.5 / 32.0));
    assert_eq!(bb.get::<f64>("out"), Ok(5.0));
}

#[test]
fn strings_allocate_only_when_copied_or_built() {
    let mut bb = Blackboard::new();
    bb.set("label", String::from("idle")).unwrap();
    let compare_literals = Script::parse("'idle' == 'idle'").unwrap();
    let read_entry = Script::parse("label == 'idle'").unwrap();
    let n = allocations(|| {
        let v = compare_literals.eval(&mut ScriptEnv::new(&mut bb));
        assert_eq!(v, Ok(Value::Bool(true)));
    });
    assert_eq!(n, 0);
    // Reading a String entry copies it: one allocation, and no more.
    let n = allocations(|| {
        let v = read_entry.eval(&mut ScriptEnv::new(&mut bb));
        assert_eq!(v, Ok(Value::Bool(true)));
    });
    assert_eq!(n, 1);
}
