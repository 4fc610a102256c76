//! Sleeping members: skipped by the frames until their deadline or a wake, with the same
//! results as members ticked every frame, on one thread or several, frame by frame or in
//! place.

use std::sync::Arc;
use std::time::Duration;

use neurotree::crowd::{Crowd, FrameReport, FrameStatus, MemberId};
use neurotree::prelude::*;
use neurotree::{AwakeReason, NodeStatus, ScriptBuilder};

/// What a member's leaves did to its context.
#[derive(Clone, Debug, Default, PartialEq)]
struct Guard {
    /// Calls of the patrol leg's `on_start` / `on_running`.
    calls: u32,
    /// Legs finished.
    legs: u32,
    /// Everything that happened, with the clock, folded in order.
    trace: u64,
}

impl Guard {
    fn note(&mut self, event: u64, now: Duration) {
        self.trace = self
            .trace
            .wrapping_mul(1_000_003)
            .wrapping_add(event * 1_000_000 + now.as_millis() as u64);
    }
}

/// A patrol leg that lasts `300 + 100 * (seed % 5)` ms, or ends early when the entry
/// `alarm` is true; it says so, so that its tree sleeps meanwhile.
struct Leg {
    seed: u64,
    until: Duration,
}

impl Leg {
    fn step(&mut self, h: &mut Handle<'_, Guard>) -> Status {
        let now = h.now();
        h.ctx_mut().calls += 1;
        let alarm = h.blackboard().get::<bool>("alarm").unwrap_or(false);
        if alarm || now >= self.until {
            let g = h.ctx_mut();
            g.legs += 1;
            g.note(1 + u64::from(alarm), now);
            return Status::Success;
        }
        h.sleep_until(self.until);
        h.wake_on("alarm");
        Status::Running
    }
}

impl StatefulAction<Guard> for Leg {
    fn on_start(&mut self, h: &mut Handle<'_, Guard>) -> Status {
        self.until = h.now() + Duration::from_millis(300 + 100 * (self.seed % 5));
        self.step(h)
    }
    fn on_running(&mut self, h: &mut Handle<'_, Guard>) -> Status {
        self.step(h)
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Guard>) {
        let now = h.now();
        h.ctx_mut().note(9, now);
    }
}

/// Patrol forever: a leg, then a pause of 200 ms.
fn patrol(seed: u64) -> Arc<Blueprint<Guard>> {
    Blueprint::<Guard>::builder()
        .keep_running_until_failure("forever", |k| {
            k.sequence("round", |s| {
                s.stateful("leg", move || Leg {
                    seed,
                    until: Duration::ZERO,
                })
                .sleep("pause", Duration::from_millis(200))
            })
        })
        .build_shared()
        .unwrap()
}

/// Everything observable of a run: per frame the statuses, at the end each context, node
/// statuses and blackboard.
type Seen = (Vec<Vec<FrameStatus>>, Vec<(Guard, Vec<NodeStatus>)>, u64);

/// 30 guards over 80 frames of 50 ms; every 7th frame guard `f % 30` is alarmed (its
/// blackboard written), every 11th woken. `sleeps`: trees may sleep.
fn run(threads: usize, sleeps: bool, in_place: bool) -> Seen {
    let clock = ManualClock::new();
    let mut crowd = Crowd::new(clock.clone()).with_threads(threads).unwrap();
    let bps: Vec<_> = (0..5).map(patrol).collect();
    let ids: Vec<MemberId> = (0..30)
        .map(|i| {
            let mut tree = Tree::with_clock(Arc::clone(&bps[i % 5]), clock.clone());
            tree.set_sleep_allowed(sleeps);
            crowd.add_tree(tree, Guard::default())
        })
        .collect();
    let waker = crowd.waker();
    let mut frames = Vec::new();
    let mut asleep = 0;
    for f in 0..80usize {
        if f % 7 == 3 {
            let mut m = crowd.get_mut(ids[f % 30]).unwrap();
            m.tree_mut()
                .blackboard_mut()
                .set("alarm", f % 2 == 0)
                .unwrap();
        }
        if f % 11 == 5 {
            waker.wake(ids[(f * 7) % 30]);
        }
        let report = frame(&mut crowd, &ids, in_place);
        assert_eq!(report.errors, 0);
        asleep += report.asleep;
        // Without sleeping, none is ever skipped.
        assert!(sleeps || report.asleep == 0);
        frames.push(
            crowd
                .iter()
                .map(|m| match m.status() {
                    // A member skipped asleep would have returned Running.
                    FrameStatus::Asleep => FrameStatus::Ticked(Status::Running),
                    other => other,
                })
                .collect(),
        );
        clock.advance(Duration::from_millis(50));
    }
    let members = crowd
        .iter()
        .map(|m| {
            let mut g = m.context().clone();
            g.calls = 0;
            (g, m.tree().statuses().to_vec())
        })
        .collect();
    (frames, members, asleep)
}

