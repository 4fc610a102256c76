//! Saving a tree's state and resuming it: a restored instance runs on tick for tick as the
//! original, and states that are not a saved state of this tree are refused.

use crate::common;

use std::time::Duration;

use common::{run, Ctx, Spec};
use neurotree_core::state::{RestoreError, SaveError, SavedInfo, StateCodecs};
use neurotree_core::{
    Blueprint, Clock, Handle, ManualClock, NodeStatus, StatefulAction, Status, Tree,
};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Cut a run anywhere, save, restore into a fresh instance of the blueprint, and the
    /// rest of the run is the same: results, every leaf call in order, every status.
    #[test]
    fn a_resumed_run_continues_as_the_original(
        spec in common::tree(false),
        before in common::ops(),
        after in common::ops(),
    ) {
        let bp = common::blueprint(&spec);
        let mut ctx = Ctx::new(&spec);
        let mut original = Tree::with_clock(bp.clone(), ManualClock::new());
        run(&mut original, &mut ctx, &before);
        let saved = original.save_state().expect("no async leaves, no halts that take ticks");
        let world = ctx.snapshot();
        let expected = run(&mut original, &mut ctx, &after);

        ctx.rewind(&world);
        let mut resumed = Tree::with_clock(bp.clone(), ManualClock::new());
        resumed.restore_state(&saved).unwrap();
        prop_assert_eq!(resumed.statuses(), &saved_statuses(&bp, &saved)[..]);
        let got = run(&mut resumed, &mut ctx, &after);
        prop_assert_eq!(got, expected, "tree {:?}", spec);
    }

    /// Any change to a saved state's bytes, or any cut, is refused or restores a state;
    /// nothing panics, and a refused restore leaves the tree as it was.
    #[test]
    fn damaged_states_are_refused_without_a_panic(
        spec in common::tree(false),
        before in common::ops(),
        flips in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..4),
        cut in any::<prop::sample::Index>(),
    ) {
        let bp = common::blueprint(&spec);
        let mut ctx = Ctx::new(&spec);
        let mut original = Tree::with_clock(bp.clone(), ManualClock::new());
        run(&mut original, &mut ctx, &before);
        let saved = original.save_state().unwrap();
        let mut damaged = saved.clone();
        for (at, byte) in &flips {
            let i = at.index(damaged.len());
            damaged[i] ^= byte | 1;
        }
        let mut fresh = Tree::with_clock(bp.clone(), ManualClock::new());
        let before_restore = fresh.statuses().to_vec();
        if fresh.restore_state(&damaged).is_err() {
            prop_assert_eq!(fresh.statuses(), &before_restore[..]);
        }
        let short = &saved[..cut.index(saved.len())];
        let mut fresh = Tree::with_clock(bp, ManualClock::new());
        prop_assert!(fresh.restore_state(short).is_err());
        prop_assert_eq!(fresh.statuses(), &before_restore[..]);
    }
}

/// Steps of a timed run: each advances the clock by its milliseconds, then acts.
fn timed_ops() -> impl Strategy<Value = Vec<(common::Op, u16)>> {
    proptest::collection::vec(
        (
            prop_oneof![
                5 => Just(common::Op::TickOnce),
                3 => Just(common::Op::TickExactlyOnce),
                1 => Just(common::Op::Halt),
            ],
            prop_oneof![Just(0u16), Just(100), 1u16..300],
        ),
        1..=14,
    )
}

fn run_timed(
    tree: &mut Tree<Ctx>,
    clock: &ManualClock,
    ctx: &mut Ctx,
    ops: &[(common::Op, u16)],
) -> Vec<common::Step> {
    ops.iter()
        .map(|&(op, ms)| {
            clock.advance(Duration::from_millis(u64::from(ms)));
            common::step(tree, ctx, op)
        })
        .collect()
}

