//! The state pages read and the controls they set, shared by the tick thread and the
//! server's tasks.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicU8, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::Duration;

use neurotree_core::{NodeId, NodeStatus, Observer, Reason, ScopeId, Status, StatusChange, Tree};
use serde::Serialize;
use serde_json::{json, Value};

use super::rewind::Travel;
use super::values;
use crate::view::{status_name, status_of_byte, TreeView};

/// A breakpoint's byte: stop before the node is ticked.
const BEFORE: u8 = 0x80;
/// No breakpoint.
const NONE: u8 = 0xff;
/// No score: a NaN, which no score is (a selector refuses one).
pub(crate) const NO_SCORE: u64 = u64::MAX;

/// Why the run stands still (PROTOCOL.md, "Paused").
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub(crate) struct Paused {
    pub why: &'static str,
    pub node: Option<u32>,
    pub status: Option<&'static str>,
}

/// A blackboard edit from a page, applied between ticks.
#[derive(Clone, Debug)]
pub(crate) struct Edit {
    pub scope: u32,
    pub key: String,
    pub value: Value,
}

/// A page's edit that was refused, as pages are told it: the field it was typed in, and
/// why.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub(crate) struct RefusedEdit {
    pub scope: u32,
    pub key: String,
    pub why: String,
}

/// What a page asked of the run, done between ticks by the run's thread.
#[derive(Clone, Debug)]
pub(crate) enum Request {
    /// Write a blackboard entry.
    Edit(Edit),
    /// Show an earlier or later kept tick (only while paused between ticks).
    Travel(Travel),
}

/// What the observer writes in the tick, per node, read by the pages' tasks without a
/// lock: its status, the last status other than Idle it had in the tick under way, what
/// the pages are shown, and its breakpoint.
pub(crate) struct RunCell {
    pub statuses: Box<[AtomicU8]>,
    pub touched: Box<[AtomicU8]>,
    /// As of the end of the latest tick (or of the breakpoint holding it): the status if
    /// not Idle, else how the node ended in that tick, so that a tree whose nodes complete
    /// and are reset within each tick does not show as all Idle.
    pub shown: Box<[AtomicU8]>,
    pub breakpoints: Box<[AtomicU8]>,
    /// The last score each node was given (a Utility's, by its UtilitySelector), as the
    /// bits of an `f64`; [`NO_SCORE`] for a node never scored.
    pub scores: Box<[AtomicU64]>,
    pub tick: AtomicU64,
    /// The tick whose end (or breakpoint) `shown` is as of: pages are sent this one, not
    /// `tick`, which a tick under way has already counted, so that a page reading between
    /// a tick's start and its end is not sent the new tick with the old statuses.
    pub shown_tick: AtomicU64,
}

impl RunCell {
    fn publish_shown(&self) {
        for ((shown, status), touched) in self.shown.iter().zip(&*self.statuses).zip(&*self.touched)
        {
            let s = status.load(Ordering::Acquire);
            let t = if s == NodeStatus::Idle as u8 {
                touched.load(Ordering::Acquire)
            } else {
                s
            };
            shown.store(t, Ordering::Release);
        }
        self.shown_tick
            .store(self.tick.load(Ordering::Acquire), Ordering::Release);
    }
}

/// The run being watched.
pub(crate) struct Run {
    pub name: String,
    /// The TreeView, serialized once.
    pub tree: Arc<str>,
    pub paths: Vec<String>,
    pub cell: Arc<RunCell>,
}

