//! Random trees for the property tests: a plain description ([`Spec`]), a proptest strategy
//! that generates it, the scripted leaves the engine runs, and the engine blueprint built from
//! a description.
//!
//! Nodes are numbered in pre-order, as the builder numbers them, so node `i` of a description
//! is `NodeId(i)` of its blueprint. Leaf `i` is named `L{i}` and plays `scripts[i]`: its
//! k-th call (on_start, on_running or a sync tick) returns the k-th outcome, and the last
//! outcome repeats.

// Each test file uses its own part of this module.
#![allow(dead_code)]

use std::cell::Cell;
use std::fmt;
use std::future::Future;
use std::pin::Pin;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll};

use neurotree_core::{
    Action, ActionFuture, AsyncAction, Blueprint, Builder, HaltFuture, HaltProgress, Handle,
    StatefulAction, Status,
};
use proptest::collection::vec;
use proptest::prelude::*;

/// Control and decorator kinds, with their parameters.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Kind {
    Sequence,
    SequenceWithMemory,
    ReactiveSequence,
    Fallback,
    ReactiveFallback,
    AsyncSequence,
    AsyncFallback,
    Parallel {
        success: i32,
        failure: i32,
    },
    ParallelAll {
        max_failures: i32,
    },
    IfThenElse,
    WhileDoElse,
    TryCatch {
        catch_on_halt: bool,
    },
    Inverter,
    ForceSuccess,
    ForceFailure,
    Repeat(i32),
    Retry(i32),
    KeepRunningUntilFailure,
    RunOnce {
        then_skip: bool,
    },
    /// The nodes that read the clock, by their milliseconds; only [`timed_tree`] makes
    /// them (the reference model has no clock). `Sleep` is a leaf: it has no children.
    Timeout(u16),
    Delay(u16),
    Cooldown(u16),
    Sleep(u16),
}

/// Leaf kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LeafKind {
    /// A `StatefulAction`: on_start / on_running / on_halted.
    Stateful,
    /// A sync `Action` object (its script holds Success and Failure only).
    Sync,
    /// A closure condition (its script holds Success and Failure only).
    Cond,
    /// An `AsyncAction`: its start plays the first outcome, each later poll of the run's
    /// future the next one; its halt takes as many polls of a halt future as a
    /// stateful leaf's takes `on_halting` calls.
    Async,
}

/// A tree description.
#[derive(Clone, Debug)]
pub enum Spec {
    Leaf(LeafKind, Vec<Status>),
    Node(Kind, Vec<Spec>),
}

impl Spec {
    /// Number of nodes.
    pub fn len(&self) -> usize {
        match self {
            Spec::Leaf(..) => 1,
            Spec::Node(_, children) => 1 + children.iter().map(Spec::len).sum::<usize>(),
        }
    }

    /// Nodes in pre-order: (kind or leaf, number of children, script).
    pub fn flatten(&self) -> Vec<Flat> {
        let mut out = Vec::new();
        self.flatten_into(&mut out);
        out
    }

    fn flatten_into(&self, out: &mut Vec<Flat>) -> usize {
        let id = out.len();
        match self {
            Spec::Leaf(kind, script) => out.push(Flat {
                node: FlatKind::Leaf(*kind),
                children: Vec::new(),
                script: script.clone(),
            }),
            Spec::Node(kind, children) => {
                out.push(Flat {
                    node: FlatKind::Node(kind.clone()),
                    children: Vec::new(),
                    script: Vec::new(),
                });
                let ids: Vec<usize> = children.iter().map(|c| c.flatten_into(out)).collect();
                out[id].children = ids;
            }
        }
        id
    }
}

/// One node of a flattened description.
#[derive(Clone, Debug)]
pub struct Flat {
    pub node: FlatKind,
    pub children: Vec<usize>,
    pub script: Vec<Status>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FlatKind {
    Leaf(LeafKind),
    Node(Kind),
}

/// What a scripted leaf did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum What {
    Start(Status),
    Running(Status),
    /// Asked to halt, answering Halting: its halt takes more ticks (see
    /// [`Ctx::with_halt_ticks`]); `Halted` comes when it is done.
    HaltRequested,
    /// An `on_halting` that answered Halting.
    StillHalting,
    Halted,
    /// A sync action or a condition was ticked.
    Tick(Status),
}

/// One call of a scripted leaf.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Event {
    pub leaf: usize,
    pub what: What,
}

