//! What the monitor knows of the tree: the observer side, which the tick path calls, and the
//! snapshots the runner publishes between ticks.

use std::collections::hash_map::RandomState;
use std::collections::VecDeque;
use std::hash::{BuildHasher, Hasher};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use neurotree_core::{
    Blueprint, Category, Failure, NodeId, NodeKind, NodeStatus, Observer, ScopeId, StatusChange,
    Tree,
};
use serde_json::{json, Map, Value};

use super::protocol::{status_byte, status_record, Transition};
use neurotree_toolkit::blackboard_json::scope_json;
use neurotree_toolkit::registry::Registry;
use neurotree_toolkit::xml::escape;
use neurotree_toolkit::xml::{write_xml, SaveOptions};

/// Transitions kept while recording, as BehaviorTree.CPP keeps: the oldest go first.
pub(crate) const MAX_TRANSITIONS: usize = 1000;

/// A Groot2 monitor for one tree: attach it as the tree's observer, publish the blackboard
/// between ticks, and [`serve`](Self::serve) it (see the [module docs](super)).
///
/// Clones share one state, so the clone given to [`Tree::set_observer`] and the one that
/// serves see the same tree.
#[derive(Clone)]
pub struct Groot2Monitor {
    pub(crate) shared: Arc<Shared>,
}

pub(crate) struct Shared {
    pub(crate) xml: String,
    pub(crate) uuid: [u8; 16],
    pub(crate) main_tree: String,
    /// Each SubTree node, with the name its blackboard goes by (its `_fullpath`).
    pub(crate) subtrees: Vec<(String, NodeId)>,
    pub(crate) state: Mutex<State>,
}

pub(crate) struct State {
    /// A status reply, kept up to date in place: 3 bytes per node, uid then status byte.
    pub(crate) statuses: Vec<u8>,
    pub(crate) recording: bool,
    /// The tree time recording started at; transitions are stamped relative to it.
    pub(crate) origin: Duration,
    /// The latest tree time an event carried.
    pub(crate) latest: Duration,
    /// Allocated in full up front, so that recording never allocates in the tick path.
    pub(crate) transitions: VecDeque<Transition>,
    /// `(blackboard name, its entries as a JSON object)`, main tree first.
    pub(crate) blackboards: Vec<(String, Value)>,
    /// Why the tree failed, as of the latest publication; turned into entries only when a
    /// client asks for the main tree's blackboard.
    pub(crate) failure: Option<Failure>,
}

