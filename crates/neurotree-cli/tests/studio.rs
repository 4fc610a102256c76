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
