//! The reference interpreter: a plain recursive walk over a tree of nodes, each with its
//! stored status and its own state, as BehaviorTree.CPP keeps them (see the test's docs).

use super::common::{self, Event, FlatKind, Kind, LeafKind, Spec, What};
use super::MAX_PASSES;
use neurotree_core::{NodeStatus, Status, TickError};

use NodeStatus::{Failure, Idle, Running, Skipped, Success};

#[derive(Clone, Debug)]
pub(crate) struct Node {
    kind: FlatKind,
    children: Vec<usize>,
    status: NodeStatus,
    // Sequence / Fallback / SequenceWithMemory / TryCatch.
    cursor: usize,
    skipped: usize,
    in_catch: bool,
    // IfThenElse: the branch in progress (0: none).
    branch: usize,
    // Repeat / RetryUntilSuccessful.
    count: i32,
    // Parallel / ParallelAll (BT.CPP's completed_list_, success_count_, failure_count_).
    completed: Vec<bool>,
    successes: usize,
    failures: usize,
    // RunOnce: the status of its one completed run.
    ran: Option<NodeStatus>,
    // Leaves.
    script: Vec<Status>,
    calls: usize,
}

#[derive(Clone, Debug)]
pub(crate) struct Model {
    nodes: Vec<Node>,
    pub(crate) events: Vec<Event>,
    wake: bool,
}

fn ns(s: Status) -> NodeStatus {
    NodeStatus::from(s)
}

fn active(s: NodeStatus) -> bool {
    matches!(s, Running | Success | Failure)
}

impl Model {
    pub(crate) fn new(spec: &Spec) -> Self {
        let nodes = spec
            .flatten()
            .into_iter()
            .map(|f| Node {
                completed: vec![false; f.children.len()],
                kind: f.node,
                children: f.children,
                status: Idle,
                cursor: 0,
                skipped: 0,
                in_catch: false,
                branch: 0,
                count: 0,
                successes: 0,
                failures: 0,
                ran: None,
                script: f.script,
                calls: 0,
            })
            .collect();
        Self {
            nodes,
            events: Vec::new(),
            wake: false,
        }
    }

    pub(crate) fn statuses(&self) -> Vec<NodeStatus> {
        self.nodes.iter().map(|n| n.status).collect()
    }

    fn child(&self, id: usize, i: usize) -> usize {
        self.nodes[id].children[i]
    }

    fn next(&mut self, id: usize) -> Status {
        let n = &mut self.nodes[id];
        let s = n.script[n.calls.min(n.script.len() - 1)];
        n.calls += 1;
        s
    }

    fn log(&mut self, leaf: usize, what: What) {
        self.events.push(Event { leaf, what });
    }

    // ---- the tree ----

    /// One pass of the root.
    fn pass(&mut self) -> NodeStatus {
        self.wake = false;
        let s = self.execute(0);
        if s == Success || s == Failure {
            self.nodes[0].status = Idle;
        }
        s
    }

    pub(crate) fn tick_exactly_once(&mut self) -> NodeStatus {
        self.pass()
    }

    /// `None` when the passes do not end.
    pub(crate) fn tick_once(&mut self) -> Option<NodeStatus> {
        for _ in 0..MAX_PASSES {
            let s = self.pass();
            if !(s == Running && self.wake) {
                return Some(s);
            }
        }
        None
    }

    /// BT.CPP's `Tree::haltTree`: halt the root, then, "just in case", `haltNode` on every
    /// node in pre-order, which also resets completed statuses a control left behind.
    pub(crate) fn halt_tree(&mut self) {
        self.halt(0);
        for id in 0..self.nodes.len() {
            self.halt(id);
        }
        self.nodes[0].status = Idle;
    }

    // ---- BT.CPP's TreeNode / ControlNode / DecoratorNode helpers ----

    /// `executeTick`: tick, then store the result (Skipped is stored as Idle).
    fn execute(&mut self, id: usize) -> NodeStatus {
        let s = self.tick(id);
        self.nodes[id].status = if s == Skipped { Idle } else { s };
        s
    }

