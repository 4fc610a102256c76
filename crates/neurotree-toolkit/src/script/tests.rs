//! What scripts compute: precedence, operators, assignment, scopes and enums.

use super::*;

/// Evaluates `src` on `bb`'s root scope with `enums`, stamped 7 ms.
pub(super) fn run_with(
    src: &str,
    bb: &mut Blackboard,
    enums: &Enums,
) -> Result<Value, ScriptError> {
    let script = Script::parse(src).unwrap_or_else(|e| panic!("{src:?}: {e}"));
    script.eval(&mut ScriptEnv {
        blackboard: bb,
        scope: ScopeId::ROOT,
        enums,
        stamp: Duration::from_millis(7),
        max_string_len: super::DEFAULT_MAX_STRING_LEN,
    })
}

pub(super) fn run(src: &str, bb: &mut Blackboard) -> Result<Value, ScriptError> {
    run_with(src, bb, &Enums::new())
}

/// The value of `src` on a fresh blackboard.
pub(super) fn value(src: &str) -> Value {
    run(src, &mut Blackboard::new()).unwrap_or_else(|e| panic!("{src:?}: {e}"))
}

fn int(v: i64) -> Value {
    Value::Int(v)
}

fn real(v: f64) -> Value {
    Value::Real(v)
}

fn s(v: &str) -> Value {
    Value::Str(v.into())
}

#[test]
fn precedence_and_associativity() {
    // Each case tells its reading from the nearest other one (shown after `//`).
    let cases: &[(&str, Value)] = &[
        ("1 + 2 * 3", int(7)),                         // (1 + 2) * 3 = 9
        ("(1 + 2) * 3", int(9)),                       //
        ("10 - 4 - 3", int(3)),                        // 10 - (4 - 3) = 9
        ("8 / 4 / 2", real(1.0)),                      // 8 / (4 / 2) = 4
        ("2 * 3 / 4", real(1.5)),                      //
        ("10 - 2 * 3 + 1", int(5)),                    //
        ("-2 * 3", int(-6)),                           //
        ("- 2 + 3", int(1)),                           // -(2 + 3) = -5
        ("-2 - -3", int(1)),                           //
        ("--1", int(1)),                               //
        ("~0", int(-1)),                               //
        ("!0", Value::Bool(true)),                     //
        ("!false && false", Value::Bool(false)),       // !(false && false) = true
        ("4 | 1 & 2", int(4)),                         // (4 | 1) & 2 = 0
        ("6 ^ 3 & 5", int(7)),                         // (6 ^ 3) & 5 = 5
        ("6 ^ 3 | 8", int(13)),                        // same level, left to right
        ("1 + 2 & 6", int(2)),                         // 1 + (2 & 6) = 3
        ("1 | 2 == 3", Value::Bool(true)),             // 1 | (2 == 3) = 1
        ("1 + 2 .. 'a'", s("3a")),                     // 1 + (2 .. 'a') is an error
        ("2 * 3 .. ''", s("6")),                       //
        ("true || false && false", Value::Bool(true)), // (true || false) && false
        ("false && true || true", Value::Bool(true)),  // false && (true || true)
        ("1 < 2 && 3 < 2", Value::Bool(false)),        //
        ("true ? 1 : 0 + 5", int(1)),                  // (true ? 1 : 0) + 5 = 6
        ("false ? 1 : true ? 2 : 3", int(2)),          // right-associative
        ("true ? false ? 1 : 2 : 3", int(2)),          // nested in the middle
        ("x := 1 + 2", int(3)),                        // (x := 1) + 2 = 3 too, see below
        ("x := 1 + 2; x", int(3)),                     // (x := 1) + 2 would store 1
        ("a := b := 4; a * 10 + b", int(44)),          // right-associative
        ("c := 1 < 2 ? 5 : 6; c", int(5)),             //
        ("(1 + 2) * (3 + 4)", int(21)),                //
    ];
    for (src, want) in cases {
        assert_eq!(&value(src), want, "{src}");
    }
}

#[test]
fn arithmetic_types() {
    assert_eq!(value("7 / 2"), real(3.5));
    assert_eq!(value("6 / 3"), real(2.0));
    assert_eq!(value("1 + 2.5"), real(3.5));
    assert_eq!(value("2 * 2"), int(4));
    assert_eq!(value("true + 1"), int(2));
    assert_eq!(value("1 / 0"), real(f64::INFINITY));
    assert_eq!(value("-1.5"), real(-1.5));
    assert_eq!(value("1e3"), real(1000.0));
    assert_eq!(value("2.5e-1 * 4"), real(1.0));
    assert_eq!(value("5 & 3 | 8 ^ 1"), int(8));
    assert_eq!(value("true & 3"), int(1));
    assert_eq!(value("!2.5"), Value::Bool(false));
    assert_eq!(value("0.5 && 1"), Value::Bool(true));
}

