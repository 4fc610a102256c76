//! Reloading a running tree: unchanged nodes keep their state exactly, and nodes removed or
//! changed while Running are halted exactly once.

use crate::common;

use std::time::Duration;

use common::{run, Ctx, Spec, What};
use neurotree_core::{Blueprint, ManualClock, NodeStatus, ReloadError, ReloadReport, Status, Tree};
use proptest::prelude::*;

/// The pre-order ids of the subtree rooted at `root`: `root .. root + its size`.
fn subtree_of(spec: &Spec, root: usize) -> std::ops::Range<usize> {
    let flat = spec.flatten();
    let mut end = root + 1;
    let mut stack = vec![root];
    while let Some(n) = stack.pop() {
        for &c in &flat[n].children {
            end = end.max(c + 1);
            stack.push(c);
        }
    }
    root..end
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Reloading the same tree changes nothing: every node keeps its state, none is
    /// halted, and the run goes on exactly as without the reload.
    #[test]
    fn reloading_the_same_tree_changes_nothing(
        spec in common::tree(false),
        before in common::ops(),
        after in common::ops(),
    ) {
        let bp = common::blueprint_by_place(&spec, None);
        let mut ctx = Ctx::new(&spec);
        let mut tree = Tree::with_clock(bp.clone(), ManualClock::new());
        run(&mut tree, &mut ctx, &before);
        let world = ctx.snapshot();
        let saved = tree.save_state().unwrap();
        let expected = run(&mut tree, &mut ctx, &after);

        ctx.rewind(&world);
        let mut again = Tree::with_clock(bp.clone(), ManualClock::new());
        again.restore_state(&saved).unwrap();
        let statuses = again.statuses().to_vec();
        let report = again.reload(common::blueprint_by_place(&spec, None), &mut ctx).unwrap();
        prop_assert_eq!(report, ReloadReport { kept: spec.len(), ..ReloadReport::default() });
        prop_assert_eq!(again.statuses(), &statuses[..]);
        prop_assert!(ctx.take_events().is_empty());
        prop_assert_eq!(run(&mut again, &mut ctx, &after), expected);
    }

    /// Replace one subtree by a leaf: every node outside it keeps its status, every
    /// stateful leaf inside it that was Running is halted exactly once, the others not at
    /// all, and the report counts them.
    #[test]
    fn a_changed_subtree_is_halted_once_and_the_rest_keeps_its_state(
        spec in common::tree(false),
        before in common::ops(),
        pick in any::<prop::sample::Index>(),
    ) {
        // The root stays: replacing it would change every node.
        prop_assume!(spec.len() > 1);
        let replaced = 1 + pick.index(spec.len() - 1);
        let gone = subtree_of(&spec, replaced);
        let mut ctx = Ctx::new(&spec);
        let mut tree = Tree::with_clock(common::blueprint_by_place(&spec, None), ManualClock::new());
        run(&mut tree, &mut ctx, &before);
        ctx.take_events();
        let old = tree.statuses().to_vec();

        let report = tree.reload(common::blueprint_by_place(&spec, Some(replaced)), &mut ctx).unwrap();
        let events = ctx.take_events();
        let running_inside = gone.clone().filter(|&i| old[i] == NodeStatus::Running).count();
        prop_assert_eq!(report.halted, running_inside);
        prop_assert_eq!(report.kept, spec.len() - gone.len());
        prop_assert_eq!(report.restarted, 1);
        prop_assert!(!report.waiting);

        let flat = spec.flatten();
        for (leaf, node) in flat.iter().enumerate() {
            let stateful = node.node == common::FlatKind::Leaf(common::LeafKind::Stateful);
            if !(stateful && old[leaf] == NodeStatus::Running) {
                continue;
            }
            let halts = events.iter().filter(|e| e.leaf == leaf && e.what == What::Halted).count();
            let expected = usize::from(gone.contains(&leaf));
            prop_assert_eq!(halts, expected, "leaf {} in {:?}", leaf, spec);
        }
        // Only the replaced subtree hears of the reload (a TryCatch in it may run its
        // catch while halted, as a halt runs it).
        prop_assert!(events.iter().all(|e| gone.contains(&e.leaf)), "{:?}", events);

        // The new tree: the nodes before the replaced one keep their ids, the leaf takes
        // its id, and the nodes after it move up by the size of what it replaced.
        let statuses = tree.statuses();
        prop_assert_eq!(statuses.len(), spec.len() - gone.len() + 1);
        for (i, &was) in old.iter().enumerate() {
            if gone.contains(&i) {
                continue;
            }
            let new_id = if i < replaced { i } else { i - gone.len() + 1 };
            prop_assert_eq!(statuses[new_id], was, "node {} of {:?}", i, spec);
        }
        prop_assert_eq!(statuses[replaced], NodeStatus::Idle);
    }
}

