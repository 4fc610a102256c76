//! `neurotree studio`, `run --studio` and `demo --studio`: the URL on its own stderr line,
//! the files served from the folder the command started in, and the run shown.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

const NAV2: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../corpus/nav2/navigate_to_pose_w_replanning_and_recovery.xml"
);

/// Starts `neurotree ARGS` in `dir`; the child and the address from its `studio:` line.
fn start(dir: &Path, args: &[&str]) -> (Child, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let url = loop {
        let line = lines.next().expect("a studio line").unwrap();
        if let Some(url) = line.strip_prefix("studio: ") {
            break url.to_string();
        }
    };
    // The rest of stderr is drained so the child never blocks on it.
    std::thread::spawn(move || for _ in lines {});
    let addr = url
        .strip_prefix("http://")
        .and_then(|u| u.strip_suffix('/'))
        .unwrap_or_else(|| panic!("the URL `{url}`"))
        .to_string();
    (child, addr)
}

fn get(addr: &str, target: &str) -> serde_json::Value {
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
    write!(
        s,
        "GET {target} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut text = String::new();
    s.read_to_string(&mut text).unwrap();
    let body = text.split_once("\r\n\r\n").map_or("", |(_, b)| b);
    serde_json::from_str(body).unwrap_or_else(|e| panic!("{e}: {text}"))
}

#[test]
fn studio_serves_the_files_of_its_folder() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(NAV2, dir.path().join("nav.xml")).unwrap();
    let (mut child, addr) = start(dir.path(), &["studio", "nav.xml", "--nav2", "--port", "0"]);
    assert!(addr.starts_with("127.0.0.1:"), "{addr}");
    let session = get(&addr, "/api/session");
    assert_eq!(session["open"], serde_json::json!(["nav.xml"]));
    let file = get(&addr, "/api/file?path=nav.xml");
    // With --nav2, every node of Nav2's tree is known: the file checks clean.
    assert_eq!(file["check"]["ok"], true, "{}", file["check"]);
    let palette = get(&addr, "/api/palette");
    let types = palette["types"].as_array().unwrap();
    assert!(types.iter().any(|t| t["type"] == "ComputePathToPose"));
    child.kill().unwrap();
    let _ = child.wait();
}

#[test]
fn studio_refuses_a_file_outside_its_folder() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(["studio", NAV2, "--port", "0"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("outside the current folder"), "{err}");
}

#[test]
fn run_shows_its_tree_to_the_studio_and_ends() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(NAV2, dir.path().join("nav.xml")).unwrap();
    let (mut child, addr) = start(
        dir.path(),
        &[
            "run",
            "nav.xml",
            "--nav2",
            "--mock-unknown",
            "--max-ticks",
            "3",
            "--pace-ms",
            "100",
            "--studio",
            "0",
            "--studio-linger",
            "3",
        ],
    );
    let session = get(&addr, "/api/session");
    assert_eq!(session["watch"], true);
    assert_eq!(session["open"], serde_json::json!(["nav.xml"]));
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(0));
}

#[test]
fn demo_shows_its_run_to_the_studio() {
    let dir = tempfile::tempdir().unwrap();
    let (mut child, addr) = start(
        dir.path(),
        &["demo", "--fast", "--studio", "0", "--studio-linger", "3"],
    );
    // The server starts before the demo loads its tree: the run is attached soon after.
    let watched = (0..200).any(|_| {
        std::thread::sleep(Duration::from_millis(10));
        get(&addr, "/api/session")["watch"] == true
    });
    assert!(watched);
    assert_eq!(child.wait().unwrap().code(), Some(0));
}

#[cfg(feature = "ros2")]
#[test]
fn the_ros2_navigator_shows_its_tree_to_the_studio() {
    let dir = tempfile::tempdir().unwrap();
    let (mut child, addr) = start(
        dir.path(),
        &[
            "ros2",
            "navigator",
            "--domain",
            "91",
            "--duration",
            "20",
            "--studio",
            "0",
        ],
    );
    let session = get(&addr, "/api/session");
    assert_eq!(session["watch"], true);
    child.kill().unwrap();
    let _ = child.wait();
}

/// A tree that counts its ticks in `n` while its `Work` (mocked RUNNING) goes on.
const COUNTING: &str = r#"<root BTCPP_format="4">
  <BehaviorTree ID="Count">
    <ReactiveSequence>
      <Script code="n += 1"/>
      <Action ID="Work"/>
    </ReactiveSequence>
  </BehaviorTree>
