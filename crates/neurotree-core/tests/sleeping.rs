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
            Event::Wake => self.tree.wake_handle().wake(),
            Event::Halt => {
                self.tree.halt(&mut self.log);
            }
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