impl fmt::Display for Event {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let l = self.leaf;
        match self.what {
            What::Start(s) => write!(f, "L{l} start -> {s}"),
            What::Running(s) => write!(f, "L{l} running -> {s}"),
            What::HaltRequested => write!(f, "L{l} halt requested"),
            What::StillHalting => write!(f, "L{l} still halting"),
            What::Halted => write!(f, "L{l} halted"),
            What::Tick(s) => write!(f, "L{l} tick -> {s}"),
        }
    }
}

/// The context the engine's trees run with: scripts, call counts and the event log.
///
/// Interior mutability lets closure conditions (which see `&Ctx`) play their scripts too.
pub struct Ctx {
    /// What the leaves play and log, shared with the futures of async leaves.
    shared: Arc<Shared>,
    /// Leaf `i`'s halt takes `halt_ticks[i]` `on_halting` calls after the request (0: it
    /// halts at once, through the default `on_halt_requested`).
    halt_ticks: Vec<usize>,
    /// `on_halting` calls left in each leaf's halt in progress.
    halting_left: Vec<Cell<usize>>,
}

/// The scripts, the call counts and the event log: what an async leaf's future, which
/// outlives the tick, needs of the context.
pub struct Shared {
    scripts: Vec<Vec<Status>>,
    calls: Vec<AtomicUsize>,
    events: Mutex<Vec<Event>>,
}

impl Shared {
    /// The next outcome of leaf `leaf`.
    fn next(&self, leaf: usize) -> Status {
        let k = self.calls[leaf].fetch_add(1, Ordering::Relaxed);
        let script = &self.scripts[leaf];
        script[k.min(script.len() - 1)]
    }

    fn log(&self, leaf: usize, what: What) {
        self.events.lock().unwrap().push(Event { leaf, what });
    }
}

impl Ctx {
    pub fn new(spec: &Spec) -> Self {
        let scripts: Vec<Vec<Status>> = spec.flatten().into_iter().map(|f| f.script).collect();
        Self {
            halt_ticks: vec![0; scripts.len()],
            halting_left: scripts.iter().map(|_| Cell::new(0)).collect(),
            shared: Arc::new(Shared {
                calls: scripts.iter().map(|_| AtomicUsize::new(0)).collect(),
                scripts,
                events: Mutex::new(Vec::new()),
            }),
        }
    }

    /// The context with leaf `i`'s halts taking `halt_ticks[i]` more ticks (indices past
    /// the end: 0).
    pub fn with_halt_ticks(mut self, halt_ticks: &[usize]) -> Self {
        for (i, &k) in halt_ticks.iter().enumerate().take(self.halt_ticks.len()) {
            self.halt_ticks[i] = k;
        }
        self
    }

    /// The next outcome of leaf `leaf`.
    fn next(&self, leaf: usize) -> Status {
        self.shared.next(leaf)
    }

    fn log(&self, leaf: usize, what: What) {
        self.shared.log(leaf, what);
    }

    /// The world's state: each leaf's place in its script and its halt in progress.
    pub fn snapshot(&self) -> (Vec<usize>, Vec<usize>) {
        let calls = self
            .shared
            .calls
            .iter()
            .map(|c| c.load(Ordering::Relaxed))
            .collect();
        let halting = self.halting_left.iter().map(Cell::get).collect();
        (calls, halting)
    }

    /// Puts the world back as [`snapshot`](Self::snapshot) found it.
    pub fn rewind(&self, (calls, halting): &(Vec<usize>, Vec<usize>)) {
        for (c, &n) in self.shared.calls.iter().zip(calls) {
            c.store(n, Ordering::Relaxed);
        }
        for (h, &n) in self.halting_left.iter().zip(halting) {
            h.set(n);
        }
    }

    /// The events logged since the last call.
    pub fn take_events(&self) -> Vec<Event> {
        std::mem::take(&mut *self.shared.events.lock().unwrap())
    }

    fn cond(&self, leaf: usize) -> bool {
        let s = self.next(leaf);
        self.log(leaf, What::Tick(s));
        s == Status::Success
    }
}

struct Scripted(usize);

