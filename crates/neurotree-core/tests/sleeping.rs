//! A sleeping tree gives what a tree ticked every frame gives: random trees under random
//! events (time passing, blackboard writes, wakes, halts), ticked by a tree that may sleep
//! and by one that may not, return the same statuses, leave every node in the same status,
//! start, complete and halt the same leaves at the same moments, and write the same
//! blackboard.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree_core::{Blueprint, ManualClock, Tree};
use proptest::prelude::*;

#[path = "sleeping/trees.rs"]
mod trees;
use trees::{blueprint, event, node, Event, Log, Node};

/// One tree and what its leaves did.
struct Run {
    tree: Tree<Log>,
    clock: ManualClock,
    log: Log,
}

impl Run {
    fn new(bp: &Arc<Blueprint<Log>>, sleeps: bool) -> Self {
        let clock = ManualClock::new();
        let mut tree = Tree::with_clock(Arc::clone(bp), clock.clone());
        tree.set_sleep_allowed(sleeps);
        Run {
            tree,
            clock,
            log: Log::default(),
        }
    }

    /// Applies `event`, then ticks; what the tick returned.
    fn step(&mut self, event: &Event, exactly_once: bool) -> String {
        match event {
            Event::Time(ms) => self.clock.advance(Duration::from_millis(*ms)),
            Event::Write(k, v) => self
                .tree
                .blackboard_mut()
                .set(&format!("k{k}"), *v)
                .unwrap(),
            Event::Wake => {
                // The program rings the bell some conditions read, and wakes the tree.
                self.log.1 += 1;
                self.tree.wake_handle().wake()
            }
            Event::Halt => {
                self.tree.halt(&mut self.log);
            }
            Event::Weather => self.log.2 += 1,
        }
        let result = if exactly_once {
            self.tree.tick_exactly_once(&mut self.log)
        } else {
            self.tree.tick_once(&mut self.log)
        };
        format!("{result:?}")
    }

    /// The blackboard's entries, as text.
    fn entries(&self) -> Vec<String> {
        let bb = self.tree.blackboard();
        let mut keys: Vec<String> = bb
            .keys_in(neurotree_core::ScopeId::ROOT)
            .map(String::from)
            .collect();
        keys.sort();
        keys.into_iter()
            .map(|k| {
                let v = bb
                    .get::<i64>(&k)
                    .map(|v| v.to_string())
                    .or_else(|_| bb.get::<bool>(&k).map(|v| v.to_string()))
                    .unwrap_or_default();
                format!("{k}={v}")
            })
            .collect()
    }
}

/// Ticks `root` under `events` twice, sleeping and not; the first difference, if any.
fn compare(root: &Node, events: &[Event], exactly_once: bool) -> Result<usize, TestCaseError> {
    let bp = blueprint(root);
    let mut sleeping = Run::new(&bp, true);
    let mut reference = Run::new(&bp, false);
    let mut slept = 0;
    for (i, e) in events.iter().enumerate() {
        let a = sleeping.step(e, exactly_once);
        let b = reference.step(e, exactly_once);
        prop_assert_eq!(&a, &b, "tick {} after {:?}", i, e);
        prop_assert_eq!(
            sleeping.tree.statuses(),
            reference.tree.statuses(),
            "tick {}",
            i
        );
        prop_assert_eq!(&sleeping.log, &reference.log, "tick {}", i);
        prop_assert_eq!(sleeping.entries(), reference.entries(), "tick {}", i);
        slept += usize::from(sleeping.tree.is_asleep());
    }
    Ok(slept)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn sleeping_changes_nothing_but_the_calls_saved(
        root in node(),
        events in prop::collection::vec(event(), 1..60),
        exactly_once in any::<bool>(),
    ) {
        compare(&root, &events, exactly_once)?;
    }
}

/// The property is not empty: a plain tree of waiting leaves sleeps most of the time.
#[test]
fn a_tree_of_waiting_leaves_sleeps() {
    let root = Node::Control(
        3,
        vec![
            Node::Waiter {
                key: 0,
                ms: 500,
                declare: true,
            },
            Node::Decorator(
                0,
                300,
                Box::new(Node::Waiter {
                    key: 1,
                    ms: 900,
                    declare: true,
                }),
            ),
        ],
    );
    let events = vec![Event::Time(30); 40];
    let slept = compare(&root, &events, false).unwrap();
    assert!(slept > 30, "slept {slept} of 40 ticks");
}

