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
//! capped in ticks, and every call in wall time ([`CALL_TIME_LIMIT`] unless `--time-limit`
//! says otherwise). A call past its time, or one the client cancels
//! (`notifications/cancelled`), has its trees halted through their halt handles
//! ([`HaltScope`]), so that its thread ends rather than running on. Calls run on threads
//! of their own while the server reads on, at most as many at once as the machine has
//! cores (`--max-calls`); a call past that is refused with a message saying so. Files are
//! written only in a scratch folder made inside the folder the server was started in, and
//! read only there. A malformed message is answered with a JSON-RPC error, and the server
//! goes on serving.

use std::collections::HashMap;
use std::io::{self, BufRead, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{mpsc, Mutex, PoisonError};
use std::thread;
use std::time::Duration;

use neurotree::runtime::HaltScope;
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
pub struct McpArgs {
    /// The longest a tool call may take, in seconds: its trees are then halted and the
    /// call answered with an error.
    #[arg(long, value_name = "SECONDS", default_value_t = CALL_TIME_LIMIT.as_secs(), value_parser = clap::value_parser!(u64).range(1..=3600))]
    time_limit: u64,
    /// The most tool calls run at once (default: the machine's cores); a call past that is
    /// refused.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=1024))]
    max_calls: Option<u64>,
}

/// How much a server's calls may take.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// The longest a call may take.
    pub call_time: Duration,
    /// The most calls run at once.
    pub calls_at_once: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            call_time: CALL_TIME_LIMIT,
            calls_at_once: thread::available_parallelism().map_or(1, usize::from),
        }
    }
}

/// Serves requests from standard input until it closes.
pub fn execute(args: &McpArgs, err: &mut impl Write) -> io::Result<Outcome> {
    let mut limits = Limits {
        call_time: Duration::from_secs(args.time_limit),
        ..Limits::default()
    };
    if let Some(n) = args.max_calls {
        limits.calls_at_once = n as usize;
    }
    let scratch = match scratch::Scratch::in_current_dir() {
        Ok(scratch) => scratch,
        Err(e) => {
            writeln!(err, "neurotree mcp: cannot make a scratch folder here: {e}")?;
            return Ok(Outcome::Refused);
        }
    };
    let stdin = io::stdin();
    // The calls answer from threads of their own, and the caller may hold `Stdout`'s lock
    // (the command line does, for every command): they write to the descriptor itself.
    #[cfg(unix)]
    let mut output = {
        use std::os::fd::AsFd;
        io::BufWriter::new(std::fs::File::from(
            io::stdout().as_fd().try_clone_to_owned()?,
        ))
    };
    #[cfg(not(unix))]
    let mut output = io::stdout();
    serve_with(&mut stdin.lock(), &mut output, scratch.dir(), limits)?;
    Ok(Outcome::Done)
}

/// Answers each message of `input` on `output`, one line each, until `input` ends and
/// every call under way has been answered. Tool calls run on threads of their own, so
/// their answers may come after those of later messages.
pub fn serve_with(
    input: &mut impl BufRead,
    output: &mut (impl Write + Send),
    scratch: &Path,
    limits: Limits,
) -> io::Result<()> {
    let output = Mutex::new(output);
    let running = AtomicUsize::new(0);
    let cancels: Mutex<HashMap<String, mpsc::Sender<Event>>> = Mutex::new(HashMap::new());
    let mut server = Server {
        scratch: scratch.to_path_buf(),
        calls: 0,
    };
    thread::scope(|scope| {
        let mut line = Vec::new();
        loop {
            match read_message(input, &mut line)? {
                Read::End => return Ok(()),
                Read::TooLong => {
                    let message = format!("the message is longer than {MAX_MESSAGE_BYTES} bytes");
                    send(&output, &error(Value::Null, INVALID_REQUEST, &message))?;
                }
                Read::Line => match server.answer(&line) {
                    None => {}
                    Some(Reply::Now(answer)) => send(&output, &answer)?,
                    Some(Reply::Cancel(id)) => {
                        let key = id.to_string();
                        if let Some(cancel) = lock(&cancels).get(&key) {
                            let _ = cancel.send(Event::Cancelled);
                        }
                    }
                    Some(Reply::Call(call)) => {
                        if running.load(Ordering::SeqCst) >= limits.calls_at_once {
                            let busy = call.answer(Err(format!(
                                "the server runs at most {} calls at once, and that many are running; call again once one has been answered",
                                limits.calls_at_once
                            )));
                            send(&output, &busy)?;
                            continue;
                        }
                        running.fetch_add(1, Ordering::SeqCst);
                        let key = call.id.to_string();
                        let (events, inbox) = mpsc::channel();
                        lock(&cancels).insert(key.clone(), events.clone());
                        let (output, running, cancels) = (&output, &running, &cancels);
                        scope.spawn(move || {
                            let answer = call.run(limits.call_time, events, &inbox);
                            lock(cancels).remove(&key);
                            running.fetch_sub(1, Ordering::SeqCst);
                            if let Some(answer) = answer {
                                // The client may be gone; the server stops when its input ends.
                                let _ = send(output, &answer);
                            }
                        });
                    }
                },
            }
        }
    })
}

fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}

fn send(output: &Mutex<&mut (impl Write + Send)>, message: &Value) -> io::Result<()> {
    let mut output = lock(output);
    writeln!(output, "{message}")?;
    output.flush()
}

/// What a call's watcher hears: the tool's outcome, or the client's cancellation.
enum Event {
    Done(Result<Value, String>),
    Cancelled,
}

/// What a message asks of the server.
enum Reply {
    /// This answer, at once.
    Now(Value),
    /// A tool call, to run on a thread of its own.
    Call(Call),
    /// The client cancelled the request with this id.
    Cancel(Value),
}

/// A tool call, checked and ready to run.
struct Call {
    id: Value,
    name: String,
    arguments: Value,
    /// Its folder in the scratch folder.
    dir: PathBuf,
    /// The request named the current revision: its result is marked.
    modern: bool,
}

impl Call {
    /// Runs the tool on a thread of its own, within `limit`; its answer, or `None` if the
    /// client cancelled it. At the limit or on a cancellation, the call's trees are halted
    /// and its thread is waited for (once more `limit` at most).
    fn run(
        self,
        limit: Duration,
        events: mpsc::Sender<Event>,
        inbox: &mpsc::Receiver<Event>,
    ) -> Option<Value> {
        let halt = HaltScope::new();
        let (name, arguments, dir) = (self.name.clone(), self.arguments.clone(), self.dir.clone());
        let trees = halt.clone();
        let started = thread::Builder::new()
            .name(format!("mcp-{name}"))
            // The loader and the engine are tested on 2 MiB threads; give them room.
            .stack_size(8 << 20)
            .spawn(move || {
                let _entered = trees.enter();
                let outcome = tools::call(&name, &arguments, &dir);
                let _ = std::fs::remove_dir_all(&dir);
                let _ = events.send(Event::Done(outcome));
            });
        if let Err(e) = started {
            return Some(self.answer(Err(format!("cannot start the call: {e}"))));
        }
        let outcome = match inbox.recv_timeout(limit) {
            Ok(Event::Done(outcome)) => outcome,
            Ok(Event::Cancelled) => {
                halt.halt();
                wait_for_end(inbox, limit);
                return None;
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                Err("the call ended without an answer".to_string())
            }
            // The time limit passed (the other error of `recv_timeout`).
            Err(_) => {
                halt.halt();
                let ended = wait_for_end(inbox, limit);
                Err(format!(
                    "the call took longer than {} s; {}; give fewer ticks or a smaller tree",
                    limit.as_secs(),
                    if ended {
                        "its trees were halted"
                    } else {
                        "it was abandoned"
                    }
                ))
            }
        };
        Some(self.answer(outcome))
    }

    /// The JSON-RPC answer carrying the tool's `outcome`: a tool's failure is the tool's
    /// answer, for the model to read (MCP's rule).
    fn answer(&self, outcome: Result<Value, String>) -> Value {
        let mut result = match outcome {
            Ok(result) => json!({
                "content": [{ "type": "text", "text": text_of(&result) }],
                "structuredContent": result,
                "isError": false,
            }),
            Err(message) => json!({
                "content": [{ "type": "text", "text": message }],
                "isError": true,
            }),
        };
        if self.modern {
            result["resultType"] = json!("complete");
        }
        json!({ "jsonrpc": "2.0", "id": self.id, "result": result })
    }
}

