//! `neurotree mcp`: a Model Context Protocol server on standard input and output, so that
//! an assistant can write, check, lint, draw and try trees.
//!
//! One JSON-RPC 2.0 message per line each way. Both ways of starting a connection are
//! served: the `initialize` handshake of protocol revisions 2024-11-05 to 2025-11-25
//! (most clients still use it), and the current revision, [`MODERN`], where a client may
//! ask `server/discover` and names the revision in every request's `_meta`. The tools are
//! in [`tools`]; each runs the code of the command it is named after.
//!
//! Everything is bounded: a message longer than [`MAX_MESSAGE_BYTES`] is refused (and
//! skipped, never held whole), as is a tree longer than [`tools::MAX_XML_BYTES`]; runs are
//! capped in ticks, and every call in wall time ([`CALL_TIME_LIMIT`]). Files are written
//! only in a scratch folder made inside the folder the server was started in, and read
//! only there. A malformed message is answered with a JSON-RPC error, and the server goes
//! on serving.

use std::io::{self, BufRead, Write};
use std::path::PathBuf;
use std::sync::mpsc;
use std::thread;
use std::time::Duration;

use serde_json::{json, Value};

use crate::Outcome;

mod scratch;
mod tools;

/// The revisions whose connections start with `initialize`, oldest first.
pub const HANDSHAKE: [&str; 4] = ["2024-11-05", "2025-03-26", "2025-06-18", "2025-11-25"];
/// The current revision: no handshake, the revision named in each request's `_meta`.
pub const MODERN: &str = "2026-07-28";
/// The longest message read, in bytes: a tree of [`tools::MAX_XML_BYTES`] and its escapes.
pub const MAX_MESSAGE_BYTES: usize = 4 << 20;
/// The longest a tool call may take before it is answered with an error.
pub const CALL_TIME_LIMIT: Duration = Duration::from_secs(20);

/// JSON-RPC's error codes.
const PARSE_ERROR: i64 = -32700;
const INVALID_REQUEST: i64 = -32600;
const METHOD_NOT_FOUND: i64 = -32601;
const INVALID_PARAMS: i64 = -32602;
const INTERNAL_ERROR: i64 = -32603;
/// MCP's: the revision a request names is not served.
const UNSUPPORTED_VERSION: i64 = -32022;

/// `_meta` keys of the current revision.
const VERSION_KEY: &str = "io.modelcontextprotocol/protocolVersion";

/// What `neurotree mcp` was asked to do.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Configure an assistant to start `neurotree mcp` in the folder of \
its trees; see docs/guide/mcp.md."
)]
pub struct McpArgs {}

/// Serves requests from standard input until it closes.
pub fn execute(_args: &McpArgs, err: &mut impl Write) -> io::Result<Outcome> {
    let scratch = match scratch::Scratch::in_current_dir() {
        Ok(scratch) => scratch,
        Err(e) => {
            writeln!(err, "neurotree mcp: cannot make a scratch folder here: {e}")?;
            return Ok(Outcome::Refused);
        }
    };
    let stdin = io::stdin();
    let stdout = io::stdout();
    serve(&mut stdin.lock(), &mut stdout.lock(), scratch.dir())?;
    Ok(Outcome::Done)
}

/// Answers each message of `input` on `output`, one line each, until `input` ends.
pub fn serve(
    input: &mut impl BufRead,
    output: &mut impl Write,
    scratch: &std::path::Path,
) -> io::Result<()> {
    let mut server = Server {
        scratch: scratch.to_path_buf(),
        calls: 0,
    };
    let mut line = Vec::new();
    loop {
        match read_message(input, &mut line)? {
            Read::End => return Ok(()),
            Read::TooLong => {
                let message = format!("the message is longer than {MAX_MESSAGE_BYTES} bytes");
                send(output, &error(Value::Null, INVALID_REQUEST, &message))?;
            }
            Read::Line => {
                if let Some(answer) = server.answer(&line) {
                    send(output, &answer)?;
                }
            }
        }
    }
}

fn send(output: &mut impl Write, message: &Value) -> io::Result<()> {
    writeln!(output, "{message}")?;
    output.flush()
}

/// What reading a message gave.
enum Read {
    Line,
    TooLong,
    End,
}

