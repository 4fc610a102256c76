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
    start_with(dir, args, Stdio::null())
}

/// [`start`], with the child's stdout kept for the test to read.
fn start_watched(dir: &Path, args: &[&str]) -> (Child, String) {
    start_with(dir, args, Stdio::piped())
}

fn start_with(dir: &Path, args: &[&str], stdout: Stdio) -> (Child, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .args(args)
        .current_dir(dir)
        .stdout(stdout)
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
    // The rest of stderr is drained to its end so the child never blocks on it (a line that
    // is not UTF-8 is skipped, not the end), into the test's output (shown when it fails).
    std::thread::spawn(move || {
        for line in lines {
            let Ok(line) = line else { continue };
            eprintln!("child: {line}");
        }
    });
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

/// The session once a run is attached to it: the server starts before the command loads its
/// tree, so the run is attached soon after the `studio:` line.
fn watched_session(addr: &str) -> serde_json::Value {
    // A hang catch of minutes: the run is attached in a moment.
    let deadline = std::time::Instant::now() + Duration::from_secs(180);
    loop {
        let session = get(addr, "/api/session");
        if session["watch"] == true {
            return session;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "no run is attached to the studio"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
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
    let session = watched_session(&addr);
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
    watched_session(&addr);
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
    watched_session(&addr);
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
    // The last messages seen, for the failure's message.
    let mut seen = std::collections::VecDeque::new();
    while std::time::Instant::now() < deadline {
        if let Ok(tungstenite::Message::Text(t)) = socket.read() {
            let m: serde_json::Value = serde_json::from_str(&t).unwrap();
            if m["type"] == "rewind" {
                LAST_REWIND.with(|r| *r.borrow_mut() = m["rewind"].clone());
            }
            if test(&m) {
                return m;
            }
            if seen.len() == 12 {
                seen.pop_front();
            }
            let mut brief = m.to_string();
            brief.truncate(300);
            seen.push_back(brief);
        }
    }
    panic!("no {what} within 20 s; the last messages: {seen:#?}");
}

/// A page's WebSocket to the studio at `addr`, read a little at a time.
fn page(addr: &str) -> Socket {
    let (socket, _) = tungstenite::connect(format!("ws://{addr}/ws")).unwrap();
    if let tungstenite::stream::MaybeTlsStream::Plain(s) = socket.get_ref() {
        s.set_read_timeout(Some(Duration::from_millis(200)))
            .unwrap();
    }
    socket
}

#[test]
fn run_forks_where_a_page_went_back_and_numbers_the_ticks_on_from_there() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("count.xml"), COUNTING).unwrap();
    let (mut child, addr) = start_watched(
        dir.path(),
        &[
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
        ],
    );
    let mut socket = page(&addr);
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
    let (mut child, addr) = start(
        dir.path(),
        &[
            "demo",
            "--speed",
            "10",
            "--studio",
            "0",
            "--studio-linger",
            "0",
        ],
    );
    let mut socket = page(&addr);
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

/// A navigator's tree that runs no ROS 2 action until a page sets `go`, then waits on
/// Nav2's `wait` server, which no process serves: its goal never leaves the client, and
/// the node runs on.
#[cfg(feature = "ros2")]
const WAITS_FOR_GO: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="go := false"/>
      <Inverter>
        <KeepRunningUntilFailure>
          <ScriptCondition code="go == false"/>
        </KeepRunningUntilFailure>
      </Inverter>
      <Wait wait_duration="30" wait_for_server_timeout="600000"/>
    </Sequence>
  </BehaviorTree>
</root>"#;

/// A DDS domain no other test process uses, held while the socket lives: the UDP port of
/// the domain's participant 0 (7410 + 250 × domain), as in the ROS 2 tests.
#[cfg(feature = "ros2")]
fn free_domain() -> (u16, std::net::UdpSocket) {
    let start = (std::process::id() * 11) % 132;
    for i in 0..132 {
        let id = 100 + ((start + i) % 132) as u16;
        if let Ok(claim) = std::net::UdpSocket::bind(("0.0.0.0", 7410 + 250 * id)) {
            return (id, claim);
        }
    }
    panic!("no free DDS domain between 100 and 231");
}

/// Sends the navigator on `domain` a goal until it accepts one.
#[cfg(feature = "ros2")]
fn send_goal(domain: u16) -> neurotree_ros2::RosNode {
    use neurotree::robotics::Pose2D;
    use neurotree_ros2::msg::nav2_msgs::{NavigateToPose, NavigateToPoseGoal};
    use neurotree_ros2::nav2::convert::pose_stamped;
    use neurotree_ros2::{RosNode, RosOptions};

    let ros = RosNode::new("goal_sender", &RosOptions::loopback(domain)).unwrap();
    let client = ros
        .action_client::<NavigateToPose>("navigate_to_pose")
        .unwrap();
    // The first goals may go out before the navigator is discovered.
    for _ in 0..30 {
        let goal = NavigateToPoseGoal {
            pose: pose_stamped(Pose2D::new(3.0, 2.0, 0.0)),
            behavior_tree: String::new(),
        };
        let (request, _) = client.send_goal(goal).unwrap();
        for _ in 0..100 {
            match client.receive_goal_response(request).unwrap() {
                Some(response) => {
                    assert!(response.accepted, "the navigator rejected the goal");
                    return ros;
                }
                None => std::thread::sleep(Duration::from_millis(20)),
            }
        }
    }
    panic!("the navigator did not accept a goal");
}

/// The statuses of a page's `hello`, by node path.
#[cfg(feature = "ros2")]
fn statuses_by_path(hello: &serde_json::Value) -> std::collections::BTreeMap<String, String> {
    let nodes = hello["tree"]["nodes"].as_array().unwrap();
    let statuses = hello["statuses"].as_array().unwrap();
    nodes
        .iter()
        .map(|n| {
            let id = n["id"].as_u64().unwrap() as usize;
            (
                n["path"].as_str().unwrap().to_string(),
                statuses[id].as_str().unwrap().to_string(),
            )
        })
        .collect()
}

/// The id of the node at `path` in a page's `hello`.
#[cfg(feature = "ros2")]
fn node_id(hello: &serde_json::Value, path: &str) -> u64 {
    hello["tree"]["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["path"] == path)
        .unwrap_or_else(|| panic!("no node `{path}` in {}", hello["tree"]))["id"]
        .as_u64()
        .unwrap()
}

#[cfg(feature = "ros2")]
#[test]
fn the_ros2_navigator_goes_back_between_its_actions_and_says_why_not_while_one_runs() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("waits.xml"), WAITS_FOR_GO).unwrap();
    let (domain, _claim) = free_domain();
    let domain = domain.to_string();
    let (mut child, addr) = start_watched(
        dir.path(),
        &[
            "ros2",
            "navigator",
            "--tree",
            "waits.xml",
            "--domain",
            &domain,
            "--duration",
            "90",
            "--studio",
            "0",
            "--rewind-window",
            "50",
        ],
    );
    let mut socket = page(&addr);
    until(&mut socket, "the run", |m| {
        m["type"] == "hello" && !m["run"].is_null()
    });
    let _ros = send_goal(domain.parse().unwrap());

    // Waiting for `go`, the tree runs built-in nodes only: every tick is kept.
    until(&mut socket, "tick 6", |m| m["tick"].as_u64() >= Some(6));
    send(&mut socket, r#"{"type":"pause"}"#);
    let paused = until(&mut socket, "the pause", |m| m["type"] == "paused")["tick"]
        .as_u64()
        .unwrap();
    // Kept, or not with why.
    let kept_now =
        |r: &serde_json::Value| r["newest"].as_u64() == Some(paused) || !r["blocked"].is_null();
    if !kept_now(&last_rewind()) {
        until(&mut socket, "what the run keeps", |_| {
            kept_now(&last_rewind())
        });
    }
    assert!(last_rewind()["blocked"].is_null(), "{}", last_rewind());
    for _ in 0..2 {
        send(&mut socket, r#"{"type":"back"}"#);
    }
    let back = paused - 2;
    let rewound = until(&mut socket, "the run back", |m| {
        m["type"] == "rewind" && m["rewind"]["at"].as_u64() == Some(back)
    });
    assert_eq!(rewound["tick"].as_u64(), Some(back), "{rewound}");
    // A page that connects now is shown that tick, with its statuses.
    let mut late = page(&addr);
    let hello = until(&mut late, "the hello of the past tick", |m| {
        m["type"] == "hello" && !m["run"].is_null()
    });
    assert_eq!(hello["tick"].as_u64(), Some(back), "{}", hello["tick"]);
    assert_eq!(hello["rewind"]["at"].as_u64(), Some(back));
    let statuses = statuses_by_path(&hello);
    for (path, status) in [
        ("Sequence", "RUNNING"),
        ("Sequence/Script", "SUCCESS"),
        ("Sequence/Inverter", "RUNNING"),
        ("Sequence/Inverter/KeepRunningUntilFailure", "RUNNING"),
        ("Sequence/Wait", "IDLE"),
    ] {
        assert_eq!(statuses[path], status, "{path}: {statuses:?}");
    }
    drop(late);

    // From there, `go`: the fork runs the Wait action, whose goal is in flight.
    send(
        &mut socket,
        r#"{"type":"set","scope":0,"key":"go","value":true}"#,
    );
    send(&mut socket, r#"{"type":"continue"}"#);
    let wait = node_id(&hello, "Sequence/Wait");
    until(&mut socket, "Wait running", |m| {
        m["type"] == "tick"
            && m["changes"].as_array().is_some_and(|changes| {
                changes
                    .iter()
                    .any(|c| c[0].as_u64() == Some(wait) && c[1] == "RUNNING")
            })
    });
    send(&mut socket, r#"{"type":"pause"}"#);
    until(&mut socket, "the second pause", |m| m["type"] == "paused");
    let blocked = |r: &serde_json::Value| !r["blocked"].is_null();
    if !blocked(&last_rewind()) {
        until(&mut socket, "the tick that cannot be kept", |_| {
            blocked(&last_rewind())
        });
    }
    let why = last_rewind()["blocked"].as_str().unwrap().to_string();
    assert!(
        why.starts_with("Sequence/Wait: this stateful action is running"),
        "{why}"
    );
    send(&mut socket, r#"{"type":"back"}"#);
    let refused = until(&mut socket, "a refusal", |m| m["type"] == "refused");
    let why = refused["why"].as_str().unwrap();
    assert!(
        why.starts_with(
            "the run cannot go back from this tick: Sequence/Wait: this stateful action is running"
        ),
        "{refused}"
    );
    child.kill().unwrap();
    let _ = child.wait();
    let mut out = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    assert!(
        out.contains(&format!(
            "[navigator] back to tick {back}: the tree goes on from there"
        )),
        "{out}"
    );
}

#[test]
fn a_result_forced_from_a_page_is_a_line_of_the_run_and_ends_the_node_running() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("count.xml"), COUNTING).unwrap();
    let (mut child, addr) = start_watched(
        dir.path(),
        &[
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
        ],
    );
    let mut socket = page(&addr);
    let hello = until(&mut socket, "the run", |m| {
        m["type"] == "hello" && !m["run"].is_null()
    });
    let work = hello["tree"]["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["path"].as_str().unwrap().ends_with("Work"))
        .unwrap_or_else(|| panic!("no Work in {}", hello["tree"]))
        .clone();
    let id = work["id"].as_u64().unwrap();
    until(&mut socket, "tick 4", |m| m["tick"].as_u64() >= Some(4));
    send(&mut socket, r#"{"type":"pause"}"#);
    let paused = until(&mut socket, "the pause", |m| m["type"] == "paused")["tick"]
        .as_u64()
        .unwrap();
    send(
        &mut socket,
        &format!(r#"{{"type":"force","node":{id},"status":"FAILURE","until":"once"}}"#),
    );
    let listed = until(&mut socket, "the force listed", |m| m["type"] == "forces");
    assert_eq!(
        listed["forces"],
        serde_json::json!([{"node": id, "status": "FAILURE", "until": "once", "applied": null}])
    );
    send(&mut socket, r#"{"type":"step"}"#);
    let applied = until(&mut socket, "the force applied", |m| {
        m["type"] == "forces" && !m["forces"][0]["applied"].is_null()
    });
    assert_eq!(applied["forces"][0]["applied"], paused + 1, "{applied}");
    drop(socket);
    let mut out = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    // The root failed with the forced node: FAILURE ends the run (exit 2).
    assert_eq!(child.wait().unwrap().code(), Some(2), "{out}");
    let lines: Vec<&str> = out.lines().collect();
    let forced = serde_json::json!({"force": {
        "tick": paused + 1,
        "node": work["path"],
        "status": "FAILURE",
        "until": "once",
    }})
    .to_string();
    let at = lines
        .iter()
        .position(|l| *l == forced)
        .unwrap_or_else(|| panic!("no {forced} in\n{out}"));
    assert_eq!(
        lines[at + 1],
        format!(r#"{{"tick":{},"status":"FAILURE"}}"#, paused + 1)
    );
    assert_eq!(
        lines
            .iter()
            .filter(|l| l.starts_with(r#"{"force""#))
            .count(),
        1,
        "{out}"
    );
    // Work was running: the forced result halted it, and its own tick was not called.
    let summary: serde_json::Value = serde_json::from_str(lines.last().unwrap()).unwrap();
    let counts = &summary["summary"]["nodes"]["Work"];
    assert_eq!(counts["halts"], 1, "{summary}");
    assert_eq!(counts["ticks"], paused, "{summary}");
}

#[test]
fn demo_builds_its_tree_so_that_a_page_forces_a_result() {
    let dir = tempfile::tempdir().unwrap();
    // Served on after the run: on a loaded machine the page's pause can come late, the
    // forced failure can then end the run, and without a linger the demo would exit
    // before the page is sent the forced tick.
    let (mut child, addr) = start(
        dir.path(),
        &["demo", "--fast", "--studio", "0", "--studio-linger", "2"],
    );
    let mut socket = page(&addr);
    let hello = until(&mut socket, "the run", |m| {
        m["type"] == "hello" && !m["run"].is_null()
    });
    assert_eq!(hello["forcing"], true);
    let checker = hello["tree"]["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["path"] == "NavigateRecovery/NavigateWithReplanning/ProgressCheckerSelector")
        .unwrap_or_else(|| panic!("{}", hello["tree"]))["id"]
        .as_u64()
        .unwrap();
    send(&mut socket, r#"{"type":"pause"}"#);
    let paused = until(&mut socket, "the pause", |m| m["type"] == "paused")["tick"]
        .as_u64()
        .unwrap();
    send(
        &mut socket,
        &format!(r#"{{"type":"force","node":{checker},"status":"FAILURE"}}"#),
    );
    until(&mut socket, "the force listed", |m| m["type"] == "forces");
    send(&mut socket, r#"{"type":"step"}"#);
    // The tick and the list that says where the force applied, in either order.
    let (tick, applied) = (
        std::cell::RefCell::new(serde_json::Value::Null),
        std::cell::RefCell::new(serde_json::Value::Null),
    );
    until(&mut socket, "the forced tick and the force applied", |m| {
        if m["type"] == "tick" && m["tick"].as_u64() == Some(paused + 1) {
            *tick.borrow_mut() = m.clone();
        }
        if m["type"] == "forces" && !m["forces"][0]["applied"].is_null() {
            *applied.borrow_mut() = m.clone();
        }
        !tick.borrow().is_null() && !applied.borrow().is_null()
    });
    let (tick, applied) = (tick.into_inner(), applied.into_inner());
    assert_eq!(applied["forces"][0]["applied"], paused + 1, "{applied}");
    // The selector failed in that tick.
    let failed = tick["changes"]
        .as_array()
        .unwrap()
        .iter()
        .any(|c| c[0] == checker && c[1] == "FAILURE");
    assert!(failed, "{tick}");
    send(&mut socket, r#"{"type":"continue"}"#);
    drop(socket);
    child.wait().unwrap();
}