impl Groot2Monitor {
    /// A monitor for trees of `blueprint`, whose main tree `tree_id` names (the
    /// `<BehaviorTree ID>` a client shows, and the name its blackboard goes by).
    ///
    /// `registry` provides the `TreeNodesModel` of the XML a client receives; every node is
    /// Idle until the attached tree reports otherwise. Uids are node ids plus one, as in
    /// [`SaveOptions::uids`]; the protocol carries them in 16 bits, so in a tree of more than
    /// 65,535 nodes only the first 65,535 are reported.
    pub fn new<C: 'static>(
        blueprint: &Blueprint<C>,
        registry: &Registry<C>,
        tree_id: &str,
    ) -> Self {
        let mut xml = write_xml(
            blueprint,
            registry,
            &SaveOptions {
                tree_id: tree_id.to_string(),
                uids: true,
                models: true,
                builtin_models: true,
            },
        );
        add_unregistered_models(&mut xml, blueprint, registry);
        let covered = blueprint.len().min(usize::from(u16::MAX));
        let mut statuses = Vec::with_capacity(covered * 3);
        for uid in 1..=covered {
            // `covered` is at most u16::MAX, so every uid fits.
            let uid = u16::try_from(uid).unwrap_or(u16::MAX);
            statuses.extend_from_slice(&status_record(uid, NodeStatus::Idle as u8));
        }
        let subtrees = blueprint
            .ids()
            .filter(|id| matches!(blueprint.kind(*id), NodeKind::SubTree(_)))
            .map(|id| (blueprint.path(id), id))
            .collect();
        Groot2Monitor {
            shared: Arc::new(Shared {
                xml,
                uuid: random_uuid(),
                main_tree: tree_id.to_string(),
                subtrees,
                state: Mutex::new(State {
                    statuses,
                    recording: false,
                    origin: Duration::ZERO,
                    latest: Duration::ZERO,
                    transitions: VecDeque::with_capacity(MAX_TRANSITIONS),
                    blackboards: vec![(tree_id.to_string(), Value::Object(Default::default()))],
                    failure: None,
                }),
            }),
        }
    }

    /// The XML a `T` request receives.
    pub fn tree_xml(&self) -> &str {
        &self.shared.xml
    }

    /// The 16-byte id every reply carries; random per monitor, the same for all its clones.
    pub fn tree_uuid(&self) -> [u8; 16] {
        self.shared.uuid
    }

    /// Takes a snapshot of `tree`'s blackboards for `B` requests: the root scope under the
    /// main tree's name, and each subtree's own scope under its `_fullpath`, with the values
    /// [`blackboard_json`](neurotree_toolkit::blackboard_json) gives them.
    ///
    /// It also takes [`Tree::last_failure`]: when the latest tick failed, the main tree's
    /// blackboard carries the [failure entries](failure_entries) too, until a call after a
    /// tick that did not fail.
    ///
    /// The monitor cannot read the blackboard while the tree ticks, so clients see the
    /// entries as of the latest call. Call it between ticks (after each one, or every few
    /// when blackboards are large): it allocates, unlike the observer callbacks. `tree`
    /// should be the tree the monitor was made for; subtrees it does not have are left out.
    pub fn publish_blackboard<C>(&self, tree: &Tree<C>) {
        let bb = tree.blackboard();
        let mut snapshot = Vec::with_capacity(1 + self.shared.subtrees.len());
        snapshot.push((
            self.shared.main_tree.clone(),
            Value::Object(scope_json(bb, ScopeId::ROOT)),
        ));
        for (name, id) in &self.shared.subtrees {
            if id.index() >= tree.blueprint().len() {
                continue;
            }
            if let Some(scope) = tree.subtree_scope(*id) {
                snapshot.push((name.clone(), Value::Object(scope_json(bb, scope))));
            }
        }
        let failure = tree.last_failure();
        let mut state = self.state();
        state.blackboards = snapshot;
        state.failure = failure;
    }

    pub(crate) fn state(&self) -> MutexGuard<'_, State> {
        // A panic elsewhere while holding the lock leaves plain data behind, still usable.
        self.shared
            .state
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

impl std::fmt::Debug for Groot2Monitor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Groot2Monitor")
            .field("main_tree", &self.shared.main_tree)
            .field("tree_uuid", &self.shared.uuid)
            .finish_non_exhaustive()
    }
}

impl Observer for Groot2Monitor {
    fn on_tick_start(&mut self, now: Duration) {
        self.state().latest = now;
    }

    fn on_status_change(&mut self, change: StatusChange) {
        let mut state = self.state();
        state.latest = change.at;
        let Some(uid) = change
            .node
            .0
            .checked_add(1)
            .and_then(|uid| u16::try_from(uid).ok())
        else {
            return;
        };
        let at = change.node.index() * 3 + 2;
        if let Some(byte) = state.statuses.get_mut(at) {
            *byte = status_byte(change.from, change.to);
        }
        if state.recording {
            let micros = change.at.saturating_sub(state.origin).as_micros();
            if state.transitions.len() == MAX_TRANSITIONS {
                state.transitions.pop_front();
            }
            state.transitions.push_back(Transition {
                micros: u64::try_from(micros).unwrap_or(u64::MAX),
                uid,
                status: change.to,
            });
        }
    }

    fn on_tick_end(&mut self, _status: NodeStatus, now: Duration) {
        self.state().latest = now;
    }
}

/// The entry of the main tree's blackboard naming the node whose failure decided the root
/// (its [path](neurotree_core::FailureLink::path)).
pub const FAILURE_PATH: &str = "@failure.path";
/// The entry holding the message of the deepest reason on the chain.
pub const FAILURE_REASON: &str = "@failure.reason";
/// The entry holding that reason's code.
pub const FAILURE_CODE: &str = "@failure.code";
/// The entry holding the whole chain, as [`Failure`]'s `Display` writes it.
pub const FAILURE_CHAIN: &str = "@failure.chain";