#[test]
fn literals() {
    assert_eq!(value("0x10 + 0XfF"), int(271));
    assert_eq!(value("0x7FFFFFFFFFFFFFFF"), int(i64::MAX));
    assert_eq!(value("-9223372036854775808"), int(i64::MIN));
    assert_eq!(value("007"), int(7));
    assert_eq!(value("'it is'"), s("it is"));
    assert_eq!(value("\"double\""), s("double"));
    assert_eq!(value("''"), s(""));
    assert_eq!(value("true"), Value::Bool(true));
    assert_eq!(value("\n\t1\r\n+\n2\n"), int(3));
}

#[test]
fn program_value_is_the_last_expression() {
    // BehaviorTree.CPP's ParseScript refuses a script without a statement ("Empty Script").
    for blank in ["", "  \n", " ;; ; "] {
        let e = Script::parse(blank).unwrap_err();
        assert_eq!(e.kind, ScriptErrorKind::Empty, "{blank:?}");
    }
    assert_eq!(value("1; 2"), int(2));
    assert_eq!(value("1; 2;;"), int(2));
    assert_eq!(value(";x := 3;; x + 1;"), int(4));
}

#[test]
fn chained_comparisons() {
    assert_eq!(value("1 < 2 < 3"), Value::Bool(true));
    assert_eq!(value("3 > 2 > 1"), Value::Bool(true));
    assert_eq!(value("1 < 3 < 2"), Value::Bool(false));
    // (3 < 2) < 1 would be `false < 1`, true.
    assert_eq!(value("3 < 2 < 1"), Value::Bool(false));
    // (2 == 2) == 2 would be `true == 2`, false.
    assert_eq!(value("2 == 2 == 2"), Value::Bool(true));
    assert_eq!(value("1 <= 1 >= 0 != 5"), Value::Bool(true));
    // Each operand is evaluated once...
    assert_eq!(value("n := 0; 1 <= (n += 1) < 3; n"), int(1));
    // ...and every one is, even after a false link.
    assert_eq!(value("n := 0; 3 < 1 < (n := 5); n"), int(5));
}

#[test]
fn comparisons_of_mixed_values() {
    assert_eq!(value("1 == 1.0"), Value::Bool(true));
    assert_eq!(value("0.1 + 0.2 == 0.3"), Value::Bool(true));
    assert_eq!(value("0.1 + 0.2 != 0.3"), Value::Bool(false));
    assert_eq!(value("0.5 == 0.6"), Value::Bool(false));
    assert_eq!(value("1 / 0 == 1 / 0"), Value::Bool(true));
    assert_eq!(
        value("9007199254740993 == 9007199254740992"),
        Value::Bool(false)
    );
    assert_eq!(value("true == 1"), Value::Bool(true));
    assert_eq!(value("'3' == 3"), Value::Bool(true));
    assert_eq!(value("2.5 < ' 3 '"), Value::Bool(true));
    assert_eq!(value("'true' == true"), Value::Bool(true));
    assert_eq!(value("'abc' < 'abd'"), Value::Bool(true));
    assert_eq!(value("'b' > 'abc'"), Value::Bool(true));
    assert_eq!(value("'a' == 'a'"), Value::Bool(true));
}

#[test]
fn string_concatenation() {
    assert_eq!(value("'a' .. 'b'"), s("ab"));
    assert_eq!(value("'x=' .. 2.5"), s("x=2.5"));
    assert_eq!(value("'x=' .. 3.0"), s("x=3"));
    assert_eq!(value("1 .. 'px'"), s("1px"));
    assert_eq!(value("'v' .. true"), s("vtrue"));
    assert_eq!(value("'a' .. 1 .. 2"), s("a12"));
    assert_eq!(value("'a' + 'b'"), s("ab"));
    let mut bb = Blackboard::new();
    bb.set("name", String::from("bot")).unwrap();
    assert_eq!(
        run("greeting := 'hi ' .. name; greeting .. '!'", &mut bb),
        Ok(s("hi bot!"))
    );
    assert_eq!(bb.get::<String>("greeting"), Ok("hi bot".into()));
    assert_eq!(run("name += '7'; name", &mut bb), Ok(s("bot7")));
}