/// A Running action that its own branch halts in the pass (a Service whose branch failed
/// resets it) starts again when a reactive node re-checks that branch: the tree stays awake
/// for it, and starts and halts it on every tick as a tree ticked every frame does.
#[test]
fn an_action_halted_in_a_branch_a_reactive_node_rechecks_keeps_the_tree_awake() {
    let waiter = || Node::Waiter {
        key: 0,
        ms: 100,
        declare: true,
    };
    // ReactiveFallback [Service [w0, pure k0], Timeout [w1]].
    let root = Node::Control(
        6,
        vec![
            Node::Control(8, vec![waiter(), Node::Pure(0)]),
            Node::Decorator(0, 100, Box::new(waiter())),
        ],
    );
    let events = vec![Event::Time(0); 4];
    let slept = compare(&root, &events, false).unwrap();
    assert_eq!(slept, 0);
    let mut run = Run::new(&blueprint(&root), true);
    for e in &events {
        run.step(e, false);
    }
    let of_w0 = |what: &str| run.log.0.iter().filter(|l| (l.0, l.1) == (0, what)).count();
    assert_eq!((of_w0("start"), of_w0("halted")), (4, 4));
}

/// The trees of the property, ticked on N threads side by side, agree with one thread.
#[test]
fn sleeping_trees_on_several_threads_agree_with_one() {
    let root = Node::Control(
        0,
        vec![
            Node::Decorator(
                1,
                200,
                Box::new(Node::Waiter {
                    key: 0,
                    ms: 600,
                    declare: true,
                }),
            ),
            Node::Control(
                4,
                vec![
                    Node::Waiter {
                        key: 1,
                        ms: 400,
                        declare: true,
                    },
                    Node::Sleep(300),
                ],
            ),
        ],
    );
    let events: Vec<Event> = (0..80)
        .map(|i| match i % 9 {
            4 => Event::Write((i % 3) as u8, i % 2 == 0),
            7 => Event::Wake,
            _ => Event::Time(50),
        })
        .collect();
    let one = |bp: &Arc<Blueprint<Log>>| {
        let mut run = Run::new(bp, true);
        let results: Vec<String> = events.iter().map(|e| run.step(e, false)).collect();
        (results, run.log.clone(), run.entries())
    };
    let bp = blueprint(&root);
    let alone = one(&bp);
    let seen = Arc::new(Mutex::new(Vec::new()));
    std::thread::scope(|s| {
        for _ in 0..4 {
            let (bp, seen, one) = (Arc::clone(&bp), Arc::clone(&seen), &one);
            s.spawn(move || {
                let mine = one(&bp);
                seen.lock().unwrap().push(mine);
            });
        }
    });
    let seen = seen.lock().unwrap();
    assert_eq!(seen.len(), 4);
    for run in seen.iter() {
        assert_eq!(run, &alone);
    }
}

/// `ReactiveSequence(bell, ReactiveFallback(pure k0, watch k1, waiter k2))`: every
/// condition re-checked says what wakes it.
fn reactive_over_declared_conditions() -> Node {
    Node::Control(
        5,
        vec![
            Node::Bell,
            Node::Control(
                6,
                vec![
                    Node::Pure(0),
                    Node::Watch(1),
                    Node::Waiter {
                        key: 2,
                        ms: 5_000,
                        declare: true,
                    },
                ],
            ),
        ],
    )
}

/// Reactive nodes over conditions that read the blackboard alone, or say what wakes them,
/// sleep between the events, and give what ticking every frame gives when they come.
#[test]
fn a_reactive_tree_over_declared_conditions_sleeps() {
    let mut events = vec![Event::Time(30); 20];
    events.push(Event::Write(2, false)); // wakes, changes nothing: asleep again
    events.extend(vec![Event::Time(30); 5]);
    events.push(Event::Wake); // the bell rings: the sequence fails, the waiter is halted
    events.extend(vec![Event::Time(30); 5]);
    events.push(Event::Wake); // rings again: the waiter starts afresh
    events.extend(vec![Event::Time(30); 5]);
    events.push(Event::Write(0, true)); // the fallback succeeds: the waiter is halted
    let slept = compare(&reactive_over_declared_conditions(), &events, false).unwrap();
    assert!(slept >= 30, "slept {slept} of {} ticks", events.len());
}

/// The same tree with a condition of the clock (which declares nothing) does not sleep, and
/// says why, naming that condition.
#[test]
fn a_reactive_tree_over_an_undeclared_condition_stays_awake_and_says_why() {
    let bp = blueprint(&Node::Control(
        5,
        vec![
            Node::Tide(10_000),
            Node::Waiter {
                key: 2,
                ms: 5_000,
                declare: true,
            },
        ],
    ));
    let mut tree = Tree::with_clock(bp, ManualClock::new());
    assert_eq!(
        tree.why_awake().map(|w| w.reason),
        Some(neurotree_core::AwakeReason::NotRunning)
    );
    let mut log = Log::default();
    for _ in 0..3 {
        tree.tick_once(&mut log).unwrap();
        assert!(!tree.is_asleep());
    }
    let why = tree.why_awake().expect("awake");
    assert_eq!(why.reason, neurotree_core::AwakeReason::ReactiveCondition);
    assert_eq!(why.path, "rseq/tide");
    assert_eq!(
        why.to_string(),
        "`rseq/tide` is re-checked every tick by a reactive node and may read more than the blackboard"
    );
    // Over declared conditions, the same shape sleeps: nothing to say.
    let mut tree = Tree::with_clock(
        blueprint(&reactive_over_declared_conditions()),
        ManualClock::new(),
    );
    tree.tick_once(&mut log).unwrap();
    assert!(tree.is_asleep());
    assert_eq!(tree.why_awake(), None);
    // A waiter that declares nothing is named as such.
    let mut tree = Tree::with_clock(
        blueprint(&Node::Control(
            0,
            vec![
                Node::Always(true),
                Node::Waiter {
                    key: 0,
                    ms: 500,
                    declare: false,
                },
            ],
        )),
        ManualClock::new(),
    );
    tree.tick_once(&mut log).unwrap();
    tree.tick_once(&mut log).unwrap(); // the resting path says it too
    let why = tree.why_awake().expect("awake");
    assert_eq!(why.reason, neurotree_core::AwakeReason::UndeclaredLeaf);
    assert_eq!(why.path, "seq/w0");
}