    /// `haltChild` / `resetChild`.
    fn halt_child(&mut self, c: usize) {
        if self.nodes[c].status == Running {
            self.halt(c);
        }
        self.nodes[c].status = Idle;
    }

    /// `resetChildren`.
    fn reset_children(&mut self, id: usize) {
        for i in 0..self.nodes[id].children.len() {
            let c = self.child(id, i);
            self.halt_child(c);
        }
    }

    /// `haltNode`: the kind's `halt()`, children first, then the node is Idle.
    fn halt(&mut self, id: usize) {
        match self.nodes[id].kind.clone() {
            FlatKind::Leaf(LeafKind::Stateful | LeafKind::Async) => {
                if self.nodes[id].status == Running {
                    self.log(id, What::Halted);
                }
            }
            FlatKind::Leaf(_) => {}
            FlatKind::Node(kind) => match kind {
                Kind::Sequence | Kind::Fallback | Kind::AsyncSequence | Kind::AsyncFallback => {
                    self.nodes[id].cursor = 0;
                    self.nodes[id].skipped = 0;
                    self.reset_children(id);
                }
                // "should we add this line of code or not? current_child_idx_ = 0;" — no.
                Kind::SequenceWithMemory => self.reset_children(id),
                Kind::Parallel { .. } | Kind::ParallelAll { .. } => {
                    let n = &mut self.nodes[id];
                    n.completed.iter_mut().for_each(|c| *c = false);
                    n.successes = 0;
                    n.failures = 0;
                    self.reset_children(id);
                }
                Kind::IfThenElse => {
                    self.nodes[id].branch = 0;
                    self.reset_children(id);
                }
                Kind::TryCatch { catch_on_halt } => {
                    let n = self.nodes[id].children.len();
                    if catch_on_halt && !self.nodes[id].in_catch && active(self.nodes[id].status) {
                        for i in 0..n - 1 {
                            let c = self.child(id, i);
                            self.halt_child(c);
                        }
                        let catch = self.child(id, n - 1);
                        if self.execute(catch) == Running {
                            self.halt_child(catch);
                        }
                    }
                    let node = &mut self.nodes[id];
                    node.cursor = 0;
                    node.skipped = 0;
                    node.in_catch = false;
                    self.reset_children(id);
                }
                Kind::Repeat(_) | Kind::Retry(_) => {
                    self.nodes[id].count = 0;
                    self.reset_children(id);
                }
                Kind::ReactiveSequence
                | Kind::ReactiveFallback
                | Kind::WhileDoElse
                | Kind::Inverter
                | Kind::ForceSuccess
                | Kind::ForceFailure
                | Kind::KeepRunningUntilFailure
                | Kind::RunOnce { .. } => self.reset_children(id),
                Kind::Timeout(_) | Kind::Delay(_) | Kind::Cooldown(_) | Kind::Sleep(_) => {
                    unreachable!("the model has no clock: timed trees are not made for it")
                }
            },
        }
        self.nodes[id].status = Idle;
    }

    // ---- the nodes' tick() ----