#[test]
fn create_versus_assign_existing() {
    let mut bb = Blackboard::new();
    let err = run("x = 1", &mut bb).unwrap_err();
    assert_eq!(err.kind, ScriptErrorKind::UnknownKey { key: "x".into() });
    assert!(!bb.contains("x"));
    assert_eq!(run("x := 1", &mut bb), Ok(int(1)));
    assert_eq!(bb.get::<i64>("x"), Ok(1));
    assert_eq!(run("x = 2; x", &mut bb), Ok(int(2)));
    // `:=` on an existing entry assigns it, with its type.
    assert_eq!(run("x := 2.0; x", &mut bb), Ok(int(2)));
    assert_eq!(bb.get::<i64>("x"), Ok(2));
    assert_eq!(bb.info("x").unwrap().sequence, 3);
    assert_eq!(bb.info("x").unwrap().stamp, Duration::from_millis(7));
    // New entries get the value's natural type.
    run("r := 1.5; b := true; t := 'x'", &mut bb).unwrap();
    assert_eq!(bb.get::<f64>("r"), Ok(1.5));
    assert_eq!(bb.get::<bool>("b"), Ok(true));
    assert_eq!(bb.get::<String>("t"), Ok("x".into()));
}

#[test]
fn compound_assignments() {
    let mut bb = Blackboard::new();
    assert_eq!(run("x := 10; x += 5", &mut bb), Ok(int(15)));
    assert_eq!(run("x -= 3; x *= 2; x", &mut bb), Ok(int(24)));
    assert_eq!(run("x /= 4", &mut bb), Ok(int(6)));
    assert_eq!(bb.get::<i64>("x"), Ok(6));
    // 6 / 4 = 1.5 does not fit the i64 entry.
    let err = run("x /= 4", &mut bb).unwrap_err();
    assert!(
        matches!(err.kind, ScriptErrorKind::OutOfRange { ref key, entry: "i64", ref value } if key == "x" && value == "1.5")
    );
    assert_eq!(bb.get::<i64>("x"), Ok(6));
    assert_eq!(run("y := 1.0; y += 2; y", &mut bb), Ok(real(3.0)));
    assert_eq!(run("y *= 0.5", &mut bb), Ok(real(1.5)));
    // The value is evaluated before the entry is read.
    assert_eq!(run("z := 1; z += (z := 5)", &mut bb), Ok(int(10)));
    let err = run("w += 1", &mut bb).unwrap_err();
    assert_eq!(err.kind, ScriptErrorKind::UnknownKey { key: "w".into() });
}

#[test]
fn conditional_evaluates_one_branch() {
    assert_eq!(value("1 > 2 ? 'a' : 'b'"), s("b"));
    assert_eq!(
        value("t := 0; f := 0; true ? t := 1 : f := 1; t * 10 + f"),
        int(10)
    );
    assert_eq!(
        value("t := 0; f := 0; 0.0 ? t := 1 : f := 1; t * 10 + f"),
        int(1)
    );
    assert_eq!(value("'' ? 1 : 2"), int(2));
    assert_eq!(value("'x' ? 1 : 2"), int(1));
}

#[test]
fn logical_operators_do_not_short_circuit() {
    assert_eq!(value("x := 0; false && (x := 1) == 1; x"), int(1));
    assert_eq!(value("y := 0; true || (y := 1) == 1; y"), int(1));
    assert_eq!(value("n := 0; (n += 1) > 5 && (n += 10) > 5; n"), int(11));
}

#[test]
fn root_keys_from_a_child_scope() {
    let mut bb = Blackboard::new();
    bb.set("x", 1_i64).unwrap();
    let child = bb.add_scope(ScopeId::ROOT, false);
    bb.set_in(child, "x", 100_i64, Duration::ZERO).unwrap();
    let enums = Enums::new();
    let mut env = ScriptEnv {
        blackboard: &mut bb,
        scope: child,
        enums: &enums,
        stamp: Duration::ZERO,
        max_string_len: super::DEFAULT_MAX_STRING_LEN,
    };
    let script = Script::parse("@x + x").unwrap();
    assert_eq!(script.eval(&mut env), Ok(int(101)));
    Script::parse("@y := 5; @x += 1; y := 9")
        .unwrap()
        .eval(&mut env)
        .unwrap();
    assert_eq!(bb.get::<i64>("y"), Ok(5));
    assert_eq!(bb.get::<i64>("x"), Ok(2));
    assert_eq!(bb.get_in::<i64>(child, "y"), Ok(9));
    assert_eq!(bb.get_in::<i64>(child, "x"), Ok(100));
}