impl StatefulAction<Ctx> for Scripted {
    fn on_start(&mut self, h: &mut Handle<'_, Ctx>) -> Status {
        let ctx = h.ctx();
        let s = ctx.next(self.0);
        ctx.log(self.0, What::Start(s));
        s
    }
    fn on_running(&mut self, h: &mut Handle<'_, Ctx>) -> Status {
        let ctx = h.ctx();
        let s = ctx.next(self.0);
        ctx.log(self.0, What::Running(s));
        s
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Ctx>) {
        h.ctx().log(self.0, What::Halted);
    }
    fn on_halt_requested(&mut self, h: &mut Handle<'_, Ctx>) -> HaltProgress {
        let ctx = h.ctx();
        let k = ctx.halt_ticks[self.0];
        if k == 0 {
            self.on_halted(h);
            return HaltProgress::Done;
        }
        ctx.halting_left[self.0].set(k);
        ctx.log(self.0, What::HaltRequested);
        HaltProgress::Halting
    }
    // A scripted leaf keeps nothing of its own: its place in the script is the world's.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(Vec::new())
    }
    fn on_halting(&mut self, h: &mut Handle<'_, Ctx>) -> HaltProgress {
        let ctx = h.ctx();
        let left = ctx.halting_left[self.0].get() - 1;
        ctx.halting_left[self.0].set(left);
        if left == 0 {
            ctx.log(self.0, What::Halted);
            HaltProgress::Done
        } else {
            ctx.log(self.0, What::StillHalting);
            HaltProgress::Halting
        }
    }
}

struct SyncLeaf(usize);

impl Action<Ctx> for SyncLeaf {
    fn tick(&self, h: &mut Handle<'_, Ctx>) -> Status {
        let ctx = h.ctx();
        let s = ctx.next(self.0);
        ctx.log(self.0, What::Tick(s));
        s
    }
}

struct AsyncLeaf(usize);

/// The run of an async leaf whose start played Running: each later poll plays the next
/// outcome.
struct AsyncRun {
    leaf: usize,
    shared: Arc<Shared>,
    /// The start's poll, which plays nothing: the start already played Running.
    started: bool,
}

impl Future for AsyncRun {
    type Output = Status;
    fn poll(mut self: Pin<&mut Self>, _cx: &mut Context<'_>) -> Poll<Status> {
        if !self.started {
            self.started = true;
            return Poll::Pending;
        }
        let s = self.shared.next(self.leaf);
        self.shared.log(self.leaf, What::Running(s));
        match s {
            Status::Running => Poll::Pending,
            done => Poll::Ready(done),
        }
    }
}

/// The halt of an async leaf: ready on its `left`-th poll after the request's.
struct AsyncHalt {
    leaf: usize,
    shared: Arc<Shared>,
    /// The request's poll, which plays nothing, as `on_halt_requested` answers Halting.
    requested: bool,
    left: usize,
    /// The run, dropped with the halt.
    _run: ActionFuture,
}

impl Future for AsyncHalt {
    type Output = ();
    fn poll(mut self: Pin<&mut Self>, _cx: &mut Context<'_>) -> Poll<()> {
        if !self.requested {
            self.requested = true;
            return Poll::Pending;
        }
        self.left -= 1;
        if self.left == 0 {
            self.shared.log(self.leaf, What::Halted);
            Poll::Ready(())
        } else {
            self.shared.log(self.leaf, What::StillHalting);
            Poll::Pending
        }
    }
}

impl AsyncAction<Ctx> for AsyncLeaf {
    fn start(&self, h: &mut Handle<'_, Ctx>) -> ActionFuture {
        let ctx = h.ctx();
        let s = ctx.next(self.0);
        ctx.log(self.0, What::Start(s));
        if s != Status::Running {
            return Box::pin(std::future::ready(s));
        }
        Box::pin(AsyncRun {
            leaf: self.0,
            shared: Arc::clone(&ctx.shared),
            started: false,
        })
    }

    fn on_halt_requested(&self, run: ActionFuture, h: &mut Handle<'_, Ctx>) -> Option<HaltFuture> {
        let ctx = h.ctx();
        let k = ctx.halt_ticks[self.0];
        if k == 0 {
            ctx.log(self.0, What::Halted);
            return None;
        }
        ctx.log(self.0, What::HaltRequested);
        Some(Box::pin(AsyncHalt {
            leaf: self.0,
            shared: Arc::clone(&ctx.shared),
            requested: false,
            left: k,
            _run: run,
        }))
    }
}

/// The engine blueprint of a description.
pub fn blueprint(spec: &Spec) -> Arc<Blueprint<Ctx>> {
    let mut next = 0;
    let bp = add(Builder::new(), spec, &mut next)
        .build_shared()
        .expect("generated trees are valid");
    assert_eq!(bp.len(), spec.len());
    bp
}

