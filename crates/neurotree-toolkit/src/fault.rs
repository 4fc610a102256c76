//! Faults injected into chosen nodes: node PATH returns STATUS on its Kth call, in place of
//! its own tick (BehaviorTree.CPP's scripted mocks and Groot2's replace hook, for one call
//! of a node that otherwise runs as written).
//!
//! A call is a tick that finds the node not Running: the start of a run of the node. On
//! the call a fault names, the node's tick is not called; the node returns the fault's
//! status, after writing the fault's error code to its `error_code_id` output and its
//! message to `error_msg` when it has them (Nav2's nodes do). A fault of status RUNNING is
//! a call that is never answered: the node stays Running, without being ticked, until it
//! is halted. A fault of status PANIC makes the node panic on that call, as a leaf with a
//! bug does: the tick catches it and returns `TickError::Panicked` naming the node (a
//! campaign records it as the variant's outcome and goes on); a panic is not recorded in
//! the [`FaultLog`].
//!
//! Faults ride on the node's hooks ([`NodeHooks`]), wrapping the pre- and post-conditions
//! the file gave it, so the rest of the tree is built and ticked as without them:
//!
//! ```
//! use neurotree::fault::{FaultLog, NodeFault};
//! use neurotree::{ManualClock, Registry, Status, Tree, XmlLoader};
//!
//! let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
//!     <Repeat num_cycles="3"><AlwaysSuccess name="work"/></Repeat>
//! </BehaviorTree></root>"#;
//! let registry = Registry::<()>::new();
//! let fault: NodeFault = "work=FAILURE@2".parse().unwrap();
//! let log = FaultLog::default();
//! let blueprint = neurotree::fault::build_with_faults(&[fault], &log, |wrap| {
//!     let mut loader = XmlLoader::new(&registry);
//!     if let Some(wrap) = wrap {
//!         loader = loader.wrap_hooks(wrap);
//!     }
//!     loader.load_str(xml, "repeat.xml")?;
//!     loader.build_main()
//! })
//! .unwrap();
//! let mut tree = Tree::with_clock(std::sync::Arc::new(blueprint), ManualClock::new());
//! assert_eq!(tree.tick_once(&mut ()), Ok(Status::Failure));
//! let hits = log.hits();
//! assert_eq!((hits[0].path.as_str(), hits[0].call), ("Repeat/work", 2));
//! ```

use std::fmt;
use std::str::FromStr;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

use neurotree_core::nodes::leaf::Handle;
use neurotree_core::{Blueprint, Category, NodeHooks, NodeId, NodeStatus, Status};

use crate::xml::SharedHookWrapper;

/// A fault: the node at `node` returns `status` on its `call`th call.
///
/// The statuses of a fault are those of a call's answer; SKIPPED is not one.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NodeFault {
    /// The node: its path (as [`Blueprint::path`] writes it), else every node of this
    /// type, else every node of this name (see [`resolve`]).
    pub node: String,
    /// The call it lands on, from 1.
    pub call: u32,
    /// What the node returns: SUCCESS, FAILURE, or RUNNING (never answers). Unused when
    /// the node panics instead.
    pub status: Status,
    /// The node panics on the call instead of returning (`PATH=PANIC@K`).
    pub panics: bool,
    /// Written to the node's `error_code_id` output, if it has one.
    pub error_code: Option<u16>,
}

impl NodeFault {
    /// The node at `node` returns `status` on call `call`.
    pub fn new(node: impl Into<String>, call: u32, status: Status) -> Self {
        Self {
            node: node.into(),
            call,
            status,
            panics: false,
            error_code: None,
        }
    }

    /// The node at `node` panics on call `call`.
    pub fn panic(node: impl Into<String>, call: u32) -> Self {
        Self {
            panics: true,
            ..Self::new(node, call, Status::Failure)
        }
    }

    /// The same, writing `code` to the node's `error_code_id` output.
    pub fn with_error_code(mut self, code: u16) -> Self {
        self.error_code = Some(code);
        self
    }
}