    fn tick(&mut self, id: usize) -> NodeStatus {
        let kind = match self.nodes[id].kind.clone() {
            FlatKind::Leaf(leaf) => return self.tick_leaf(id, leaf),
            FlatKind::Node(kind) => kind,
        };
        match kind {
            Kind::Sequence => self.ordered(id, true, false, false),
            Kind::AsyncSequence => self.ordered(id, true, true, false),
            Kind::SequenceWithMemory => self.ordered(id, true, true, true),
            Kind::Fallback => self.ordered(id, false, false, false),
            Kind::AsyncFallback => self.ordered(id, false, true, false),
            Kind::ReactiveSequence => self.reactive(id, Success),
            Kind::ReactiveFallback => self.reactive(id, Failure),
            Kind::Parallel { success, failure } => self.parallel(id, success, failure),
            Kind::ParallelAll { max_failures } => self.parallel_all(id, max_failures),
            Kind::IfThenElse => self.if_then_else(id),
            Kind::WhileDoElse => self.while_do_else(id),
            Kind::TryCatch { .. } => self.try_catch(id),
            Kind::Inverter => {
                self.nodes[id].status = Running;
                let c = self.child(id, 0);
                match self.execute(c) {
                    Success => {
                        self.halt_child(c);
                        Failure
                    }
                    Failure => {
                        self.halt_child(c);
                        Success
                    }
                    other => other,
                }
            }
            Kind::ForceSuccess | Kind::ForceFailure => {
                self.nodes[id].status = Running;
                let c = self.child(id, 0);
                match self.execute(c) {
                    Success | Failure => {
                        self.halt_child(c);
                        if kind == Kind::ForceSuccess {
                            Success
                        } else {
                            Failure
                        }
                    }
                    other => other,
                }
            }
            Kind::Repeat(n) => self.repeat(id, n, Success),
            Kind::Retry(n) => self.repeat(id, n, Failure),
            Kind::KeepRunningUntilFailure => {
                self.nodes[id].status = Running;
                let c = self.child(id, 0);
                match self.execute(c) {
                    Failure => {
                        self.halt_child(c);
                        Failure
                    }
                    Success => {
                        self.halt_child(c);
                        Running
                    }
                    // Running; and Skipped, where BT.CPP returns its own status, Running.
                    _ => Running,
                }
            }
            Kind::RunOnce { then_skip } => {
                if let Some(done) = self.nodes[id].ran {
                    return if then_skip { Skipped } else { done };
                }
                self.nodes[id].status = Running;
                let c = self.child(id, 0);
                let s = self.execute(c);
                if s == Success || s == Failure {
                    self.nodes[id].ran = Some(s);
                    self.halt_child(c);
                }
                s
            }
            Kind::Timeout(_) | Kind::Delay(_) | Kind::Cooldown(_) | Kind::Sleep(_) => {
                unreachable!("the model has no clock: timed trees are not made for it")
            }
        }
    }

    fn tick_leaf(&mut self, id: usize, leaf: LeafKind) -> NodeStatus {
        match leaf {
            LeafKind::Stateful | LeafKind::Async => match self.nodes[id].status {
                Idle => {
                    let s = self.next(id);
                    self.log(id, What::Start(s));
                    ns(s)
                }
                Running => {
                    let s = self.next(id);
                    self.log(id, What::Running(s));
                    ns(s)
                }
                done => done,
            },
            LeafKind::Sync | LeafKind::Cond => {
                let s = self.next(id);
                self.log(id, What::Tick(s));
                ns(s)
            }
        }
    }

    /// Sequence (`seq`) or Fallback (`!seq`); `yields`: async or with memory; `memory`:
    /// SequenceWithMemory.
    fn ordered(&mut self, id: usize, seq: bool, yields: bool, memory: bool) -> NodeStatus {
        let (go_on, stop) = if seq {
            (Success, Failure)
        } else {
            (Failure, Success)
        };
        let n = self.nodes[id].children.len();
        if !active(self.nodes[id].status) {
            self.nodes[id].skipped = 0;
        }
        self.nodes[id].status = Running;
        while self.nodes[id].cursor < n {
            let c = self.child(id, self.nodes[id].cursor);
            let prev = self.nodes[c].status;
            let s = self.execute(c);
            if s == Running {
                return Running;
            } else if s == stop {
                if memory {
                    for i in self.nodes[id].cursor..n {
                        let c = self.child(id, i);
                        self.halt_child(c);
                    }
                } else {
                    self.reset_children(id);
                    self.nodes[id].cursor = 0;
                }
                return s;
            } else if s == go_on {
                self.nodes[id].cursor += 1;
                if yields && prev == Idle && self.nodes[id].cursor < n {
                    self.wake = true;
                    return Running;
                }
            } else {
                assert_eq!(s, Skipped);
                self.nodes[id].cursor += 1;
                self.nodes[id].skipped += 1;
            }
        }
        let all_skipped = self.nodes[id].skipped == n;
        self.reset_children(id);
        self.nodes[id].cursor = 0;
        self.nodes[id].skipped = 0;
        if all_skipped {
            Skipped
        } else {
            go_on
        }
    }