/// How a timed run is carried on after its cut.
#[derive(Clone, Copy, Debug)]
enum Carry {
    /// Saved, and restored into a fresh instance whose clock reads `0` ms later than the
    /// saved one's (the CLI's `--resume` sets it to the saved time: `0`), or any other.
    Restore { clock_offset_ms: i32 },
    /// The same instance reloaded with the same blueprint.
    Reload,
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 384, ..ProptestConfig::default() })]

    /// The nodes that read the clock (Timeout, Delay, Cooldown, Sleep) among the others,
    /// the clock moving between steps: cut anywhere, save and restore on a clock at the saved
    /// time or another, or reload the same blueprint, and the rest of the run is the
    /// uninterrupted one's, call for call and status for status.
    #[test]
    fn a_timed_run_resumed_or_reloaded_continues_as_the_original(
        spec in common::timed_tree(),
        before in timed_ops(),
        after in timed_ops(),
        carry in prop_oneof![
            2 => Just(Carry::Restore { clock_offset_ms: 0 }),
            1 => (-5_000i32..5_000).prop_map(|clock_offset_ms| Carry::Restore { clock_offset_ms }),
            1 => Just(Carry::Reload),
        ],
        start_ms in 0u32..10_000,
    ) {
        let bp = common::blueprint(&spec);
        let mut ctx = Ctx::new(&spec);
        let clock = ManualClock::new();
        clock.set(Duration::from_millis(u64::from(start_ms)));
        let mut original = Tree::with_clock(bp.clone(), clock.clone());
        run_timed(&mut original, &clock, &mut ctx, &before);
        let saved = original.save_state().expect("no async leaves, no halts that take ticks");
        let at_cut = clock.now();
        let world = ctx.snapshot();
        let expected = run_timed(&mut original, &clock, &mut ctx, &after);

        ctx.rewind(&world);
        let got = match carry {
            Carry::Restore { clock_offset_ms } => {
                let there = ManualClock::new();
                let offset = Duration::from_millis(u64::from(clock_offset_ms.unsigned_abs()));
                there.set(if clock_offset_ms < 0 {
                    at_cut.saturating_sub(offset)
                } else {
                    at_cut + offset
                });
                let mut resumed = Tree::with_clock(bp.clone(), there.clone());
                resumed.restore_state(&saved).unwrap();
                run_timed(&mut resumed, &there, &mut ctx, &after)
            }
            Carry::Reload => {
                let again = ManualClock::new();
                again.set(at_cut);
                let mut tree = Tree::with_clock(bp.clone(), again.clone());
                tree.restore_state(&saved).unwrap();
                let report = tree.reload(bp.clone(), &mut ctx).unwrap();
                prop_assert_eq!((report.restarted, report.halted), (0, 0));
                run_timed(&mut tree, &again, &mut ctx, &after)
            }
        };
        prop_assert_eq!(got, expected, "tree {:?}", spec);
    }
}

/// The statuses a saved state holds, read by restoring it into a fresh instance.
fn saved_statuses(bp: &std::sync::Arc<Blueprint<Ctx>>, saved: &[u8]) -> Vec<NodeStatus> {
    let mut tree = Tree::with_clock(bp.clone(), ManualClock::new());
    tree.restore_state(saved).unwrap();
    tree.statuses().to_vec()
}

/// A stateful action that counts its ticks, and can save the count.
#[derive(Default)]
struct Counter {
    ticks: u32,
}

impl StatefulAction<()> for Counter {
    fn on_start(&mut self, _h: &mut Handle<'_, ()>) -> Status {
        self.ticks += 1;
        Status::Running
    }
    fn on_running(&mut self, _h: &mut Handle<'_, ()>) -> Status {
        self.ticks += 1;
        if self.ticks >= 4 {
            Status::Success
        } else {
            Status::Running
        }
    }
    fn on_halted(&mut self, _h: &mut Handle<'_, ()>) {}
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&self.ticks))
    }
    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|ticks| self.ticks = ticks)
            .is_some()
    }
}

/// The same without saving.
struct Forgetful;