/// `PATH=STATUS@K`, or `PATH=STATUS@K#CODE` with an error code; STATUS is SUCCESS,
/// FAILURE, RUNNING or PANIC.
impl FromStr for NodeFault {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        let usage = || {
            format!(
                "`{text}` should be PATH=STATUS@CALL or PATH=STATUS@CALL#CODE, \
                 such as `ComputePathToPose=FAILURE@3#106`"
            )
        };
        let (node, rest) = text.rsplit_once('=').ok_or_else(usage)?;
        let (status, rest) = rest.split_once('@').ok_or_else(usage)?;
        let (call, code) = match rest.split_once('#') {
            Some((call, code)) => (call, Some(code)),
            None => (rest, None),
        };
        let panics = status.trim().eq_ignore_ascii_case("PANIC");
        let status = if panics {
            Status::Failure
        } else {
            parse_status(status.trim()).ok_or_else(usage)?
        };
        let call = call
            .trim()
            .parse::<u32>()
            .ok()
            .filter(|c| *c > 0)
            .ok_or_else(usage)?;
        let error_code = match code {
            Some(code) => Some(code.trim().parse::<u16>().map_err(|_| usage())?),
            None => None,
        };
        if node.trim().is_empty() {
            return Err(usage());
        }
        Ok(Self {
            node: node.trim().to_string(),
            call,
            status,
            panics,
            error_code,
        })
    }
}

impl fmt::Display for NodeFault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}={}@{}",
            self.node,
            if self.panics {
                "PANIC"
            } else {
                status_name(self.status)
            },
            self.call
        )?;
        if let Some(code) = self.error_code {
            write!(f, "#{code}")?;
        }
        Ok(())
    }
}

/// SUCCESS, FAILURE or RUNNING (any case).
pub fn parse_status(text: &str) -> Option<Status> {
    match text.to_ascii_uppercase().as_str() {
        "SUCCESS" => Some(Status::Success),
        "FAILURE" => Some(Status::Failure),
        "RUNNING" => Some(Status::Running),
        _ => None,
    }
}

/// The name a fault writes a status with.
pub fn status_name(status: Status) -> &'static str {
    match status {
        Status::Success => "SUCCESS",
        Status::Failure => "FAILURE",
        Status::Running => "RUNNING",
    }
}

/// Where a fault landed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FaultHit {
    /// The node's path.
    pub path: String,
    /// The call of the node it landed on.
    pub call: u32,
    /// What the node returned.
    pub status: Status,
}

/// The faults that landed, in order; shared by the hooks of one tree.
#[derive(Clone, Debug, Default)]
pub struct FaultLog(Arc<Mutex<Vec<FaultHit>>>);

impl FaultLog {
    /// The faults that landed so far.
    pub fn hits(&self) -> Vec<FaultHit> {
        self.0.lock().map(|hits| hits.clone()).unwrap_or_default()
    }

    fn push(&self, hit: FaultHit) {
        if let Ok(mut hits) = self.0.lock() {
            hits.push(hit);
        }
    }
}

/// The nodes each fault names in `blueprint`: the node of its path, else every node of its
/// type (a fault of a server hits each node that calls it, each counting its own calls),
/// else every node of its name. Type before name: Nav2's files name the controls that retry
/// an action after it (a RecoveryNode `ComputePathToPose`). An error names a fault that
/// matches no node.
pub fn resolve<C>(
    blueprint: &Blueprint<C>,
    faults: &[NodeFault],
) -> Result<Vec<(NodeId, String, NodeFault)>, String> {
    let paths = blueprint.paths();
    let mut out = Vec::with_capacity(faults.len());
    for fault in faults {
        let matching = |pick: &dyn Fn(NodeId) -> bool| -> Vec<NodeId> {
            blueprint.ids().filter(|id| pick(*id)).collect()
        };
        let mut hit = matching(&|id| paths[id.index()] == fault.node);
        if hit.is_empty() {
            hit = matching(&|id| blueprint.type_id(id) == fault.node);
        }
        if hit.is_empty() {
            hit = matching(&|id| blueprint.name(id) == fault.node);
        }
        if hit.is_empty() {
            return Err(format!(
                "the fault `{fault}` names no node of the tree: give a node's path (such as \
                 `{}`), name or type",
                paths.last().map_or("", String::as_str)
            ));
        }
        out.extend(
            hit.into_iter()
                .map(|id| (id, paths[id.index()].clone(), fault.clone())),
        );
    }
    Ok(out)
}

