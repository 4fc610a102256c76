//! Errors: their kinds and positions, and the absence of panics on any input.

use proptest::prelude::*;

use super::tests::{run, value};
use super::*;

fn parse_err(src: &str) -> ScriptError {
    match Script::parse(src) {
        Ok(s) => panic!("{src:?} parsed: {s:?}"),
        Err(e) => e,
    }
}

fn expected(what: &'static str, found: &str) -> ScriptErrorKind {
    ScriptErrorKind::Expected {
        expected: what,
        found: found.into(),
    }
}

/// `(kind, offset, line, column)` of an error, for compact assertions.
fn at(e: &ScriptError) -> (usize, u32, u32) {
    (e.offset, e.line, e.column)
}

#[test]
fn parse_error_positions() {
    let e = parse_err("a := (1 + 2");
    assert_eq!(e.kind, expected("`)`", "end of script"));
    assert_eq!(at(&e), (11, 1, 12));
    assert_eq!(e.to_string(), "1:12: expected `)`, found end of script");

    let e = parse_err("x := 1;\n  y := 'abc");
    assert_eq!(e.kind, ScriptErrorKind::UnterminatedString('\''));
    assert_eq!(at(&e), (15, 2, 8));

    let e = parse_err("1 + 2 := 3");
    assert_eq!(e.kind, ScriptErrorKind::InvalidAssignTarget { op: ":=" });
    assert_eq!(at(&e), (0, 1, 1));
    let e = parse_err("x := (a == b) = 3");
    assert_eq!(e.kind, ScriptErrorKind::InvalidAssignTarget { op: "=" });
    assert_eq!(at(&e), (5, 1, 6));
    assert_eq!(value("(x) := 2"), Value::Int(2));

    let e = parse_err("1 +");
    assert_eq!(
        (e.kind, e.offset),
        (expected("an expression", "end of script"), 3)
    );
    let e = parse_err("x := 1 2");
    assert_eq!(
        (e.kind, e.offset),
        (expected("`;` or the end of the script", "`2`"), 7)
    );
    let e = parse_err("(1))");
    assert_eq!(
        (e.kind, e.offset),
        (expected("`;` or the end of the script", "`)`"), 3)
    );
    let e = parse_err("true ? 1 ; 2");
    assert_eq!(
        (e.kind, e.offset),
        (expected("`:` of the conditional `c ? a : b`", "`;`"), 9)
    );
    let e = parse_err("a == * 2");
    assert_eq!((e.kind, e.offset), (expected("an expression", "`*`"), 5));
    let e = parse_err("a := 'x' 'y'");
    assert_eq!(
        (e.kind, e.offset),
        (
            expected("`;` or the end of the script", "the string 'y'"),
            9
        )
    );
    let e = parse_err("x := 1 # 2");
    assert_eq!(
        (e.kind, e.offset),
        (ScriptErrorKind::UnexpectedChar('#'), 7)
    );
    let e = parse_err("x := 12abc");
    assert_eq!(
        (e.kind, e.offset),
        (
            ScriptErrorKind::BadNumber {
                text: "12abc".into(),
                reason: "letters may not follow a number"
            },
            5
        )
    );
    let e = parse_err("1.5.2");
    assert_eq!(
        (e.kind, e.offset),
        (ScriptErrorKind::UnexpectedChar('.'), 3)
    );
    let e = parse_err("x := 9223372036854775808");
    assert!(matches!(e.kind, ScriptErrorKind::BadNumber { .. }));
    assert_eq!(e.offset, 5);
}

#[test]
fn columns_count_characters() {
    let e = parse_err("s := 'é' +");
    assert_eq!(at(&e), (11, 1, 11));
    let e = parse_err("a;\r\nb := (");
    assert_eq!(at(&e), (10, 2, 7));
}

#[test]
fn render_shows_the_line_and_a_caret() {
    let src = "x := 1;\ny := (x + 2";
    let e = parse_err(src);
    assert_eq!(
        e.render(src),
        "2:12: expected `)`, found end of script\n  |\n2 | y := (x + 2\n  |            ^"
    );
    let src = "a := 1;\n\tb = 'x' + a;\nc := 3";
    let e = run(src, &mut Blackboard::new()).unwrap_err();
    assert_eq!(
        e.render(src),
        "2:2: no blackboard entry `b`: write it first, or create it with `b := value`\n  |\n2 | \tb = 'x' + a;\n  | \t^"
    );
    // Any text renders without panicking.
    let _ = e.render("");
    let _ = e.render("é");
}