/// What changes under the lock, each part with a version so that a page sends a part only
/// when it changed.
pub(crate) struct Inner {
    /// Bumped when another run (or a reload) is attached: pages then send `hello`.
    pub generation: u64,
    pub run: Option<Run>,
    pub blackboards: (u64, Value),
    pub failure: (u64, Value),
    pub paused: Option<Paused>,
    pub paused_version: u64,
    pub breakpoints_version: u64,
    pub ended: Option<&'static str>,
    /// The kept ticks, as pages are told them (PROTOCOL.md, "Rewind").
    pub rewind: (u64, Value),
    /// The scene of the tick shown, as JSON, or why none is shown (PROTOCOL.md, "Scene").
    pub scene: (u64, Result<Arc<str>, String>),
    /// A page's request the run refused when it came to do it (a travel past the kept
    /// ticks, asked for before the pages heard where the run stands): told to every page.
    pub refusal: (u64, String),
    /// The pages' blackboard edits refused, each with why, until the entry is edited
    /// again and the edit applies (PROTOCOL.md, "edits").
    pub refused_edits: (u64, Vec<RefusedEdit>),
    pause_requested: bool,
    /// A breakpoint met in a tick that did not wait there ([`Hub::defer_breaks`]): the run
    /// stands still after the tick.
    pub(super) broke: Option<Paused>,
    /// Stops between ticks to pass before a step pauses: 1 from a pause between ticks
    /// (tick once), 2 from a breakpoint inside a tick (finish it, tick the next).
    steps_owed: u8,
    pub(super) requests: Vec<Request>,
}

impl Default for Inner {
    fn default() -> Self {
        Self {
            generation: 0,
            run: None,
            blackboards: Default::default(),
            failure: Default::default(),
            paused: None,
            paused_version: 0,
            breakpoints_version: 0,
            ended: None,
            rewind: (0, Value::Null),
            scene: (0, Err(String::new())),
            refusal: (0, String::new()),
            refused_edits: (0, Vec::new()),
            pause_requested: false,
            broke: None,
            steps_owed: 0,
            requests: Vec::new(),
        }
    }
}

/// The watch state shared by the run, the observer and the pages.
pub(crate) struct Hub {
    inner: Mutex<Inner>,
    pub(super) resume: Condvar,
    version: tokio::sync::watch::Sender<u64>,
    pages: AtomicUsize,
    /// Breakpoints stop the run only while a page is attached.
    armed: AtomicBool,
    refused: AtomicU64,
    /// The results pages forced on nodes ([`super::force`]).
    pub(crate) forces: super::force::Forces,
    /// A breakpoint does not hold the tick but stands the run still after it (a crowd's
    /// frame, which the other members' ticks share, is not held for one member).
    pub(super) defer_breaks: AtomicBool,
    /// The crowd whose agents the pages list, if one is watched.
    pub(crate) desk: super::agents::Desk,
}

impl Hub {
    pub fn new() -> Arc<Self> {
        Arc::new(Self {
            inner: Mutex::new(Inner::default()),
            resume: Condvar::new(),
            version: tokio::sync::watch::Sender::new(0),
            pages: AtomicUsize::new(0),
            armed: AtomicBool::new(false),
            refused: AtomicU64::new(0),
            forces: Default::default(),
            defer_breaks: AtomicBool::new(false),
            desk: Default::default(),
        })
    }

    pub fn lock(&self) -> MutexGuard<'_, Inner> {
        // A page's task that panicked left the state whole: each change is one assignment.
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Wakes every page's task.
    pub fn bump(&self) {
        self.version.send_modify(|v| *v = v.wrapping_add(1));
    }

    pub fn subscribe(&self) -> tokio::sync::watch::Receiver<u64> {
        self.version.subscribe()
    }

    pub fn pages(&self) -> usize {
        self.pages.load(Ordering::Acquire)
    }

    pub fn refused(&self) -> u64 {
        self.refused.load(Ordering::Relaxed)
    }

    pub fn count_refused(&self) {
        self.refused.fetch_add(1, Ordering::Relaxed);
    }

