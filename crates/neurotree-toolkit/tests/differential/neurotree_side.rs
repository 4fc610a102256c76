//! NeuroTree's side of the differential test: the case's XML through [`XmlLoader`], the
//! scripted leaves registered in a [`Registry`], and an [`Observer`] that records what each
//! step did.

use std::cell::{Cell, RefCell};
use std::sync::{Arc, Mutex};

use neurotree::{
    Handle, ManualClock, NodeId, NodeStatus, Observer, Registry, StatefulAction, Status,
    StatusChange, TickError, Tree, XmlLoader,
};

use super::trees::{Case, Op};
use super::Step;

/// Passes one NeuroTree `tick_once` may make. A step whose `tick_once` makes more (a tree
/// that yields on every pass, as `Repeat -1` over a child that succeeds at once) becomes a
/// `tick_exactly_once` for both sides, since BehaviorTree.CPP's `tickOnce` would not end.
const MAX_PASSES: u32 = 1000;

/// The scripted leaves' context: scripts and call counts by node index, and the calls.
pub struct Ctx {
    names: Vec<String>,
    scripts: Vec<Vec<Status>>,
    calls: Vec<Cell<usize>>,
    log: RefCell<Vec<[String; 3]>>,
}

impl Ctx {
    fn new(names: Vec<String>, case: &Case) -> Self {
        let script = |name: &String| -> Vec<Status> {
            let letters = case.scripts.get(name).map_or("", String::as_str);
            letters
                .chars()
                .map(|c| match c {
                    'S' => Status::Success,
                    'F' => Status::Failure,
                    _ => Status::Running,
                })
                .collect()
        };
        Ctx {
            calls: names.iter().map(|_| Cell::new(0)).collect(),
            scripts: names.iter().map(script).collect(),
            names,
            log: RefCell::new(Vec::new()),
        }
    }

    fn play(&self, id: NodeId, what: &str) -> Status {
        let i = id.index();
        let k = self.calls[i].get();
        self.calls[i].set(k + 1);
        let script = &self.scripts[i];
        let s = script[k.min(script.len() - 1)];
        self.log.borrow_mut().push([
            self.names[i].clone(),
            what.to_string(),
            NodeStatus::from(s).as_str().to_string(),
        ]);
        s
    }
}

struct Act;

impl StatefulAction<Ctx> for Act {
    fn on_start(&mut self, h: &mut Handle<'_, Ctx>) -> Status {
        let id = h.node();
        h.ctx().play(id, "start")
    }
    fn on_running(&mut self, h: &mut Handle<'_, Ctx>) -> Status {
        let id = h.node();
        h.ctx().play(id, "running")
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Ctx>) {
        let name = h.ctx().names[h.node().index()].clone();
        h.ctx()
            .log
            .borrow_mut()
            .push([name, "halted".into(), "null".into()]);
    }
}

pub fn registry() -> Registry<Ctx> {
    let mut r = Registry::new();
    r.register_stateful("Act", vec![], || Act).unwrap();
    r.register_action("Sync", vec![], |h| {
        let id = h.node();
        h.ctx().play(id, "tick")
    })
    .unwrap();
    r.register_condition("Cond", vec![], |h| {
        h.ctx().play(h.node(), "tick") == Status::Success
    })
    .unwrap();
    r
}

/// What the observer saw in the current step.
#[derive(Default)]
struct Seen {
    /// The stored statuses, as the changes told them.
    statuses: Vec<NodeStatus>,
    changes: Vec<(NodeId, NodeStatus, NodeStatus)>,
    ticks: Vec<u64>,
    skipped: Vec<NodeId>,
}

impl Seen {
    /// The step's record: what was seen since the last one, by node name.
    fn take_step(
        &mut self,
        names: &[String],
        outcome: String,
        error: Option<String>,
        calls: Vec<[String; 3]>,
    ) -> Step {
        let changes = self
            .changes
            .drain(..)
            .map(|(n, from, to)| {
                [
                    names[n.index()].clone(),
                    from.as_str().to_string(),
                    to.as_str().to_string(),
                ]
            })
            .collect();
        let ticks = self
            .ticks
            .iter_mut()
            .enumerate()
            .filter(|(_, t)| **t > 0)
            .map(|(i, t)| (names[i].clone(), std::mem::take(t)))
            .collect();
        let skipped = self
            .skipped
            .drain(..)
            .map(|n| names[n.index()].clone())
            .collect();
        Step {
            outcome,
            changes,
            calls,
            ticks,
            error,
            skipped,
            stale_wake: false,
        }
    }
}