fn add(b: Builder<Ctx>, spec: &Spec, next: &mut usize) -> Builder<Ctx> {
    add_named(b, spec, next, &Naming::ById, 0)
}

/// How [`add_named`] names nodes.
enum Naming {
    /// `L{id}` and `N{id}`, by pre-order id.
    ById,
    /// `c{i}` by place among its siblings, and the node of pre-order id `replaced` (with
    /// its subtree) replaced by an AlwaysSuccess leaf.
    ByPlace { replaced: Option<usize> },
}

/// A blueprint of `spec` whose nodes are named by their place among their siblings, so
/// that a node's path stays when another subtree changes; with `replaced`, the node of that
/// pre-order id and its subtree become one AlwaysSuccess leaf. Leaves keep their
/// pre-order ids of `spec` (their scripts in a [`Ctx`] of `spec`).
pub fn blueprint_by_place(spec: &Spec, replaced: Option<usize>) -> Arc<Blueprint<Ctx>> {
    let mut next = 0;
    add_named(
        Builder::new(),
        spec,
        &mut next,
        &Naming::ByPlace { replaced },
        0,
    )
    .build_shared()
    .expect("generated trees are valid")
}

fn add_named(
    b: Builder<Ctx>,
    spec: &Spec,
    next: &mut usize,
    naming: &Naming,
    place: usize,
) -> Builder<Ctx> {
    let id = *next;
    *next += 1;
    let (leaf_name, node_name) = match naming {
        Naming::ById => (format!("L{id}"), format!("N{id}")),
        Naming::ByPlace { replaced } => {
            if *replaced == Some(id) {
                *next = id + spec.len();
                return b.always_success(&format!("c{place}"));
            }
            (format!("c{place}"), format!("c{place}"))
        }
    };
    let name = leaf_name;
    let (kind, children) = match spec {
        Spec::Leaf(LeafKind::Stateful, _) => return b.stateful(&name, move || Scripted(id)),
        Spec::Leaf(LeafKind::Sync, _) => return b.action_node(&name, SyncLeaf(id)),
        Spec::Leaf(LeafKind::Cond, _) => return b.condition(&name, move |c: &Ctx| c.cond(id)),
        Spec::Leaf(LeafKind::Async, _) => return b.async_action_node(&name, AsyncLeaf(id)),
        Spec::Node(kind, children) => (kind, children),
    };
    let name = node_name;
    let kids = |mut b: Builder<Ctx>| {
        for (i, c) in children.iter().enumerate() {
            b = add_named(b, c, next, naming, i);
        }
        b
    };
    match *kind {
        Kind::Sequence => b.sequence(&name, kids),
        Kind::SequenceWithMemory => b.sequence_with_memory(&name, kids),
        Kind::ReactiveSequence => b.reactive_sequence(&name, kids),
        Kind::Fallback => b.fallback(&name, kids),
        Kind::ReactiveFallback => b.reactive_fallback(&name, kids),
        Kind::AsyncSequence => b.async_sequence(&name, kids),
        Kind::AsyncFallback => b.async_fallback(&name, kids),
        Kind::Parallel { success, failure } => b.parallel(&name, success, failure, kids),
        Kind::ParallelAll { max_failures } => b.parallel_all(&name, max_failures, kids),
        Kind::IfThenElse => b.if_then_else(&name, kids),
        Kind::WhileDoElse => b.while_do_else(&name, kids),
        Kind::TryCatch { catch_on_halt } => b.try_catch(&name, catch_on_halt, kids),
        Kind::Inverter => b.inverter(&name, kids),
        Kind::ForceSuccess => b.force_success(&name, kids),
        Kind::ForceFailure => b.force_failure(&name, kids),
        Kind::Repeat(n) => b.repeat(&name, n, kids),
        Kind::Retry(n) => b.retry(&name, n, kids),
        Kind::KeepRunningUntilFailure => b.keep_running_until_failure(&name, kids),
        Kind::RunOnce { then_skip } => b.run_once(&name, then_skip, kids),
        Kind::Timeout(ms) => b.timeout(&name, millis(ms), kids),
        Kind::Delay(ms) => b.delay(&name, millis(ms), kids),
        Kind::Cooldown(ms) => b.cooldown(&name, millis(ms), kids),
        Kind::Sleep(ms) => b.sleep(&name, millis(ms)),
    }
}