    pub fn page_joined(&self) {
        let before = self.pages.fetch_add(1, Ordering::AcqRel);
        self.armed.store(true, Ordering::Release);
        // Nothing was kept for the pages while none was attached: start from the statuses
        // as they stand. With a page attached, what is shown is kept up to date, and the
        // statuses as they stand between ticks are the Idle that completed nodes were
        // reset to, which would show the new page (and the others) a tree of Idle nodes.
        if before > 0 {
            return;
        }
        if let Some(run) = &self.lock().run {
            for (shown, status) in run.cell.shown.iter().zip(&*run.cell.statuses) {
                shown.store(status.load(Ordering::Acquire), Ordering::Release);
            }
            let tick = run.cell.tick.load(Ordering::Acquire);
            run.cell.shown_tick.store(tick, Ordering::Release);
        }
    }

    /// The last page to leave lets a paused run go on: nobody is left to continue it.
    pub fn page_left(&self) {
        if self.pages.fetch_sub(1, Ordering::AcqRel) == 1 {
            self.armed.store(false, Ordering::Release);
            let mut inner = self.lock();
            inner.pause_requested = false;
            inner.steps_owed = 0;
            drop(inner);
            self.resume.notify_all();
        }
    }

    /// Shows `tree` to the pages; returns the observer that feeds them.
    pub fn attach<C>(self: &Arc<Self>, tree: &Tree<C>, name: &str) -> StudioObserver {
        let blueprint = tree.blueprint();
        let view = TreeView::of_blueprint(blueprint, name);
        let bytes = || -> Box<[AtomicU8]> {
            tree.statuses()
                .iter()
                .map(|s| AtomicU8::new(*s as u8))
                .collect()
        };
        let (statuses, shown) = (bytes(), bytes());
        let touched: Box<[AtomicU8]> = (0..blueprint.len()).map(|_| AtomicU8::new(0)).collect();
        let breakpoints: Box<[AtomicU8]> =
            (0..blueprint.len()).map(|_| AtomicU8::new(NONE)).collect();
        let scores: Box<[AtomicU64]> = (0..blueprint.len())
            .map(|_| AtomicU64::new(NO_SCORE))
            .collect();
        let paths = blueprint.paths();
        let mut inner = self.lock();
        // Breakpoints stay on the nodes whose paths the new tree still has.
        if let Some(old) = &inner.run {
            for (i, path) in old.paths.iter().enumerate() {
                let bp = old.cell.breakpoints[i].load(Ordering::Relaxed);
                if bp != NONE {
                    if let Some(j) = paths.iter().position(|p| p == path) {
                        breakpoints[j].store(bp, Ordering::Relaxed);
                    }
                }
            }
        }
        let tick = inner
            .run
            .as_ref()
            .map_or(0, |r| r.cell.tick.load(Ordering::Relaxed));
        let cell = Arc::new(RunCell {
            statuses,
            touched,
            shown,
            breakpoints,
            scores,
            tick: AtomicU64::new(tick),
            shown_tick: AtomicU64::new(tick),
        });
        let tree_json = serde_json::to_string(&view).unwrap_or_else(|_| "null".into());
        inner.run = Some(Run {
            name: name.to_string(),
            tree: tree_json.into(),
            paths,
            cell: Arc::clone(&cell),
        });
        inner.generation += 1;
        inner.ended = None;
        self.forces.clear();
        inner.refused_edits.1.clear();
        drop(inner);
        self.bump();
        StudioObserver {
            hub: Arc::clone(self),
            cell,
            broke: false,
        }
    }

    pub fn finish(&self, status: Status) {
        self.lock().ended = Some(status_name(status.into()));
        self.bump();
    }