#[test]
fn sleeping_members_give_what_members_ticked_every_frame_give() {
    let (frames, members, _) = run(1, false, false);
    for (threads, in_place) in [(1, false), (4, false), (1, true), (4, true)] {
        let (f, m, asleep) = run(threads, true, in_place);
        assert_eq!(f, frames, "{threads} threads, in place: {in_place}");
        assert_eq!(m, members, "{threads} threads, in place: {in_place}");
        // Most member-frames were spent asleep.
        assert!(asleep > 30 * 80 / 2, "{asleep}");
    }
}

#[test]
fn a_sleeping_member_is_called_only_when_something_it_waits_on_happens() {
    let clock = ManualClock::new();
    let mut crowd = Crowd::new(clock.clone()).with_threads(1).unwrap();
    let id = crowd.add(patrol(0), Guard::default());
    // A leg of 300 ms, then a pause of 200 ms, frames of 50 ms.
    let mut statuses = Vec::new();
    for _ in 0..12 {
        let report = crowd.frame();
        statuses.push((report.ticked, report.asleep));
        clock.advance(Duration::from_millis(50));
    }
    let t = (1, 0);
    let z = (0, 1);
    // Ticked at 0 ms; asleep until the leg ends at 300; asleep in the pause until 500,
    // when the round succeeds and KeepRunningUntilFailure, with nothing left waiting,
    // keeps the member awake: the next leg starts at 550.
    assert_eq!(statuses, [t, z, z, z, z, z, t, z, z, z, t, t]);
    assert_eq!(crowd.get(id).unwrap().context().calls, 3);
    assert_eq!(crowd.get(id).unwrap().context().legs, 1);
    // A wake from another thread: ticked in the next frame, and asleep again.
    let waker = crowd.waker();
    std::thread::spawn(move || waker.wake(id)).join().unwrap();
    assert!(crowd.get_mut(id).unwrap().is_asleep());
    let report = crowd.frame();
    assert_eq!((report.ticked, report.asleep), (1, 0));
    assert_eq!(crowd.get(id).unwrap().context().calls, 4);
    assert_eq!(crowd.asleep(), 1);
    // A write to its blackboard: ticked, and the alarm ends the leg.
    crowd
        .get_mut(id)
        .unwrap()
        .tree_mut()
        .blackboard_mut()
        .set("alarm", true)
        .unwrap();
    let report = crowd.frame();
    assert_eq!((report.ticked, report.asleep), (1, 0));
    assert_eq!(crowd.get(id).unwrap().context().legs, 2);
}