/// Reads one line into `line`, at most [`MAX_MESSAGE_BYTES`] of it: a longer one is
/// skipped to its end without being kept.
fn read_message(input: &mut impl BufRead, line: &mut Vec<u8>) -> io::Result<Read> {
    line.clear();
    let mut too_long = false;
    loop {
        let buf = input.fill_buf()?;
        if buf.is_empty() {
            return Ok(match (too_long, line.is_empty()) {
                (true, _) => Read::TooLong,
                (false, true) => Read::End,
                (false, false) => Read::Line,
            });
        }
        let (chunk, done) = match buf.iter().position(|&b| b == b'\n') {
            Some(at) => (&buf[..at], Some(at + 1)),
            None => (buf, None),
        };
        if !too_long && line.len() + chunk.len() <= MAX_MESSAGE_BYTES {
            line.extend_from_slice(chunk);
        } else {
            too_long = true;
            line.clear();
        }
        let used = done.unwrap_or(buf.len());
        input.consume(used);
        if done.is_some() {
            if too_long {
                return Ok(Read::TooLong);
            }
            // A blank line between messages is no message.
            if line.iter().all(u8::is_ascii_whitespace) {
                line.clear();
                continue;
            }
            return Ok(Read::Line);
        }
    }
}

/// A JSON-RPC error answer.
fn error(id: Value, code: i64, message: &str) -> Value {
    json!({ "jsonrpc": "2.0", "id": id, "error": { "code": code, "message": message } })
}

/// The server's state: where tools write, and how many calls have been made (each gets
/// its own folder).
struct Server {
    scratch: PathBuf,
    calls: u64,
}

impl Server {
    /// The answer to one message, or `None` for a notification.
    fn answer(&mut self, line: &[u8]) -> Option<Value> {
        let message: Value = match serde_json::from_slice(line) {
            Ok(message) => message,
            Err(e) => return Some(error(Value::Null, PARSE_ERROR, &format!("not JSON: {e}"))),
        };
        let Value::Object(message) = message else {
            // Batches were removed from MCP in 2025-06-18.
            return Some(error(
                Value::Null,
                INVALID_REQUEST,
                "a message must be one JSON object",
            ));
        };
        let id = message.get("id").cloned();
        let method = message.get("method").and_then(Value::as_str);
        let valid_id = matches!(id, Some(Value::String(_) | Value::Number(_)));
        let (Some(method), true) = (method, message.get("jsonrpc") == Some(&json!("2.0"))) else {
            // A response from the client is not answered (the server asks nothing of it).
            let response = message.contains_key("result") || message.contains_key("error");
            let id = if valid_id {
                id.unwrap_or(Value::Null)
            } else {
                Value::Null
            };
            return (!response).then(|| error(id, INVALID_REQUEST, "not a JSON-RPC 2.0 request"));
        };
        let Some(id) = id else {
            // A notification (`notifications/initialized`, `notifications/cancelled`).
            return None;
        };
        if !valid_id {
            return Some(error(
                Value::Null,
                INVALID_REQUEST,
                "the id must be a string or a number",
            ));
        }
        let params = message.get("params").cloned().unwrap_or(json!({}));
        if !params.is_object() {
            return Some(error(id, INVALID_PARAMS, "params must be an object"));
        }
        Some(match self.request(method, &params) {
            Ok(result) => json!({ "jsonrpc": "2.0", "id": id, "result": result }),
            Err(Refusal {
                code,
                message,
                data,
            }) => {
                let mut answer = error(id, code, &message);
                if let Some(data) = data {
                    answer["error"]["data"] = data;
                }
                answer
            }
        })
    }

    fn request(&mut self, method: &str, params: &Value) -> Result<Value, Refusal> {
        let modern = match params.pointer(&format!("/_meta/{}", VERSION_KEY.replace('/', "~1"))) {
            None => false,
            Some(version) if version == MODERN => true,
            Some(version) => {
                return Err(Refusal {
                    code: UNSUPPORTED_VERSION,
                    message: format!("protocol version {version} is not supported"),
                    data: Some(json!({ "supported": [MODERN], "requested": version })),
                })
            }
        };
        let mut result = match method {
            "initialize" => initialize(params),
            "server/discover" => json!({
                "supportedVersions": supported(),
                "capabilities": capabilities(),
                "serverInfo": server_info(),
                "instructions": INSTRUCTIONS,
                "ttlMs": 0,
                "cacheScope": "private",
            }),
            "ping" => json!({}),
            "tools/list" => {
                let mut list = json!({ "tools": tools::list() });
                if modern {
                    list["ttlMs"] = json!(0);
                    list["cacheScope"] = json!("private");
                }
                list
            }
            "tools/call" => self.call(params)?,
            other => {
                return Err(Refusal::new(
                    METHOD_NOT_FOUND,
                    format!("no method `{other}`"),
                ));
            }
        };
        if modern || method == "server/discover" {
            result["resultType"] = json!("complete");
        }
        Ok(result)
    }