/// The paths of the action leaves of `blueprint` (actions and services: what a fault of a
/// server hits), in tree order.
pub fn action_paths<C>(blueprint: &Blueprint<C>) -> Vec<String> {
    let paths = blueprint.paths();
    blueprint
        .ids()
        .filter(|id| {
            blueprint.children(*id).is_empty() && blueprint.kind(*id).category() == Category::Action
        })
        .map(|id| paths[id.index()].clone())
        .collect()
}

/// Builds a tree twice when there are faults: once as written, to find the nodes they
/// name, then with their hooks. `build` is given the wrapper to hand to
/// [`XmlLoader::wrap_hooks`](crate::XmlLoader::wrap_hooks) (`None` the first time).
pub fn build_with_faults<C: 'static, E>(
    faults: &[NodeFault],
    log: &FaultLog,
    mut build: impl FnMut(Option<SharedHookWrapper<C>>) -> Result<Blueprint<C>, E>,
) -> Result<Blueprint<C>, FaultBuildError<E>> {
    let plain = build(None).map_err(FaultBuildError::Load)?;
    if faults.is_empty() {
        return Ok(plain);
    }
    let resolved = resolve(&plain, faults).map_err(FaultBuildError::Fault)?;
    drop(plain);
    build(Some(wrapper(resolved, log.clone()))).map_err(FaultBuildError::Load)
}

/// Why [`build_with_faults`] failed.
#[derive(Debug)]
pub enum FaultBuildError<E> {
    /// The tree did not load.
    Load(E),
    /// A fault names no node.
    Fault(String),
}

impl<E: fmt::Display> fmt::Display for FaultBuildError<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FaultBuildError::Load(e) => e.fmt(f),
            FaultBuildError::Fault(e) => f.write_str(e),
        }
    }
}

/// The hook wrapper that puts `faults` on their nodes, recording hits in `log`.
pub fn wrapper<C: 'static>(
    faults: Vec<(NodeId, String, NodeFault)>,
    log: FaultLog,
) -> SharedHookWrapper<C> {
    Arc::new(move |id, inner| {
        let mine: Vec<NodeFault> = faults
            .iter()
            .filter(|(at, _, _)| *at == id)
            .map(|(_, _, f)| f.clone())
            .collect();
        if mine.is_empty() {
            return inner;
        }
        let path = faults
            .iter()
            .find(|(at, _, _)| *at == id)
            .map(|(_, p, _)| p.clone())
            .unwrap_or_default();
        Some(Box::new(FaultHooks {
            inner,
            plan: Plan::Calls {
                faults: mine,
                path,
                calls: AtomicU32::new(0),
                log: log.clone(),
            },
            hanging: AtomicBool::new(false),
        }))
    })
}

/// The wrapper that applies `inner` (if any), then `outer`, to each node's hooks.
pub fn chain<C: 'static>(
    inner: Option<SharedHookWrapper<C>>,
    outer: SharedHookWrapper<C>,
) -> SharedHookWrapper<C> {
    match inner {
        None => outer,
        Some(inner) => Arc::new(move |id, hooks| outer(id, inner(id, hooks))),
    }
}

/// Results decided while the tree runs, by hand (a studio's forced results): asked each
/// time a node is ticked, whatever its status.
pub trait LiveFaults: Send + Sync {
    /// The status node `node` returns now in place of its tick, if one is forced. A
    /// SUCCESS or FAILURE forced on a Running node halts it first; a RUNNING is a call
    /// never answered, as a fault's: the node stays Running, not ticked, until halted.
    fn forced(&self, node: NodeId) -> Option<Status>;

    /// Whether `node` is Running under a RUNNING forced on it, not ticked until halted.
    /// The source keeps this, not the hooks (which a blueprint's trees share, and which a
    /// restored state does not reach), so that a run gone back to before the force finds
    /// the node as it was then.
    fn hanging(&self, node: NodeId) -> bool;

    /// `node` began hanging (`true`, a RUNNING was forced on it) or stopped (`false`, it
    /// was halted).
    fn set_hanging(&self, node: NodeId, hanging: bool);
}

/// The hook wrapper that lets `live` decide the result of any node of the tree when it
/// is ticked; `inner` (the faults of a file, say) wraps first. Every node gets hooks: a
/// tree built with it runs its nodes through them, as a tree of scripted conditions does.
pub fn live_wrapper<C: 'static>(
    live: Arc<dyn LiveFaults>,
    inner: Option<SharedHookWrapper<C>>,
) -> SharedHookWrapper<C> {
    Arc::new(move |id, hooks| {
        let hooks = match &inner {
            Some(wrap) => wrap(id, hooks),
            None => hooks,
        };
        Some(Box::new(FaultHooks {
            inner: hooks,
            plan: Plan::Live {
                node: id,
                live: Arc::clone(&live),
            },
            hanging: AtomicBool::new(false),
        }) as Box<dyn NodeHooks<C>>)
    })
}

