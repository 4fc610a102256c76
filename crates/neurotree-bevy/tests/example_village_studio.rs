//! The village example with `--studio 0`, as a person runs it: it prints the studio's
//! address, whose page answers and lists the villagers, watching the first; it runs until
//! it is killed.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

/// Kills the example however the test ends.
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// `GET target` from `addr`: the status line and the body.
fn get(addr: &str, target: &str) -> (String, String) {
    let mut stream = TcpStream::connect(addr).expect("the studio accepts");
    stream
        .set_read_timeout(Some(Duration::from_secs(60)))
        .unwrap();
    write!(
        stream,
        "GET {target} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut text = String::new();
    stream.read_to_string(&mut text).unwrap();
    let (head, body) = text.split_once("\r\n\r\n").unwrap_or((&text, ""));
    (
        head.lines().next().unwrap_or("").to_string(),
        body.to_string(),
    )
}

#[test]
fn the_village_with_a_studio_prints_its_address_and_serves_the_villagers() {
    // As typed in the guide, in the profile the tests run in; standard input closed, which
    // the example does not read.
    let child = Command::new(env!("CARGO"))
        .args([
            "run",
            "--quiet",
            "-p",
            "neurotree-bevy",
            "--example",
            "village",
            "--",
            "--studio",
            "0",
        ])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("cargo runs the example");
    let mut child = Killed(child);
    let stdout = child.0.stdout.take().unwrap();
    let (send, lines) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if send.send(line).is_err() {
                break;
            }
        }
    });
    // A bound for a wedged build, not a measurement: the example may be compiled first.
    let line = lines
        .recv_timeout(Duration::from_secs(900))
        .expect("the example prints its first line");
    let addr = line
        .strip_prefix("studio: http://")
        .and_then(|rest| rest.strip_suffix('/'))
        .unwrap_or_else(|| panic!("not the studio's address: {line}"));
    assert!(addr.starts_with("127.0.0.1:"), "{line}");
    let (status, page) = get(addr, "/");
    assert!(status.contains(" 200 "), "{status}");
    assert!(page.contains("<title>NeuroTree Studio</title>"), "{page}");
    // The villagers, a page of them, the first one watched.
    let (status, agents) = get(addr, "/api/agents?limit=5");
    assert!(status.contains(" 200 "), "{status}");
    let agents: serde_json::Value = serde_json::from_str(&agents).unwrap();
    assert_eq!(agents["crowd"], true);
    assert_eq!(agents["total"], 1000);
    assert_eq!(agents["agents"].as_array().unwrap().len(), 5);
    assert_eq!(agents["watched"]["id"], agents["agents"][0]["id"]);
    // Still running: killed, not ended.
    assert!(child.0.try_wait().unwrap().is_none());
}