    /// Publishes the blackboards and the failure chain, if a page is attached to read them.
    pub fn publish<C>(&self, tree: &Tree<C>) {
        if self.pages() == 0 {
            return;
        }
        let scopes = values::scopes(tree);
        let failure = tree.last_failure().map_or(Value::Null, |f| {
            let reason = f.reason();
            json!({
                "path": f.leaf().path,
                "reason": reason.map(|r| r.message().into_owned()),
                "code": reason.map(|r| r.code()).filter(|c| *c != 0),
                "chain": f.to_string(),
                "nodes": f.all_links().iter().map(|l| l.node.0).collect::<Vec<_>>(),
            })
        });
        let mut inner = self.lock();
        let mut changed = false;
        if inner.blackboards.1 != scopes {
            inner.blackboards = (inner.blackboards.0 + 1, scopes);
            changed = true;
        }
        if inner.failure.1 != failure {
            inner.failure = (inner.failure.0 + 1, failure);
            changed = true;
        }
        drop(inner);
        if changed {
            self.bump();
        }
    }

    /// Between two ticks: the pages' edits applied, the blackboards published, and the
    /// run held while a page paused it, the pages then told the kept ticks (`rewind`);
    /// `travel` restores a kept tick a paused page asked for, and shows it to the pages.
    pub fn between_ticks<C>(
        &self,
        tree: &mut Tree<C>,
        rewind: Value,
        travel: &mut dyn FnMut(&mut Tree<C>, Travel),
    ) {
        self.apply_edits(tree);
        self.publish(tree);
        if let Some(why) = self.stop_reason() {
            // Told only when the run stands still, where pages use it: not a message every
            // tick.
            self.set_rewind(rewind);
            self.hold(
                Paused {
                    why,
                    node: None,
                    status: None,
                },
                Some(&mut |requests: Vec<Request>| {
                    for request in requests {
                        match request {
                            Request::Edit(e) => self.apply_edit(tree, &e),
                            Request::Travel(t) => travel(tree, t),
                        }
                    }
                    self.publish(tree);
                }),
            );
        }
    }