fn millis(ms: u16) -> std::time::Duration {
    std::time::Duration::from_millis(u64::from(ms))
}

/// Resolves a Parallel threshold as BehaviorTree.CPP does: negative `t` is `n + t + 1`,
/// floored at 0.
pub fn resolve(t: i32, n: usize) -> usize {
    if t < 0 {
        (n as i64 + i64::from(t) + 1).max(0) as usize
    } else {
        t as usize
    }
}

// ---- strategies ----

fn outcome() -> impl Strategy<Value = Status> {
    prop_oneof![
        2 => Just(Status::Success),
        2 => Just(Status::Failure),
        3 => Just(Status::Running),
    ]
}

fn instant() -> impl Strategy<Value = Status> {
    prop_oneof![Just(Status::Success), Just(Status::Failure)]
}

/// A leaf; with `async_leaves`, half of the leaves that run are async actions.
fn leaf(async_leaves: bool) -> BoxedStrategy<Spec> {
    if !async_leaves {
        return prop_oneof![
            4 => vec(outcome(), 1..5).prop_map(|s| Spec::Leaf(LeafKind::Stateful, s)),
            1 => vec(instant(), 1..4).prop_map(|s| Spec::Leaf(LeafKind::Sync, s)),
            1 => vec(instant(), 1..4).prop_map(|s| Spec::Leaf(LeafKind::Cond, s)),
        ]
        .boxed();
    }
    prop_oneof![
        2 => vec(outcome(), 1..5).prop_map(|s| Spec::Leaf(LeafKind::Stateful, s)),
        2 => vec(outcome(), 1..5).prop_map(|s| Spec::Leaf(LeafKind::Async, s)),
        1 => vec(instant(), 1..4).prop_map(|s| Spec::Leaf(LeafKind::Sync, s)),
        1 => vec(instant(), 1..4).prop_map(|s| Spec::Leaf(LeafKind::Cond, s)),
    ]
    .boxed()
}

fn ordered_kind() -> impl Strategy<Value = Kind> {
    prop_oneof![
        Just(Kind::Sequence),
        Just(Kind::SequenceWithMemory),
        Just(Kind::ReactiveSequence),
        Just(Kind::Fallback),
        Just(Kind::ReactiveFallback),
        Just(Kind::AsyncSequence),
        Just(Kind::AsyncFallback),
    ]
}

fn decorator_kind(forever: bool) -> impl Strategy<Value = Kind> {
    let low = if forever { -1 } else { 0 };
    prop_oneof![
        Just(Kind::Inverter),
        Just(Kind::ForceSuccess),
        Just(Kind::ForceFailure),
        (low..4).prop_map(Kind::Repeat),
        (low..4).prop_map(Kind::Retry),
        Just(Kind::KeepRunningUntilFailure),
        any::<bool>().prop_map(|then_skip| Kind::RunOnce { then_skip }),
    ]
}

/// Random trees of stateful actions, sync actions and conditions under the nodes that
/// pass a Running child's tick straight through (Sequence, Fallback, Inverter,
/// ForceSuccess, ForceFailure, Repeat, RetryUntilSuccessful with fixed counts, -1 among
/// them): the trees whose ticks may start at the stateful action they rest in.
pub fn pass_through_tree() -> impl Strategy<Value = Spec> {
    leaf(false).prop_recursive(4, 160, 4, move |inner| {
        let kinds = prop_oneof![
            Just(Kind::Sequence),
            Just(Kind::Fallback),
            Just(Kind::Inverter),
            Just(Kind::ForceSuccess),
            Just(Kind::ForceFailure),
            (-1..4).prop_map(Kind::Repeat),
            (-1..4).prop_map(Kind::Retry),
        ];
        (kinds, vec(inner, 1..=4)).prop_map(|(kind, mut kids)| {
            if !matches!(kind, Kind::Sequence | Kind::Fallback) {
                kids.truncate(1);
            }
            Spec::Node(kind, kids)
        })
    })
}

/// Random trees of depth at most 4 whose nodes have at most 5 children.
///
/// With `forever`, Repeat and RetryUntilSuccessful may get -1 (forever), which can make
/// `tick_once` loop without end; without it, every `tick_once` terminates.
pub fn tree(forever: bool) -> impl Strategy<Value = Spec> {
    tree_with(forever, false)
}

