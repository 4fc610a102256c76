//! One page's WebSocket: the first message tells everything, later ones what changed;
//! the page's controls are checked before they reach the run.

use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::{Duration, Instant};

use axum::extract::ws::{Message, WebSocket};
use neurotree_core::NodeStatus;
use serde::Deserialize;
use serde_json::{json, Value};

use super::hub::{scores, statuses, Edit, Hub, Inner};
use super::rewind::Travel;

/// The largest message a page may send: controls are a few dozen bytes.
pub const MAX_PAGE_MESSAGE: usize = 64 * 1024;
/// The most messages a page may send in a second before the rest are refused.
pub const MAX_PAGE_RATE: u32 = 100;
/// The largest scene sent to pages, as JSON: a bigger one is replaced by the reason.
pub const MAX_SCENE_BYTES: usize = 1024 * 1024;
/// `tick` messages a page that acknowledges may have unacknowledged: two, so that one
/// travels while the page draws the other, and no more, so that none goes stale in a queue.
const IN_FLIGHT: u8 = 2;

/// What a page may send (PROTOCOL.md).
#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
enum FromPage {
    Pause,
    Step,
    Continue,
    /// Show the kept tick before the one shown (paused only).
    Back,
    /// Show the kept tick after the one shown (paused only).
    Forward,
    Breakpoint {
        node: u64,
        when: String,
    },
    /// Force the node's next result (`until`: `once`, the default, or `cleared`), or
    /// clear its force (`status`: `off`).
    Force {
        node: u64,
        status: String,
        until: Option<String>,
    },
    Set {
        scope: u32,
        key: String,
        value: Value,
    },
    /// The page applied the `tick` (or `hello`) it was sent: the next may go.
    Ack {
        #[allow(dead_code)]
        tick: u64,
    },
}

/// What this page was last sent, to send it only what changed.
#[derive(Default)]
struct Sent {
    generation: Option<u64>,
    statuses: Vec<&'static str>,
    /// `(id, bits)` of the nodes scored.
    scores: Vec<(usize, u64)>,
    tick: u64,
    blackboards: u64,
    failure: u64,
    paused: u64,
    breakpoints: u64,
    forces: u64,
    rewind: u64,
    scene: u64,
    refusal: u64,
    edits: u64,
    ended: bool,
}

/// Serves one page until it leaves.
pub(crate) async fn serve_page(mut socket: WebSocket, hub: Arc<Hub>) {
    hub.page_joined();
    let mut version = hub.subscribe();
    let mut sent = Sent::default();
    let mut window = (Instant::now(), 0u32);
    // A page that acknowledges what it drew (PROTOCOL.md, `ack`) is sent a `tick` only
    // once it drew the last: the socket then never holds a queue of stale ticks, and the
    // page is always shown the newest. A page that never acknowledges is sent every change.
    let mut acks = false;
    let mut in_flight: u8 = 0;
    'page: loop {
        for text in changes(&hub, &mut sent, !acks || in_flight < IN_FLIGHT) {
            if text.starts_with("{\"type\":\"tick\"") || text.starts_with("{\"tree\"") {
                in_flight = in_flight.saturating_add(1);
            }
            if socket.send(Message::Text(text.into())).await.is_err() {
                break 'page;
            }
        }
        tokio::select! {
            changed = version.changed() => {
                if changed.is_err() {
                    break;
                }
            }
            incoming = socket.recv() => {
                let Some(Ok(message)) = incoming else { break };
                let text = match message {
                    Message::Text(t) => t,
                    Message::Close(_) => break,
                    Message::Ping(_) | Message::Pong(_) => continue,
                    Message::Binary(_) => {
                        if refuse(&hub, &mut socket, "binary messages are not understood").await {
                            break;
                        }
                        continue;
                    }
                };
                // An awaited acknowledgement is part of the flow the server set, not a
                // message of the page's own: it is not counted against the rate.
                if in_flight > 0 && text.len() < 64 && text.contains("\"ack\"") {
                    if let Ok(FromPage::Ack { .. }) = serde_json::from_str::<FromPage>(&text) {
                        acks = true;
                        in_flight -= 1;
                        continue;
                    }
                }
                if window.0.elapsed() >= Duration::from_secs(1) {
                    window = (Instant::now(), 0);
                }
                window.1 += 1;
                let why = if window.1 > MAX_PAGE_RATE {
                    Some(format!("more than {MAX_PAGE_RATE} messages a second"))
                } else if text.len() > MAX_PAGE_MESSAGE {
                    Some(format!("a message over {MAX_PAGE_MESSAGE} bytes"))
                } else {
                    match serde_json::from_str::<FromPage>(&text) {
                        Ok(m) => control(&hub, m),
                        Err(e) => Some(format!("not a message the studio knows: {e}")),
                    }
                };
                if let Some(why) = why {
                    // Past the rate, refusals are counted but not answered: answering a
                    // flood would be a flood.
                    let quiet = window.1 > MAX_PAGE_RATE + 1;
                    hub.count_refused();
                    if !quiet && refuse(&hub, &mut socket, &why).await {
                        break;
                    }
                }
            }
        }
    }
    hub.page_left();
}