    fn reactive(&mut self, id: usize, go_on: NodeStatus) -> NodeStatus {
        let n = self.nodes[id].children.len();
        let mut all_skipped = true;
        self.nodes[id].status = Running;
        for index in 0..n {
            let c = self.child(id, index);
            let s = self.execute(c);
            all_skipped &= s == Skipped;
            if s == Running {
                for i in 0..n {
                    if i != index {
                        let other = self.child(id, i);
                        self.halt_child(other);
                    }
                }
                return Running;
            } else if s == Skipped {
                self.halt_child(c);
            } else if s != go_on {
                self.reset_children(id);
                return s;
            }
        }
        self.reset_children(id);
        if all_skipped {
            Skipped
        } else {
            go_on
        }
    }

    fn parallel(&mut self, id: usize, success: i32, failure: i32) -> NodeStatus {
        let n = self.nodes[id].children.len();
        let need = common::resolve(success, n);
        let max_fail = common::resolve(failure, n);
        self.nodes[id].status = Running;
        let mut skipped = 0;
        for i in 0..n {
            if !self.nodes[id].completed[i] {
                let c = self.child(id, i);
                match self.execute(c) {
                    Skipped => skipped += 1,
                    Success => {
                        self.nodes[id].completed[i] = true;
                        self.nodes[id].successes += 1;
                    }
                    Failure => {
                        self.nodes[id].completed[i] = true;
                        self.nodes[id].failures += 1;
                    }
                    _ => {}
                }
            }
            let (successes, failures) = (self.nodes[id].successes, self.nodes[id].failures);
            let done = if successes >= need || (success < 0 && successes + skipped >= need) {
                Some(Success)
            } else if n - failures < need || failures == max_fail {
                Some(Failure)
            } else {
                None
            };
            if let Some(done) = done {
                let node = &mut self.nodes[id];
                node.completed.iter_mut().for_each(|c| *c = false);
                node.successes = 0;
                node.failures = 0;
                self.reset_children(id);
                return done;
            }
        }
        if skipped == n {
            Skipped
        } else {
            Running
        }
    }

    fn parallel_all(&mut self, id: usize, max_failures: i32) -> NodeStatus {
        let n = self.nodes[id].children.len();
        let threshold = common::resolve(max_failures, n);
        self.nodes[id].status = Running;
        let mut skipped = 0;
        for i in 0..n {
            if self.nodes[id].completed[i] {
                continue;
            }
            let c = self.child(id, i);
            match self.execute(c) {
                Success => self.nodes[id].completed[i] = true,
                Failure => {
                    self.nodes[id].completed[i] = true;
                    self.nodes[id].failures += 1;
                }
                Skipped => skipped += 1,
                _ => {}
            }
        }
        if skipped == n {
            return Skipped;
        }
        let completed = self.nodes[id].completed.iter().filter(|c| **c).count();
        if skipped + completed >= n {
            self.reset_children(id);
            let node = &mut self.nodes[id];
            node.completed.iter_mut().for_each(|c| *c = false);
            let status = if node.failures >= threshold {
                Failure
            } else {
                Success
            };
            node.failures = 0;
            return status;
        }
        Running
    }