#[test]
fn a_halt_that_takes_ticks_delays_the_swap_until_it_is_done() {
    let spec = Spec::Node(
        common::Kind::Sequence,
        vec![Spec::Leaf(
            common::LeafKind::Stateful,
            vec![Status::Running],
        )],
    );
    let mut ctx = Ctx::new(&spec).with_halt_ticks(&[0, 2]);
    let mut tree = Tree::with_clock(common::blueprint_by_place(&spec, None), ManualClock::new());
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Running));
    ctx.take_events();

    let report = tree
        .reload(common::blueprint_by_place(&spec, Some(1)), &mut ctx)
        .unwrap();
    assert_eq!(
        report,
        ReloadReport {
            kept: 1,
            restarted: 1,
            halted: 1,
            waiting: true
        }
    );
    assert_eq!(
        tree.reload(common::blueprint_by_place(&spec, Some(1)), &mut ctx),
        Err(ReloadError::Halting)
    );
    // The old leaf is still halting: the old tree is in place.
    assert_eq!(tree.blueprint().len(), 2);
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Running));
    assert_eq!(
        tree.blueprint().kind(neurotree_core::NodeId(1)).type_name(),
        "StatefulAction"
    );
    // Its second `on_halting` ends the halt, and the new tree ticks at once.
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Success));
    assert_eq!(
        tree.blueprint().kind(neurotree_core::NodeId(1)).type_name(),
        "AlwaysSuccess"
    );
    let halted = ctx
        .take_events()
        .iter()
        .filter(|e| e.what == What::Halted)
        .count();
    assert_eq!(halted, 1);
}

#[test]
fn blackboard_entries_and_waits_are_kept() {
    let v1 = Blueprint::<()>::builder()
        .sequence("main", |s| {
            s.action("count", |_| Status::Success)
                .delay("d", Duration::from_millis(300), |d| d.always_success("a"))
        })
        .build_shared()
        .unwrap();
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(v1, clock.clone());
    tree.blackboard_mut().set("laps", 7_i64).unwrap();
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    clock.advance(Duration::from_millis(200));
    // The first action renamed: the delay keeps its 200 ms.
    let v2 = Blueprint::<()>::builder()
        .sequence("main", |s| {
            s.action("tally", |_| Status::Success)
                .delay("d", Duration::from_millis(300), |d| d.always_success("a"))
        })
        .build_shared()
        .unwrap();
    let report = tree.reload(v2, &mut ()).unwrap();
    assert_eq!((report.kept, report.restarted, report.halted), (3, 1, 0));
    assert_eq!(tree.blackboard().get::<i64>("laps"), Ok(7));
    clock.advance(Duration::from_millis(100));
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
}

/// A stateful leaf whose factory panics.
struct Unmakeable;

impl neurotree_core::StatefulAction<()> for Unmakeable {
    fn on_start(&mut self, _: &mut neurotree_core::Handle<'_, ()>) -> Status {
        Status::Success
    }
    fn on_running(&mut self, _: &mut neurotree_core::Handle<'_, ()>) -> Status {
        Status::Success
    }
}

/// A reload whose new leaf's factory panics leaves the tree on its old blueprint and its
/// old node state together, never the new blueprint over the old state (which the ticks
/// read by the blueprint's indices): caught, the panic leaves a tree that ticks as before.
#[test]
fn a_factory_that_panics_in_a_reload_leaves_blueprint_and_state_together() {
    let v1 = Blueprint::<()>::builder()
        .sequence("main", |s| s.action("a", |_| Status::Success))
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(v1, ManualClock::new());
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    let v2 = Blueprint::<()>::builder()
        .sequence("main", |s| {
            s.action("a", |_| Status::Success)
                .action("b", |_| Status::Success)
                .action("c", |_| Status::Success)
                .stateful("new", || -> Unmakeable { panic!("no such leaf") })
        })
        .build_shared()
        .unwrap();
    let caught = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let _ = tree.reload(v2, &mut ());
    }));
    assert!(caught.is_err());
    // The old tree, whole: it ticks as before.
    assert_eq!(tree.blueprint().len(), 2);
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
}

/// Counts its calls in a shared counter, running until halted.
struct Counting(std::sync::Arc<std::sync::atomic::AtomicU32>);

impl neurotree_core::StatefulAction<()> for Counting {
    fn on_start(&mut self, _: &mut neurotree_core::Handle<'_, ()>) -> Status {
        self.0.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        Status::Running
    }
    fn on_running(&mut self, _: &mut neurotree_core::Handle<'_, ()>) -> Status {
        self.0.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        Status::Running
    }
}

/// The new leaves' objects are made before a kept leaf's object leaves the old tree: a
/// factory's panic leaves the kept leaf running on its own object, not on a vacant place.
#[test]
fn a_factory_that_panics_in_a_reload_leaves_the_kept_leaves_objects_in_place() {
    use std::sync::atomic::{AtomicU32, Ordering};
    use std::sync::Arc;
    let calls = Arc::new(AtomicU32::new(0));
    let count = {
        let calls = Arc::clone(&calls);
        move || Counting(Arc::clone(&calls))
    };
    let v1 = Blueprint::<()>::builder()
        .sequence("main", |s| s.stateful("count", count.clone()))
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(v1, ManualClock::new());
    assert_eq!(tree.tick_exactly_once(&mut ()), Ok(Status::Running));
    let v2 = Blueprint::<()>::builder()
        .sequence("main", |s| {
            s.stateful("count", count)
                .stateful("new", || -> Unmakeable { panic!("no such leaf") })
        })
        .build_shared()
        .unwrap();
    let caught = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let _ = tree.reload(v2, &mut ());
    }));
    assert!(caught.is_err());
    assert_eq!(calls.load(Ordering::Relaxed), 1);
    // The kept leaf's own object answers: Running, counted.
    assert_eq!(tree.tick_exactly_once(&mut ()), Ok(Status::Running));
    assert_eq!(calls.load(Ordering::Relaxed), 2);
}