/// Tells the page its message was refused; `true` if the page is gone.
async fn refuse(_hub: &Hub, socket: &mut WebSocket, why: &str) -> bool {
    let text = json!({"type": "refused", "why": why}).to_string();
    socket.send(Message::Text(text.into())).await.is_err()
}

/// Carries out a page's control; the reason it was refused, if it was.
fn control(hub: &Hub, message: FromPage) -> Option<String> {
    match message {
        FromPage::Pause => hub.pause(),
        FromPage::Step => hub.step(),
        FromPage::Continue => hub.resume(),
        FromPage::Back => return hub.travel(Travel::Back).err(),
        FromPage::Forward => return hub.travel(Travel::Forward).err(),
        FromPage::Breakpoint { node, when } => {
            let (before, status) = match when.as_str() {
                "before" => (true, None),
                "off" => (false, None),
                "RUNNING" => (false, Some(NodeStatus::Running)),
                "SUCCESS" => (false, Some(NodeStatus::Success)),
                "FAILURE" => (false, Some(NodeStatus::Failure)),
                "SKIPPED" => (false, Some(NodeStatus::Skipped)),
                other => {
                    return Some(format!(
                        "a breakpoint is `before`, a status or `off`, not `{other}`"
                    ))
                }
            };
            if !hub.set_breakpoint(node, status, before) {
                return Some(format!("no node {node} in the tree watched"));
            }
        }
        FromPage::Force {
            node,
            status,
            until,
        } => return hub.force(node, &status, until.as_deref()).err(),
        FromPage::Ack { .. } => {
            return Some("an `ack` answers a `tick` or `hello`; none was awaited".into())
        }
        FromPage::Set { scope, key, value } => {
            // Whether the value fits the entry is for the run to say, at the field.
            if key.is_empty() {
                return Some("`set` takes the key of the entry to write".into());
            }
            hub.edit(Edit { scope, key, value });
        }
    }
    None
}