impl StatefulAction<()> for Forgetful {
    fn on_start(&mut self, _h: &mut Handle<'_, ()>) -> Status {
        Status::Running
    }
    fn on_running(&mut self, _h: &mut Handle<'_, ()>) -> Status {
        Status::Running
    }
    fn on_halted(&mut self, _h: &mut Handle<'_, ()>) {}
}

#[test]
fn an_objects_own_state_travels_with_the_tree() {
    let bp = Blueprint::<()>::builder()
        .stateful("count", Counter::default)
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(bp.clone(), ManualClock::new());
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    let saved = tree.save_state().unwrap();
    let mut resumed = Tree::with_clock(bp, ManualClock::new());
    resumed.restore_state(&saved).unwrap();
    // Ticks 3 and 4 of the count: without its state it would need four more.
    assert_eq!(resumed.tick_once(&mut ()), Ok(Status::Running));
    assert_eq!(resumed.tick_once(&mut ()), Ok(Status::Success));
}

#[test]
fn an_object_that_does_not_opt_in_is_named() {
    let bp = Blueprint::<()>::builder()
        .sequence("main", |s| s.stateful("radio", || Forgetful))
        .build_shared()
        .unwrap();
    let tree = Tree::with_clock(bp, ManualClock::new());
    let err = tree.save_state().unwrap_err();
    assert!(matches!(&err, SaveError::Unsaveable { path, .. } if path == "main/radio"));
    assert!(err.to_string().contains("save_state"), "{err}");
}

#[test]
fn a_running_async_action_is_refused_and_an_idle_one_is_not() {
    let bp = Blueprint::<()>::builder()
        .async_action("drive", |_h| std::future::pending::<Status>())
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(bp.clone(), ManualClock::new());
    assert!(tree.save_state().is_ok());
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    assert!(matches!(
        tree.save_state(),
        Err(SaveError::AsyncRunning { path, .. }) if path == "drive"
    ));
    tree.halt(&mut ());
    assert!(tree.save_state().is_ok());
}

#[test]
fn blackboard_values_are_saved_with_their_types_and_stamps() {
    #[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
    struct Pose {
        x: f64,
        y: f64,
    }
    let bp = Blueprint::<()>::builder()
        .always_success("a")
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(bp.clone(), ManualClock::new());
    let bb = tree.blackboard_mut();
    bb.set("count", 3_i32).unwrap();
    bb.set("count", 4_i32).unwrap();
    bb.set("name", String::from("dock")).unwrap();
    bb.set("pose", Pose { x: 1.0, y: 2.0 }).unwrap();
    let err = tree.save_state().unwrap_err();
    assert!(
        matches!(&err, SaveError::Value { key, .. } if key == "pose"),
        "{err}"
    );

    let codecs = StateCodecs::new().with::<Pose>();
    let saved = tree.save_state_with(&codecs).unwrap();
    let mut resumed = Tree::with_clock(bp.clone(), ManualClock::new());
    let refused = resumed.restore_state(&saved).unwrap_err();
    assert!(matches!(&refused, RestoreError::Value { key, .. } if key == "pose"));
    assert!(
        resumed.blackboard().keys().next().is_none(),
        "a refused restore changes nothing"
    );
    resumed.restore_state_with(&saved, &codecs).unwrap();
    let bb = resumed.blackboard();
    assert_eq!(bb.get_exact::<i32>("count"), Ok(4));
    assert_eq!(bb.info("count").unwrap().sequence, 2);
    assert_eq!(bb.get_exact::<String>("name").as_deref(), Ok("dock"));
    assert_eq!(bb.get_exact::<Pose>("pose"), Ok(Pose { x: 1.0, y: 2.0 }));
}

#[test]
fn waits_keep_the_time_left_on_another_clock() {
    let bp = Blueprint::<()>::builder()
        .sequence("s", |s| {
            s.delay("d", Duration::from_millis(300), |d| d.always_success("a"))
                .sleep("nap", Duration::from_millis(500))
        })
        .build_shared()
        .unwrap();
    let clock = ManualClock::new();
    clock.set(Duration::from_secs(100));
    let mut tree = Tree::with_clock(bp.clone(), clock.clone());
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    clock.advance(Duration::from_millis(200));
    let saved = tree.save_state().unwrap();
    assert_eq!(
        SavedInfo::read(&saved).unwrap().clock,
        Duration::from_millis(100_200)
    );

    // Elsewhere, a clock that began later: 100 ms of the delay are left.
    let there = ManualClock::new();
    there.set(Duration::from_secs(7));
    let mut resumed = Tree::with_clock(bp, there.clone());
    resumed.restore_state(&saved).unwrap();
    there.advance(Duration::from_millis(99));
    assert_eq!(resumed.tick_once(&mut ()), Ok(Status::Running));
    assert_eq!(
        resumed.status(neurotree_core::NodeId(1)),
        NodeStatus::Running
    );
    there.advance(Duration::from_millis(1));
    // The delay is over; the sleep begins and takes its 500 ms.
    assert_eq!(resumed.tick_once(&mut ()), Ok(Status::Running));
    there.advance(Duration::from_millis(499));
    assert_eq!(resumed.tick_once(&mut ()), Ok(Status::Running));
    there.advance(Duration::from_millis(1));
    assert_eq!(resumed.tick_once(&mut ()), Ok(Status::Success));
}

#[test]
fn a_state_of_another_tree_or_other_bytes_is_refused() {
    let one = Blueprint::<()>::builder()
        .sequence("s", |s| s.always_success("a"))
        .build_shared()
        .unwrap();
    let other = Blueprint::<()>::builder()
        .sequence("s", |s| s.always_failure("a"))
        .build_shared()
        .unwrap();
    assert_ne!(one.structure_hash(), other.structure_hash());
    let same = Blueprint::<()>::builder()
        .sequence("s", |s| s.always_success("a"))
        .build_shared()
        .unwrap();
    assert_eq!(one.structure_hash(), same.structure_hash());

    let saved = Tree::with_clock(one, ManualClock::new())
        .save_state()
        .unwrap();
    let mut tree = Tree::with_clock(other.clone(), ManualClock::new());
    assert!(matches!(
        tree.restore_state(&saved),
        Err(RestoreError::OtherTree { expected, .. }) if expected == other.structure_hash()
    ));
    for bytes in [&b""[..], b"hello, world", &saved[..saved.len() - 1]] {
        assert!(matches!(
            tree.restore_state(bytes),
            Err(RestoreError::Corrupt(_))
        ));
    }
    let mut longer = saved.clone();
    longer.push(0);
    assert!(matches!(
        Tree::with_clock(same, ManualClock::new()).restore_state(&longer),
        Err(RestoreError::Corrupt(_))
    ));
}

#[test]
fn a_halt_in_progress_is_not_saved() {
    let spec = Spec::Leaf(common::LeafKind::Stateful, vec![Status::Running]);
    let bp = common::blueprint(&spec);
    let mut ctx = Ctx::new(&spec).with_halt_ticks(&[2]);
    let mut tree = Tree::with_clock(bp, ManualClock::new());
    assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Running));
    assert!(!tree.halt(&mut ctx));
    assert!(matches!(tree.save_state(), Err(SaveError::Halting { .. })));
    while !tree.tick_halt(&mut ctx) {}
    assert!(tree.save_state().is_ok());
}