/// Who decides a node's results: faults on chosen calls, or a live source.
enum Plan {
    Calls {
        faults: Vec<NodeFault>,
        path: String,
        calls: AtomicU32,
        log: FaultLog,
    },
    Live {
        node: NodeId,
        live: Arc<dyn LiveFaults>,
    },
}

/// The hooks of a node with faults: answers for it when its plan decides, and otherwise
/// hands over to the hooks the file gave it.
///
/// The counts live in the hooks, which a blueprint shares among its trees: build one
/// blueprint per run that injects faults.
struct FaultHooks<C> {
    inner: Option<Box<dyn NodeHooks<C>>>,
    plan: Plan,
    /// Under a plan of calls, the node hangs under a RUNNING fault (a live source keeps
    /// its own, [`LiveFaults::hanging`]).
    hanging: AtomicBool,
}

impl<C> FaultHooks<C> {
    /// Whether the node is Running under a RUNNING its plan gave, not to be ticked.
    fn is_hanging(&self) -> bool {
        match &self.plan {
            Plan::Live { node, live } => live.hanging(*node),
            Plan::Calls { .. } => self.hanging.load(Ordering::Relaxed),
        }
    }

    fn hang(&self, hanging: bool) {
        match &self.plan {
            Plan::Live { node, live } => live.set_hanging(*node, hanging),
            Plan::Calls { .. } => self.hanging.store(hanging, Ordering::Relaxed),
        }
    }

    /// The status and error code the plan gives this tick, if any.
    fn decide(&self, stored: NodeStatus) -> Option<(Status, Option<u16>, String)> {
        match &self.plan {
            Plan::Live { node, live } => live
                .forced(*node)
                .map(|s| (s, None, format!("forced {}", status_name(s)))),
            Plan::Calls { .. } if stored == NodeStatus::Running => None,
            Plan::Calls {
                faults,
                path,
                calls,
                log,
            } => {
                let call = calls.fetch_add(1, Ordering::Relaxed) + 1;
                let fault = faults.iter().find(|f| f.call == call)?;
                if fault.panics {
                    panic!("injected fault: {path} panics on its call {call}");
                }
                log.push(FaultHit {
                    path: path.clone(),
                    call,
                    status: fault.status,
                });
                Some((
                    fault.status,
                    fault.error_code,
                    format!("injected fault {fault}"),
                ))
            }
        }
    }
}

impl<C> NodeHooks<C> for FaultHooks<C> {
    fn before(&self, h: &mut Handle<'_, C>, stored: NodeStatus) -> Option<NodeStatus> {
        let Some((status, code, message)) = self.decide(stored) else {
            if stored == NodeStatus::Running && self.is_hanging() {
                return Some(NodeStatus::Running);
            }
            return self.inner.as_ref().and_then(|i| i.before(h, stored));
        };
        if let Some(code) = code {
            // A node without these outputs gets only the status.
            let _ = h.output::<u16>("error_code_id", code);
            let _ = h.output::<String>("error_msg", message);
        }
        if status == Status::Running {
            self.hang(true);
        }
        Some(NodeStatus::from(status))
    }

    fn after(&self, h: &mut Handle<'_, C>, status: NodeStatus) {
        if let Some(inner) = &self.inner {
            inner.after(h, status);
        }
    }

    fn halted(&self, h: &mut Handle<'_, C>) {
        self.hang(false);
        if let Some(inner) = &self.inner {
            inner.halted(h);
        }
    }

    fn attributes(&self, f: &mut dyn FnMut(&str, &str)) {
        if let Some(inner) = &self.inner {
            inner.attributes(f);
        }
    }

    fn reads_only_blackboard(&self) -> bool {
        // A live source changes only when a person forces a result, between ticks: it
        // keeps no sleeping tree awake.
        match &self.plan {
            Plan::Live { .. } => self
                .inner
                .as_ref()
                .is_none_or(|i| i.reads_only_blackboard()),
            Plan::Calls { .. } => false,
        }
    }
}