</root>"#;

type Socket = tungstenite::WebSocket<tungstenite::stream::MaybeTlsStream<TcpStream>>;

fn send(socket: &mut Socket, text: &str) {
    socket
        .send(tungstenite::Message::Text(text.into()))
        .unwrap();
}

thread_local! {
    /// The latest `rewind` a page was sent (PROTOCOL.md, "Rewind").
    static LAST_REWIND: std::cell::RefCell<serde_json::Value> = const { std::cell::RefCell::new(serde_json::Value::Null) };
}

fn last_rewind() -> serde_json::Value {
    LAST_REWIND.with(|r| r.borrow().clone())
}

/// A page's WebSocket: what it is sent, as JSON, until one message satisfies `test`.
fn until(
    socket: &mut Socket,
    what: &str,
    test: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    let deadline = std::time::Instant::now() + Duration::from_secs(20);
    while std::time::Instant::now() < deadline {
        if let Ok(tungstenite::Message::Text(t)) = socket.read() {
            let m: serde_json::Value = serde_json::from_str(&t).unwrap();
            if m["type"] == "rewind" {
                LAST_REWIND.with(|r| *r.borrow_mut() = m["rewind"].clone());
            }
            if test(&m) {
                return m;
            }
        }
    }
    panic!("no {what} within 20 s");
}