    /// Why the run is to stop before its next tick (a step done, a pause asked for), if it
    /// is; counts a step's tick.
    pub(super) fn stop_reason(&self) -> Option<&'static str> {
        let mut inner = self.lock();
        if self.pages() == 0 {
            return None;
        }
        if inner.steps_owed > 0 {
            inner.steps_owed -= 1;
            (inner.steps_owed == 0).then_some("step")
        } else if inner.pause_requested {
            Some("pause")
        } else {
            None
        }
    }

    /// Edits made while the run went on; a travel asked for then (the page saw the run
    /// paused, and it went on since) is dropped.
    pub fn apply_edits<C>(&self, tree: &mut Tree<C>) {
        let requests = std::mem::take(&mut self.lock().requests);
        for r in &requests {
            if let Request::Edit(e) = r {
                self.apply_edit(tree, e);
            }
        }
    }

    /// Writes a page's edit; a refused one leaves the entry as it was and is told to the
    /// pages with why, at the entry's field, until an edit of the entry applies.
    fn apply_edit<C>(&self, tree: &mut Tree<C>, edit: &Edit) {
        let outcome = values::write(tree, edit);
        let mut inner = self.lock();
        let refused = &mut inner.refused_edits;
        let before = refused.1.len();
        refused
            .1
            .retain(|r| !(r.scope == edit.scope && r.key == edit.key));
        let changed = match outcome {
            Ok(()) => refused.1.len() != before,
            Err(why) => {
                refused.1.push(RefusedEdit {
                    scope: edit.scope,
                    key: edit.key.clone(),
                    why,
                });
                true
            }
        };
        if changed {
            refused.0 += 1;
            drop(inner);
            self.bump();
        }
    }

    /// Stands the run still until a page continues or steps it, or the last page leaves;
    /// `apply` (between ticks only) applies blackboard edits made meanwhile.
    fn hold(&self, paused: Paused, mut apply: Option<&mut dyn FnMut(Vec<Request>)>) {
        let mut inner = self.lock();
        if self.pages() == 0 {
            return;
        }
        inner.paused = Some(paused);
        inner.paused_version += 1;
        self.bump();
        while inner.paused.is_some() && self.pages() > 0 {
            if let Some(apply) = apply.as_mut() {
                if !inner.requests.is_empty() {
                    let requests = std::mem::take(&mut inner.requests);
                    drop(inner);
                    apply(requests);
                    inner = self.lock();
                    continue;
                }
            }
            // The timeout only guards against a lost wake-up; every release notifies.
            inner = self
                .resume
                .wait_timeout(inner, Duration::from_millis(250))
                .unwrap_or_else(|e| e.into_inner())
                .0;
        }
        inner.paused = None;
        inner.paused_version += 1;
        drop(inner);
        self.bump();
    }

    /// A page asked for the run to stop before its next tick.
    pub fn pause(&self) {
        self.lock().pause_requested = true;
    }

    /// A page asked for one tick: a run paused between ticks ticks once and stops; one held
    /// at a breakpoint inside a tick finishes it, ticks the next and stops (a breakpoint
    /// met on the way ends the step there); a running one stops after its tick.
    pub fn step(&self) {
        let mut inner = self.lock();
        let inside_a_tick = inner.paused.as_ref().is_some_and(|p| p.why == "breakpoint")
            && !self.defer_breaks.load(Ordering::Acquire);
        inner.steps_owed = if inside_a_tick { 2 } else { 1 };
        inner.pause_requested = true;
        inner.paused = None;
        drop(inner);
        self.resume.notify_all();
    }

    /// A page asked the run to go on.
    pub fn resume(&self) {
        let mut inner = self.lock();
        inner.pause_requested = false;
        inner.steps_owed = 0;
        inner.paused = None;
        drop(inner);
        self.resume.notify_all();
    }

    /// A page set or cleared a breakpoint; `false` if the node is not in the tree.
    pub fn set_breakpoint(&self, node: u64, when: Option<NodeStatus>, before: bool) -> bool {
        let mut inner = self.lock();
        let Some(run) = &inner.run else { return false };
        let Some(id) = super::node_in(node, run.cell.breakpoints.len()) else {
            return false;
        };
        let byte = match (before, when) {
            (true, _) => BEFORE,
            (false, Some(s)) => s as u8,
            (false, None) => NONE,
        };
        run.cell.breakpoints[id.index()].store(byte, Ordering::Release);
        inner.breakpoints_version += 1;
        drop(inner);
        self.bump();
        true
    }

    /// A page edited a blackboard entry; applied between ticks (at once if paused there).
    pub fn edit(&self, edit: Edit) {
        self.lock().requests.push(Request::Edit(edit));
        self.resume.notify_all();
    }

    /// The breakpoints of the run, as pages list them.
    pub fn breakpoints(run: &Run) -> Vec<Value> {
        run.cell
            .breakpoints
            .iter()
            .enumerate()
            .filter_map(|(i, b)| {
                let b = b.load(Ordering::Relaxed);
                let when = match b {
                    NONE => return None,
                    BEFORE => "before",
                    s => status_name(status_of_byte(s)),
                };
                Some(json!({"node": i, "when": when}))
            })
            .collect()
    }
}

/// The observer a watched tree runs with (made by [`Studio::attach`](crate::Studio::attach)):
/// statuses into the shared bytes, breakpoints checked at each node.
pub struct StudioObserver {
    hub: Arc<Hub>,
    cell: Arc<RunCell>,
    /// A deferred breakpoint was met in this tick: the statuses shown stay as they were
    /// there.
    broke: bool,
}

impl std::fmt::Debug for StudioObserver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StudioObserver").finish_non_exhaustive()
    }
}