/// Alerts written through `for_each_mut` or with the frame by `frame_with`, shared among
/// the crowd's threads or on the caller's: each named member is visited once per naming, a
/// member that left is skipped, and exactly the members alerted wake and are ticked in the
/// next frame, whatever the threads and however the named members bunch in the slots.
#[test]
fn alerts_written_on_the_crowds_threads_wake_exactly_the_members_named() {
    let members = 6000;
    // A bunch of neighbours too small to share out (but for `frame_with`), and one large
    // enough.
    let bunches = [
        1000..1400,
        1000..1000 + neurotree::crowd::SHARED_VISITS + 100,
    ];
    for (threads, with_frame) in [(1, false), (2, false), (1, true), (2, true)] {
        for bunch in bunches.clone() {
            let clock = ManualClock::new();
            let mut crowd = Crowd::new(clock.clone()).with_threads(threads).unwrap();
            let ids: Vec<MemberId> = (0..members)
                .map(|i| crowd.add(patrol(i as u64), Guard::default()))
                .collect();
            assert_eq!(crowd.frame().ticked, members as u64);
            clock.advance(Duration::from_millis(50));
            assert_eq!(crowd.frame().asleep, members as u64);
            let gone = ids[7];
            crowd.remove(gone).unwrap();
            // The bunch, a few far apart, one named twice, one that left.
            let mut named: Vec<MemberId> = ids[bunch.clone()].to_vec();
            named.extend([ids[members - 1], ids[3], ids[1200], gone]);
            let seen = std::sync::Mutex::new(Vec::new());
            let alert = |mut m: neurotree::crowd::MemberMut<'_, Guard>| {
                seen.lock().unwrap().push(m.id());
                m.context_mut().trace += 1;
                m.tree_mut().blackboard_mut().set("alarm", true).unwrap();
            };
            let report = if with_frame {
                clock.advance(Duration::from_millis(50));
                Some(crowd.frame_with(&named, alert))
            } else {
                crowd.for_each_mut(&named, alert);
                None
            };
            let mut seen = seen.into_inner().unwrap();
            let case = format!(
                "{threads} threads, {} named, with the frame: {with_frame}",
                named.len()
            );
            // One visit per naming but the one of the member that left.
            assert_eq!(seen.len(), named.len() - 1, "{case}");
            assert_eq!(
                seen.iter().filter(|&&id| id == ids[1200]).count(),
                2,
                "{case}"
            );
            seen.sort();
            // Each member's visits: as often as it was named (the context counts them too,
            // until the frame's ticks write it).
            let mut times = std::collections::HashMap::new();
            for id in &seen {
                *times.entry(*id).or_insert(0u64) += 1;
            }
            for i in (0..members).filter(|&i| i != 7) {
                let named_times = named.iter().filter(|&&id| id == ids[i]).count() as u64;
                let visits = times.get(&ids[i]).copied().unwrap_or(0);
                assert_eq!(visits, named_times, "member {i}, {case}");
                if !with_frame {
                    let trace = crowd.get(ids[i]).unwrap().context().trace;
                    assert_eq!(trace, named_times, "member {i}, {case}");
                }
            }
            let visits = |i: usize| times.get(&ids[i]).copied().unwrap_or(0);
            assert_eq!(
                (visits(1200), visits(1201), visits(3), visits(4)),
                (2, 1, 1, 0)
            );
            seen.dedup();
            let woken = bunch.len() + 2;
            assert_eq!(seen.len(), woken, "{case}");
            assert!(!seen.contains(&gone), "{case}");
            let report = report.unwrap_or_else(|| {
                clock.advance(Duration::from_millis(50));
                crowd.frame()
            });
            let asleep = (members - 1 - woken) as u64;
            assert_eq!(
                (report.ticked, report.asleep),
                (woken as u64, asleep),
                "{case}"
            );
            let legs: Vec<usize> = (0..members)
                .filter(|&i| i != 7 && crowd.get(ids[i]).unwrap().context().legs == 1)
                .collect();
            let mut expected: Vec<usize> = bunch.clone().chain([3, members - 1]).collect();
            expected.sort();
            assert_eq!(legs, expected, "{case}");
        }
    }
}

/// Runs a frame of `crowd`: in place, visiting `ids` in reverse (not the crowd's order),
/// or by `Crowd::frame`.
pub(crate) fn frame<C: Send>(
    crowd: &mut Crowd<C>,
    ids: &[MemberId],
    in_place: bool,
) -> FrameReport {
    if !in_place {
        return crowd.frame();
    }
    let frame = crowd.frame_in_place().unwrap();
    let mut visitor = frame.visitor();
    for &id in ids.iter().rev() {
        visitor.visit(id, |_| {});
    }
    drop(visitor);
    frame.finish()
}

/// A hundred sleeping guards, halted through the crowd: the next frame ticks every one,
/// as a tree halted by hand starts over at its next tick.
#[test]
fn halting_the_crowd_wakes_every_sleeping_member() {
    let clock = ManualClock::new();
    let mut crowd = Crowd::new(clock.clone()).with_threads(2).unwrap();
    let ids: Vec<_> = (0..100)
        .map(|i| crowd.add(patrol(i), Guard::default()))
        .collect();
    for _ in 0..3 {
        crowd.frame();
        clock.advance(Duration::from_millis(50));
    }
    assert_eq!(crowd.asleep(), 100);
    crowd.halt_all();
    assert_eq!(crowd.asleep(), 0);
    let report = crowd.frame();
    assert_eq!((report.ticked, report.asleep), (100, 0), "{report:?}");
    // Each leg was halted once and started afresh: two starts.
    for &id in &ids {
        assert_eq!(crowd.get(id).unwrap().context().calls, 2);
    }
}