#[test]
fn strings_stop_growing_at_the_limit() {
    // Forty doublings would make a string of 2^41 bytes.
    let src = format!("s := 'ab'; {}", "s = s .. s; ".repeat(40));
    let mut bb = Blackboard::new();
    let e = run(&src, &mut bb).unwrap_err();
    assert_eq!(
        e.kind,
        ScriptErrorKind::StringTooLong {
            len: 2 << 20,
            max: DEFAULT_MAX_STRING_LEN
        }
    );
    // The 19th doubling made 1 MiB, the most that fits; the error points at the 20th `..`.
    assert_eq!(bb.get::<String>("s").unwrap().len(), 1 << 20);
    assert_eq!(e.offset, src.match_indices("..").nth(19).unwrap().0);
    // A smaller limit, for `+` of two strings too.
    let enums = Enums::new();
    let mut env = ScriptEnv::new(&mut bb);
    env.enums = &enums;
    env.max_string_len = 8;
    let e = Script::parse("t := 'abcd' + 'efghi'")
        .unwrap()
        .eval(&mut env)
        .unwrap_err();
    assert_eq!(e.kind, ScriptErrorKind::StringTooLong { len: 9, max: 8 });
    assert_eq!(at(&e), (12, 1, 13));
    let e = Script::parse("t := 'abcdefg' .. 12")
        .unwrap()
        .eval(&mut env)
        .unwrap_err();
    assert_eq!(e.kind, ScriptErrorKind::StringTooLong { len: 9, max: 8 });
    assert_eq!(
        Script::parse("t := 'abcd' .. 'efgh'")
            .unwrap()
            .eval(&mut env),
        Ok(Value::Str("abcdefgh".into()))
    );
}

#[test]
fn a_long_script_is_quoted_in_part() {
    let src = format!(
        "{}nope + 1; {}",
        "a := 1; ".repeat(50),
        "b := 2; ".repeat(50)
    );
    let e = run(&src, &mut Blackboard::new()).unwrap_err();
    let quoted = e.excerpt(&src);
    assert_eq!(quoted.chars().count(), EXCERPT_CHARS + 2, "{quoted}");
    assert!(quoted.starts_with('…') && quoted.ends_with('…'), "{quoted}");
    assert!(quoted.contains("nope + 1"), "{quoted}");
    // The rendered line is cut the same way, the caret still under `nope`.
    let rendered = e.render(&src);
    let lines: Vec<&str> = rendered.lines().collect();
    let text = lines[2].strip_prefix("1 | ").unwrap();
    let caret = lines[3].strip_prefix("  | ").unwrap();
    assert_eq!(text, quoted);
    let column = caret.chars().count() - 1;
    assert_eq!(
        text.chars().skip(column).take(4).collect::<String>(),
        "nope"
    );
    // A short script is quoted whole.
    assert_eq!(e.excerpt("x := 1"), "x := 1");
}

#[test]
fn runtime_error_positions_and_messages() {
    let mut bb = Blackboard::new();
    let e = run("x := 1;\ny = 2", &mut bb).unwrap_err();
    assert_eq!(e.kind, ScriptErrorKind::UnknownKey { key: "y".into() });
    assert_eq!(at(&e), (8, 2, 1));
    // Earlier statements keep their effect.
    assert_eq!(bb.get::<i64>("x"), Ok(1));

    let e = run("1 + foo", &mut bb).unwrap_err();
    assert_eq!(
        (e.kind, e.offset),
        (ScriptErrorKind::UnknownKey { key: "foo".into() }, 4)
    );

    let e = run("1 + 'a'", &mut bb).unwrap_err();
    assert_eq!(e.offset, 2);
    assert_eq!(
        e.to_string(),
        "1:3: cannot apply `+` to int and string: use `..` to join a string and a number"
    );
    let e = run("x := 2; x -= 'a'", &mut bb).unwrap_err();
    assert_eq!(e.offset, 10);
    assert_eq!(e.to_string(), "1:11: cannot apply `-` to int and string");
    let e = run("1 .. 2", &mut bb).unwrap_err();
    assert!(matches!(
        e.kind,
        ScriptErrorKind::BinaryType {
            op: "..",
            left: "int",
            right: "int",
            ..
        }
    ));
    let e = run("1.0 & 1", &mut bb).unwrap_err();
    assert_eq!(
        e.to_string(),
        "1:5: cannot apply `&` to real and int: bitwise operators need integers"
    );
    let e = run("~1.5", &mut bb).unwrap_err();
    assert_eq!(
        (e.kind, e.offset),
        (
            ScriptErrorKind::UnaryType {
                op: "~",
                operand: "real"
            },
            0
        )
    );
    let e = run("!'a'", &mut bb).unwrap_err();
    assert!(matches!(
        e.kind,
        ScriptErrorKind::UnaryType {
            op: "!",
            operand: "string"
        }
    ));
    let e = run("-'a'", &mut bb).unwrap_err();
    assert!(matches!(
        e.kind,
        ScriptErrorKind::UnaryType {
            op: "-",
            operand: "string"
        }
    ));
    let e = run("'a' && true", &mut bb).unwrap_err();
    assert!(matches!(
        e.kind,
        ScriptErrorKind::BinaryType { op: "&&", .. }
    ));
    let e = run("1 < 2 < 'abc'", &mut bb).unwrap_err();
    assert_eq!(
        (e.kind, e.offset),
        (ScriptErrorKind::NotANumber { text: "abc".into() }, 6)
    );
    let e = run("9223372036854775807 + 1", &mut bb).unwrap_err();
    assert_eq!((e.kind, e.offset), (ScriptErrorKind::Overflow("+"), 20));
    let e = run("-(-9223372036854775808)", &mut bb).unwrap_err();
    assert_eq!(e.kind, ScriptErrorKind::Overflow("-"));
    let e = run("x := 1; x = 'one'", &mut bb).unwrap_err();
    assert_eq!(
        e.to_string(),
        "1:9: blackboard entry `x` has type `i64` and cannot hold a value of type string: an \
         entry's type is fixed by its first write"
    );
}

