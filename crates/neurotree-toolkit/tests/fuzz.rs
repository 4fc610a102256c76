//! Fuzzing on stable Rust: the XML loader, the script parser and evaluator, and the Groot2
//! request decoder, each fed inputs mutated from real ones (`corpus/` files, the scripts in
//! them, well-formed requests). Each must answer without panicking, and the loader's and
//! the parser's errors must point into the input.
//!
//! `cargo test` runs 2,000 to 6,000 cases per target, in about a second. A long run, on
//! demand:
//!
//! ```sh
//! NEUROTREE_FUZZ_CASES=200000 cargo test --release -p neurotree-toolkit --test integration fuzz::
//! ```
//!
//! with `NEUROTREE_FUZZ_SEED=<n>` for other inputs than the default seed's.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree::groot::protocol::{RequestHeader, RequestType, Transition, ERROR_FRAME};
use neurotree::groot::Groot2Monitor;
use neurotree::script::{Enums, Script, ScriptEnv, ScriptError};
use neurotree::{Blackboard, ManualClock, Registry, ScopeId, Tree, XmlLoader};

use crate::load_all;
use crate::mutate;

use mutate::fuzz;

/// Cases per target in a plain `cargo test`.
const QUICK_CASES: usize = 2000;

fn bytes(texts: impl IntoIterator<Item = impl Into<String>>) -> Vec<Vec<u8>> {
    texts.into_iter().map(|t| t.into().into_bytes()).collect()
}

#[test]
fn loader_answers_mutated_corpus_files_with_trees_or_errors_in_them() {
    let seeds = bytes(load_all::corpus_texts());
    let dictionary: &[&[u8]] = &[
        b"<root BTCPP_format=\"4\">",
        b"</root>",
        b"<BehaviorTree ID=\"T\">",
        b"</BehaviorTree>",
        b"<SubTree ID=\"T\" _autoremap=\"true\"/>",
        b"<Sequence>",
        b"</Sequence>",
        b"<Parallel success_count=\"-1\">",
        b"<Repeat num_cycles=\"-1\">",
        b"<TreeNodesModel>",
        b"<input_port name=\"p\" default=\"{x}\"/>",
        b"<include path=\"other.xml\"/>",
        b"<Script code=\"a := (\"/>",
        b" _skipIf=\"x &&\"",
        b" _while=\"",
        b"{=}",
        b"{@x}",
        b"&amp;",
        b"&#x0;",
        b"<!--",
        b"-->",
        b"<![CDATA[",
        b"]]>",
        b"<?xml version=\"1.0\"?>",
        b"<!DOCTYPE root>",
        b"99999999999999999999",
        b"-1",
    ];
    fuzz("loader", QUICK_CASES, &seeds, dictionary, |input| {
        load_all::load_everything(&String::from_utf8_lossy(input));
    });
}

/// Attributes whose values are scripts.
const SCRIPT_ATTRIBUTES: [&str; 10] = [
    "code",
    "if",
    "_skipIf",
    "_successIf",
    "_failureIf",
    "_while",
    "_onSuccess",
    "_onFailure",
    "_onHalted",
    "_post",
];

/// The scripts of the corpus, and some that use every operator.
fn script_seeds() -> Vec<Vec<u8>> {
    let mut scripts: Vec<String> = [
        "a := 1; b := a + 2.5 * (3 - 1) / 2; c := b > 3 && !c || a == 1",
        "d := 'x' .. 'y'; s := d + 'z'; n := -a; m := ~a & 0x0f | 1 ^ 2",
        "a += 1; a -= 2; b *= 3.0; b /= 2; e = E; x := a != 1 ? 'yes' : 'no'",
        "@a := 5; a <= 4 || a >= 6 || a < 1e3",
    ]
    .map(String::from)
    .into();
    for text in load_all::corpus_texts() {
        let Ok(doc) = roxmltree::Document::parse(&text) else {
            continue;
        };
        for node in doc.descendants().filter(|n| n.is_element()) {
            for attr in node.attributes() {
                if SCRIPT_ATTRIBUTES.contains(&attr.name()) {
                    scripts.push(attr.value().to_string());
                }
            }
        }
    }
    scripts.sort();
    scripts.dedup();
    assert!(scripts.len() >= 20, "only {} scripts found", scripts.len());
    bytes(scripts)
}