/// Sleeping guards halted from another thread through their trees' own halt handles, made
/// before joining the crowd or after: the next frame ticks each one, whose tick serves the
/// request (the tree halted, the leg noting its halt), and the frame after starts its
/// patrol afresh, as a tree halted from outside does.
#[test]
fn a_sleeping_member_halted_through_its_own_halt_handle_is_ticked_next_frame() {
    let clock = ManualClock::new();
    let mut crowd = Crowd::new(clock.clone()).with_threads(2).unwrap();
    let mut handles = Vec::new();
    let mut ids = Vec::new();
    for i in 0..10 {
        let mut tree = Tree::with_clock(patrol(i), clock.clone());
        let before = i.is_multiple_of(2).then(|| tree.halt_handle());
        let id = crowd.add_tree(tree, Guard::default());
        let handle = before.unwrap_or_else(|| crowd.get_mut(id).unwrap().tree_mut().halt_handle());
        handles.push(handle);
        ids.push(id);
    }
    for _ in 0..3 {
        crowd.frame();
        clock.advance(Duration::from_millis(50));
    }
    assert_eq!(crowd.asleep(), 10);
    // Half of them, from another thread.
    std::thread::scope(|s| {
        for handle in handles.iter().step_by(2) {
            s.spawn(|| handle.request());
        }
    });
    let report = crowd.frame();
    assert_eq!(
        (report.ticked, report.errors, report.asleep),
        (5, 5, 5),
        "{report:?}"
    );
    for (i, &id) in ids.iter().enumerate() {
        let member = crowd.get(id).unwrap();
        if i % 2 == 0 {
            assert_eq!(member.error(), Some(&TickError::HaltRequested));
            assert_eq!(member.tree().statuses()[0], NodeStatus::Idle);
            assert!(!handles[i].is_pending());
        } else {
            assert_eq!(member.status(), FrameStatus::Asleep);
        }
        assert_eq!(member.context().calls, 1);
    }
    clock.advance(Duration::from_millis(50));
    let report = crowd.frame();
    assert_eq!((report.ticked, report.errors), (5, 0), "{report:?}");
    for (i, &id) in ids.iter().enumerate() {
        let expected = if i % 2 == 0 { 2 } else { 1 };
        assert_eq!(
            crowd.get(id).unwrap().context().calls,
            expected,
            "guard {i}"
        );
    }
}

/// A tree made on a clock of its own sleeps on the crowd's: it wakes when the crowd's
/// clock reaches the end of its leg, though its own never moves.
#[test]
fn a_member_added_with_a_clock_of_its_own_wakes_by_the_crowds() {
    let clock = ManualClock::new();
    let mut crowd = Crowd::new(clock.clone()).with_threads(1).unwrap();
    let own = ManualClock::new();
    let id = crowd.add_tree(Tree::with_clock(patrol(0), own), Guard::default());
    // A leg of 300 ms, frames of 50 ms: the leg ends in the frame at 300 ms.
    let mut ticked = Vec::new();
    for _ in 0..8 {
        ticked.push(crowd.frame().ticked);
        clock.advance(Duration::from_millis(50));
    }
    assert_eq!(ticked, [1, 0, 0, 0, 0, 0, 1, 0]);
    assert_eq!(crowd.get(id).unwrap().context().legs, 1);
}

/// A tree put in a member's place: the old one is halted, the new one runs on the crowd's
/// clock from the next frame, though the member slept.
#[test]
fn a_replaced_tree_is_halted_and_its_successor_ticked_next_frame() {
    let clock = ManualClock::new();
    let mut crowd = Crowd::new(clock.clone()).with_threads(1).unwrap();
    let id = crowd.add(patrol(0), Guard::default());
    crowd.frame();
    clock.advance(Duration::from_millis(50));
    assert!(crowd.get_mut(id).unwrap().is_asleep());
    let old = crowd
        .get_mut(id)
        .unwrap()
        .replace_tree(Tree::with_clock(patrol(1), ManualClock::new()));
    assert_eq!(old.statuses()[0], NodeStatus::Idle);
    let trace = crowd.get(id).unwrap().context().trace;
    assert_ne!(trace, 0, "the halted leg noted its halt");
    let report = crowd.frame();
    assert_eq!((report.ticked, report.asleep), (1, 0));
    assert_eq!(crowd.get(id).unwrap().context().calls, 2);
    // The new leg lasts 400 ms from 50 ms, on the crowd's clock.
    let mut ticked = Vec::new();
    for _ in 0..8 {
        clock.advance(Duration::from_millis(50));
        ticked.push(crowd.frame().ticked);
    }
    assert_eq!(ticked, [0, 0, 0, 0, 0, 0, 0, 1]);
}