/// As [`tree`], with async actions among the leaves when `async_leaves` is set.
pub fn tree_with(forever: bool, async_leaves: bool) -> impl Strategy<Value = Spec> {
    leaf(async_leaves).prop_recursive(3, 160, 3, move |inner| {
        let kids = vec(inner.clone(), 1..=5);
        prop_oneof![
            6 => (ordered_kind(), kids.clone()).prop_map(|(k, c)| Spec::Node(k, c)),
            2 => kids.clone().prop_flat_map(|c| {
                let n = c.len() as i32;
                (Just(c), -(n + 1)..=n, -(n + 1)..=n).prop_map(|(c, success, failure)| {
                    Spec::Node(Kind::Parallel { success, failure }, c)
                })
            }),
            1 => kids.prop_flat_map(|c| {
                let n = c.len() as i32;
                (Just(c), -(n + 1)..=n)
                    .prop_map(|(c, max_failures)| Spec::Node(Kind::ParallelAll { max_failures }, c))
            }),
            2 => (
                prop_oneof![Just(Kind::IfThenElse), Just(Kind::WhileDoElse)],
                vec(inner.clone(), 2..=3)
            )
                .prop_map(|(k, c)| Spec::Node(k, c)),
            1 => (any::<bool>(), vec(inner.clone(), 2..=4))
                .prop_map(|(catch_on_halt, c)| Spec::Node(Kind::TryCatch { catch_on_halt }, c)),
            5 => (decorator_kind(forever), inner).prop_map(|(k, c)| Spec::Node(k, vec![c])),
        ]
    })
}

/// As [`tree`], with the nodes that read the clock among the others: Timeout, Delay and
/// Cooldown over a child, Sleep among the leaves, each of 0 to 400 ms.
pub fn timed_tree() -> impl Strategy<Value = Spec> {
    // Round times as well as any: with steps of 100 ms, a wait then ends exactly at a tick.
    let ms = || prop_oneof![Just(0u16), (1u16..4).prop_map(|n| n * 100), 1u16..400];
    let timed_leaf = prop_oneof![
        4 => leaf(false),
        1 => ms().prop_map(|ms| Spec::Node(Kind::Sleep(ms), Vec::new())),
    ];
    timed_leaf.prop_recursive(3, 120, 3, move |inner| {
        let timed = prop_oneof![
            ms().prop_map(Kind::Timeout),
            ms().prop_map(Kind::Delay),
            ms().prop_map(Kind::Cooldown),
        ];
        prop_oneof![
            4 => (ordered_kind(), vec(inner.clone(), 1..=4)).prop_map(|(k, c)| Spec::Node(k, c)),
            1 => vec(inner.clone(), 1..=3).prop_flat_map(|c| {
                let n = c.len() as i32;
                (Just(c), -(n + 1)..=n, -(n + 1)..=n).prop_map(|(c, success, failure)| {
                    Spec::Node(Kind::Parallel { success, failure }, c)
                })
            }),
            3 => (timed, inner.clone()).prop_map(|(k, c)| Spec::Node(k, vec![c])),
            2 => (decorator_kind(false), inner).prop_map(|(k, c)| Spec::Node(k, vec![c])),
        ]
    })
}

/// One step of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    TickOnce,
    TickExactlyOnce,
    Halt,
}

/// 1 to 12 random steps.
pub fn ops() -> impl Strategy<Value = Vec<Op>> {
    vec(
        prop_oneof![
            4 => Just(Op::TickOnce),
            3 => Just(Op::TickExactlyOnce),
            1 => Just(Op::Halt),
        ],
        1..=12,
    )
}

/// What one step of a run shows: its result, the events it caused, every status after it.
pub type Step = (
    Option<Result<Status, neurotree_core::TickError>>,
    Vec<Event>,
    Vec<neurotree_core::NodeStatus>,
);

/// Makes one step of a run and tells what it showed.
pub fn step(tree: &mut neurotree_core::Tree<Ctx>, ctx: &mut Ctx, op: Op) -> Step {
    let result = match op {
        Op::TickOnce => Some(tree.tick_once(ctx)),
        Op::TickExactlyOnce => Some(tree.tick_exactly_once(ctx)),
        Op::Halt => {
            tree.halt(ctx);
            None
        }
    };
    (result, ctx.take_events(), tree.statuses().to_vec())
}

/// Makes the steps `ops` of a run, one after the other.
pub fn run(tree: &mut neurotree_core::Tree<Ctx>, ctx: &mut Ctx, ops: &[Op]) -> Vec<Step> {
    ops.iter().map(|&op| step(tree, ctx, op)).collect()
}
