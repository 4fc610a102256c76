//! `neurotree mcp` after a call that hit its time limit: the call's thread has ended, the
//! server spends no CPU, and it answers the next request at once.

use std::io::{BufRead, BufReader, Write};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

use serde_json::{json, Value};

struct Server {
    child: Child,
    input: ChildStdin,
    output: BufReader<ChildStdout>,
}

impl Server {
    fn start(dir: &std::path::Path) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_neurotree"))
            .args(["mcp", "--time-limit", "1"])
            .current_dir(dir)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let input = child.stdin.take().unwrap();
        let output = BufReader::new(child.stdout.take().unwrap());
        Server {
            child,
            input,
            output,
        }
    }

    /// Sends `request` and reads the next message.
    fn ask(&mut self, request: &Value) -> Value {
        writeln!(self.input, "{request}").unwrap();
        self.input.flush().unwrap();
        let mut line = String::new();
        self.output.read_line(&mut line).unwrap();
        serde_json::from_str(&line).unwrap()
    }

    /// The `initialize` handshake, which a connection starts with.
    fn initialize(&mut self) {
        let answer = self.ask(&json!({"jsonrpc":"2.0","id":0,"method":"initialize","params":{
            "protocolVersion":"2025-11-25","capabilities":{},"clientInfo":{"name":"bounds","version":"1"}}}));
        assert_eq!(
            answer["result"]["serverInfo"]["name"], "neurotree",
            "{answer}"
        );
        writeln!(
            self.input,
            "{}",
            json!({"jsonrpc":"2.0","method":"notifications/initialized"})
        )
        .unwrap();
    }

    fn ping(&mut self, id: u32) {
        let answer = self.ask(&json!({"jsonrpc":"2.0","id":id,"method":"ping"}));
        assert_eq!(answer, json!({"jsonrpc":"2.0","id":id,"result":{}}));
    }

    fn proc(&self, tail: &str) -> std::path::PathBuf {
        std::path::Path::new("/proc")
            .join(self.child.id().to_string())
            .join(tail)
    }

    /// Clock ticks of CPU the server has used, in user and system time.
    fn cpu_ticks(&self) -> u64 {
        let stat = std::fs::read_to_string(self.proc("stat")).unwrap();
        // Fields after the command's name, which is in parentheses and may hold spaces.
        let fields: Vec<&str> = stat[stat.rfind(')').unwrap() + 2..].split(' ').collect();
        // utime and stime: fields 14 and 15 of the line, 12 and 13 after the name.
        fields[11].parse::<u64>().unwrap() + fields[12].parse::<u64>().unwrap()
    }

    /// The names of the server's threads.
    fn threads(&self) -> Vec<String> {
        std::fs::read_dir(self.proc("task"))
            .unwrap()
            .map(|task| {
                std::fs::read_to_string(task.unwrap().path().join("comm"))
                    .unwrap()
                    .trim()
                    .to_string()
            })
            .collect()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn after_a_call_past_its_time_the_server_is_idle_and_answers_at_once() {
    if !std::path::Path::new("/proc/self/stat").exists() {
        // No /proc to read the server's threads and CPU from (not Linux).
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut server = Server::start(dir.path());
    server.initialize();
    server.ping(1);
    // 10,000 passes over 20,000 leaves: far longer than the second it is given.
    let leaves = "<AlwaysSuccess/>".repeat(20_000);
    let xml = format!(
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Repeat num_cycles="-1"><Sequence>{leaves}</Sequence></Repeat></BehaviorTree></root>"#
    );
    let call = json!({"jsonrpc":"2.0","id":2,"method":"tools/call","params":{"name":"run_scenario","arguments":{"xml":xml,"scenario":"ticks = 10000"}}});
    let answer = server.ask(&call);
    assert_eq!(answer["id"], 2);
    assert_eq!(answer["result"]["isError"], true);
    let text = answer["result"]["content"][0]["text"].as_str().unwrap();
    assert!(text.contains("its trees were halted"), "{text}");

    // The call's thread ended before the answer was sent; its watcher ends once it has
    // sent it, which a few round trips see.
    let mut round_trips = 0;
    while server.threads().iter().any(|t| t.starts_with("mcp-")) {
        round_trips += 1;
        assert!(round_trips < 1000, "threads left: {:?}", server.threads());
        server.ping(100 + round_trips);
    }
    // Idle: a hundred round trips cost next to no CPU (a thread left spinning would have
    // used all the time they took).
    let before = server.cpu_ticks();
    for i in 0..100 {
        server.ping(2000 + i);
    }
    let used = server.cpu_ticks() - before;
    assert!(used <= 5, "{used} clock ticks of CPU over 100 pings");
}