/// The random trees and events of `neurotree-core`'s property of sleeping trees.
#[path = "../../neurotree-core/tests/sleeping/trees.rs"]
mod trees;

mod random {
    use std::sync::Arc;
    use std::time::Duration;

    use neurotree::crowd::{Crowd, FrameStatus, MemberId, MemberMut};
    use neurotree::prelude::*;
    use neurotree::{HaltHandle, NodeStatus};
    use proptest::prelude::*;

    use super::trees::{blueprint, event, node, Event, Log, Node};

    /// What happens to one member before a frame.
    #[derive(Clone, Debug)]
    enum Touch {
        /// Entry `k{key}` of its blackboard is written.
        Write(u8, bool),
        /// The program wakes it: 0 through a [`CrowdWaker`](neurotree::crowd::CrowdWaker),
        /// 1 through the crowd, 2 through the member.
        Wake(u8),
        /// Its tree is halted.
        Halt,
        /// It leaves, and a fresh member of the same tree takes its slot.
        Replace,
        /// Every member's tree is halted through the crowd.
        HaltAll,
        /// A fresh instance of its blueprint takes the place of its tree.
        Swap,
        /// It leaves (its tree halted) and joins again with the same tree and context.
        Rejoin,
        /// Its tree is halted from outside through its own
        /// [`HaltHandle`](neurotree::HaltHandle): made before it joined for even members,
        /// through the crowd at the first request for odd ones.
        HaltHandle,
        /// In the sleeping crowd only, an observer that lets its tree sleep (as the
        /// studio's, watching one agent) is set on it, or taken off if it has one.
        Observe,
    }

    /// An observer that counts what it is told and lets its tree sleep.
    struct Watcher(usize);

    impl neurotree::Observer for Watcher {
        fn on_status_change(&mut self, _: neurotree::StatusChange) {
            self.0 += 1;
        }
        fn lets_tree_sleep(&self) -> bool {
            true
        }
    }

    fn touch() -> impl Strategy<Value = Touch> {
        prop_oneof![
            3 => (0u8..3, any::<bool>()).prop_map(|(k, v)| Touch::Write(k, v)),
            2 => (0u8..3).prop_map(Touch::Wake),
            1 => Just(Touch::Halt),
            1 => Just(Touch::Replace),
            1 => Just(Touch::HaltAll),
            1 => Just(Touch::Swap),
            1 => Just(Touch::Rejoin),
            1 => Just(Touch::HaltHandle),
            1 => Just(Touch::Observe),
        ]
    }

    /// How the crowd is run.
    #[derive(Clone, Copy, Debug)]
    struct Setup {
        threads: usize,
        in_place: bool,
        /// In place, only the members the frame says are awake are visited.
        awake_only: bool,
        /// A level-of-detail hook, from the member's context.
        lod: bool,
        /// The sleeping crowd's writes that no other touch follows in their frame are
        /// delivered by [`Crowd::frame_with`](neurotree::crowd::Crowd::frame_with).
        deliver: bool,
    }

    /// A frame's events: how far the clock moves (from the core property's events), and
    /// which members are touched how.
    type Frame = (u64, Vec<(usize, Touch)>);

    fn frame() -> impl Strategy<Value = Frame> {
        (
            event().prop_map(|e| match e {
                Event::Time(ms) => ms,
                _ => 50,
            }),
            prop::collection::vec((0usize..16, touch()), 0..3),
        )
    }

    /// Every frame's statuses, then each member's context, node statuses and blackboard
    /// after every frame.
    type Seen = Vec<(Vec<FrameStatus>, Vec<(Log, Vec<NodeStatus>, Vec<String>)>)>;