impl StudioObserver {
    fn breakpoint(&mut self, node: NodeId, byte: u8, status: Option<NodeStatus>) {
        if self.broke || !self.hub.armed.load(Ordering::Acquire) {
            return;
        }
        let Some(bp) = self.cell.breakpoints.get(node.index()) else {
            return;
        };
        if bp.load(Ordering::Acquire) == byte {
            // The tick waits here, inside the tree: edits wait for the next pause between
            // ticks.
            self.cell.publish_shown();
            self.hub.bump();
            let paused = Paused {
                why: "breakpoint",
                node: Some(node.0),
                status: status.map(status_name),
            };
            if self.hub.defer_breaks.load(Ordering::Acquire) {
                self.broke = true;
                self.hub.lock().broke = Some(paused);
                return;
            }
            self.hub.hold(paused, None);
        }
    }
}

impl Observer for StudioObserver {
    fn on_tick_start(&mut self, _now: Duration) {
        // After a reload the pages read a new cell: follow it (once per tick, not per node).
        if let Some(run) = &self.hub.lock().run {
            if !Arc::ptr_eq(&run.cell, &self.cell) {
                self.cell = Arc::clone(&run.cell);
            }
        }
        self.cell.tick.fetch_add(1, Ordering::Release);
        self.broke = false;
        if self.hub.armed.load(Ordering::Acquire) {
            for t in &*self.cell.touched {
                t.store(NodeStatus::Idle as u8, Ordering::Relaxed);
            }
        }
    }

    fn on_status_change(&mut self, change: StatusChange) {
        let i = change.node.index();
        if let Some(s) = self.cell.statuses.get(i) {
            s.store(change.to as u8, Ordering::Release);
        }
        if change.to != NodeStatus::Idle {
            if let Some(t) = self.cell.touched.get(i) {
                t.store(change.to as u8, Ordering::Release);
            }
        }
        self.breakpoint(change.node, change.to as u8, Some(change.to));
    }

    fn on_node_tick(&mut self, node: NodeId) {
        self.breakpoint(node, BEFORE, None);
    }

    fn on_tick_end(&mut self, _status: NodeStatus, _now: Duration) {
        if self.hub.armed.load(Ordering::Acquire) && !self.broke {
            self.cell.publish_shown();
        }
        self.hub.bump();
    }

    fn on_failure_reason(&mut self, _node: NodeId, _reason: &Reason) {}

    /// A crowd's agent ([`CrowdWatch`](crate::CrowdWatch)) sleeps as it would unwatched; a
    /// tree ticked on its own is shown every tick.
    fn lets_tree_sleep(&self) -> bool {
        self.hub.defer_breaks.load(Ordering::Relaxed)
    }

    fn on_node_score(&mut self, node: NodeId, score: f64) {
        if let Some(s) = self.cell.scores.get(node.index()) {
            s.store(score.to_bits(), Ordering::Release);
        }
    }
}

/// The scores of the run's nodes as pages are shown them: `[id, score]` for each node
/// scored.
pub(crate) fn scores(cell: &RunCell) -> Vec<(usize, u64)> {
    cell.scores
        .iter()
        .enumerate()
        .map(|(i, s)| (i, s.load(Ordering::Acquire)))
        .filter(|(_, bits)| *bits != NO_SCORE)
        .collect()
}

/// Statuses of the run as the pages are shown them (see [`RunCell::shown`]).
pub(crate) fn statuses(cell: &RunCell) -> Vec<&'static str> {
    cell.shown
        .iter()
        .map(|s| status_name(status_of_byte(s.load(Ordering::Acquire))))
        .collect()
}

/// Scope ids of a tree's blackboards, root first, with the path pages show them by.
pub(crate) fn scope_paths<C>(tree: &Tree<C>) -> Vec<(ScopeId, String)> {
    let blueprint = tree.blueprint();
    let mut out = vec![(ScopeId::ROOT, String::new())];
    let mut seen: HashMap<u32, ()> = HashMap::new();
    seen.insert(ScopeId::ROOT.0, ());
    for id in blueprint.ids() {
        if let Some(scope) = tree.subtree_scope(id) {
            if seen.insert(scope.0, ()).is_none() {
                out.push((scope, blueprint.path(id)));
            }
        }
    }
    out
}
