//! Nav2's `test/plugins/control/test_persistent_sequence.cpp`, without ROS.

use crate::support;
use support::*;

use neurotree::nav2::PersistentSequence;

fn sequence(bound: bool, children: usize) -> (Tree<Bench>, Bench) {
    let clock = ManualClock::new();
    let mut tree = tree(&clock, |b| {
        b.custom("persistent", PersistentSequence::spec(), |mut c| {
            if bound {
                c = c.ports([Port::entry("current_child_idx", "seq_child_idx")]);
            }
            for i in 0..children {
                c = c.dummy(i);
            }
            c
        })
    });
    tree.blackboard_mut().set("seq_child_idx", 0_i32).unwrap();
    (tree, Bench::new(children))
}

fn index(tree: &Tree<Bench>) -> i32 {
    tree.blackboard().get("seq_child_idx").unwrap()
}

/// Ports `TEST_F(PersistentSequenceTestFixture, test_empty_fails)`: without
/// `current_child_idx` the tick is an error, as Nav2 throws.
#[test]
fn test_empty_fails() {
    let (mut tree, mut bench) = sequence(false, 1);
    bench.set(0, S);
    let err = bench.tick(&mut tree).unwrap_err();
    assert!(err.to_string().contains("current_child_idx"), "{err}");
    assert_eq!(bench.ticks, [0]);
}

/// Ports `TEST_F(PersistentSequenceTestFixture, test_tick)`.
#[test]
fn test_tick() {
    let (mut tree, mut bench) = sequence(true, 1);
    bench.set(0, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(index(&tree), 0);
}

/// Ports `TEST_F(PersistentSequenceTestFixture, test_behavior)`.
#[test]
fn test_behavior() {
    let (mut tree, mut bench) = sequence(true, 3);
    for i in 0..3 {
        bench.set(i, R);
    }
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(index(&tree), 0);
    bench.set(0, S);
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(index(&tree), 1);
    bench.set(1, F);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(index(&tree), 0);
    // Whoever writes the entry moves the sequence: from child 1, which is skipped.
    tree.blackboard_mut().set("seq_child_idx", 1_i32).unwrap();
    bench.set(0, F);
    bench.set(1, K);
    bench.set(2, R);
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(index(&tree), 2);
    bench.set(2, S);
    assert_eq!(bench.ok(&mut tree), S);
    assert_eq!(index(&tree), 0);
    assert_eq!(bench.ticks, [2, 3, 2]);
    assert_eq!(children(&tree, 3), [I, I, I]);
}
