//! One agent of a crowd watched: the pages list the crowd's agents (a page of them at a
//! time, searched by id or label) and watch one, with everything a single tree is watched
//! with; pausing it (or a breakpoint it meets) holds that agent alone while the rest of the
//! crowd runs on, or the whole crowd, as the page chose.
//!
//! The crowd is reached through [`Agents`], which a crowd type implements (the `neurotree`
//! crate does for its `Crowd`, the Bevy plugin for its agents), so that the studio does not
//! depend on the crowd. What watching costs: the watched agent's tree carries the studio's
//! observer and the others none; the list is rebuilt from the agents' ids only when
//! agents join or leave ([`Agents::membership`]), and pages are sent a page of it at a
//! time; a frame costs a lock and a few comparisons, plus, while a page is open, the
//! watched agent's blackboard and why it is awake.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use axum::extract::{Query, State};
use axum::http::StatusCode;
use axum::Json;
use neurotree_core::{Observer, Tree};
use serde::Deserialize;
use serde_json::{json, Value};

use super::Hub;

/// The most agents a page is sent at once.
pub const MAX_AGENTS_PAGE: usize = 200;

/// One agent as the pages list it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AgentEntry {
    /// What the crowd finds the agent by (a slot, an entity's bits).
    pub key: u64,
    /// The id pages show and choose it by (`data-agent`).
    pub id: String,
    /// What else pages show of it, and search it by (a name, the tree it runs).
    pub label: String,
}

/// A crowd the studio can watch one agent of: the hooks it needs, each touching one agent.
pub trait Agents {
    /// The context the agents' trees tick with.
    type Context;
    /// A number that changes whenever agents join or leave.
    fn membership(&self) -> u64;
    /// Appends every agent to `out` (called only when [`membership`](Self::membership)
    /// changed).
    fn list(&self, out: &mut Vec<AgentEntry>);
    /// The agent's tree, to read, without waking it.
    fn tree(&self, key: u64) -> Option<&Tree<Self::Context>>;
    /// The agent's tree, to write a page's blackboard edit in (which wakes it).
    fn tree_mut(&mut self, key: u64) -> Option<&mut Tree<Self::Context>>;
    /// Sets (or, `None`, removes) the observer on the agent's tree without waking it;
    /// gives back the one it replaced.
    fn set_observer(
        &mut self,
        key: u64,
        observer: Option<Box<dyn Observer>>,
    ) -> Option<Box<dyn Observer>>;
    /// Holds the agent still (no frame ticks it) or lets it go on.
    fn hold(&mut self, key: u64, held: bool);
}

/// What the pages read of the crowd and ask of it.
#[derive(Default)]
pub(crate) struct Desk {
    active: AtomicBool,
    together: AtomicBool,
    state: Mutex<DeskState>,
}

#[derive(Default)]
struct DeskState {
    /// In key order.
    list: Arc<Vec<AgentEntry>>,
    watched: Option<AgentEntry>,
    /// Why the watched agent is awake, or that it sleeps, or that it is held.
    awake: Option<String>,
    /// The agent a page chose, until the run switches to it.
    wanted: Option<String>,
}

impl Desk {
    /// `true` once a crowd is watched.
    pub(crate) fn is_active(&self) -> bool {
        self.active.load(Ordering::Acquire)
    }

    fn lock(&self) -> MutexGuard<'_, DeskState> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A page of the agents whose id or label holds `query` (any case), from `offset`.
    fn page(&self, query: &str, offset: usize, limit: usize) -> Value {
        if !self.active.load(Ordering::Acquire) {
            return json!({"crowd": false});
        }
        let state = self.lock();
        let list = Arc::clone(&state.list);
        let watched = state.watched.clone();
        let awake = state.awake.clone();
        drop(state);
        let query = query.trim().to_lowercase();
        let hits = |a: &&AgentEntry| {
            query.is_empty()
                || a.id.to_lowercase().contains(&query)
                || a.label.to_lowercase().contains(&query)
        };
        let limit = limit.clamp(1, MAX_AGENTS_PAGE);
        let mut matches = 0usize;
        let mut agents = Vec::new();
        for a in list.iter().filter(hits) {
            if matches >= offset && agents.len() < limit {
                agents.push(json!({"id": a.id, "label": a.label}));
            }
            matches += 1;
        }
        json!({
            "crowd": true,
            "total": list.len(),
            "matches": matches,
            "offset": offset,
            "agents": agents,
            "watched": watched.map(|w| json!({"id": w.id, "label": w.label})),
            "awake": awake,
            "together": self.together.load(Ordering::Acquire),
        })
    }
}

