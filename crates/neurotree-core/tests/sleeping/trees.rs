//! Random trees of waiting leaves and random events, for the properties that a sleeping
//! tree (`sleeping.rs`) and a crowd of sleeping members (`neurotree`'s `crowd_sleeping.rs`,
//! which includes this file) give what ticking every frame gives.

#![allow(dead_code)]

use std::sync::Arc;
use std::time::Duration;

use neurotree_core::{
    Action, Blueprint, Builder, Condition, Handle, ParallelPolicy, StatefulAction, Status,
};
use proptest::prelude::*;

/// What the leaves did, in order: (leaf, what, clock in ms); and the context a
/// [`Bell`] reads: how many times the program rang (it wakes the tree when it does); and
/// the weather a closure condition reads, which changes without waking anyone.
#[derive(Default, Debug, Clone, PartialEq)]
pub struct Log(pub Vec<(u8, &'static str, u64)>, pub u64, pub u64);

/// A stateful action: Success once entry `k{key}` is true, Failure once `ms` has passed
/// since it started; on completing it counts itself in entry `n{id}`. With `declare` it
/// says so (`sleep_until` and `wake_on`); without, it keeps the tree awake.
pub struct Waiter {
    id: u8,
    key: u8,
    ms: u64,
    declare: bool,
    until: Duration,
}

impl Waiter {
    fn step(&mut self, h: &mut Handle<'_, Log>) -> Status {
        let now = h.now();
        let done = if h
            .blackboard()
            .get::<bool>(&format!("k{}", self.key))
            .unwrap_or(false)
        {
            Some(Status::Success)
        } else if now >= self.until {
            Some(Status::Failure)
        } else {
            None
        };
        let Some(status) = done else {
            if self.declare {
                h.sleep_until(self.until);
                h.wake_on(&format!("k{}", self.key));
            }
            return Status::Running;
        };
        let entry = format!("n{}", self.id);
        let n = h.blackboard().get::<i64>(&entry).unwrap_or(0);
        h.blackboard_mut().set(&entry, n + 1).unwrap();
        let what = if status == Status::Success {
            "success"
        } else {
            "failure"
        };
        h.ctx_mut().0.push((self.id, what, now.as_millis() as u64));
        status
    }
}

impl StatefulAction<Log> for Waiter {
    fn on_start(&mut self, h: &mut Handle<'_, Log>) -> Status {
        self.until = h.now() + Duration::from_millis(self.ms);
        let at = h.now().as_millis() as u64;
        h.ctx_mut().0.push((self.id, "start", at));
        self.step(h)
    }
    fn on_running(&mut self, h: &mut Handle<'_, Log>) -> Status {
        self.step(h)
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Log>) {
        let at = h.now().as_millis() as u64;
        h.ctx_mut().0.push((self.id, "halted", at));
    }
}

/// A check of entry `k{key}`: Success if it is true.
pub struct Check(u8);

impl Action<Log> for Check {
    fn tick(&self, h: &mut Handle<'_, Log>) -> Status {
        let set = h
            .blackboard()
            .get::<bool>(&format!("k{}", self.0))
            .unwrap_or(false);
        Status::from(set)
    }
}

/// A check of the clock that declares nothing: Success in the first half of every period
/// of `0` ms. A reactive parent re-checks it every tick, so it must keep the tree awake.
pub struct Tide(u64);

impl Action<Log> for Tide {
    fn tick(&self, h: &mut Handle<'_, Log>) -> Status {
        let ms = h.now().as_millis() as u64;
        Status::from(ms % self.0 < self.0 / 2)
    }
}

/// A condition of the clock, as [`Tide`], that declares nothing: a `Condition` object,
/// called from its parent's loop (and from a guard's, with its siblings), which a reactive
/// node above it, however high, must not let sleep.
pub struct Ebb(u64);

impl Condition<Log> for Ebb {
    fn check(&self, h: &Handle<'_, Log>) -> bool {
        let ms = h.now().as_millis() as u64;
        ms % self.0 < self.0 / 2
    }
}

/// A condition of entry `k{key}` that says it reads only the blackboard: a reactive parent
/// re-checking it lets the tree sleep.
pub struct Pure(u8);

impl Condition<Log> for Pure {
    fn check(&self, h: &Handle<'_, Log>) -> bool {
        h.blackboard()
            .get::<bool>(&format!("k{}", self.0))
            .unwrap_or(false)
    }
    fn reads_only_blackboard(&self) -> bool {
        true
    }
}

/// A condition of entry `k{key}` that declares, each time, the entry it waits on.
pub struct Watch(u8);

impl Condition<Log> for Watch {
    fn check(&self, h: &Handle<'_, Log>) -> bool {
        let key = format!("k{}", self.0);
        h.wake_on(&key);
        h.blackboard().get::<bool>(&key).unwrap_or(false)
    }
}

/// A condition of the context: Success while the program has rung an even number of times.
/// It declares `wake_on_handle`: the program wakes the tree when it rings.
pub struct Bell;

impl Condition<Log> for Bell {
    fn check(&self, h: &Handle<'_, Log>) -> bool {
        h.wake_on_handle();
        h.ctx().1 & 1 == 0
    }
}

/// A node of a random tree.
#[derive(Clone, Debug)]
pub enum Node {
    Waiter { key: u8, ms: u64, declare: bool },
    Check(u8),
    Tide(u64),
    Ebb(u64),
    Pure(u8),
    Watch(u8),
    Bell,
    Fair,
    Sleep(u64),
    Always(bool),
    Control(u8, Vec<Node>),
    Decorator(u8, u64, Box<Node>),
}

pub fn node() -> impl Strategy<Value = Node> {
    let leaf = prop_oneof![
        4 => (0u8..3, 1u64..8, prop::bool::weighted(0.85))
            .prop_map(|(key, t, declare)| Node::Waiter { key, ms: t * 100, declare }),
        2 => (0u8..3).prop_map(Node::Check),
        2 => (2u64..9).prop_map(|t| Node::Tide(t * 100)),
        2 => (2u64..9).prop_map(|t| Node::Ebb(t * 100)),
        2 => (0u8..3).prop_map(Node::Pure),
        2 => (0u8..3).prop_map(Node::Watch),
        1 => Just(Node::Bell),
        1 => Just(Node::Fair),
        1 => (1u64..8).prop_map(|t| Node::Sleep(t * 100)),
        1 => any::<bool>().prop_map(Node::Always),
    ];
    leaf.prop_recursive(3, 16, 3, |inner| {
        prop_oneof![
            (0u8..9, prop::collection::vec(inner.clone(), 1..4))
                .prop_map(|(kind, kids)| Node::Control(kind, kids)),
            (0u8..9, 1u64..8, inner).prop_map(|(kind, t, kid)| Node::Decorator(
                kind,
                t * 100,
                Box::new(kid)
            )),
        ]
    })
}

/// Adds `node` to `b`; `ids` numbers the leaves.
pub fn add(b: Builder<Log>, node: &Node, ids: &mut u8) -> Builder<Log> {
    match node {
        Node::Waiter { key, ms, declare } => {
            let (id, key, ms, declare) = (*ids, *key, *ms, *declare);
            *ids += 1;
            b.stateful(&format!("w{id}"), move || Waiter {
                id,
                key,
                ms,
                declare,
                until: Duration::ZERO,
            })
        }
        Node::Check(key) => b.action_node("check", Check(*key)),
        Node::Tide(period) => b.action_node("tide", Tide(*period)),
        Node::Ebb(period) => b.condition_node("ebb", Ebb(*period)),
        Node::Pure(key) => b.condition_node("pure", Pure(*key)),
        Node::Watch(key) => b.condition_node("watch", Watch(*key)),
        Node::Bell => b.condition_node("bell", Bell),
        Node::Fair => b.condition("fair", |log: &Log| log.2 & 1 == 0),
        Node::Sleep(ms) => b.sleep("sleep", Duration::from_millis(*ms)),
        Node::Always(true) => b.always_success("yes"),
        Node::Always(false) => b.always_failure("no"),
        Node::Control(kind, kids) => {
            let kids = kids.clone();
            let mut ids2 = *ids;
            let children = |mut c: Builder<Log>| {
                for k in &kids {
                    c = add(c, k, &mut ids2);
                }
                c
            };
            let b = match kind % 9 {
                7 if (2..=3).contains(&kids.len()) => b.while_do_else("while", children),
                8 if kids.len() == 2 => b.service("service", Duration::from_millis(200), children),
                0 => b.sequence("seq", children),
                1 => b.fallback("fb", children),
                2 => b.sequence_with_memory("mem", children),
                3 => b.parallel_policy("all", ParallelPolicy::RequireAll, children),
                4 => b.parallel_policy("one", ParallelPolicy::RequireOne, children),
                5 => b.reactive_sequence("rseq", children),
                6 => b.reactive_fallback("rfb", children),
                _ => b.sequence("seq", children),
            };
            *ids = ids2;
            b
        }
        Node::Decorator(kind, ms, kid) => {
            let mut ids2 = *ids;
            let child = |c: Builder<Log>| add(c, kid, &mut ids2);
            let d = Duration::from_millis(*ms);
            let b = match kind % 9 {
                8 => b.cooldown("cooldown", d, child),
                0 => b.timeout("timeout", d, child),
                1 => b.delay("delay", d, child),
                2 => b.inverter("not", child),
                3 => b.keep_running_until_failure("keep", child),
                4 => b.retry("retry", 2, child),
                5 => b.repeat("repeat", 2, child),
                6 => b.force_success("force", child),
                _ => b.run_once("once", true, child),
            };
            *ids = ids2;
            b
        }
    }
}

pub fn blueprint(root: &Node) -> Arc<Blueprint<Log>> {
    let mut ids = 0;
    add(Builder::new(), root, &mut ids)
        .build_shared()
        .expect("a generated tree is valid")
}

/// Something that happens before a tick.
#[derive(Clone, Debug)]
pub enum Event {
    /// The clock advances by this many ms.
    Time(u64),
    /// Entry `k{key}` is written.
    Write(u8, bool),
    /// The program wakes the tree.
    Wake,
    /// The program halts the tree.
    Halt,
    /// The weather changes (the context), waking no one.
    Weather,
}

pub fn event() -> impl Strategy<Value = Event> {
    prop_oneof![
        8 => prop_oneof![Just(0u64), Just(30), Just(100), Just(250), Just(700)].prop_map(Event::Time),
        3 => (0u8..3, any::<bool>()).prop_map(|(k, v)| Event::Write(k, v)),
        1 => Just(Event::Wake),
        1 => Just(Event::Halt),
        1 => Just(Event::Weather),
    ]
}