    /// The entries of a member's blackboard, as text.
    fn entries(tree: &Tree<Log>) -> Vec<String> {
        let bb = tree.blackboard();
        let mut keys: Vec<String> = bb
            .keys_in(neurotree::ScopeId::ROOT)
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

    /// The ids to name and the visit that delivers `pending` writes: each member named
    /// enough times to be shared among the frame's threads, each visit making every write
    /// held for its member, in order (the same writes again: those seen).
    fn deliver(
        pending: &[(MemberId, String, bool)],
    ) -> (
        Vec<MemberId>,
        impl Fn(MemberMut<'_, Log>) + Send + Sync + '_,
    ) {
        let named = pending
            .iter()
            .flat_map(|p| std::iter::repeat_n(p.0, neurotree::crowd::SHARED_IN_FRAME))
            .collect();
        let write = move |mut member: MemberMut<'_, Log>| {
            let id = member.id();
            for (_, key, v) in pending.iter().filter(|p| p.0 == id) {
                member.tree_mut().blackboard_mut().set(key, *v).unwrap();
            }
        };
        (named, write)
    }

    /// 16 members of `roots`' trees, intervals 1 to 3, under `frames`.
    fn run(roots: &[Node], frames: &[Frame], setup: Setup, sleeps: bool) -> Seen {
        let clock = ManualClock::new();
        let mut crowd = Crowd::new(clock.clone())
            .with_threads(setup.threads)
            .unwrap();
        let bps: Vec<_> = roots.iter().map(blueprint).collect();
        let fresh = |i: usize| {
            let mut tree = Tree::with_clock(Arc::clone(&bps[i % bps.len()]), clock.clone());
            tree.set_sleep_allowed(sleeps);
            tree
        };
        let join = |crowd: &mut Crowd<Log>, i: usize| {
            let mut tree = fresh(i);
            let handle = i.is_multiple_of(2).then(|| tree.halt_handle());
            let id = crowd.add_tree(tree, Log::default());
            crowd.get_mut(id).unwrap().set_interval(1 + (i % 3) as u32);
            (id, handle)
        };
        let (mut ids, mut handles): (Vec<MemberId>, Vec<Option<HaltHandle>>) =
            (0..16).map(|i| join(&mut crowd, i)).unzip();
        if setup.lod {
            crowd.set_level_of_detail(|log: &Log| 1 + (log.0.len() % 3) as u32);
        }
        let waker = crowd.waker();
        let mut seen = Vec::new();
        // Writes held for `frame_with`, in order.
        let mut pending: Vec<(MemberId, String, bool)> = Vec::new();
        for (ms, touches) in frames {
            for (m, t) in touches {
                let id = ids[*m];
                if setup.deliver && sleeps {
                    if let Touch::Write(k, v) = t {
                        pending.push((id, format!("k{k}"), *v));
                        continue;
                    }
                    let (named, write) = deliver(&pending);
                    crowd.for_each_mut(&named, write);
                    pending.clear();
                }
                match t {
                    // The sleeping crowd is written through `for_each_mut`, the member named
                    // enough times to be shared among threads (the same value: one write
                    // seen), the reference one by one.
                    Touch::Write(k, v) if sleeps => {
                        let key = format!("k{k}");
                        let named = vec![id; neurotree::crowd::SHARED_VISITS];
                        crowd.for_each_mut(&named, |mut member| {
                            member.tree_mut().blackboard_mut().set(&key, *v).unwrap();
                        });
                    }
                    Touch::Write(k, v) => {
                        let mut member = crowd.get_mut(id).unwrap();
                        member
                            .tree_mut()
                            .blackboard_mut()
                            .set(&format!("k{k}"), *v)
                            .unwrap();
                    }
                    Touch::Wake(how) => {
                        // The program rings the bell some conditions read, then wakes.
                        crowd.get_mut(id).unwrap().context_mut().1 += 1;
                        match how {
                            0 => waker.wake(id),
                            1 => assert!(crowd.wake(id)),
                            _ => crowd.get_mut(id).unwrap().wake(),
                        }
                    }
                    Touch::Halt => {
                        let mut member = crowd.get_mut(id).unwrap();
                        let (tree, log) = member.tree_and_context_mut();
                        tree.halt(log);
                    }
                    Touch::Replace => {
                        crowd.remove(id).unwrap();
                        (ids[*m], handles[*m]) = join(&mut crowd, *m);
                    }
                    Touch::HaltAll => crowd.halt_all(),
                    Touch::Swap => {
                        let mut tree = fresh(*m);
                        handles[*m] = m.is_multiple_of(2).then(|| tree.halt_handle());
                        crowd.get_mut(id).unwrap().replace_tree(tree);
                    }
                    Touch::Rejoin => {
                        let (tree, log) = crowd.remove(id).unwrap();
                        ids[*m] = crowd.add_tree(tree, log);
                        crowd
                            .get_mut(ids[*m])
                            .unwrap()
                            .set_interval(1 + (*m % 3) as u32);
                    }
                    Touch::HaltHandle => {
                        let handle = handles[*m].get_or_insert_with(|| {
                            crowd.get_mut(id).unwrap().tree_mut().halt_handle()
                        });
                        handle.request();
                    }
                    // The reference is not observed: what it gives, the watched crowd must.
                    Touch::Observe if sleeps => {
                        if crowd.set_observer(id, None).is_none() {
                            crowd.set_observer(id, Some(Box::new(Watcher(0))));
                        }
                    }
                    Touch::Observe => {}
                }
            }
            let report = if !pending.is_empty() {
                let (named, write) = deliver(&pending);
                let report = crowd.frame_with(&named, write);
                pending.clear();
                report
            } else if setup.in_place {
                let frame = crowd.frame_in_place().unwrap();
                let mut visit = ids.clone();
                if setup.awake_only {
                    frame.awake_members(&mut visit);
                    assert_eq!(visit.len(), frame.awake());
                }
                let mut visitor = frame.visitor();
                for &id in visit.iter().rev() {
                    visitor.visit(id, |_| {});
                }
                drop(visitor);
                frame.finish()
            } else {
                crowd.frame()
            };
            assert!(sleeps || report.asleep == 0);
            let statuses: Vec<FrameStatus> = ids
                .iter()
                .map(|&id| crowd.get(id).unwrap().status())
                .collect();
            // The members the frame counts asleep are those it left asleep.
            let marked = statuses.iter().filter(|s| **s == FrameStatus::Asleep);
            assert_eq!(marked.count() as u64, report.asleep);
            let members = ids
                .iter()
                .map(|&id| {
                    let m = crowd.get(id).unwrap();
                    (
                        m.context().clone(),
                        m.tree().statuses().to_vec(),
                        entries(m.tree()),
                    )
                })
                .collect();
            seen.push((statuses, members));
            clock.advance(Duration::from_millis(*ms));
        }
        seen
    }

    /// Runs `frames` with sleeping members under `setup` and without sleeping on one
    /// thread; the first difference, if any.
    fn compare(roots: &[Node], frames: &[Frame], setup: Setup) -> Result<usize, TestCaseError> {
        let reference = run(
            roots,
            frames,
            Setup {
                threads: 1,
                ..setup
            },
            false,
        );
        let sleeping = run(roots, frames, setup, true);
        let mut asleep = 0;
        for (f, (a, b)) in sleeping.iter().zip(&reference).enumerate() {
            for (m, (s, r)) in a.0.iter().zip(&b.0).enumerate() {
                // A member skipped asleep would have returned Running when due.
                let agrees = s == r
                    || (*s == FrameStatus::Asleep
                        && matches!(
                            r,
                            FrameStatus::NotDue | FrameStatus::Ticked(Status::Running)
                        ));
                prop_assert!(agrees, "frame {f}, member {m}: {s:?} against {r:?}");
                asleep += usize::from(*s == FrameStatus::Asleep);
            }
            prop_assert_eq!(&a.1, &b.1, "frame {}", f);
        }
        Ok(asleep)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(150))]

