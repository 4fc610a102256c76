//! Nav2's `test/plugins/control/test_pause_resume_controller.cpp`, without ROS: a call of
//! the `pause` or `resume` service is writing `true` to the entry of that name.

use crate::support;
use support::*;

use neurotree::nav2::PauseResumeController;

fn controller(children: usize) -> (Tree<Bench>, Bench) {
    let clock = ManualClock::new();
    let tree = tree(&clock, |b| {
        b.custom("pause", PauseResumeController::spec(), |mut c| {
            c = c.ports([
                Port::literal("pause_service_name", "pause"),
                Port::literal("resume_service_name", "resume"),
            ]);
            for i in 0..children {
                c = c.dummy(i);
            }
            c
        })
    });
    (tree, Bench::new(children))
}

fn call(tree: &mut Tree<Bench>, service: &str) {
    tree.blackboard_mut().set(service, true).unwrap();
}

/// `false` once the node has answered the call.
fn pending(tree: &Tree<Bench>, service: &str) -> bool {
    tree.blackboard().get(service).unwrap()
}

/// Ports `TEST_F(PauseResumeControllerTestFixture, test_incorrect_num_children)`: the tree
/// is refused when it is built.
#[test]
fn test_incorrect_num_children() {
    let built = Builder::<Bench>::new()
        .custom("pause", PauseResumeController::spec(), |c| c)
        .build_shared();
    assert!(built.is_err());
    let built = Builder::<Bench>::new()
        .custom("pause", PauseResumeController::spec(), |c| {
            c.dummy(0).dummy(1).dummy(2).dummy(3).dummy(4)
        })
        .build_shared();
    assert!(built.is_err());
}

/// Ports `TEST_F(PauseResumeControllerTestFixture, test_unused_children)`. The states are
/// seen through the children ticked: only the RESUMED child exists.
#[test]
fn test_unused_children() {
    let (mut tree, mut bench) = controller(1);
    bench.set(0, R);
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(bench.ticks, [1]);
    // Pause: ON_PAUSE and PAUSED have no child; the node is Running, ticking nothing.
    call(&mut tree, "pause");
    assert_eq!(bench.ok(&mut tree), R);
    assert!(!pending(&tree, "pause"));
    assert_eq!(bench.halts, [1]);
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(bench.ticks, [1]);
    call(&mut tree, "resume");
    assert_eq!(bench.ok(&mut tree), R);
    assert!(!pending(&tree, "resume"));
    assert_eq!(bench.ticks, [1]);
    // RESUMED again: the child is ticked.
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(bench.ticks, [2]);
}

/// Ports `TEST_F(PauseResumeControllerTestFixture, test_behavior)`.
#[test]
fn test_behavior() {
    let (mut tree, mut bench) = controller(4);
    for i in 0..4 {
        bench.set(i, R);
    }
    // RESUMED.
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(bench.ticks, [1, 0, 0, 0]);
    // Pause: the resumed child is halted, ON_PAUSE runs.
    call(&mut tree, "pause");
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(bench.halts, [1, 0, 0, 0]);
    assert_eq!(bench.ticks, [1, 0, 1, 0]);
    bench.set(2, S);
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(bench.ticks, [1, 0, 2, 0]);
    // PAUSED: its child's Success or Skipped keeps the node paused.
    bench.set(1, S);
    assert_eq!(bench.ok(&mut tree), R);
    bench.set(1, K);
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(bench.ticks, [1, 2, 2, 0]);
    // A pause while paused is refused (answered, nothing changes).
    call(&mut tree, "pause");
    assert_eq!(bench.ok(&mut tree), R);
    assert!(!pending(&tree, "pause"));
    assert_eq!(bench.ticks, [1, 3, 2, 0]);
    // Resume: ON_RESUME fails, and so does the node.
    call(&mut tree, "resume");
    bench.set(3, F);
    assert_eq!(bench.ok(&mut tree), F);
    assert_eq!(bench.ticks, [1, 3, 2, 1]);
    // A halt goes back to RESUMED.
    tree.halt(&mut bench);
    assert_eq!(bench.ok(&mut tree), R);
    assert_eq!(bench.ticks, [2, 3, 2, 1]);
    bench.set(0, S);
    assert_eq!(bench.ok(&mut tree), S);
    // A resume while resumed is refused.
    call(&mut tree, "resume");
    assert_eq!(bench.ok(&mut tree), S);
    assert!(!pending(&tree, "resume"));
    assert_eq!(bench.ticks, [4, 3, 2, 1]);
}