/// A condition object of the clock that declares nothing keeps awake the reactive node
/// above it however deep it sits (in a guard of conditions, in a Sequence, under the
/// reactive node), and only a reactive node: with none above it, the tree sleeps.
#[test]
fn an_undeclared_condition_object_keeps_awake_only_a_reactive_node_above_it() {
    let waiter = || Node::Waiter {
        key: 2,
        ms: 5_000,
        declare: true,
    };
    // seq(fb(pure, ebb), yes): the Fallback is a guard of condition objects; the entry
    // `pure` reads is never written, so the second one decides.
    let guarded = |ebb: Node| {
        Node::Control(
            0,
            vec![
                Node::Control(1, vec![Node::Pure(0), ebb]),
                Node::Always(true),
            ],
        )
    };
    let awake_for = |root: &Node| {
        let mut tree = Tree::with_clock(blueprint(root), ManualClock::new());
        let mut log = Log::default();
        for _ in 0..3 {
            tree.tick_once(&mut log).unwrap();
        }
        tree.why_awake().map(|w| (w.reason, w.path))
    };
    // The clock's half-period is far off: the ebb holds in every tick.
    let deep = Node::Control(5, vec![guarded(Node::Ebb(1_000_000)), waiter()]);
    assert_eq!(
        awake_for(&deep),
        Some((
            neurotree_core::AwakeReason::ReactiveCondition,
            "rseq/seq/fb".to_string()
        ))
    );
    // Called straight from the reactive node's loop, it is named itself.
    let direct = Node::Control(5, vec![Node::Ebb(1_000_000), waiter()]);
    assert_eq!(
        awake_for(&direct),
        Some((
            neurotree_core::AwakeReason::ReactiveCondition,
            "rseq/ebb".to_string()
        ))
    );
    // The same leaves with a declared one in its place sleep.
    let declared = Node::Control(5, vec![guarded(Node::Bell), waiter()]);
    assert_eq!(awake_for(&declared), None);
    // With no reactive node above it, nothing re-checks the ebb: the tree sleeps.
    let plain = Node::Control(0, vec![guarded(Node::Ebb(1_000_000)), waiter()]);
    assert_eq!(awake_for(&plain), None);
}

/// The context of [`WakesItself`]: its tree's wake handle, and the action's starts.
struct SelfWaking {
    handle: Option<neurotree_core::tree::WakeHandle>,
    starts: u32,
}

/// Starts by saying it waits for the program's wake, and wakes its own tree at once (as
/// another thread might during the pass); succeeds when ticked again.
struct WakesItself;

impl neurotree_core::StatefulAction<SelfWaking> for WakesItself {
    fn on_start(
        &mut self,
        h: &mut neurotree_core::Handle<'_, SelfWaking>,
    ) -> neurotree_core::Status {
        h.wake_on_handle();
        h.ctx_mut().starts += 1;
        if let Some(handle) = &h.ctx().handle {
            handle.wake();
        }
        neurotree_core::Status::Running
    }
    fn on_running(
        &mut self,
        _: &mut neurotree_core::Handle<'_, SelfWaking>,
    ) -> neurotree_core::Status {
        neurotree_core::Status::Success
    }
}

#[test]
fn a_tick_call_whose_next_pass_completes_the_root_leaves_the_tree_awake() {
    let bp = neurotree_core::Builder::<SelfWaking>::new()
        .sequence("root", |s| s.stateful("w", || WakesItself))
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(bp, ManualClock::new());
    let handle = tree.wake_handle();
    let mut ctx = SelfWaking {
        handle: Some(handle),
        starts: 0,
    };
    // The first pass leaves the root Running with the action waiting, so the tree falls
    // asleep; the wake during it makes the call pass again, and that pass completes.
    for starts in 1..=3 {
        assert_eq!(
            tree.tick_once(&mut ctx),
            Ok(neurotree_core::Status::Success)
        );
        assert_eq!(tree.last_passes(), 2);
        assert!(!tree.is_asleep());
        // Each call is a new run of the action, not a sleep.
        assert_eq!(ctx.starts, starts);
    }
}