#[test]
fn unknown_scope_is_an_error() {
    let mut bb = Blackboard::new();
    let enums = Enums::new();
    let mut env = ScriptEnv {
        blackboard: &mut bb,
        scope: ScopeId(3),
        enums: &enums,
        stamp: Duration::ZERO,
        max_string_len: super::DEFAULT_MAX_STRING_LEN,
    };
    let e = Script::parse("x := 1").unwrap().eval(&mut env).unwrap_err();
    assert_eq!(
        e.kind,
        ScriptErrorKind::Blackboard(BlackboardError::NoSuchScope { scope: 3 })
    );
    assert!(bb.keys().next().is_none());
}

#[test]
fn nesting_is_bounded() {
    let too_deep = ScriptErrorKind::TooDeep(parser::MAX_DEPTH);
    let n = 100_000;
    for src in [
        "(".repeat(n),
        format!("{}1{}", "(".repeat(n), ")".repeat(n)),
        format!("{}1", "-".repeat(n)),
        format!("{}1", "!~".repeat(n)),
        format!("1{}", "+1".repeat(n)),
        format!("{}1", "a:=".repeat(n)),
        format!("{}1", "a ? 1 : ".repeat(n)),
        format!("x{}", " && x".repeat(n)),
    ] {
        assert_eq!(parse_err(&src).kind, too_deep, "{}", &src[..20]);
    }
    // Long flat lists are fine.
    let src = format!("1{}", " < 2".repeat(n));
    assert!(Script::parse(&src).is_ok());
    let src = "x := 1;".repeat(n);
    assert!(Script::parse(&src).is_ok());
    // So is nesting up to the limit, and evaluating it.
    let depth = parser::MAX_DEPTH - 1;
    let src = format!("{}1{}", "(".repeat(depth), ")".repeat(depth));
    assert_eq!(value(&src), Value::Int(1));
    let src = format!("0{}", " + 1".repeat(parser::MAX_DEPTH - 1));
    assert_eq!(value(&src), Value::Int(63));
}

/// A blackboard with one entry of each kind scripts use.
fn small_blackboard() -> Blackboard {
    let mut bb = Blackboard::new();
    bb.set("a", 3_i64).unwrap();
    bb.set("b", 2.5_f64).unwrap();
    bb.set("c", true).unwrap();
    bb.set("d", String::from("x")).unwrap();
    bb.set("e", 7_u8).unwrap();
    bb
}

fn eval_anything(src: &str) {
    match Script::parse(src) {
        Ok(script) => {
            let mut bb = small_blackboard();
            let enums: Enums = [("E", 4)].into_iter().collect();
            let scope = bb.add_scope(ScopeId::ROOT, true);
            let mut env = ScriptEnv {
                blackboard: &mut bb,
                scope,
                enums: &enums,
                stamp: Duration::ZERO,
                max_string_len: super::DEFAULT_MAX_STRING_LEN,
            };
            if let Err(e) = script.eval(&mut env) {
                assert!(e.offset <= src.len());
                let _ = e.render(src);
            }
        }
        Err(e) => {
            assert!(e.offset <= src.len());
            let _ = e.render(src);
        }
    }
}

/// Tokens that scripts are made of, so that random programs often parse.
fn token() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec![
        "a",
        "b",
        "c",
        "d",
        "e",
        "E",
        "@a",
        "z",
        "0",
        "1",
        "-1",
        "0x7f",
        "2.5",
        "1e3",
        "9223372036854775807",
        "'x'",
        "'3'",
        "''",
        "true",
        "false",
        ":=",
        "=",
        "+=",
        "-=",
        "*=",
        "/=",
        "?",
        ":",
        "||",
        "&&",
        "==",
        "!=",
        "<",
        "<=",
        ">",
        ">=",
        "|",
        "^",
        "&",
        "+",
        "-",
        "..",
        "*",
        "/",
        "~",
        "!",
        "(",
        ")",
        ";",
        " ",
    ])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn arbitrary_text_never_panics(src in any::<String>()) {
        eval_anything(&src);
    }

    #[test]
    fn script_like_text_never_panics(src in "[a-e@0-9x .'\"+\\-*/<>=!&|^~?:;()]{0,40}") {
        eval_anything(&src);
    }

    #[test]
    fn token_soup_never_panics(tokens in prop::collection::vec(token(), 0..24)) {
        eval_anything(&tokens.join(" "));
    }
}
