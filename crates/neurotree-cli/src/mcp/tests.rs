//! The protocol's edge cases, message by message: what each answer is, and that the server
//! goes on after a bad one.

use super::*;

/// The answers to `lines`, one per message that has one.
fn answers(lines: &[&str]) -> Vec<Value> {
    let dir = tempfile::tempdir().unwrap();
    let input = lines.join("\n") + "\n";
    let mut output = Vec::new();
    serve(&mut input.as_bytes(), &mut output, dir.path()).unwrap();
    String::from_utf8(output)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

const PING: &str = r#"{"jsonrpc":"2.0","id":9,"method":"ping"}"#;

#[test]
fn the_handshake_answers_the_clients_revision_or_the_newest() {
    for (asked, answered) in [
        ("2025-11-25", "2025-11-25"),
        ("2025-03-26", "2025-03-26"),
        ("1999-01-01", "2025-11-25"),
    ] {
        let init = format!(
            r#"{{"jsonrpc":"2.0","id":1,"method":"initialize","params":{{"protocolVersion":"{asked}","capabilities":{{}},"clientInfo":{{"name":"t","version":"1"}}}}}}"#
        );
        let got = answers(&[
            &init,
            r#"{"jsonrpc":"2.0","method":"notifications/initialized"}"#,
            PING,
        ]);
        assert_eq!(got.len(), 2, "{got:?}");
        assert_eq!(got[0]["id"], 1);
        assert_eq!(got[0]["result"]["protocolVersion"], answered);
        assert_eq!(got[0]["result"]["serverInfo"]["name"], "neurotree");
        assert!(got[0]["result"]["capabilities"]["tools"].is_object());
        assert_eq!(got[1], json!({"jsonrpc":"2.0","id":9,"result":{}}));
    }
}

#[test]
fn the_current_revision_discovers_and_marks_every_result() {
    let meta = r#""_meta":{"io.modelcontextprotocol/protocolVersion":"2026-07-28","io.modelcontextprotocol/clientCapabilities":{}}"#;
    let got = answers(&[
        &format!(r#"{{"jsonrpc":"2.0","id":"a","method":"server/discover","params":{{{meta}}}}}"#),
        &format!(r#"{{"jsonrpc":"2.0","id":"b","method":"tools/list","params":{{{meta}}}}}"#),
        r#"{"jsonrpc":"2.0","id":"c","method":"tools/list","params":{"_meta":{"io.modelcontextprotocol/protocolVersion":"2099-01-01"}}}"#,
    ]);
    assert_eq!(got[0]["id"], "a");
    let versions = got[0]["result"]["supportedVersions"].as_array().unwrap();
    assert!(versions.contains(&json!("2025-11-25")) && versions.contains(&json!(MODERN)));
    assert_eq!(got[0]["result"]["resultType"], "complete");
    assert_eq!(got[1]["result"]["resultType"], "complete");
    assert_eq!(got[1]["result"]["cacheScope"], "private");
    assert_eq!(got[1]["result"]["tools"].as_array().unwrap().len(), 7);
    assert_eq!(got[2]["error"]["code"], UNSUPPORTED_VERSION);
    assert_eq!(got[2]["error"]["data"]["requested"], "2099-01-01");
}

#[test]
fn malformed_messages_get_errors_and_the_server_goes_on() {
    let got = answers(&[
        "{not json",
        "[1, 2]",
        r#"{"jsonrpc":"1.0","id":1,"method":"ping"}"#,
        r#"{"jsonrpc":"2.0","id":{"x":1},"method":"ping"}"#,
        r#"{"jsonrpc":"2.0","id":2,"method":"no/such"}"#,
        r#"{"jsonrpc":"2.0","id":3,"method":"tools/call","params":[1]}"#,
        r#"{"jsonrpc":"2.0","id":4,"method":"tools/call","params":{"name":"nope"}}"#,
        r#"{"jsonrpc":"2.0","id":5,"method":"tools/call","params":{"name":"check_tree","arguments":"x"}}"#,
        "{}",
        r#"{"jsonrpc":"2.0","id":6,"result":{}}"#,
        "",
        PING,
    ]);
    let codes: Vec<(Value, Value)> = got
        .iter()
        .map(|a| (a["id"].clone(), a["error"]["code"].clone()))
        .collect();
    assert_eq!(
        codes,
        [
            (Value::Null, json!(PARSE_ERROR)),
            (Value::Null, json!(INVALID_REQUEST)),
            (json!(1), json!(INVALID_REQUEST)),
            (Value::Null, json!(INVALID_REQUEST)),
            (json!(2), json!(METHOD_NOT_FOUND)),
            (json!(3), json!(INVALID_PARAMS)),
            (json!(4), json!(INVALID_PARAMS)),
            (json!(5), json!(INVALID_PARAMS)),
            (Value::Null, json!(INVALID_REQUEST)),
            (json!(9), Value::Null),
        ]
    );
}

#[test]
fn a_message_too_long_is_refused_without_being_kept() {
    let long = format!(
        r#"{{"jsonrpc":"2.0","id":1,"method":"ping","params":{{"x":"{}"}}}}"#,
        "a".repeat(MAX_MESSAGE_BYTES)
    );
    let got = answers(&[&long, PING]);
    assert_eq!(got[0]["error"]["code"], INVALID_REQUEST);
    assert!(got[0]["error"]["message"]
        .as_str()
        .unwrap()
        .contains("longer than"));
    assert_eq!(got[1]["id"], 9);
}

fn call(name: &str, arguments: Value) -> Value {
    let request = json!({"jsonrpc":"2.0","id":7,"method":"tools/call","params":{"name":name,"arguments":arguments}});
    answers(&[&request.to_string()]).remove(0)["result"].clone()
}

#[test]
fn a_tool_s_failure_is_its_answer() {
    let result = call("check_tree", json!({}));
    assert_eq!(result["isError"], true);
    assert_eq!(
        result["content"][0]["text"],
        "give the tree's XML text in `xml`"
    );
    let big = "x".repeat(tools::MAX_XML_BYTES + 1);
    let result = call("lint_tree", json!({ "xml": big }));
    assert_eq!(result["isError"], true);
    let result = call(
        "run_tree",
        json!({ "xml": "<root/>", "max_ticks": 1_000_000 }),
    );
    assert_eq!(result["isError"], true);
    assert!(result["content"][0]["text"]
        .as_str()
        .unwrap()
        .contains("from 1 to 10000"));
}

#[test]
fn lint_tree_finds_what_neurotree_lint_finds() {
    let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="M">
        <Fallback><AlwaysSuccess/><AlwaysFailure/></Fallback></BehaviorTree></root>"#;
    let result = call("lint_tree", json!({ "xml": xml }));
    assert_eq!(result["isError"], false);
    let found = &result["structuredContent"]["diagnostics"];
    assert_eq!(found[0]["code"], "NT0201");
    assert_eq!(found[0]["line"], 2);
    assert!(result["content"][0]["text"]
        .as_str()
        .unwrap()
        .contains("warning[NT0201]"));
}

#[test]
fn an_include_cannot_leave_the_call() {
    let xml = r#"<root BTCPP_format="4"><include path="../../../etc/passwd"/>
        <BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>"#;
    for tool in ["check_tree", "run_tree"] {
        let result = call(tool, json!({ "xml": xml }));
        let text = result["content"][0]["text"].as_str().unwrap().to_string();
        assert!(text.contains("include"), "{tool}: {text}");
        assert!(!text.contains("root:"), "{tool}: {text}");
    }
}