    /// Runs a tool on its own thread, so that a call that takes too long is answered.
    fn call(&mut self, params: &Value) -> Result<Value, Refusal> {
        let name = params
            .get("name")
            .and_then(Value::as_str)
            .unwrap_or_default()
            .to_string();
        if !tools::exists(&name) {
            return Err(Refusal::new(
                INVALID_PARAMS,
                format!("no tool `{name}`; tools/list lists them"),
            ));
        }
        let arguments = params.get("arguments").cloned().unwrap_or(json!({}));
        if !arguments.is_object() {
            return Err(Refusal::new(
                INVALID_PARAMS,
                "arguments must be an object".to_string(),
            ));
        }
        self.calls += 1;
        let dir = self.scratch.join(format!("call-{}", self.calls));
        let (send, receive) = mpsc::channel();
        thread::Builder::new()
            .name(format!("mcp-{name}"))
            // The loader and the engine are tested on 2 MiB threads; give them room.
            .stack_size(8 << 20)
            .spawn(move || {
                let outcome = tools::call(&name, &arguments, &dir);
                let _ = std::fs::remove_dir_all(&dir);
                let _ = send.send(outcome);
            })
            .map_err(|e| Refusal::new(INTERNAL_ERROR, format!("cannot start the call: {e}")))?;
        let outcome = match receive.recv_timeout(CALL_TIME_LIMIT) {
            Ok(outcome) => outcome,
            Err(_) => Err(format!(
                "the call took longer than {} s and was abandoned; give fewer ticks",
                CALL_TIME_LIMIT.as_secs()
            )),
        };
        Ok(match outcome {
            Ok(result) => json!({
                "content": [{ "type": "text", "text": text_of(&result) }],
                "structuredContent": result,
                "isError": false,
            }),
            // A tool's failure is the tool's answer, for the model to read (MCP's rule).
            Err(message) => json!({
                "content": [{ "type": "text", "text": message }],
                "isError": true,
            }),
        })
    }
}

/// A tool's structured result as the text content that goes with it.
fn text_of(result: &Value) -> String {
    match result.get("text").and_then(Value::as_str) {
        Some(text) => text.to_string(),
        None => format!("{result:#}"),
    }
}

/// An error answer to a request.
struct Refusal {
    code: i64,
    message: String,
    data: Option<Value>,
}

impl Refusal {
    fn new(code: i64, message: String) -> Self {
        Self {
            code,
            message,
            data: None,
        }
    }
}

const INSTRUCTIONS: &str = "NeuroTree checks, lints, draws and runs BehaviorTree.CPP 4 XML \
trees. Pass a tree's XML text as `xml`. Lint a tree before running it; run_tree mocks the \
leaves you name and every leaf it does not know.";

fn supported() -> Vec<&'static str> {
    HANDSHAKE.iter().copied().chain([MODERN]).collect()
}

fn capabilities() -> Value {
    json!({ "tools": { "listChanged": false } })
}

fn server_info() -> Value {
    json!({ "name": "neurotree", "title": "NeuroTree", "version": env!("CARGO_PKG_VERSION") })
}

/// The `initialize` answer: the client's revision if it is one of the handshake's, else
/// the newest of them (the client then decides whether to go on).
fn initialize(params: &Value) -> Value {
    let asked = params
        .get("protocolVersion")
        .and_then(Value::as_str)
        .unwrap_or_default();
    let version = HANDSHAKE
        .iter()
        .find(|v| **v == asked)
        .unwrap_or(&HANDSHAKE[3]);
    json!({
        "protocolVersion": version,
        "capabilities": capabilities(),
        "serverInfo": server_info(),
        "instructions": INSTRUCTIONS,
    })
}

#[cfg(test)]
mod tests {
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
            &format!(
                r#"{{"jsonrpc":"2.0","id":"a","method":"server/discover","params":{{{meta}}}}}"#
            ),
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
}