/// Waits, `limit` at most, for the call's thread to give its outcome (dropped: the call
/// was halted or cancelled); `true` if it did.
fn wait_for_end(inbox: &mpsc::Receiver<Event>, limit: Duration) -> bool {
    let until = std::time::Instant::now() + limit;
    loop {
        let left = until.saturating_duration_since(std::time::Instant::now());
        match inbox.recv_timeout(left) {
            Ok(Event::Done(_)) => return true,
            Ok(Event::Cancelled) => {}
            Err(_) => return false,
        }
    }
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
    /// What to do about one message: nothing for a notification other than a cancellation.
    fn answer(&mut self, line: &[u8]) -> Option<Reply> {
        self.reply(line).map(|reply| match reply {
            Ok(reply) => reply,
            Err(answer) => Reply::Now(answer),
        })
    }

    /// As [`answer`](Self::answer), an answer given at once as `Err`.
    fn reply(&mut self, line: &[u8]) -> Option<Result<Reply, Value>> {
        let message: Value = match serde_json::from_slice(line) {
            Ok(message) => message,
            Err(e) => {
                return Some(Err(error(
                    Value::Null,
                    PARSE_ERROR,
                    &format!("not JSON: {e}"),
                )))
            }
        };
        let Value::Object(message) = message else {
            // Batches were removed from MCP in 2025-06-18.
            return Some(Err(error(
                Value::Null,
                INVALID_REQUEST,
                "a message must be one JSON object",
            )));
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
            return (!response)
                .then(|| Err(error(id, INVALID_REQUEST, "not a JSON-RPC 2.0 request")));
        };
        let Some(id) = id else {
            // A notification: `notifications/cancelled` names a call to stop; others
            // (`notifications/initialized`) ask nothing.
            return (method == "notifications/cancelled")
                .then(|| message.get("params")?.get("requestId").cloned())
                .flatten()
                .map(|id| Ok(Reply::Cancel(id)));
        };
        if !valid_id {
            return Some(Err(error(
                Value::Null,
                INVALID_REQUEST,
                "the id must be a string or a number",
            )));
        }
        let params = message.get("params").cloned().unwrap_or(json!({}));
        if !params.is_object() {
            return Some(Err(error(id, INVALID_PARAMS, "params must be an object")));
        }
        Some(match self.request(method, &params) {
            Ok(Answer::Result(result)) => {
                Err(json!({ "jsonrpc": "2.0", "id": id, "result": result }))
            }
            Ok(Answer::Call(mut call)) => {
                call.id = id;
                Ok(Reply::Call(call))
            }
            Err(Refusal {
                code,
                message,
                data,
            }) => {
                let mut answer = error(id, code, &message);
                if let Some(data) = data {
                    answer["error"]["data"] = data;
                }
                Err(answer)
            }
        })
    }

    fn request(&mut self, method: &str, params: &Value) -> Result<Answer, Refusal> {
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
            "tools/call" => return Ok(Answer::Call(self.call(params, modern)?)),
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
        Ok(Answer::Result(result))
    }

    /// The tool call `params` asks for, checked, to run on a thread of its own.
    fn call(&mut self, params: &Value, modern: bool) -> Result<Call, Refusal> {
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
        Ok(Call {
            id: Value::Null,
            name,
            arguments,
            dir: self.scratch.join(format!("call-{}", self.calls)),
            modern,
        })
    }
}