#[test]
fn enums_resolve_before_the_blackboard() {
    let enums: Enums = [("RED", 1), ("GREEN", 2)].into_iter().collect();
    let mut bb = Blackboard::new();
    bb.set("RED", 50_i64).unwrap();
    assert_eq!(run_with("RED", &mut bb, &enums), Ok(int(1)));
    assert_eq!(
        run_with("c := GREEN; c == GREEN", &mut bb, &enums),
        Ok(Value::Bool(true))
    );
    assert_eq!(bb.get::<i64>("c"), Ok(2));
    assert_eq!(
        run_with("'GREEN' == 2", &mut bb, &enums),
        Ok(Value::Bool(true))
    );
    let err = run_with("RED := 3", &mut bb, &enums).unwrap_err();
    assert_eq!(err.kind, ScriptErrorKind::AssignToEnum("RED".into()));
    assert_eq!(bb.get::<i64>("RED"), Ok(50));
    assert_eq!(enums.get("GREEN"), Some(2));
    assert_eq!(enums.len(), 2);
    assert_eq!(enums.iter().collect::<Vec<_>>(), [("GREEN", 2), ("RED", 1)]);
}

#[test]
fn entry_type_is_fixed_by_the_first_write() {
    let mut bb = Blackboard::new();
    bb.set("n", 5_i64).unwrap();
    let err = run("n = 'five'", &mut bb).unwrap_err();
    assert_eq!(
        err.kind,
        ScriptErrorKind::WrongEntryType {
            key: "n".into(),
            entry: "i64",
            value: "string"
        }
    );
    assert_eq!(bb.get::<i64>("n"), Ok(5));
    assert_eq!(bb.info("n").unwrap().sequence, 1);
    // A script's first write fixes the type as well.
    let err = run("m := 'a'; m = 1", &mut bb).unwrap_err();
    assert!(matches!(
        err.kind,
        ScriptErrorKind::WrongEntryType {
            entry: "String",
            value: "int",
            ..
        }
    ));
}

#[test]
fn writes_convert_to_the_entry_type() {
    let mut bb = Blackboard::new();
    bb.set("i", 0_i32).unwrap();
    bb.set("u", 0_u8).unwrap();
    bb.set("f", 0.0_f32).unwrap();
    bb.set("d", 0.0_f64).unwrap();
    bb.set("b", false).unwrap();
    bb.set("big", 0_u64).unwrap();
    assert_eq!(run("i = 70000; i", &mut bb), Ok(int(70000)));
    assert_eq!(bb.get::<i32>("i"), Ok(70000));
    assert_eq!(run("i = 4.0", &mut bb), Ok(int(4)));
    assert!(matches!(
        run("i = 2.5", &mut bb).unwrap_err().kind,
        ScriptErrorKind::OutOfRange { .. }
    ));
    assert!(matches!(
        run("i = 3000000000", &mut bb).unwrap_err().kind,
        ScriptErrorKind::OutOfRange { .. }
    ));
    assert_eq!(bb.get::<i32>("i"), Ok(4));
    assert_eq!(
        run("u = 255; u += true", &mut bb).unwrap_err().kind,
        ScriptErrorKind::OutOfRange {
            key: "u".into(),
            entry: "u8",
            value: "256".into()
        }
    );
    assert!(matches!(
        run("u = -1", &mut bb).unwrap_err().kind,
        ScriptErrorKind::OutOfRange { .. }
    ));
    assert_eq!(bb.get::<u8>("u"), Ok(255));
    assert_eq!(run("f = 1; f += 0.25", &mut bb), Ok(real(1.25)));
    assert_eq!(bb.get::<f32>("f"), Ok(1.25));
    assert_eq!(run("d = 3", &mut bb), Ok(real(3.0)));
    assert_eq!(bb.get::<f64>("d"), Ok(3.0));
    assert_eq!(run("b = 1", &mut bb), Ok(Value::Bool(true)));
    assert_eq!(run("b = 0.0", &mut bb), Ok(Value::Bool(false)));
    assert!(matches!(
        run("b = 2", &mut bb).unwrap_err().kind,
        ScriptErrorKind::OutOfRange { .. }
    ));
    assert!(matches!(
        run("b = 'x'", &mut bb).unwrap_err().kind,
        ScriptErrorKind::WrongEntryType { entry: "bool", .. }
    ));
    // Past i64::MAX: stored in the u64 entry, read back as a real.
    assert_eq!(
        run("big = 9223372036854775807 * 1.0", &mut bb),
        Ok(real(9223372036854775808.0))
    );
    assert!(matches!(
        run("big = 2.0 * 9223372036854775807", &mut bb)
            .unwrap_err()
            .kind,
        ScriptErrorKind::OutOfRange { .. }
    ));
    assert_eq!(bb.get::<u64>("big"), Ok(1 << 63));
    bb.set("list", vec![1_i32]).unwrap();
    let err = run("list", &mut bb).unwrap_err();
    assert!(
        matches!(err.kind, ScriptErrorKind::UnsupportedEntryType { type_name, .. } if type_name.contains("Vec"))
    );
    assert!(matches!(
        run("list = 1", &mut bb).unwrap_err().kind,
        ScriptErrorKind::UnsupportedEntryType { .. }
    ));
}