struct Watch(Arc<Mutex<Seen>>);

impl Observer for Watch {
    fn on_status_change(&mut self, c: StatusChange) {
        let mut s = self.0.lock().unwrap();
        s.statuses[c.node.index()] = c.to;
        s.changes.push((c.node, c.from, c.to));
    }
    fn on_node_tick(&mut self, node: NodeId) {
        let mut s = self.0.lock().unwrap();
        // BehaviorTree.CPP's side counts with `_while`, which runs only from these two.
        if matches!(
            s.statuses[node.index()],
            NodeStatus::Idle | NodeStatus::Running
        ) {
            s.ticks[node.index()] += 1;
        }
    }
    fn on_node_skipped(&mut self, node: NodeId) {
        self.0.lock().unwrap().skipped.push(node);
    }
}

/// Runs `case` in NeuroTree: a load error, or one record per step. A `tick_once` that makes
/// more than [`MAX_PASSES`] passes is recorded as `error` ("runaway").
pub fn run(registry: &Registry<Ctx>, case: &Case) -> Result<Vec<Step>, String> {
    let mut loader = XmlLoader::new(registry);
    loader
        .load_str(&case.xml, "case.xml")
        .map_err(|e| e.to_string())?;
    let blueprint = Arc::new(loader.build_main().map_err(|e| e.to_string())?);
    let names: Vec<String> = blueprint
        .ids()
        .map(|id| blueprint.name(id).to_string())
        .collect();
    let mut ctx = Ctx::new(names.clone(), case);
    let seen = Arc::new(Mutex::new(Seen {
        statuses: vec![NodeStatus::Idle; names.len()],
        changes: Vec::new(),
        ticks: vec![0; names.len()],
        skipped: Vec::new(),
    }));
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    tree.set_max_passes(MAX_PASSES);
    tree.set_observer(Watch(Arc::clone(&seen)));
    let mut steps = Vec::new();
    for op in &case.ops {
        let result = match op {
            Op::TickOnce => Some(tree.tick_once(&mut ctx)),
            Op::TickExactlyOnce => Some(tree.tick_exactly_once(&mut ctx)),
            Op::Halt => {
                tree.halt(&mut ctx);
                None
            }
        };
        let (outcome, error) = match result {
            None => ("halted".to_string(), None),
            Some(Ok(s)) => (NodeStatus::from(s).as_str().to_string(), None),
            // NeuroTree's tick returns a `Status`, which has no Skipped: a skipped root is
            // this error, where BehaviorTree.CPP's tick returns SKIPPED. The same outcome.
            Some(Err(TickError::RootSkipped)) => ("SKIPPED".into(), None),
            Some(Err(TickError::TooManyPasses { .. })) => ("error".into(), Some("runaway".into())),
            Some(Err(e)) => ("error".into(), Some(e.to_string())),
        };
        let failed = error.is_some();
        let calls = std::mem::take(&mut *ctx.log.borrow_mut());
        steps.push(
            seen.lock()
                .unwrap()
                .take_step(&names, outcome, error, calls),
        );
        if failed {
            break;
        }
    }
    Ok(steps)
}

/// Turns each `tick_once` that NeuroTree finds running away into a `tick_exactly_once`,
/// so that BehaviorTree.CPP's `tickOnce` (which has no bound) is never asked to run one.
pub fn tame(registry: &Registry<Ctx>, case: &mut Case) {
    for _ in 0..case.ops.len() {
        let Ok(steps) = run(registry, case) else {
            return;
        };
        let runaway = steps
            .iter()
            .position(|s| s.error.as_deref() == Some("runaway"));
        match runaway {
            Some(i) if case.ops[i] == Op::TickOnce => case.ops[i] = Op::TickExactlyOnce,
            _ => return,
        }
    }
}
