//! `neurotree run --groot`: the run served to Groot2's protocol, checked with a Rust client
//! and, when it is installed, with the third-party terminal monitor `btview`.

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use zeromq::{ReqSocket, Socket, SocketRecv, SocketSend, ZmqMessage};

/// Long enough for a loaded machine; nothing waits this long when all goes well.
const TIMEOUT: Duration = Duration::from_secs(60);

/// Writes `xml` to a file of this process; each test names its own, since tests run at once.
fn write_tree(name: &str, xml: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("neurotree-groot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(name);
    std::fs::write(&file, xml).unwrap();
    file
}

use crate::corpus_dir;
use corpus_dir::corpus;

const MOVE: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence name="seq">
      <Script name="init" code="count := 41"/>
      <MoveBase name="move" goal="{goal}"/>
    </Sequence>
  </BehaviorTree>
</root>"#;

/// A `neurotree run` serving Groot2, killed when dropped.
struct Serving {
    child: Child,
    port: u16,
    stdout: String,
}

impl Serving {
    /// Runs `args` with `--groot 0` and the given linger, and waits for the port it chose.
    fn start(args: &[&str], linger: &str) -> Serving {
        let mut child = Command::new(env!("CARGO_BIN_EXE_neurotree"))
            .args(args)
            .args(["--groot", "0", "--groot-linger", linger])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let stderr = child.stderr.take().unwrap();
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines() {
                let Ok(line) = line else { break };
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        let first = rx
            .recv_timeout(TIMEOUT)
            .expect("neurotree says where it serves");
        let port = first
            .strip_prefix("neurotree: Groot2 monitor on tcp://127.0.0.1:")
            .and_then(|rest| rest.split(' ').next())
            .and_then(|p| p.parse().ok())
            .unwrap_or_else(|| panic!("unexpected first line on stderr: {first}"));
        assert_eq!(
            first,
            format!(
                "neurotree: Groot2 monitor on tcp://127.0.0.1:{port} (publisher on port {})",
                port + 1
            )
        );
        // The run ends before the linger: its output is complete once this line is out.
        let ended = rx.recv_timeout(TIMEOUT).expect("the run ends");
        assert!(ended.starts_with("neurotree: the run ended"), "{ended}");
        let mut stdout = String::new();
        let mut out = BufReader::new(child.stdout.take().unwrap());
        while let Ok(n) = out.read_line(&mut stdout) {
            if n == 0 || stdout.contains("{\"summary\"") {
                break;
            }
        }
        Serving {
            child,
            port,
            stdout,
        }
    }
}

impl Drop for Serving {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// One request on a fresh REQ socket, as a client that connects, asks and leaves.
fn request(port: u16, frames: &[&[u8]]) -> Vec<Vec<u8>> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let mut message = ZmqMessage::from(frames[0].to_vec());
    for frame in &frames[1..] {
        message.push_back(frame.to_vec().into());
    }
    runtime.block_on(async {
        tokio::time::timeout(TIMEOUT, async {
            let mut socket = ReqSocket::new();
            socket
                .connect(&format!("tcp://127.0.0.1:{port}"))
                .await
                .unwrap();
            socket.send(message).await.unwrap();
            socket.recv().await.unwrap()
        })
        .await
        .expect("no reply in time")
        .into_vec()
        .into_iter()
        .map(|b| b.to_vec())
        .collect()
    })
}

#[test]
fn serving_groot_leaves_the_output_unchanged() {
    let file = write_tree("serving.xml", MOVE);
    let args = [
        "run",
        file.to_str().unwrap(),
        "--mock",
        "move=RUNNING,SUCCESS",
        "--set",
        "goal=kitchen",
    ];
    let plain = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .output()
        .unwrap();
    let served = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .args(["--groot", "0", "--groot-linger", "0"])
        .output()
        .unwrap();
    assert!(plain.status.success() && served.status.success());
    assert_eq!(
        String::from_utf8_lossy(&served.stdout),
        String::from_utf8_lossy(&plain.stdout)
    );
    let err = String::from_utf8_lossy(&served.stderr);
    assert!(
        err.starts_with("neurotree: Groot2 monitor on tcp://127.0.0.1:"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
}

#[test]
fn linger_needs_groot() {
    let file = write_tree("linger.xml", MOVE);
    let out = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(["run", file.to_str().unwrap(), "--groot-linger", "1"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--groot <PORT>"));
}

#[test]
fn groot_bind_takes_an_address_and_needs_groot() {
    let file = write_tree("bind.xml", MOVE);
    let run = |extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_neurotree"))
            .args(["run", file.to_str().unwrap(), "--mock", "move=SUCCESS"])
            .args(extra)
            .output()
            .unwrap()
    };
    let out = run(&[
        "--groot",
        "0",
        "--groot-linger",
        "0",
        "--groot-bind",
        "127.0.0.1",
    ]);
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.starts_with("neurotree: Groot2 monitor on tcp://127.0.0.1:"),
        "{err}"
    );
    // A host name is not an address; and without `--groot` there is nothing to bind.
    let out = run(&["--groot", "0", "--groot-bind", "localhost"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--groot-bind <ADDR>"));
    let out = run(&["--groot-bind", "127.0.0.1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--groot <PORT>"));
}

#[test]
fn a_client_finds_the_last_statuses_and_blackboard_after_the_run() {
    let file = write_tree("client.xml", MOVE);
    let run = Serving::start(
        &[
            "run",
            file.to_str().unwrap(),
            "--mock",
            "move=RUNNING",
            "--set",
            "goal=kitchen",
            "--max-ticks",
            "2",
        ],
        "120",
    );
    assert!(run.stdout.contains(r#"{"tick":2,"status":"RUNNING"}"#));

    let tree = request(run.port, &[&[2, b'T', 1, 0, 0, 0]]);
    let xml = String::from_utf8(tree[1].clone()).unwrap();
    assert!(xml.contains(r#"<root BTCPP_format="4" main_tree_to_execute="Main">"#));
    assert!(xml.contains(r#"<MoveBase name="move" _uid="3"/>"#), "{xml}");
    assert!(xml.contains(r#"<Action ID="MoveBase"/>"#), "{xml}");

    // Uids 1 to 3: the sequence and the move run, the script succeeded.
    let status = request(run.port, &[&[2, b'S', 2, 0, 0, 0]]);
    assert_eq!(status[0][..6], [2, b'S', 2, 0, 0, 0]);
    assert_eq!(status[0][6..], tree[0][6..], "one tree id for every reply");
    assert_eq!(status[1], [1, 0, 1, 2, 0, 2, 3, 0, 1]);

    let blackboard = request(run.port, &[&[2, b'B', 3, 0, 0, 0], b"Main"]);
    let mut expected = vec![0x81, 0xa4];
    expected.extend_from_slice(b"Main");
    expected.extend_from_slice(&[0x82, 0xa5]);
    expected.extend_from_slice(b"count");
    expected.extend_from_slice(&[41, 0xa4]);
    expected.extend_from_slice(b"goal");
    expected.push(0xa7);
    expected.extend_from_slice(b"kitchen");
    assert_eq!(blackboard[1], expected);
}

/// The reference this test compares with is missing. Under `.ci/run`, which installs it and
/// sets `NEUROTREE_REQUIRE_REFERENCES=1`, the test fails: a run without it proves nothing.
/// Elsewhere (a fresh checkout's `cargo test`) it says on stderr what it skipped, and passes.
fn reference_missing(why: &str) {
    if std::env::var("NEUROTREE_REQUIRE_REFERENCES").as_deref() == Ok("1") {
        panic!("{why}; `.ci/run` installs it (with NEUROTREE_ALLOW_SKIP=1 it goes without)");
    }
    use std::io::Write as _;
    // Straight to stderr, past the test harness's capture, so that the run says so.
    let _ = writeln!(
        std::io::stderr(),
        "skipped: {why} (`bash .ci/run` installs it and runs this test)"
    );
}

/// `btview`, from `$BTVIEW` or the `PATH`.
fn btview() -> Option<PathBuf> {
    if let Some(path) = std::env::var_os("BTVIEW") {
        return Some(PathBuf::from(path));
    }
    std::env::split_paths(&std::env::var_os("PATH")?)
        .map(|dir| dir.join("btview"))
        .find(|p| p.is_file())
}

fn run_btview(btview: &PathBuf, args: &[&str]) -> String {
    let out = Command::new(btview)
        .args(args)
        .env("COLUMNS", "100")
        .env("NO_COLOR", "1")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "btview {args:?}: {text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

#[test]
fn btview_shows_the_tree_its_statuses_and_its_blackboard() {
    let Some(btview) = btview() else {
        reference_missing("btview is neither in $BTVIEW nor on PATH (pip install btview==0.2.0)");
        return;
    };
    let file = corpus("nav2/navigate_to_pose_w_bounds_check.xml");
    let run = Serving::start(
        &[
            "run",
            file.to_str().unwrap(),
            "--mock-unknown",
            "--mock",
            "FollowPath=RUNNING",
            "--set",
            "goal=kitchen",
            "--max-ticks",
            "3",
        ],
        "120",
    );
    let port = run.port.to_string();

    let snapshot = run_btview(
        &btview,
        &[
            "snapshot",
            "--port",
            &port,
            "--no-color",
            "--uid",
            "--no-legend",
        ],
    );
    // Each node, by uid, with what it did: the follower still runs; the bounds check
    // succeeded, and the reactive sequence reset it before ticking it again.
    for (node, status) in [
        ("[-] Sequence #1", "▶ RUNNING"),
        ("├─ --> ComputePathToPose #2", "✔ SUCCESS"),
        ("└─ [-] ReactiveSequence #3", "▶ RUNNING"),
        ("├─ --> IsWithinPathTrackingBounds #4", "· was SUCCESS"),
        ("└─ --> FollowPath #5", "▶ RUNNING"),
    ] {
        assert!(
            snapshot
                .lines()
                .any(|l| l.trim_start().starts_with(node) && l.trim_end().ends_with(status)),
            "no `{node} … {status}` in\n{snapshot}"
        );
    }
    assert!(snapshot.contains("5 nodes"), "{snapshot}");

    let blackboard = run_btview(&btview, &["blackboard", "--port", &port, "--json"]);
    let blackboard: serde_json::Value = serde_json::from_str(&blackboard).unwrap();
    assert_eq!(
        blackboard,
        serde_json::json!({ "NavigateToPoseWBoundsCheck": { "goal": "kitchen" } })
    );
}
