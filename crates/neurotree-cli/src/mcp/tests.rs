//! The server message by message, as a client drives it: the answers to bad lines, the
//! tools' answers, and the bounds on calls (time, cancellation, how many at once).

use std::io::Read;
use std::sync::mpsc::{channel, Receiver, Sender};
use std::thread::JoinHandle;

use super::*;

/// A hang catch: far longer than any answer below takes on a loaded machine.
const HANG: Duration = Duration::from_secs(180);

/// The server's input: the lines a test sends, until it drops the sender.
struct Input {
    lines: Receiver<Vec<u8>>,
    left: Vec<u8>,
}

impl Read for Input {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.left.is_empty() {
            match self.lines.recv() {
                Ok(line) => self.left = line,
                Err(_) => return Ok(0),
            }
        }
        let n = buf.len().min(self.left.len());
        buf[..n].copy_from_slice(&self.left[..n]);
        self.left.drain(..n);
        Ok(n)
    }
}

/// The server's output: each line it writes, parsed, to the test.
struct Output {
    answers: Sender<Value>,
    line: Vec<u8>,
}

impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        for &b in buf {
            if b == b'\n' {
                let answer = serde_json::from_slice(&self.line).expect("a JSON line");
                let _ = self.answers.send(answer);
                self.line.clear();
            } else {
                self.line.push(b);
            }
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// A server under test and the client's ends of its input and output.
struct Client {
    input: Option<Sender<Vec<u8>>>,
    answers: Receiver<Value>,
    server: Option<JoinHandle<io::Result<()>>>,
    _dir: tempfile::TempDir,
}

impl Client {
    fn start(limits: Limits) -> Client {
        let dir = tempfile::tempdir().unwrap();
        let (input, lines) = channel();
        let (answers_tx, answers) = channel();
        let scratch = dir.path().to_path_buf();
        let server = thread::spawn(move || {
            let input = io::BufReader::new(Input {
                lines,
                left: Vec::new(),
            });
            let mut output = Output {
                answers: answers_tx,
                line: Vec::new(),
            };
            serve_with(input, &mut output, &scratch, limits)
        });
        Client {
            input: Some(input),
            answers,
            server: Some(server),
            _dir: dir,
        }
    }

    /// A server past the `initialize` handshake.
    fn initialized(limits: Limits) -> Client {
        let client = Client::start(limits);
        client.send(&initialize("2025-11-25"));
        let answer = client.next();
        assert_eq!(answer["id"], 0, "{answer}");
        client.send(r#"{"jsonrpc":"2.0","method":"notifications/initialized"}"#);
        client
    }

    fn send(&self, line: &str) {
        let line = format!("{line}\n").into_bytes();
        self.input.as_ref().unwrap().send(line).unwrap();
    }

    /// The next answer.
    fn next(&self) -> Value {
        self.answers.recv_timeout(HANG).expect("an answer")
    }

    /// Ends the input, waits for the server to stop, and gives the answers not read yet.
    fn close(mut self) -> Vec<Value> {
        self.input.take();
        self.server.take().unwrap().join().unwrap().unwrap();
        self.answers.try_iter().collect()
    }
}

fn initialize(version: &str) -> String {
    json!({"jsonrpc":"2.0","id":0,"method":"initialize","params":{
        "protocolVersion":version,"capabilities":{},"clientInfo":{"name":"t","version":"1"}}})
    .to_string()
}

fn ping(id: u32) -> String {
    json!({"jsonrpc":"2.0","id":id,"method":"ping"}).to_string()
}

fn pong(id: u32) -> Value {
    json!({"jsonrpc":"2.0","id":id,"result":{}})
}

#[test]
fn the_handshake_answers_the_clients_revision_or_the_newest() {
    for (asked, answered) in [
        ("2025-11-25", "2025-11-25"),
        ("2025-03-26", "2025-03-26"),
        ("1999-01-01", "2025-11-25"),
    ] {
        let client = Client::start(Limits::default());
        client.send(&initialize(asked));
        let got = client.next();
        assert_eq!(got["result"]["protocolVersion"], answered);
        assert_eq!(got["result"]["serverInfo"]["name"], "neurotree");
        assert!(got["result"]["capabilities"]["tools"].is_object());
        client.send(r#"{"jsonrpc":"2.0","method":"notifications/initialized"}"#);
        client.send(&ping(9));
        assert_eq!(client.next(), pong(9));
        assert_eq!(client.close(), Vec::<Value>::new());
    }
}

#[test]
fn the_current_revision_discovers_and_marks_every_result() {
    let meta = r#""_meta":{"io.modelcontextprotocol/protocolVersion":"2026-07-28","io.modelcontextprotocol/clientCapabilities":{}}"#;
    let client = Client::start(Limits::default());
    client.send(&format!(
        r#"{{"jsonrpc":"2.0","id":"a","method":"server/discover","params":{{{meta}}}}}"#
    ));
    let got = client.next();
    assert_eq!(got["id"], "a");
    let versions = got["result"]["supportedVersions"].as_array().unwrap();
    assert!(versions.contains(&json!("2025-11-25")) && versions.contains(&json!("2026-07-28")));
    assert_eq!(got["result"]["resultType"], "complete");
    client.send(&format!(
        r#"{{"jsonrpc":"2.0","id":"b","method":"tools/list","params":{{{meta}}}}}"#
    ));
    let got = client.next();
    assert_eq!(got["result"]["resultType"], "complete");
    assert_eq!(got["result"]["cacheScope"], "private");
    assert_eq!(got["result"]["tools"].as_array().unwrap().len(), 7);
    client.send(r#"{"jsonrpc":"2.0","id":"c","method":"tools/list","params":{"_meta":{"io.modelcontextprotocol/protocolVersion":"2099-01-01","io.modelcontextprotocol/clientCapabilities":{}}}}"#);
    let got = client.next();
    assert_eq!(got["error"]["code"], -32022);
    assert_eq!(got["error"]["data"]["requested"], "2099-01-01");
}

#[test]
fn malformed_messages_get_errors_and_the_server_goes_on() {
    // Before the handshake: a response and a notification ask nothing, and do not end the
    // connection.
    let client = Client::start(Limits::default());
    client.send(r#"{"jsonrpc":"2.0","id":6,"result":{}}"#);
    client.send(r#"{"jsonrpc":"2.0","method":"notifications/cancelled","params":{"requestId":1}}"#);
    client.send(&ping(8));
    assert_eq!(client.next(), pong(8));
    client.send(&initialize("2025-11-25"));
    assert_eq!(client.next()["id"], 0);
    for (line, id, code) in [
        ("{not json", Value::Null, -32700),
        ("[1, 2]", Value::Null, -32600),
        (
            r#"{"jsonrpc":"1.0","id":1,"method":"ping"}"#,
            json!(1),
            -32600,
        ),
        (
            r#"{"jsonrpc":"2.0","id":{"x":1},"method":"ping"}"#,
            Value::Null,
            -32600,
        ),
        (
            r#"{"jsonrpc":"2.0","id":2,"method":"no/such"}"#,
            json!(2),
            -32601,
        ),
        (
            r#"{"jsonrpc":"2.0","id":3,"method":"tools/call","params":[1]}"#,
            json!(3),
            -32600,
        ),
        (
            r#"{"jsonrpc":"2.0","id":4,"method":"tools/call","params":{"name":"nope"}}"#,
            json!(4),
            -32602,
        ),
        ("{}", Value::Null, -32600),
    ] {
        client.send(line);
        let got = client.next();
        assert_eq!(
            (&got["id"], &got["error"]["code"]),
            (&id, &json!(code)),
            "{line}: {got}"
        );
    }
    client.send("");
    client.send(&ping(9));
    assert_eq!(client.next(), pong(9));
}

#[test]
fn a_message_too_long_is_refused_without_being_kept() {
    let long = format!(
        r#"{{"jsonrpc":"2.0","id":1,"method":"ping","params":{{"x":"{}"}}}}"#,
        "a".repeat(MAX_MESSAGE_BYTES)
    );
    let client = Client::start(Limits::default());
    client.send(&long);
    let got = client.next();
    assert_eq!(got["error"]["code"], -32600);
    assert!(got["error"]["message"]
        .as_str()
        .unwrap()
        .contains("longer than"));
    client.send(&ping(9));
    assert_eq!(client.next(), pong(9));
}

fn call_request(id: u32, name: &str, arguments: Value) -> String {
    json!({"jsonrpc":"2.0","id":id,"method":"tools/call","params":{"name":name,"arguments":arguments}}).to_string()
}

/// The result of one call on a fresh server.
fn call(name: &str, arguments: Value) -> Value {
    let client = Client::initialized(Limits::default());
    client.send(&call_request(7, name, arguments));
    let got = client.next();
    assert_eq!(got["id"], 7, "{got}");
    got["result"].clone()
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
    let text = text.split_once("tree.xml:").map_or(text, |(_, rest)| rest);
    text.split('`')
        .enumerate()
        .map(|(i, part)| if i % 2 == 1 { "`…`" } else { part })
        .collect()
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

/// A `run_scenario` call (id `id`) that takes far longer than any limit below: 10,000
/// passes over 20,000 leaves.
fn slow_call(id: u32) -> String {
    let leaves = "<AlwaysSuccess/>".repeat(20_000);
    let xml = format!(
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Repeat num_cycles="-1"><Sequence>{leaves}</Sequence></Repeat></BehaviorTree></root>"#
    );
    call_request(
        id,
        "run_scenario",
        json!({"xml":xml,"scenario":"ticks = 10000"}),
    )
}

fn cancel(id: u32) -> String {
    json!({"jsonrpc":"2.0","method":"notifications/cancelled","params":{"requestId":id,"reason":"enough"}}).to_string()
}

#[test]
fn a_call_past_its_time_has_its_tree_halted_and_the_server_goes_on() {
    let client = Client::initialized(Limits {
        call_time: Duration::from_secs(1),
        calls_at_once: 2,
    });
    client.send(&slow_call(1));
    client.send(&ping(9));
    // The ping is answered while the call runs; the call, once its tree was halted.
    assert_eq!(client.next(), pong(9));
    let got = client.next();
    assert_eq!(got["id"], 1);
    assert_eq!(got["result"]["isError"], true);
    let text = got["result"]["content"][0]["text"].as_str().unwrap();
    assert!(text.contains("its trees were halted"), "{text}");
}

/// One call at once: a second is refused while the first runs. The first, cancelled, is
/// halted and never answered: its place is free again long before its time limit (an hour)
/// would have freed it.
#[test]
fn calls_past_the_most_at_once_are_refused_and_a_cancelled_call_is_halted_unanswered() {
    let client = Client::initialized(Limits {
        call_time: Duration::from_secs(3600),
        calls_at_once: 1,
    });
    client.send(&slow_call(1));
    client.send(&slow_call(2));
    let got = client.next();
    assert_eq!(got["id"], 2);
    let text = got["result"]["content"][0]["text"].as_str().unwrap();
    assert!(text.contains("at most 1 calls at once"), "{text}");
    client.send(&cancel(1));
    let quick = json!({ "xml": r#"<root BTCPP_format="4"><BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>"# });
    // Each refusal is a round trip; the first call's thread ends once halted.
    let mut id = 100;
    let answered = loop {
        id += 1;
        assert!(id < 100_000, "the cancelled call kept its place");
        client.send(&call_request(id, "check_tree", quick.clone()));
        let got = client.next();
        assert_ne!(got["id"], 1, "the cancelled call was answered: {got}");
        assert_eq!(got["id"], id);
        if got["result"]["isError"] == false {
            break got;
        }
    };
    assert_eq!(
        answered["result"]["structuredContent"]["ok"], true,
        "{answered}"
    );
    client.send(&ping(9));
    assert_eq!(client.next(), pong(9));
    assert!(client.close().iter().all(|a| a["id"] != 1));
}

/// Junk lines, one a read, counted as they are read.
struct Junk {
    read: Arc<AtomicUsize>,
    left: usize,
}

impl Read for Junk {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.left == 0 {
            return Ok(0);
        }
        self.left -= 1;
        self.read.fetch_add(1, Ordering::SeqCst);
        buf[..2].copy_from_slice(b"x\n");
        Ok(2)
    }
}

#[test]
fn a_client_that_does_not_read_its_answers_is_read_no_further_ahead() {
    let read = Arc::new(AtomicUsize::new(0));
    let input = io::BufReader::new(Junk {
        read: Arc::clone(&read),
        left: 1000,
    });
    let (messages, _incoming) = tokio::sync::mpsc::channel(lines::QUEUED);
    let (outgoing, answers) = mpsc::sync_channel(lines::QUEUED);
    let reader = thread::spawn(move || lines::read(input, messages, outgoing));
    for taken in 1..=1000 {
        let answer = answers
            .recv_timeout(HANG)
            .expect("an answer")
            .expect("a line");
        assert!(answer.contains("not JSON"), "{answer}");
        // Each line read waits for the answer to the one before to find room.
        let ahead = read.load(Ordering::SeqCst);
        assert!(
            ahead <= taken + lines::QUEUED + 1,
            "{ahead} lines read with {taken} answers taken"
        );
    }
    reader.join().unwrap();
}