        #[test]
        fn a_crowd_of_sleeping_members_gives_what_ticking_every_frame_gives(
            roots in prop::collection::vec(node(), 1..4),
            frames in prop::collection::vec(frame(), 1..40),
            threads in prop_oneof![Just(1usize), Just(3)],
            in_place in any::<bool>(),
            awake_only in any::<bool>(),
            lod in any::<bool>(),
            deliver in any::<bool>(),
        ) {
            compare(&roots, &frames, Setup { threads, in_place, awake_only, lod, deliver })?;
        }
    }

    /// The property is not empty: members of a plain tree of waiting leaves sleep most of
    /// the frames, and wake by their deadlines exactly when ticking every frame would end
    /// their waits.
    #[test]
    fn members_of_waiting_leaves_sleep_most_frames() {
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
        let frames: Vec<Frame> = (0..40)
            .map(|f| {
                let touches = match f % 10 {
                    3 => vec![(f % 16, Touch::Write(0, true))],
                    7 => vec![(f % 16, Touch::Wake((f % 3) as u8)), (5, Touch::Replace)],
                    _ => vec![],
                };
                (30, touches)
            })
            .collect();
        for threads in [1, 3] {
            for (in_place, awake_only, deliver) in [
                (false, false, false),
                (true, false, false),
                (true, true, false),
                (false, false, true),
            ] {
                let setup = Setup {
                    threads,
                    in_place,
                    awake_only,
                    lod: false,
                    deliver,
                };
                let asleep = compare(std::slice::from_ref(&root), &frames, setup).unwrap();
                assert!(asleep > 16 * 40 / 2, "{asleep} member-frames asleep");
            }
        }
    }
}