/// Panics unless `e` is at a character boundary of `src` and its line and column are
/// those of its offset.
fn assert_points_into(e: &ScriptError, src: &str) {
    assert!(
        e.offset <= src.len(),
        "offset {} of {}: {e}",
        e.offset,
        src.len()
    );
    assert!(
        src.is_char_boundary(e.offset),
        "offset inside a character: {e}"
    );
    let again = ScriptError::new(e.kind.clone(), e.offset, src);
    assert_eq!((e.line, e.column), (again.line, again.column), "{e}");
    let _ = e.render(src);
}

fn parse_and_eval(src: &str) {
    let script = match Script::parse(src) {
        Ok(script) => script,
        Err(e) => return assert_points_into(&e, src),
    };
    let mut bb = Blackboard::new();
    bb.set("a", 3_i64).unwrap();
    bb.set("b", 2.5_f64).unwrap();
    bb.set("c", true).unwrap();
    bb.set("d", String::from("x")).unwrap();
    let enums: Enums = [("E", 4)].into_iter().collect();
    let scope = bb.add_scope(ScopeId::ROOT, true);
    let mut env = ScriptEnv::new(&mut bb);
    env.scope = scope;
    env.enums = &enums;
    // Small, so that doubling a string meets the limit within a few operations.
    env.max_string_len = 4096;
    if let Err(e) = script.eval(&mut env) {
        assert_points_into(&e, src);
    }
}

#[test]
fn scripts_parse_and_run_or_fail_at_a_position_in_them() {
    let seeds = script_seeds();
    let dictionary: &[&[u8]] = &[
        b":=",
        b"=",
        b"+=",
        b"-=",
        b"*=",
        b"/=",
        b"==",
        b"!=",
        b"<=",
        b">=",
        b"&&",
        b"||",
        b"..",
        b"?",
        b":",
        b"(",
        b")",
        b";",
        b"'",
        b"\"",
        b"@",
        b"0x",
        b"1e308",
        b"-",
        b"~",
        b"!",
        b"9223372036854775807",
        b"-9223372036854775808",
        b"a",
        b"E",
        b"true",
        b"false",
        b"' '",
    ];
    fuzz("script", QUICK_CASES * 3, &seeds, dictionary, |input| {
        parse_and_eval(&String::from_utf8_lossy(input));
    });
}

/// Separates the frames of one request in a fuzzed input.
const FRAME_END: u8 = 0x1e;
/// Separates the requests of one fuzzed input.
const REQUEST_END: u8 = 0x1d;

/// Valid requests of every type, each with its plausible payloads.
fn request_seeds() -> Vec<Vec<u8>> {
    let payloads: [&[u8]; 6] = [
        b"",
        b"start",
        b"stop",
        b"T",
        b"T;T/sub::1;x",
        &[0, 0, 0, 0, 0, 0, 1, 0, 2],
    ];
    let mut seeds = Vec::new();
    for (i, kind) in RequestType::ALL.into_iter().enumerate() {
        let header = RequestHeader::new(kind, 7 + i as u32).encode();
        seeds.push(header.to_vec());
        for payload in payloads {
            let mut request = header.to_vec();
            request.push(FRAME_END);
            request.extend_from_slice(payload);
            seeds.push(request);
        }
    }
    // A session as Groot2 opens one: the tree, recording, statuses, transitions.
    let mut session = Vec::new();
    for request in [&seeds[0], &seeds[7 * 10 + 2], &seeds[7], &seeds[7 * 11]] {
        session.extend_from_slice(request);
        session.push(REQUEST_END);
    }
    seeds.push(session);
    seeds
}