    fn if_then_else(&mut self, id: usize) -> NodeStatus {
        let n = self.nodes[id].children.len();
        self.nodes[id].status = Running;
        if self.nodes[id].branch == 0 {
            let c = self.child(id, 0);
            match self.execute(c) {
                Running => return Running,
                Success => self.nodes[id].branch = 1,
                Failure if n == 3 => self.nodes[id].branch = 2,
                // BT.CPP returns without resetting the condition.
                Failure => return Failure,
                _ => return Skipped,
            }
        }
        let b = self.child(id, self.nodes[id].branch);
        let s = self.execute(b);
        if s == Running {
            return Running;
        }
        self.reset_children(id);
        self.nodes[id].branch = 0;
        s
    }

    fn while_do_else(&mut self, id: usize) -> NodeStatus {
        let n = self.nodes[id].children.len();
        self.nodes[id].status = Running;
        let c = self.child(id, 0);
        let s = match self.execute(c) {
            Running => return Running,
            Success => {
                if n == 3 {
                    let otherwise = self.child(id, 2);
                    self.halt_child(otherwise);
                }
                let body = self.child(id, 1);
                self.execute(body)
            }
            Failure if n == 3 => {
                let body = self.child(id, 1);
                self.halt_child(body);
                let otherwise = self.child(id, 2);
                self.execute(otherwise)
            }
            Failure => Failure,
            _ => Skipped,
        };
        if s == Running {
            return Running;
        }
        self.reset_children(id);
        s
    }

    fn try_catch(&mut self, id: usize) -> NodeStatus {
        let n = self.nodes[id].children.len();
        if !active(self.nodes[id].status) {
            self.nodes[id].skipped = 0;
            self.nodes[id].in_catch = false;
        }
        self.nodes[id].status = Running;
        let tries = n - 1;
        if !self.nodes[id].in_catch {
            while self.nodes[id].cursor < tries {
                let c = self.child(id, self.nodes[id].cursor);
                match self.execute(c) {
                    Running => return Running,
                    Failure => {
                        self.reset_children(id);
                        self.nodes[id].cursor = 0;
                        self.nodes[id].in_catch = true;
                        // BT.CPP re-enters tick() to run the catch child.
                        return self.try_catch(id);
                    }
                    Success => self.nodes[id].cursor += 1,
                    _ => {
                        self.nodes[id].cursor += 1;
                        self.nodes[id].skipped += 1;
                    }
                }
            }
            let all_skipped = self.nodes[id].skipped == tries;
            self.reset_children(id);
            self.nodes[id].cursor = 0;
            self.nodes[id].skipped = 0;
            return if all_skipped { Skipped } else { Success };
        }
        let catch = self.child(id, tries);
        if self.execute(catch) == Running {
            return Running;
        }
        self.reset_children(id);
        self.nodes[id].cursor = 0;
        self.nodes[id].in_catch = false;
        Failure
    }

    /// Repeat (`again` = Success) or RetryUntilSuccessful (`again` = Failure).
    fn repeat(&mut self, id: usize, limit: i32, again: NodeStatus) -> NodeStatus {
        let stop = if again == Success { Failure } else { Success };
        let more = |count: i32| count < limit || limit == -1;
        let c = self.child(id, 0);
        let mut do_loop = more(self.nodes[id].count);
        self.nodes[id].status = Running;
        while do_loop {
            let prev = self.nodes[c].status;
            let s = self.execute(c);
            if s == again {
                self.nodes[id].count += 1;
                do_loop = more(self.nodes[id].count);
                self.halt_child(c);
                if prev == Idle && do_loop {
                    self.wake = true;
                    return Running;
                }
            } else if s == stop {
                self.nodes[id].count = 0;
                self.halt_child(c);
                return stop;
            } else if s == Running {
                return Running;
            } else {
                // Skipped: reset the child, keep the count.
                self.halt_child(c);
                return Skipped;
            }
        }
        self.nodes[id].count = 0;
        again
    }
}

pub(crate) fn to_result(s: NodeStatus) -> Result<Status, TickError> {
    match s {
        Success => Ok(Status::Success),
        Failure => Ok(Status::Failure),
        Running => Ok(Status::Running),
        Skipped => Err(TickError::RootSkipped),
        Idle => panic!("the root returned Idle"),
    }
}
