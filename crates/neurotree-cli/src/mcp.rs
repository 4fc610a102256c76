//! `neurotree mcp`: a Model Context Protocol server on standard input and output, so that
//! an assistant can write, check, lint, draw and try trees.
//!
//! The protocol is the official Rust SDK's ([`rmcp`]): both ways of starting a connection
//! are served, the `initialize` handshake of revisions 2024-11-05 to 2025-11-25 (most
//! clients still use it) and the current revision's, where a client may ask
//! `server/discover` and names the revision in every request's `_meta`. The tools are in
//! [`tools`]; each runs the code of the command it is named after. One JSON-RPC message
//! per line each way ([`lines`]); a line that is not a message is answered with a JSON-RPC
//! error, and the server goes on serving.
//!
//! Everything is bounded: a message longer than [`MAX_MESSAGE_BYTES`] is refused (and
//! skipped, never held whole), as is a tree longer than [`tools::MAX_XML_BYTES`]; a client
//! that sends without reading its answers is read no further than a few messages ahead
//! ([`lines::QUEUED`]); runs are
//! capped in ticks, and every call in wall time ([`CALL_TIME_LIMIT`] unless `--time-limit`
//! says otherwise). A call past its time, or one the client cancels
//! (`notifications/cancelled`), has its trees halted through their halt handles
//! ([`HaltScope`]), so that its thread ends rather than running on. Calls run on threads
//! of their own while the server reads on, at most as many at once as the machine has
//! cores (`--max-calls`); a call past that is refused with a message saying so. Files are
//! written only in a scratch folder made inside the folder the server was started in, and
//! read only there.

use std::io::{self, BufRead, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{mpsc, Arc};
use std::thread;
use std::time::Duration;

use neurotree::runtime::HaltScope;
use rmcp::model::{
    CallToolRequestParams, CallToolResponse, CallToolResult, ErrorData, Implementation,
    ListToolsResult, PaginatedRequestParams, ResultType, ServerCapabilities, ServerConfig, Tool,
};
use rmcp::service::{RequestContext, ServerInitializeError};
use rmcp::{RoleServer, ServerHandler, ServiceExt};
use serde_json::{json, Value};

use crate::Outcome;

mod lines;
mod scratch;
mod tools;

/// The longest message read, in bytes: a tree of [`tools::MAX_XML_BYTES`] and its escapes.
pub const MAX_MESSAGE_BYTES: usize = 4 << 20;
/// The longest a tool call may take before it is answered with an error.
pub const CALL_TIME_LIMIT: Duration = Duration::from_secs(20);

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
    // The caller may hold `Stdout`'s lock (the command line does, for every command): the
    // answers are written to the descriptor itself.
    #[cfg(unix)]
    let mut output = {
        use std::os::fd::AsFd;
        io::BufWriter::new(std::fs::File::from(
            io::stdout().as_fd().try_clone_to_owned()?,
        ))
    };
    #[cfg(not(unix))]
    let mut output = io::stdout();
    let input = io::BufReader::new(io::stdin());
    if let Err(e) = serve_with(input, &mut output, scratch.dir(), limits) {
        writeln!(err, "neurotree mcp: {e}")?;
        return Ok(Outcome::Refused);
    }
    Ok(Outcome::Done)
}

/// Answers the messages of `input` on `output`, one line each, until `input` ends. Tool
/// calls run on threads of their own, so their answers may come after those of later
/// messages.
pub fn serve_with(
    input: impl BufRead + Send + 'static,
    output: &mut (impl Write + Send),
    scratch: &Path,
    limits: Limits,
) -> io::Result<()> {
    let (outgoing, answers) = mpsc::sync_channel::<lines::Out>(lines::QUEUED);
    let (transport, incoming) = lines::transport(outgoing.clone());
    let server = Server {
        scratch: scratch.to_path_buf(),
        limits,
        running: Arc::new(AtomicUsize::new(0)),
        calls: Arc::new(AtomicU64::new(0)),
    };
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()?;
    thread::scope(|scope| {
        let writer = scope.spawn(move || -> io::Result<()> {
            while let Ok(Some(line)) = answers.recv() {
                writeln!(output, "{line}")?;
                output.flush()?;
            }
            Ok(())
        });
        // Not waited for: it may be blocked reading when the server stops for another
        // reason than the input's end.
        let reader = outgoing.clone();
        thread::Builder::new()
            .name("input".into())
            .spawn(move || lines::read(input, incoming, reader))?;
        let served = runtime.block_on(async move {
            match server.serve(transport).await {
                Ok(running) => running.waiting().await.map(drop).map_err(io::Error::other),
                // The input ended before a connection started: nothing to serve.
                Err(ServerInitializeError::ConnectionClosed(_)) => Ok(()),
                Err(e) => Err(io::Error::other(e.to_string())),
            }
        });
        // The calls still under way are dropped, their trees halted.
        drop(runtime);
        let _ = outgoing.send(None);
        let written = writer.join().unwrap_or(Ok(()));
        served.and(written)
    })
}

/// The server: where tools write, how many calls run now and have been made (each gets
/// its own folder), and its limits.
#[derive(Clone)]
struct Server {
    scratch: PathBuf,
    limits: Limits,
    running: Arc<AtomicUsize>,
    calls: Arc<AtomicU64>,
}