/// The query of `GET /api/agents`.
#[derive(Deserialize)]
pub(crate) struct AgentsQuery {
    #[serde(default)]
    q: String,
    #[serde(default)]
    offset: usize,
    limit: Option<usize>,
}

/// `GET /api/agents?q=&offset=&limit=`: a page of the agents, the one watched, why it is
/// awake (PROTOCOL.md, "Agents").
pub(crate) async fn agents(
    State(shared): State<Arc<crate::server::Shared>>,
    Query(q): Query<AgentsQuery>,
) -> Json<Value> {
    let limit = q.limit.unwrap_or(100);
    Json(shared.hub.desk.page(&q.q, q.offset, limit))
}

/// The body of `POST /api/agents/watch`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Choice {
    id: String,
}

/// `POST /api/agents/watch {"id"}`: watch that agent from the next frame.
pub(crate) async fn choose(
    State(shared): State<Arc<crate::server::Shared>>,
    Json(choice): Json<Choice>,
) -> Result<Json<Value>, (StatusCode, Json<Value>)> {
    let desk = &shared.hub.desk;
    let mut state = desk.lock();
    if !desk.active.load(Ordering::Acquire) || !state.list.iter().any(|a| a.id == choice.id) {
        let why = format!("no agent `{}` in the crowd watched", choice.id);
        return Err((StatusCode::NOT_FOUND, Json(json!({"error": why}))));
    }
    state.wanted = Some(choice.id);
    drop(state);
    Ok(Json(json!({"ok": true})))
}

/// The body of `POST /api/agents/together`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Together {
    together: bool,
}

/// `POST /api/agents/together {"together"}`: whether a pause (or a breakpoint) of the
/// watched agent stands the whole crowd still, or that agent alone.
pub(crate) async fn together(
    State(shared): State<Arc<crate::server::Shared>>,
    Json(t): Json<Together>,
) -> Json<Value> {
    shared
        .hub
        .desk
        .together
        .store(t.together, Ordering::Release);
    shared.hub.bump();
    Json(json!({"together": t.together}))
}

/// The run's side of a watched crowd (made by
/// [`Studio::watch_crowd`](crate::Studio::watch_crowd)): call
/// [`before_frame`](Self::before_frame) before each frame, and run the frame only if it
/// returns `true`; call [`after_frame`](Self::after_frame) after it.
pub struct CrowdWatch {
    hub: Arc<Hub>,
    name: String,
    membership: Option<u64>,
    list: Arc<Vec<AgentEntry>>,
    watched: Option<u64>,
    /// The observer the watched agent had before the studio's, given back when another is
    /// watched.
    prior: Option<Box<dyn Observer>>,
    held: bool,
    standing: bool,
}

impl std::fmt::Debug for CrowdWatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CrowdWatch")
            .field("name", &self.name)
            .field("watched", &self.watched)
            .finish_non_exhaustive()
    }
}

impl CrowdWatch {
    pub(crate) fn new(hub: Arc<Hub>, name: &str) -> Self {
        hub.defer_breaks();
        hub.desk.active.store(true, Ordering::Release);
        Self {
            hub,
            name: name.to_string(),
            membership: None,
            list: Arc::default(),
            watched: None,
            prior: None,
            held: false,
            standing: false,
        }
    }