/// What a request gets: its result at once, or a tool call to run.
enum Answer {
    Result(Value),
    Call(Call),
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
        answers_within(lines, Limits::default())
    }

    /// The answers to `lines` from a server under `limits`, in the order they were sent.
    fn answers_within(lines: &[&str], limits: Limits) -> Vec<Value> {
        let dir = tempfile::tempdir().unwrap();
        let input = lines.join("\n") + "\n";
        let mut output = Vec::new();
        serve_with(&mut input.as_bytes(), &mut output, dir.path(), limits).unwrap();
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

    /// A `run_scenario` call (id `id`) that takes far longer than a second: 10,000 passes
    /// over 20,000 leaves.
    fn slow_call(id: u32) -> String {
        let leaves = "<AlwaysSuccess/>".repeat(20_000);
        let xml = format!(
            r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Repeat num_cycles="-1"><Sequence>{leaves}</Sequence></Repeat></BehaviorTree></root>"#
        );
        json!({"jsonrpc":"2.0","id":id,"method":"tools/call","params":{"name":"run_scenario","arguments":{"xml":xml,"scenario":"ticks = 10000"}}}).to_string()
    }

    const FILE_IN_MESSAGES: &str = "tree.xml:";

    fn cancel(id: u32) -> String {
        json!({"jsonrpc":"2.0","method":"notifications/cancelled","params":{"requestId":id,"reason":"enough"}}).to_string()
    }

    #[test]
    fn run_scenario_s_ticks_are_capped_as_run_tree_s() {
        let xml =
            r#"<root BTCPP_format="4"><BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>"#;
        let result = call(
            "run_scenario",
            json!({ "xml": xml, "scenario": "ticks = 4294967295" }),
        );
        assert_eq!(result["isError"], true);
        let text = result["content"][0]["text"].as_str().unwrap();
        assert!(
            text.contains("4294967295") && text.contains("10000"),
            "{text}"
        );
        let result = call(
            "run_scenario",
            json!({ "xml": xml, "scenario": "ticks = 10000" }),
        );
        assert_eq!(result["structuredContent"]["passed"], true, "{result}");
    }

    #[test]
    fn a_call_past_its_time_has_its_tree_halted_and_the_server_goes_on() {
        let limits = Limits {
            call_time: Duration::from_secs(1),
            calls_at_once: 2,
        };
        let got = answers_within(&[&slow_call(1), PING], limits);
        // The ping is answered while the call runs; the call, once its tree was halted.
        assert_eq!(got[0]["id"], 9);
        assert_eq!(got[1]["id"], 1);
        assert_eq!(got[1]["result"]["isError"], true);
        let text = got[1]["result"]["content"][0]["text"].as_str().unwrap();
        assert!(text.contains("its trees were halted"), "{text}");
    }

    #[test]
    fn a_cancelled_call_is_halted_and_not_answered() {
        // Had the cancellation been ignored, the call would have been answered at its
        // time limit.
        let got = answers(&[&slow_call(1), &cancel(1), PING]);
        assert_eq!(got, [json!({"jsonrpc":"2.0","id":9,"result":{}})]);
    }

    #[test]
    fn calls_past_the_most_at_once_are_refused() {
        let limits = Limits {
            call_time: CALL_TIME_LIMIT,
            calls_at_once: 1,
        };
        let got = answers_within(&[&slow_call(1), &slow_call(2), &cancel(1), PING], limits);
        assert_eq!(got.len(), 2, "{got:?}");
        assert_eq!(got[0]["id"], 2);
        let text = got[0]["result"]["content"][0]["text"].as_str().unwrap();
        assert!(text.contains("at most 1 calls at once"), "{text}");
        assert_eq!(got[1]["id"], 9);
    }

    #[test]
    fn an_include_outside_the_call_is_refused_alike_whether_or_not_it_exists() {
        let message = |path: &str| {
            let xml = format!(
                r#"<root BTCPP_format="4"><include path="{path}"/><BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>"#
            );
            let result = call("run_tree", json!({ "xml": xml }));
            assert_eq!(result["isError"], true);
            result["content"][0]["text"].as_str().unwrap().to_string()
        };
        let exists = std::env::current_exe().unwrap();
        let exists = format!("../../../../../../../../..{}", exists.display());
        let missing = "../../../../../../../../../no/such/file.xml";
        let (a, b) = (message(&exists), message(missing));
        assert!(a.contains("outside the base directory"), "{a}");
        assert_eq!(strip_call_dir(&a), strip_call_dir(&b));
    }

    /// `text` without the call's own folder and the paths, which differ from call to call.
    fn strip_call_dir(text: &str) -> String {
        let text = text
            .split_once(FILE_IN_MESSAGES)
            .map_or(text, |(_, rest)| rest);
        text.split('`')
            .enumerate()
            .map(|(i, part)| if i % 2 == 1 { "`…`" } else { part })
            .collect()
    }
}