#[test]
fn run_forks_where_a_page_went_back_and_numbers_the_ticks_on_from_there() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("count.xml"), COUNTING).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args([
            "run",
            "count.xml",
            "--mock",
            "Work=RUNNING*1000",
            "--set",
            "n=0",
            "--max-ticks",
            "30",
            "--pace-ms",
            "20",
            "--studio",
            "0",
            "--studio-linger",
            "0",
            "--rewind-window",
            "5",
        ])
        .current_dir(dir.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let addr = loop {
        let line = lines.next().expect("a studio line").unwrap();
        if let Some(url) = line.strip_prefix("studio: http://") {
            break url.trim_end_matches('/').to_string();
        }
    };
    std::thread::spawn(move || for _ in lines {});
    let (mut socket, _) = tungstenite::connect(format!("ws://{addr}/ws")).unwrap();
    if let tungstenite::stream::MaybeTlsStream::Plain(s) = socket.get_ref() {
        s.set_read_timeout(Some(Duration::from_millis(200)))
            .unwrap();
    }
    until(&mut socket, "the run", |m| {
        m["type"] == "hello" && !m["run"].is_null()
    });
    until(&mut socket, "tick 8", |m| m["tick"].as_u64() >= Some(8));
    send(&mut socket, r#"{"type":"pause"}"#);
    let paused = until(&mut socket, "the pause", |m| m["type"] == "paused")["tick"]
        .as_u64()
        .unwrap();
    // Back three ticks, then one forward: at paused - 2.
    for _ in 0..3 {
        send(&mut socket, r#"{"type":"back"}"#);
    }
    let back = paused - 3;
    until(&mut socket, "the run back", |m| {
        m["type"] == "rewind" && m["rewind"]["at"].as_u64() == Some(back)
    });
    send(&mut socket, r#"{"type":"forward"}"#);
    until(&mut socket, "a tick forward", |m| {
        m["type"] == "rewind" && m["rewind"]["at"].as_u64() == Some(back + 1)
    });
    // Beyond the window of 5: refused, with why.
    for _ in 0..5 {
        send(&mut socket, r#"{"type":"back"}"#);
    }
    let refused = until(&mut socket, "a refusal", |m| m["type"] == "refused");
    assert!(
        refused["why"]
            .as_str()
            .unwrap()
            .contains("is the oldest kept"),
        "{refused}"
    );
    // Forward to paused - 2 again, and continue from there: a fork.
    let at_oldest = |r: &serde_json::Value| !r["at"].is_null() && r["at"] == r["oldest"];
    if !at_oldest(&last_rewind()) {
        until(&mut socket, "the oldest", |m| {
            m["type"] == "rewind" && at_oldest(&m["rewind"])
        });
    }
    let oldest = last_rewind()["oldest"].as_u64().unwrap();
    for _ in oldest..back + 1 {
        send(&mut socket, r#"{"type":"forward"}"#);
    }
    until(&mut socket, "the run at the fork", |m| {
        m["type"] == "rewind" && m["rewind"]["at"].as_u64() == Some(back + 1)
    });
    send(&mut socket, r#"{"type":"continue"}"#);
    let mut out = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    assert_eq!(child.wait().unwrap().code(), Some(3), "{out}");
    let lines: Vec<&str> = out.lines().collect();
    let fork = format!(r#"{{"rewind":{{"to":{}}}}}"#, back + 1);
    let at = lines
        .iter()
        .position(|l| *l == fork)
        .unwrap_or_else(|| panic!("{out}"));
    assert_eq!(
        lines[at - 1],
        format!(r#"{{"tick":{paused},"status":"RUNNING"}}"#)
    );
    assert_eq!(
        lines[at + 1],
        format!(r#"{{"tick":{},"status":"RUNNING"}}"#, back + 2)
    );
    // The run ends at 30 ticks as counted after the fork, and its blackboard counted them
    // so: the state of tick back + 1 was restored, not the ticks after it.
    let summary: serde_json::Value = serde_json::from_str(lines.last().unwrap()).unwrap();
    assert_eq!(summary["summary"]["ticks"], 30);
    assert_eq!(summary["summary"]["blackboard"]["n"], 30, "{summary}");
    assert_eq!(
        summary["summary"]["nodes"]["Script"]["ticks"], 30,
        "{summary}"
    );
}

/// The `points` of the scene item `id` in a `scene` message.
fn item<'a>(scene: &'a serde_json::Value, id: &str) -> &'a serde_json::Value {
    scene["scene"]["items"]
        .as_array()
        .and_then(|items| items.iter().find(|i| i["id"] == id))
        .unwrap_or_else(|| panic!("no `{id}` in {scene}"))
}

#[test]
fn demo_draws_its_warehouse_and_the_robot_goes_back_with_the_tree() {
    let dir = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args([
            "demo",
            "--speed",
            "10",
            "--studio",
            "0",
            "--studio-linger",
            "0",
        ])
        .current_dir(dir.path())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let addr = loop {
        let line = lines.next().expect("a studio line").unwrap();
        if let Some(url) = line.strip_prefix("studio: http://") {
            break url.trim_end_matches('/').to_string();
        }
    };
    std::thread::spawn(move || for _ in lines {});
    let (mut socket, _) = tungstenite::connect(format!("ws://{addr}/ws")).unwrap();
    if let tungstenite::stream::MaybeTlsStream::Plain(s) = socket.get_ref() {
        s.set_read_timeout(Some(Duration::from_millis(200)))
            .unwrap();
    }
    until(&mut socket, "the run", |m| {
        m["type"] == "hello" && !m["run"].is_null()
    });
    // The robot under way on its plan, 3 s in.
    until(&mut socket, "tick 30", |m| {
        m["type"] == "tick" && m["tick"].as_u64() >= Some(30)
    });
    send(&mut socket, r#"{"type":"pause"}"#);
    // The scene of a tick goes out before the pause after it.
    let scene = std::cell::RefCell::new(serde_json::Value::Null);
    let paused = until(&mut socket, "the pause", |m| {
        if m["type"] == "scene" {
            *scene.borrow_mut() = m.clone();
        }
        m["type"] == "paused"
    })["tick"]
        .as_u64()
        .unwrap();
    let now = scene.into_inner();
    assert_eq!(now["tick"].as_u64(), Some(paused), "{now}");
    for id in ["floor", "wall", "inflation", "path", "goal", "robot"] {
        item(&now, id);
    }
    let robot = item(&now, "robot")["points"].clone();
    for _ in 0..10 {
        send(&mut socket, r#"{"type":"back"}"#);
    }
    let back = until(&mut socket, "the scene 10 ticks back", |m| {
        m["type"] == "scene" && m["tick"].as_u64() == Some(paused - 10)
    });
    let then = item(&back, "robot")["points"].clone();
    // A metre a second, a tenth of a second a tick: the robot is about a metre back.
    let centre = |points: &serde_json::Value| {
        let p = points.as_array().unwrap();
        let sum = |k: usize| p.iter().map(|q| q[k].as_f64().unwrap()).sum::<f64>() / 3.0;
        (sum(0), sum(1))
    };
    let (a, b) = (centre(&robot), centre(&then));
    let moved = ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt();
    assert!(
        (0.5..1.5).contains(&moved),
        "moved {moved}: {robot} then {then}"
    );
    send(&mut socket, r#"{"type":"continue"}"#);
    // The fork goes on to the goal.
    assert_eq!(child.wait().unwrap().code(), Some(0));
}
