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
mod tests;
