//! The server's transport: one JSON-RPC message per line each way, read on a thread of its
//! own and bounded in length, written by another.
//!
//! The SDK's own stdio transport drops a line that is not a message without a word; this
//! one answers it as JSON-RPC asks (a parse error, or an invalid request), so that a client
//! sending one learns what went wrong, and the server goes on. The SDK also ends a
//! connection whose first message is a notification or a response rather than a request:
//! until a connection has started, those (which ask for no answer) are let pass by.

use std::future::Future;
use std::io::{self, BufRead};
use std::sync::mpsc;

use rmcp::model::ProtocolVersion;
use rmcp::service::{RxJsonRpcMessage, TxJsonRpcMessage};
use rmcp::transport::Transport;
use rmcp::RoleServer;
use serde_json::{json, Value};
use tokio::sync::mpsc::{channel, Receiver, Sender};

use super::MAX_MESSAGE_BYTES;

/// JSON-RPC's error codes for a line that is not a request.
const PARSE_ERROR: i64 = -32700;
const INVALID_REQUEST: i64 = -32600;

/// A line to write, or `None`: the server is done, the writer stops.
pub(super) type Out = Option<String>;

/// The most messages read and not yet taken by the SDK, and the most lines not yet
/// written: a client that sends without reading its answers is then no longer read from,
/// rather than having them pile up in memory (a message is at most
/// [`MAX_MESSAGE_BYTES`]).
pub(super) const QUEUED: usize = 16;

/// The SDK's side of the transport: the messages read, and where answers go.
pub(super) struct Lines {
    incoming: Receiver<RxJsonRpcMessage<RoleServer>>,
    outgoing: mpsc::SyncSender<Out>,
}

/// The transport writing to `outgoing`, and where [`read`] puts the messages it reads.
pub(super) fn transport(
    outgoing: mpsc::SyncSender<Out>,
) -> (Lines, Sender<RxJsonRpcMessage<RoleServer>>) {
    let (messages, incoming) = channel(QUEUED);
    (Lines { incoming, outgoing }, messages)
}

impl Transport<RoleServer> for Lines {
    type Error = io::Error;

    fn send(
        &mut self,
        item: TxJsonRpcMessage<RoleServer>,
    ) -> impl Future<Output = Result<(), Self::Error>> + Send + 'static {
        let sent = serde_json::to_string(&item)
            .map_err(io::Error::other)
            .and_then(|line| {
                self.outgoing
                    .send(Some(line))
                    .map_err(|_| io::Error::new(io::ErrorKind::BrokenPipe, "the output is closed"))
            });
        std::future::ready(sent)
    }

    fn receive(&mut self) -> impl Future<Output = Option<RxJsonRpcMessage<RoleServer>>> + Send {
        self.incoming.recv()
    }

    async fn close(&mut self) -> Result<(), Self::Error> {
        self.incoming.close();
        Ok(())
    }
}

/// Reads `input` to its end: each message goes to `messages`, and each line that is not
/// one is answered on `outgoing`.
pub(super) fn read(
    mut input: impl BufRead,
    messages: Sender<RxJsonRpcMessage<RoleServer>>,
    outgoing: mpsc::SyncSender<Out>,
) {
    let mut line = Vec::new();
    let mut started = false;
    loop {
        let refusal = match read_message(&mut input, &mut line) {
            Ok(Read::End) | Err(_) => return,
            Ok(Read::TooLong) => error(
                Value::Null,
                INVALID_REQUEST,
                &format!("the message is longer than {MAX_MESSAGE_BYTES} bytes"),
            ),
            Ok(Read::Line) => match parse(&line) {
                Ok((message, kind)) => {
                    if !started {
                        match kind {
                            Kind::Other => {}
                            Kind::Start => started = true,
                            Kind::AsksNothing => continue,
                        }
                    }
                    if messages.blocking_send(message).is_err() {
                        return;
                    }
                    continue;
                }
                Err(refusal) => refusal,
            },
        };
        if outgoing.send(Some(refusal.to_string())).is_err() {
            return;
        }
    }
}

/// What a message is to a connection that has not started.
enum Kind {
    /// A request that starts it: `initialize`, or one naming a revision of the current
    /// lifecycle (every request carries its revision in `_meta`).
    Start,
    /// A notification or a response: it asks for no answer.
    AsksNothing,
    /// A request answered before the connection starts (`ping`, `server/discover`, or one
    /// refused).
    Other,
}

impl Kind {
    fn of(message: &Value) -> Kind {
        let method = message.get("method").and_then(Value::as_str);
        let (Some(method), Some(_)) = (method, message.get("id")) else {
            return Kind::AsksNothing;
        };
        let meta = message.pointer("/params/_meta");
        let version = meta
            .and_then(|m| m.get("io.modelcontextprotocol/protocolVersion"))
            .and_then(Value::as_str);
        let capabilities = meta.and_then(|m| m.get("io.modelcontextprotocol/clientCapabilities"));
        let known = version.is_some_and(|v| {
            ProtocolVersion::KNOWN_VERSIONS
                .iter()
                .any(|k| k.as_str() == v)
        });
        match method {
            "initialize" => Kind::Start,
            "server/discover" | "ping" => Kind::Other,
            _ if known && capabilities.is_some() => Kind::Start,
            _ => Kind::Other,
        }
    }
}

/// The message `line` holds, or the answer saying why it holds none.
fn parse(line: &[u8]) -> Result<(RxJsonRpcMessage<RoleServer>, Kind), Value> {
    let value: Value = serde_json::from_slice(line)
        .map_err(|e| error(Value::Null, PARSE_ERROR, &format!("not JSON: {e}")))?;
    let id = match value.get("id") {
        Some(id @ (Value::String(_) | Value::Number(_))) => id.clone(),
        _ => Value::Null,
    };
    if !value.is_object() {
        // Batches were removed from MCP in 2025-06-18.
        return Err(error(
            id,
            INVALID_REQUEST,
            "a message must be one JSON object",
        ));
    }
    let kind = Kind::of(&value);
    let message = serde_json::from_value(value).map_err(|e| {
        error(
            id,
            INVALID_REQUEST,
            &format!("not a JSON-RPC 2.0 message of MCP: {e}"),
        )
    })?;
    Ok((message, kind))
}

/// A JSON-RPC error answer.
fn error(id: Value, code: i64, message: &str) -> Value {
    json!({ "jsonrpc": "2.0", "id": id, "error": { "code": code, "message": message } })
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