    /// Before a frame: the agent list brought up to date if agents joined or left, the
    /// agent a page chose watched (the first agent if none is), the pages' blackboard
    /// edits written, and the watched agent held or let go as the pages paused or
    /// continued it. `false`: the pages stood the whole crowd still; skip the frame.
    pub fn before_frame<A: Agents>(&mut self, crowd: &mut A) -> bool {
        let membership = crowd.membership();
        if self.membership != Some(membership) {
            self.membership = Some(membership);
            let mut list = Vec::new();
            crowd.list(&mut list);
            list.sort_by_key(|a| a.key);
            self.list = Arc::new(list);
            self.hub.desk.lock().list = Arc::clone(&self.list);
            if let Some(key) = self.watched {
                if crowd.tree(key).is_none() {
                    // It left, with the observer; pages no longer show it, whether or
                    // not another is left to watch.
                    self.watched = None;
                    self.prior = None;
                    self.held = false;
                    let mut desk = self.hub.desk.lock();
                    desk.watched = None;
                    desk.awake = None;
                }
            }
        }
        let wanted = self.hub.desk.lock().wanted.take();
        let target = match wanted {
            Some(id) => self.list.iter().find(|a| a.id == id).map(|a| a.key),
            None if self.watched.is_none() => self.list.first().map(|a| a.key),
            None => None,
        };
        if let Some(key) = target.filter(|k| Some(*k) != self.watched) {
            self.switch(crowd, key);
        }
        let Some(key) = self.watched else {
            return true;
        };
        if self.hub.has_requests() {
            if let Some(tree) = crowd.tree_mut(key) {
                self.hub.apply_edits(tree);
            }
        }
        self.standing = self.hub.stands(self.standing);
        let together = self.hub.desk.together.load(Ordering::Acquire);
        let hold = self.standing && !together;
        if hold != self.held {
            crowd.hold(key, hold);
            self.held = hold;
        }
        if self.standing {
            // Edits made while it stands are shown at once.
            if let Some(tree) = crowd.tree(key) {
                self.hub.publish(tree);
            }
        }
        !(self.standing && together)
    }

    /// After a frame: the watched agent's blackboard, failure and why it is awake, for the
    /// pages attached (nothing when none is).
    pub fn after_frame<A: Agents>(&mut self, crowd: &A) {
        let Some(key) = self.watched else {
            return;
        };
        if self.hub.pages() == 0 {
            return;
        }
        let Some(tree) = crowd.tree(key) else {
            return;
        };
        self.hub.publish(tree);
        let awake = if self.held {
            "held: paused in the studio".to_string()
        } else {
            match tree.why_awake() {
                Some(why) => format!("awake: {why}"),
                None => "asleep".to_string(),
            }
        };
        let mut desk = self.hub.desk.lock();
        if desk.awake.as_deref() != Some(awake.as_str()) {
            desk.awake = Some(awake);
            drop(desk);
            self.hub.bump();
        }
    }

    /// The id of the agent watched.
    pub fn watched(&self) -> Option<&str> {
        let key = self.watched?;
        self.list
            .iter()
            .find(|a| a.key == key)
            .map(|a| a.id.as_str())
    }

    /// Watches the agent with id `id` from now on; `false` if the crowd has none (as of
    /// the last [`before_frame`](Self::before_frame)).
    pub fn watch<A: Agents>(&mut self, crowd: &mut A, id: &str) -> bool {
        let Some(key) = self.list.iter().find(|a| a.id == id).map(|a| a.key) else {
            return false;
        };
        if Some(key) != self.watched {
            self.switch(crowd, key);
        }
        true
    }

    /// Moves the studio's observer from the agent watched to `key`'s, which the pages are
    /// shown at once, as its tree stands (asleep or not).
    fn switch<A: Agents>(&mut self, crowd: &mut A, key: u64) {
        if let Some(old) = self.watched.take() {
            drop(crowd.set_observer(old, self.prior.take()));
            if self.held {
                crowd.hold(old, false);
                self.held = false;
            }
        }
        let Some(entry) = self.list.iter().find(|a| a.key == key).cloned() else {
            return;
        };
        let Some(tree) = crowd.tree(key) else {
            return;
        };
        let name = if entry.label.is_empty() {
            format!("{} · agent {}", self.name, entry.id)
        } else {
            format!("{} · agent {} ({})", self.name, entry.id, entry.label)
        };
        let observer = self.hub.attach(tree, &name);
        self.hub.publish(tree);
        let awake = match tree.why_awake() {
            Some(why) => format!("awake: {why}"),
            None => "asleep".to_string(),
        };
        self.prior = crowd.set_observer(key, Some(Box::new(observer)));
        self.watched = Some(key);
        let mut desk = self.hub.desk.lock();
        desk.watched = Some(entry);
        desk.awake = Some(awake);
    }
}