#[test]
fn value_helpers() {
    assert_eq!(Value::from_any(&5_u16), Some(int(5)));
    assert_eq!(Value::from_any(&u64::MAX), None);
    assert_eq!(Value::from_any(&1.5_f32), Some(real(1.5)));
    assert_eq!(Value::from_any(&String::from("a")), Some(s("a")));
    assert_eq!(Value::from_any(&"a"), None);
    assert_eq!(Value::from_any(&()), None);
    let mut bb = Blackboard::new();
    assert_eq!(
        Value::from(2_i64).store(&mut bb, ScopeId::ROOT, "k", Duration::ZERO),
        Ok(int(2))
    );
    assert_eq!(
        Value::from(true).store(&mut bb, ScopeId::ROOT, "k", Duration::ZERO),
        Ok(int(1))
    );
    assert!(Value::Empty
        .store(&mut bb, ScopeId::ROOT, "k", Duration::ZERO)
        .is_err());
    assert_eq!(bb.get::<i64>("k"), Ok(1));
    assert_eq!(Value::from("x").to_string(), "x");
    assert_eq!(Value::from(2.0).to_string(), "2");
    assert_eq!(Value::Empty.type_name(), "empty");
}

#[test]
fn scripts_are_shareable_and_keep_their_source() {
    fn shareable<T: Send + Sync + Clone + 'static>() {}
    shareable::<Script>();
    let script = Script::parse("x := 1").unwrap();
    let copy = script.clone();
    assert_eq!(copy.source(), "x := 1");
    assert_eq!(format!("{copy:?}"), "Script(\"x := 1\")");
}

#[test]
fn an_entry_a_script_created_takes_another_scalar_type_as_in_bt_cpp() {
    let mut bb = Blackboard::new();
    // BehaviorTree.CPP holds `true` as the real 1.0: the number 3 replaces it, as a real.
    assert_eq!(run("a := true; a := 3; a", &mut bb), Ok(real(3.0)));
    assert_eq!(bb.get::<f64>("a"), Ok(3.0));
    assert_eq!(bb.info("a").unwrap().sequence, 2);
    assert_eq!(run("a = false; a", &mut bb), Ok(real(0.0)));
    // An integer entry takes a boolean (0 or 1) and a whole real; not 2.5.
    assert_eq!(run("n := 5; n = true; n", &mut bb), Ok(int(1)));
    assert_eq!(run("n = 4.0; n", &mut bb), Ok(int(4)));
    assert!(matches!(
        run("n = 2.5", &mut bb).unwrap_err().kind,
        ScriptErrorKind::OutOfRange { .. }
    ));
    assert_eq!(bb.get::<i64>("n"), Ok(4));
    // Text that reads as a number becomes that real (BT.CPP's StringToDouble); other text
    // is refused.
    assert_eq!(run("n = '7.5'; n", &mut bb), Ok(real(7.5)));
    assert_eq!(bb.get::<f64>("n"), Ok(7.5));
    assert!(matches!(
        run("n = 'seven'", &mut bb).unwrap_err().kind,
        ScriptErrorKind::WrongEntryType { .. }
    ));
    // A text entry takes text only.
    assert!(matches!(
        run("t := 'x'; t = 1", &mut bb).unwrap_err().kind,
        ScriptErrorKind::WrongEntryType {
            entry: "String",
            ..
        }
    ));
    // Typed entries keep refusing: written from Rust, or declared by a port.
    bb.set("flag", true).unwrap();
    assert!(matches!(
        run("flag = 3", &mut bb).unwrap_err().kind,
        ScriptErrorKind::OutOfRange { .. }
    ));
    bb.declare_in(ScopeId::ROOT, "port");
    assert!(matches!(
        run("port := true; port = 3", &mut bb).unwrap_err().kind,
        ScriptErrorKind::OutOfRange { .. }
    ));
    assert_eq!(bb.get::<bool>("port"), Ok(true));
}