/// The messages that bring the page from what it was sent to what is now; the statuses
/// (`tick`) only if `ticks` (else they wait, and are sent as one later).
fn changes(hub: &Hub, sent: &mut Sent, ticks: bool) -> Vec<String> {
    let inner = hub.lock();
    let mut out = Vec::new();
    let Some(run) = &inner.run else {
        if sent.generation != Some(inner.generation) {
            sent.generation = Some(inner.generation);
            out.push(json!({"type": "hello", "run": null}).to_string());
        }
        return out;
    };
    // The tick first: statuses published after it are at worst newer than it says, and go
    // out again with the next tick's number.
    let tick = run.cell.shown_tick.load(Ordering::Acquire);
    let now = statuses(&run.cell);
    let scored = scores(&run.cell);
    if sent.generation != Some(inner.generation) {
        let forces = (hub.forces.list(), hub.forces.hooked());
        out.push(hello(&inner, run, &now, &scored, tick, forces));
        *sent = Sent {
            generation: Some(inner.generation),
            statuses: now,
            scores: scored,
            tick,
            blackboards: inner.blackboards.0,
            failure: inner.failure.0,
            paused: inner.paused_version,
            breakpoints: inner.breakpoints_version,
            forces: hub.forces.version(),
            rewind: inner.rewind.0,
            scene: inner.scene.0,
            refusal: inner.refusal.0,
            edits: inner.refused_edits.0,
            ended: inner.ended.is_some(),
        };
        return out;
    }
    let changed: Vec<Value> = now
        .iter()
        .zip(&sent.statuses)
        .enumerate()
        .filter(|(_, (a, b))| a != b)
        .map(|(i, (a, _))| json!([i, a]))
        .collect();
    if ticks && (!changed.is_empty() || tick != sent.tick) {
        let mut message = json!({"type": "tick", "tick": tick, "changes": changed});
        // Only a tree that has scores (a UtilitySelector's) is sent them.
        if scored != sent.scores {
            // Scores gone (a kept tick shown from before a node was scored) are `null`.
            let gone = sent
                .scores
                .iter()
                .filter(|(i, _)| !scored.iter().any(|(j, _)| i == j))
                .map(|&(i, _)| json!([i, null]));
            let new: Vec<Value> = scored
                .iter()
                .filter(|s| !sent.scores.contains(s))
                .map(|&(i, bits)| json!([i, f64::from_bits(bits)]))
                .chain(gone)
                .collect();
            message["scores"] = Value::Array(new);
            sent.scores = scored;
        }
        out.push(message.to_string());
        sent.statuses = now;
        sent.tick = tick;
    }
    // A scene goes with the ticks, at their pace: a page slower than the run is sent the
    // newest, never a queue of them.
    if ticks && sent.scene != inner.scene.0 {
        sent.scene = inner.scene.0;
        out.push(scene_message(&inner, tick));
    }
    if sent.refusal != inner.refusal.0 {
        sent.refusal = inner.refusal.0;
        out.push(json!({"type": "refused", "why": inner.refusal.1}).to_string());
    }
    if sent.edits != inner.refused_edits.0 {
        sent.edits = inner.refused_edits.0;
        out.push(json!({"type": "edits", "refused": inner.refused_edits.1}).to_string());
    }
    if sent.rewind != inner.rewind.0 {
        sent.rewind = inner.rewind.0;
        out.push(json!({"type": "rewind", "tick": tick, "rewind": inner.rewind.1}).to_string());
    }
    if sent.blackboards != inner.blackboards.0 {
        sent.blackboards = inner.blackboards.0;
        out.push(
            json!({"type": "blackboards", "tick": tick, "scopes": inner.blackboards.1}).to_string(),
        );
    }
    if sent.failure != inner.failure.0 {
        sent.failure = inner.failure.0;
        out.push(json!({"type": "failure", "tick": tick, "failure": inner.failure.1}).to_string());
    }
    if sent.breakpoints != inner.breakpoints_version {
        sent.breakpoints = inner.breakpoints_version;
        out.push(json!({"type": "breakpoints", "breakpoints": Hub::breakpoints(run)}).to_string());
    }
    let forces = hub.forces.version();
    if sent.forces != forces {
        sent.forces = forces;
        out.push(json!({"type": "forces", "forces": hub.forces.list()}).to_string());
    }
    if sent.paused != inner.paused_version {
        sent.paused = inner.paused_version;
        out.push(match &inner.paused {
            Some(p) => json!({"type": "paused", "tick": tick, "paused": p}).to_string(),
            None => json!({"type": "resumed", "tick": tick}).to_string(),
        });
    }
    if let (Some(status), false) = (inner.ended, sent.ended) {
        sent.ended = true;
        out.push(json!({"type": "ended", "tick": tick, "status": status}).to_string());
    }
    out
}

fn hello(
    inner: &Inner,
    run: &super::hub::Run,
    statuses: &[&str],
    scored: &[(usize, u64)],
    tick: u64,
    (forces, hub_forcing): (Value, bool),
) -> String {
    // The tree is serialized once per attach and spliced in, not rebuilt per page.
    let rest = json!({
        "type": "hello",
        "run": {"name": run.name},
        "tick": tick,
        "statuses": statuses,
        "scores": scored.iter().map(|&(i, bits)| json!([i, f64::from_bits(bits)])).collect::<Vec<_>>(),
        "paused": inner.paused,
        "breakpoints": Hub::breakpoints(run),
        "forces": forces,
        "forcing": hub_forcing,
        "blackboards": inner.blackboards.1,
        "failure": inner.failure.1,
        "ended": inner.ended,
        "rewind": inner.rewind.1,
        "edits": inner.refused_edits.1,
    })
    .to_string();
    // `rest` is a JSON object: `{"type":…}`; the tree and the scene go in as its first
    // members.
    let scene = match &inner.scene.1 {
        Ok(scene) => scene,
        Err(_) => "null",
    };
    format!("{{\"tree\":{},\"scene\":{scene},{}", run.tree, &rest[1..])
}

/// `{"type": "scene", …}`: the scene spliced in as it was serialized once for all pages.
fn scene_message(inner: &Inner, tick: u64) -> String {
    match &inner.scene.1 {
        Ok(scene) => format!("{{\"type\":\"scene\",\"tick\":{tick},\"scene\":{scene}}}"),
        Err(why) => {
            let why = (!why.is_empty()).then_some(why);
            json!({"type": "scene", "tick": tick, "scene": null, "why": why}).to_string()
        }
    }
}
