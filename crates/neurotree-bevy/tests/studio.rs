//! The plugin's studio, as a page drives it: a pause holds the agent watched while the
//! others walk on; with the whole crowd asked to stand still, no agent walks; continued,
//! every agent walks again.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use bevy_app::App;
use bevy_ecs::prelude::*;
use bevy_ecs::query::QueryItem;
use neurotree::prelude::*;
use neurotree_bevy::{AgentContext, NeuroTreePlugin, TreeAgent, TreeStudio};

/// Steps walked, written back by the plugin.
#[derive(Component, Clone, Copy, Default, PartialEq, Debug)]
struct Steps(u32);

#[derive(Default)]
struct Walker {
    steps: u32,
}

impl AgentContext for Walker {
    type Components = &'static mut Steps;
    type Shared = ();
    fn load(&mut self, steps: &QueryItem<'_, '_, Self::Components>, _: &()) {
        self.steps = steps.0;
    }
    fn store(&self, steps: &mut QueryItem<'_, '_, Self::Components>) {
        steps.0 = self.steps;
    }
}

/// A step every frame, forever.
fn walk() -> std::sync::Arc<Blueprint<Walker>> {
    Blueprint::<Walker>::builder()
        .keep_running_until_failure("forever", |k| {
            k.action("step", |w: &mut Walker| {
                w.steps += 1;
                Status::Success
            })
        })
        .build_shared()
        .unwrap()
}

/// The page's socket.
type Socket = tungstenite::WebSocket<tungstenite::stream::MaybeTlsStream<TcpStream>>;

/// The messages of `socket` until one of `kind`, updating the app between reads; failing
/// only after minutes, a catch for a page never told, not a bound on how long it takes.
fn until_message(app: &mut App, socket: &mut Socket, kind: &str) {
    let deadline = Instant::now() + Duration::from_secs(180);
    loop {
        assert!(Instant::now() < deadline, "no `{kind}` message");
        app.update();
        match socket.read() {
            Ok(tungstenite::Message::Text(t)) => {
                let m: serde_json::Value = serde_json::from_str(&t).unwrap();
                if m["type"] == kind {
                    return;
                }
            }
            Ok(_) => {}
            Err(tungstenite::Error::Io(e))
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) => {}
            Err(e) => panic!("the socket failed: {e}"),
        }
    }
}

fn post(addr: &str, target: &str, body: &str) -> String {
    let mut s = TcpStream::connect(addr).unwrap();
    write!(
        s,
        "POST {target} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    let mut text = String::new();
    s.read_to_string(&mut text).unwrap();
    text
}

fn steps(app: &mut App, agents: &[Entity]) -> Vec<u32> {
    agents
        .iter()
        .map(|&e| app.world().get::<Steps>(e).unwrap().0)
        .collect()
}

#[test]
fn a_page_holds_the_agent_watched_alone_or_the_whole_crowd() {
    let mut app = App::new();
    app.add_plugins(NeuroTreePlugin::new(Registry::<Walker>::new()).with_studio(0, "walkers"));
    let tree = walk();
    let agents: Vec<Entity> = (0..5)
        .map(|_| {
            app.world_mut()
                .spawn((Steps(0), TreeAgent::new(tree.clone(), Walker::default())))
                .id()
        })
        .collect();
    app.finish();
    app.cleanup();
    app.update();
    let url = app.world().resource::<TreeStudio<Walker>>().url();
    let addr = url
        .strip_prefix("http://")
        .and_then(|u| u.strip_suffix('/'))
        .unwrap()
        .to_string();
    let (mut socket, _) = tungstenite::connect(format!("ws://{addr}/ws")).unwrap();
    if let tungstenite::stream::MaybeTlsStream::Plain(s) = socket.get_ref() {
        s.set_read_timeout(Some(Duration::from_millis(50))).unwrap();
    }
    until_message(&mut app, &mut socket, "hello");

    // Paused: the first agent, watched, stands still; the others walk on.
    socket
        .send(tungstenite::Message::Text(r#"{"type":"pause"}"#.into()))
        .unwrap();
    until_message(&mut app, &mut socket, "paused");
    let before = steps(&mut app, &agents);
    for _ in 0..5 {
        app.update();
    }
    let after = steps(&mut app, &agents);
    assert_eq!(after[0], before[0], "the agent watched is held");
    for i in 1..5 {
        assert_eq!(after[i], before[i] + 5, "agent {i} walks on");
    }

    // The whole crowd with it: nobody walks.
    let answer = post(&addr, "/api/agents/together", r#"{"together":true}"#);
    assert!(answer.starts_with("HTTP/1.1 200"), "{answer}");
    app.update();
    let before = steps(&mut app, &agents);
    for _ in 0..5 {
        app.update();
    }
    assert_eq!(steps(&mut app, &agents), before);

    // Continued: every agent walks, the one watched too.
    socket
        .send(tungstenite::Message::Text(r#"{"type":"continue"}"#.into()))
        .unwrap();
    until_message(&mut app, &mut socket, "resumed");
    let before = steps(&mut app, &agents);
    for _ in 0..5 {
        app.update();
    }
    let after = steps(&mut app, &agents);
    for i in 0..5 {
        assert_eq!(after[i], before[i] + 5, "agent {i} walks");
    }
}