/// A tree with a SubTree, a blackboard and a node that keeps running, ticked by the
/// monitor's side of the fuzz target.
const MONITORED: &str = r#"
<root BTCPP_format="4" main_tree_to_execute="T">
  <BehaviorTree ID="T">
    <Sequence>
      <Script code="x := 1; name := 'robot'"/>
      <SubTree ID="Sub" _autoremap="true"/>
      <KeepRunningUntilFailure><AlwaysSuccess/></KeepRunningUntilFailure>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Sub"><Script code="y := x + 1"/></BehaviorTree>
</root>"#;

/// Panics unless `reply` answers `request`: an error reply (`error`, a message), or the
/// request's header echoed with the tree's id, then a payload of its type's shape.
fn assert_answers(reply: &[Vec<u8>], request: &[&[u8]], uuid: [u8; 16]) {
    assert!(!reply.is_empty(), "no reply to {request:?}");
    if reply[0] == ERROR_FRAME {
        assert_eq!(reply.len(), 2, "{reply:?}");
        assert!(!reply[1].is_empty());
        return;
    }
    let header = RequestHeader::parse(request[0]).expect("answered only a readable header");
    assert_eq!(reply[0].len(), 22, "{reply:?}");
    assert_eq!(reply[0][0], 2);
    assert_eq!(reply[0][1..6], header.encode()[1..6]);
    assert_eq!(reply[0][6..], uuid);
    let payload = reply.get(1).map_or(&[][..], Vec::as_slice);
    match RequestType::from_byte(header.kind) {
        Some(RequestType::Status) => assert_eq!(payload.len() % 3, 0),
        Some(RequestType::GetTransitions) => {
            let records = Transition::parse_all(payload).expect("transitions it encoded");
            assert_eq!(records.len() * Transition::SIZE, payload.len());
        }
        _ => {}
    }
}

#[test]
fn groot_requests_are_answered_or_refused_never_a_panic() {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(MONITORED, "monitored.xml").unwrap();
    let blueprint = Arc::new(loader.build_main().unwrap());
    let monitor = Groot2Monitor::new(&blueprint, &registry, "T");
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(blueprint, clock.clone());
    tree.set_observer(monitor.clone());
    let tree = Mutex::new(tree);
    let uuid = monitor.tree_uuid();

    let seeds = request_seeds();
    let dictionary: &[&[u8]] = &[
        &[FRAME_END],
        &[REQUEST_END],
        &[2],
        b"T",
        b"S",
        b"B",
        b"r",
        b"t",
        b"I",
        b"start",
        b"stop",
        b";",
        &[0xff; 4],
    ];
    fuzz("groot", QUICK_CASES * 3, &seeds, dictionary, |input| {
        for request in input.split(|b| *b == REQUEST_END) {
            let frames: Vec<&[u8]> = request.split(|b| *b == FRAME_END).collect();
            // The decoders on their own: a header reads back to its bytes; a transitions
            // payload is whole records or an error.
            if let Ok(header) = RequestHeader::parse(frames[0]) {
                assert_eq!(header.encode(), frames[0]);
            }
            for frame in &frames[1..] {
                if let Ok(records) = Transition::parse_all(frame) {
                    let encoded: Vec<u8> = records.iter().flat_map(|t| t.encode()).collect();
                    assert_eq!(&encoded, frame);
                }
            }
            assert_answers(&monitor.answer(&frames), &frames, uuid);
            // Something happens between requests, for statuses and transitions to report.
            let mut tree = tree.lock().unwrap_or_else(|e| e.into_inner());
            clock.advance(Duration::from_millis(10));
            let _ = tree.tick_once(&mut ());
            monitor.publish_blackboard(&tree);
        }
    });
}