/// What a member's alert leaf did.
#[derive(Clone, Debug, Default, PartialEq)]
struct Watcher {
    calls: u32,
    halts: u32,
}

/// Runs until the entry `alert` is true, and says so: its tree sleeps meanwhile.
struct UntilAlert;

impl StatefulAction<Watcher> for UntilAlert {
    fn on_start(&mut self, h: &mut Handle<'_, Watcher>) -> Status {
        self.on_running(h)
    }
    fn on_running(&mut self, h: &mut Handle<'_, Watcher>) -> Status {
        h.ctx_mut().calls += 1;
        if h.blackboard().get::<bool>("alert").unwrap_or(false) {
            return Status::Success;
        }
        h.wake_on("alert");
        Status::Running
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Watcher>) {
        h.ctx_mut().halts += 1;
    }
}

/// `ReactiveSequence(ScriptCondition "hungry == false", a leaf sleeping until "alert")`:
/// the crowd settles asleep, a frame then ticks none of the 100 members, and writing
/// `hungry` for 10 of them ticks exactly those 10, whose condition fails and halts the
/// sleeping leaf.
#[test]
fn a_reactive_crowd_over_a_script_condition_sleeps_and_wakes_exactly_the_written() {
    let bp = Blueprint::<Watcher>::builder()
        .reactive_sequence("needs", |r| {
            r.script_condition("fed", "hungry == false")
                .stateful("watch", || UntilAlert)
        })
        .build_shared()
        .unwrap();
    let clock = ManualClock::new();
    let mut crowd = Crowd::new(clock.clone()).with_threads(2).unwrap();
    let ids: Vec<MemberId> = (0..100)
        .map(|_| {
            let mut tree = Tree::with_clock(Arc::clone(&bp), clock.clone());
            tree.blackboard_mut().set("hungry", false).unwrap();
            crowd.add_tree(tree, Watcher::default())
        })
        .collect();
    let first = crowd.frame();
    assert_eq!((first.ticked, first.asleep), (100, 0));
    assert_eq!(first.awake.total(), 0, "{:?}", first.awake);
    for _ in 0..3 {
        clock.advance(Duration::from_millis(16));
        let report = crowd.frame();
        assert_eq!((report.ticked, report.asleep), (0, 100));
    }
    for &id in &ids[..10] {
        let mut member = crowd.get_mut(id).unwrap();
        member
            .tree_mut()
            .blackboard_mut()
            .set("hungry", true)
            .unwrap();
    }
    clock.advance(Duration::from_millis(16));
    let report = crowd.frame();
    assert_eq!((report.ticked, report.asleep), (10, 90));
    for (i, &id) in ids.iter().enumerate() {
        let member = crowd.get(id).unwrap();
        let watcher = member.context();
        if i < 10 {
            assert_eq!(member.status(), FrameStatus::Ticked(Status::Failure));
            assert_eq!(*watcher, Watcher { calls: 1, halts: 1 });
        } else {
            assert!(member.tree().is_asleep());
            assert_eq!(*watcher, Watcher { calls: 1, halts: 0 });
        }
    }
    // The 10 failed: their roots are not Running, so they are awake, and say why.
    assert_eq!(report.awake.get(AwakeReason::NotRunning), 10);
    assert_eq!(report.awake.total(), 10);
}