/// The entries a Groot2 client finds in the main tree's blackboard when the tree failed:
/// [`FAILURE_PATH`] and [`FAILURE_CHAIN`] always, [`FAILURE_REASON`] when a node on the
/// chain gave a reason, [`FAILURE_CODE`] when that reason has a code other than 0. Strings
/// and an integer only, which every version of Groot2 shows in its blackboard panel.
///
/// ```
/// use neurotree::groot::failure_entries;
/// use neurotree::{Action, Blueprint, Handle, ManualClock, Status, Tree};
///
/// struct Walk;
/// impl Action<()> for Walk {
///     fn tick(&self, h: &mut Handle<'_, ()>) -> Status {
///         h.fail_with(106, "blocked")
///     }
/// }
///
/// let blueprint = Blueprint::<()>::builder()
///     .fallback("find", |f| f.always_failure("near").action_node("walk", Walk))
///     .build_shared()
///     .unwrap();
/// let mut tree = Tree::with_clock(blueprint, ManualClock::new());
/// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Failure));
/// let entries = failure_entries(&tree.last_failure().unwrap());
/// assert_eq!(
///     serde_json::Value::Object(entries),
///     serde_json::json!({
///         "@failure.path": "find/walk",
///         "@failure.reason": "blocked",
///         "@failure.code": 106,
///         "@failure.chain": "find\n  tried find/near: no reason given\n  \
///                            tried find/walk: blocked (error 106)\n  \
///                            find/walk: blocked (error 106)",
///     })
/// );
/// ```
pub fn failure_entries(failure: &Failure) -> Map<String, Value> {
    let mut entries = Map::new();
    entries.insert(FAILURE_PATH.into(), json!(failure.leaf().path));
    if let Some(reason) = failure.reason() {
        entries.insert(FAILURE_REASON.into(), json!(reason.message()));
        if reason.code() != 0 {
            entries.insert(FAILURE_CODE.into(), json!(reason.code()));
        }
    }
    entries.insert(FAILURE_CHAIN.into(), json!(failure.to_string()));
    entries
}

/// Adds to the `TreeNodesModel` of `xml` the types of `blueprint` that `registry` does not
/// know (mocks of unknown nodes, leaves made from closures), so that a client finds a model
/// for every element of the tree, as it would in BehaviorTree.CPP, where every node is
/// registered.
fn add_unregistered_models<C: 'static>(
    xml: &mut String,
    blueprint: &Blueprint<C>,
    registry: &Registry<C>,
) {
    let mut models = String::new();
    let mut seen: Vec<&str> = Vec::new();
    for id in blueprint.ids() {
        let kind = blueprint.kind(id);
        if matches!(kind, NodeKind::SubTree(_)) {
            continue;
        }
        // As the XML names it: a builder's leaf by its name, anything else by its type.
        let type_id = blueprint.type_id(id);
        let name = if neurotree_toolkit::xml::save::no_file_form(blueprint, id) {
            blueprint.name(id)
        } else {
            type_id
        };
        if registry.get(name).is_some() || seen.contains(&name) {
            continue;
        }
        seen.push(name);
        let tag = match kind.category() {
            Category::SubTree => Category::Action.as_str(),
            category => category.as_str(),
        };
        models.push_str(&format!("    <{tag} ID=\"{}\"/>\n", escape(name)));
    }
    if let Some(end) = xml.rfind("  </TreeNodesModel>") {
        xml.insert_str(end, &models);
    }
}

/// A version-4 UUID from the standard library's per-process random hash keys, shaped as
/// BehaviorTree.CPP shapes its own.
fn random_uuid() -> [u8; 16] {
    let mut out = [0; 16];
    for (i, half) in out.chunks_exact_mut(8).enumerate() {
        let mut h = RandomState::new().build_hasher();
        h.write_usize(i);
        half.copy_from_slice(&h.finish().to_le_bytes());
    }
    out[6] = (out[6] & 0x0F) | 0x40;
    out[8] = (out[8] & 0x3F) | 0x80;
    out
}