/// A call's place among those that may run at once, given back when dropped.
struct Slot(Arc<AtomicUsize>);

impl Drop for Slot {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Halts a call's trees when dropped: a call whose answer is no longer awaited (the
/// server stops) does not run on.
struct HaltOnDrop(HaltScope);

impl Drop for HaltOnDrop {
    fn drop(&mut self) {
        self.0.halt();
    }
}

impl Server {
    /// A place for one more call, if fewer than the most run now.
    fn slot(&self) -> Option<Slot> {
        let most = self.limits.calls_at_once;
        self.running
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| {
                (n < most).then_some(n + 1)
            })
            .ok()
            .map(|_| Slot(Arc::clone(&self.running)))
    }

    /// Runs the tool `name` on a thread of its own, within the time limit, and gives its
    /// outcome. At the limit or on a cancellation, the call's trees are halted and its
    /// thread is waited for (once more the limit at most).
    async fn run(
        &self,
        name: String,
        arguments: Value,
        context: RequestContext<RoleServer>,
    ) -> Result<Value, String> {
        let dir = self.scratch.join(format!(
            "call-{}",
            self.calls.fetch_add(1, Ordering::SeqCst) + 1
        ));
        let halt = HaltOnDrop(HaltScope::new());
        let trees = halt.0.clone();
        let (done, mut outcome) = tokio::sync::oneshot::channel();
        thread::Builder::new()
            .name(format!("mcp-{name}"))
            // The loader and the engine are tested on 2 MiB threads; give them room.
            .stack_size(8 << 20)
            .spawn(move || {
                let _entered = trees.enter();
                let result = tools::call(&name, &arguments, &dir);
                let _ = std::fs::remove_dir_all(&dir);
                let _ = done.send(result);
            })
            .map_err(|e| format!("cannot start the call: {e}"))?;
        let limit = self.limits.call_time;
        tokio::select! {
            result = &mut outcome => {
                result.unwrap_or_else(|_| Err("the call ended without an answer".to_string()))
            }
            () = context.ct.cancelled() => {
                // Not answered: the client said it no longer wants it.
                halt.0.halt();
                let _ = tokio::time::timeout(limit, outcome).await;
                Err("the call was cancelled; its trees were halted".to_string())
            }
            () = tokio::time::sleep(limit) => {
                halt.0.halt();
                let ended = tokio::time::timeout(limit, outcome).await.is_ok();
                Err(format!(
                    "the call took longer than {} s; {}; give fewer ticks or a smaller tree",
                    limit.as_secs(),
                    if ended { "its trees were halted" } else { "it was abandoned" }
                ))
            }
        }
    }
}

impl ServerHandler for Server {
    fn get_info(&self) -> ServerConfig {
        let capabilities = ServerCapabilities::builder().enable_tools().build();
        ServerConfig::new(capabilities)
            .with_server_info(
                Implementation::new("neurotree", env!("CARGO_PKG_VERSION")).with_title("NeuroTree"),
            )
            .with_instructions(INSTRUCTIONS)
    }

    async fn list_tools(
        &self,
        _request: Option<PaginatedRequestParams>,
        _context: RequestContext<RoleServer>,
    ) -> Result<ListToolsResult, ErrorData> {
        let tools = tools::list()
            .into_iter()
            .map(serde_json::from_value::<Tool>)
            .collect::<Result<_, _>>()
            .map_err(|e| ErrorData::internal_error(format!("a tool's schema: {e}"), None))?;
        Ok(ListToolsResult::with_all_items(tools))
    }

    async fn call_tool(
        &self,
        request: CallToolRequestParams,
        context: RequestContext<RoleServer>,
    ) -> Result<CallToolResponse, ErrorData> {
        let name = request.name.into_owned();
        if !tools::exists(&name) {
            return Err(ErrorData::invalid_params(
                format!("no tool `{name}`; tools/list lists them"),
                None,
            ));
        }
        let arguments = Value::Object(request.arguments.unwrap_or_default());
        let outcome = match self.slot() {
            Some(_slot) => self.run(name, arguments, context).await,
            None => Err(format!(
                "the server runs at most {} calls at once, and that many are running; call again once one has been answered",
                self.limits.calls_at_once
            )),
        };
        answer(outcome).map(CallToolResponse::from)
    }
}

/// The result carrying the tool's `outcome`: a tool's failure is the tool's answer, for
/// the model to read (MCP's rule).
fn answer(outcome: Result<Value, String>) -> Result<CallToolResult, ErrorData> {
    let result = match outcome {
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
    let mut result: CallToolResult = serde_json::from_value(result)
        .map_err(|e| ErrorData::internal_error(format!("a tool's result: {e}"), None))?;
    result.result_type = Some(ResultType::COMPLETE);
    Ok(result)
}

/// A tool's structured result as the text content that goes with it.
fn text_of(result: &Value) -> String {
    match result.get("text").and_then(Value::as_str) {
        Some(text) => text.to_string(),
        None => format!("{result:#}"),
    }
}

const INSTRUCTIONS: &str = "NeuroTree checks, lints, draws and runs BehaviorTree.CPP 4 XML \
trees. Pass a tree's XML text as `xml`. Lint a tree before running it; run_tree mocks the \
leaves you name and every leaf it does not know.";

#[cfg(test)]
mod tests;
