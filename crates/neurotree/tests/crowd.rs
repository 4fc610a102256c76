//! Crowds: schedules, budgets, membership and results, counted exactly; and the same
//! results with one thread or several.

use std::sync::Arc;
use std::time::Duration;

use neurotree::crowd::{Behind, Crowd, FrameReport, FrameStatus, MemberId, TickMode, Visit};
use neurotree::prelude::*;
use neurotree::NodeStatus;

/// A context that counts what its tree did to it.
#[derive(Clone, Debug, Default, PartialEq)]
struct Walker {
    seed: i64,
    x: i64,
    food: i64,
    far: bool,
    ticks: u32,
    starts: u32,
    halts: u32,
    /// Everything that happened, folded into one number in order.
    trace: u64,
}

impl Walker {
    fn new(seed: i64) -> Self {
        Self {
            seed,
            food: seed % 60,
            ..Self::default()
        }
    }

    fn note(&mut self, event: u64) {
        self.trace = self.trace.wrapping_mul(1_000_003).wrapping_add(event);
    }
}

/// Runs until halted, counting starts and halts in the context.
struct Work;

impl StatefulAction<Walker> for Work {
    fn on_start(&mut self, h: &mut Handle<'_, Walker>) -> Status {
        h.ctx_mut().starts += 1;
        Status::Running
    }
    fn on_running(&mut self, _h: &mut Handle<'_, Walker>) -> Status {
        Status::Running
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Walker>) {
        h.ctx_mut().halts += 1;
    }
}

/// One action that counts its ticks and succeeds.
fn counter() -> Arc<Blueprint<Walker>> {
    Blueprint::<Walker>::builder()
        .action("count", |w: &mut Walker| {
            w.ticks += 1;
            Status::Success
        })
        .build_shared()
        .unwrap()
}

/// A crowd on two threads of `n` members of [`counter`], and their ids.
fn counters(n: i64) -> (Crowd<Walker>, Vec<MemberId>) {
    let mut crowd = Crowd::new(ManualClock::new()).with_threads(2).unwrap();
    let bp = counter();
    let ids = (0..n)
        .map(|i| crowd.add(bp.clone(), Walker::new(i)))
        .collect();
    (crowd, ids)
}

/// Each member's status in the last frame, in slot order.
fn statuses(crowd: &Crowd<Walker>) -> Vec<FrameStatus> {
    crowd.iter().map(|m| m.status()).collect()
}

const T: FrameStatus = FrameStatus::Ticked(Status::Success);
const N: FrameStatus = FrameStatus::NotDue;
const D: FrameStatus = FrameStatus::Deferred;

#[test]
fn intervals_and_phases_spread_members_over_the_frames() {
    let (mut crowd, ids) = counters(8);
    for id in &ids {
        crowd.get_mut(*id).unwrap().set_interval(4);
    }
    // Member i (phase i) is due in the frames f with (f + i) % 4 == 0.
    assert_eq!(crowd.frame().ticked, 2);
    assert_eq!(statuses(&crowd), [T, N, N, N, T, N, N, N]);
    assert_eq!(crowd.frame().ticked, 2);
    assert_eq!(statuses(&crowd), [N, N, N, T, N, N, N, T]);
    for _ in 2..8 {
        let report = crowd.frame();
        assert_eq!((report.due, report.ticked, report.visits), (2, 2, 2));
    }
    assert!(crowd.iter().all(|m| m.context().ticks == 2));
    assert_eq!(crowd.frames(), 8);
}

#[test]
fn the_level_of_detail_hook_chooses_intervals_every_frame() {
    let mut crowd = Crowd::new(ManualClock::new()).with_threads(2).unwrap();
    let bp = counter();
    let near = crowd.add(bp.clone(), Walker::new(0));
    let far = crowd.add(bp.clone(), Walker::new(1));
    crowd.get_mut(far).unwrap().context_mut().far = true;
    crowd.set_level_of_detail(|w: &Walker| if w.far { 8 } else { 1 });
    for _ in 0..16 {
        crowd.frame();
    }
    assert_eq!(crowd.get(near).unwrap().context().ticks, 16);
    assert_eq!(crowd.get(far).unwrap().context().ticks, 2);
    assert_eq!(crowd.get(far).unwrap().interval(), 8);
    // Coming near: due every frame from the next one on.
    crowd.get_mut(far).unwrap().context_mut().far = false;
    for _ in 0..4 {
        crowd.frame();
    }
    assert_eq!(crowd.get(far).unwrap().context().ticks, 6);
    // A hook answering 0 means every frame.
    crowd.set_level_of_detail(|_: &Walker| 0);
    crowd.frame();
    assert_eq!(crowd.get(far).unwrap().interval(), 1);
    assert_eq!(crowd.get(far).unwrap().context().ticks, 7);
}

#[test]
fn a_budget_defers_the_rest_oldest_first_and_reports_the_lag() {
    let mut crowd = Crowd::new(ManualClock::new()).with_threads(2).unwrap();
    let bp = counter();
    for i in 0..10 {
        crowd.add(bp.clone(), Walker::new(i));
    }
    // One node each: four ticks per frame.
    crowd.set_budget(Some(4));
    let report = crowd.frame();
    assert_eq!(
        report,
        FrameReport {
            frame: 0,
            due: 10,
            asleep: 0,
            ticked: 4,
            visits: 4,
            failures: 0,
            errors: 0,
            behind: Behind {
                overdue: 6,
                frames: 1
            },
            // The counter's trees complete every tick: not Running.
            awake: report.awake,
        }
    );
    assert_eq!(statuses(&crowd), [T, T, T, T, D, D, D, D, D, D]);
    // The six owed from frame 0 come first: 4..8 now, 8 and 9 wait, and 0..4, due again,
    // wait behind them. A member owed a tick is owed one, however often it falls due.
    let report = crowd.frame();
    assert_eq!((report.due, report.ticked), (10, 4));
    assert_eq!(statuses(&crowd), [D, D, D, D, T, T, T, T, D, D]);
    assert_eq!(
        report.behind,
        Behind {
            overdue: 6,
            frames: 2
        }
    );
    assert_eq!(crowd.behind(), report.behind);
    let report = crowd.frame();
    assert_eq!(statuses(&crowd), [T, T, D, D, D, D, D, D, T, T]);
    // Member 2 has waited since frame 1.
    assert_eq!(
        report.behind,
        Behind {
            overdue: 6,
            frames: 2
        }
    );
    let ticks: Vec<u32> = crowd.iter().map(|m| m.context().ticks).collect();
    assert_eq!(ticks, [2, 2, 1, 1, 1, 1, 1, 1, 1, 1]);

    // Lifted: every owed or due member is ticked once, and the crowd has caught up.
    crowd.set_budget(None);
    let report = crowd.frame();
    assert_eq!((report.due, report.ticked), (10, 10));
    assert_eq!(report.behind, Behind::default());
    let ticks: Vec<u32> = crowd.iter().map(|m| m.context().ticks).collect();
    assert_eq!(ticks, [3, 3, 2, 2, 2, 2, 2, 2, 2, 2]);

    // A budget smaller than one tick still lets one member through per frame.
    crowd.set_budget(Some(0));
    assert_eq!(crowd.frame().ticked, 1);
    assert_eq!(crowd.frame().ticked, 1);
    assert_eq!(statuses(&crowd)[..3], [D, T, D]);
}

/// Ticks so far, member by member.
fn ticks(crowd: &Crowd<Walker>) -> Vec<u32> {
    crowd.iter().map(|m| m.context().ticks).collect()
}

/// A frame in place whose visits tick `ids`, each of them due; not finished.
fn ticked_in_place<'c>(
    crowd: &'c mut Crowd<Walker>,
    ids: &[MemberId],
) -> neurotree::crowd::InPlaceFrame<'c, Walker> {
    let frame = crowd.frame_in_place().unwrap();
    let mut visitor = frame.visitor();
    for &id in ids {
        assert!(matches!(visitor.visit(id, |_| {}), Visit::Ticked(..)));
    }
    drop(visitor);
    frame
}

#[test]
fn members_owed_a_tick_and_not_visited_in_place_are_owed_it_under_the_next_budget() {
    let (mut crowd, ids) = counters(10);
    crowd.set_budget(Some(4));
    crowd.frame();
    assert_eq!(statuses(&crowd), [T, T, T, T, D, D, D, D, D, D]);
    // Without a budget, a frame in place visits members 0 to 5: 4 and 5, owed since
    // frame 0, tick; 6 to 9 are not visited and are still owed a tick.
    crowd.set_budget(None);
    let report = ticked_in_place(&mut crowd, &ids[..6]).finish();
    assert_eq!(report.ticked, 6);
    assert_eq!(
        report.behind,
        Behind {
            overdue: 4,
            frames: 2
        }
    );
    assert_eq!(crowd.behind(), report.behind);
    assert_eq!(ticks(&crowd), [2, 2, 2, 2, 1, 1, 0, 0, 0, 0]);
    // Still owed, they say so: deferred, not "not due".
    assert_eq!(statuses(&crowd), [T, T, T, T, T, T, D, D, D, D]);
    // Under a budget again, those four go first, before the members due in this frame.
    crowd.set_budget(Some(4));
    let report = crowd.frame();
    assert_eq!((report.due, report.ticked), (10, 4));
    assert_eq!(statuses(&crowd), [D, D, D, D, D, D, T, T, T, T]);
    assert_eq!(ticks(&crowd), [2, 2, 2, 2, 1, 1, 1, 1, 1, 1]);
    crowd.frame();
    assert_eq!(statuses(&crowd), [T, T, T, T, D, D, D, D, D, D]);
}

#[test]
fn a_frame_in_place_dropped_unfinished_leaves_no_member_it_ticked_owed() {
    let (mut crowd, ids) = counters(10);
    crowd.set_budget(Some(4));
    crowd.frame();
    crowd.set_budget(None);
    drop(ticked_in_place(&mut crowd, &ids[4..6]));
    // 4 and 5 had their tick: the budget goes to 6 to 9, and no member ticks twice.
    crowd.set_budget(Some(4));
    let report = crowd.frame();
    assert_eq!(statuses(&crowd), [D, D, D, D, D, D, T, T, T, T]);
    assert_eq!(ticks(&crowd), [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]);
    assert_eq!(
        report.behind,
        Behind {
            overdue: 6,
            frames: 1
        }
    );
    // The six due in frame 2 come next, each once.
    crowd.frame();
    assert_eq!(statuses(&crowd), [T, T, T, T, D, D, D, D, D, D]);
    crowd.frame();
    assert_eq!(statuses(&crowd), [D, D, D, D, T, T, T, T, D, D]);
    assert_eq!(ticks(&crowd), [2, 2, 2, 2, 2, 2, 2, 2, 1, 1]);
}

#[test]
fn members_owed_past_the_first_part_of_a_frame_in_place_keep_their_turn() {
    let (mut crowd, ids) = counters(1100);
    crowd.set_budget(Some(1050));
    crowd.frame();
    crowd.set_budget(None);
    let report = ticked_in_place(&mut crowd, &ids[1050..1075]).finish();
    assert_eq!((report.ticked, report.behind.overdue), (25, 25));
    crowd.set_budget(Some(1050));
    let report = crowd.frame();
    assert_eq!(report.ticked, 1050);
    let ticks = ticks(&crowd);
    // The 25 still owed went first, then the members due in slot order.
    assert!(
        ticks[1075..].iter().all(|&t| t == 1),
        "{:?}",
        &ticks[1075..]
    );
    assert!(ticks[1050..1075].iter().all(|&t| t == 1));
    assert!(ticks[..1025].iter().all(|&t| t == 2));
    assert!(ticks[1025..1050].iter().all(|&t| t == 1));
}

#[test]
fn a_held_member_owed_a_tick_takes_no_share_of_the_budget_and_ticks_once_released() {
    let (mut crowd, ids) = counters(10);
    crowd.set_budget(Some(4));
    crowd.frame();
    // Member 4 heads the queue of those owed a tick; held, it is not ticked, and the
    // budget goes to the four after it.
    assert!(crowd.hold(ids[4]));
    assert!(!crowd.get(ids[4]).unwrap().is_owed());
    let report = crowd.frame();
    assert_eq!(report.ticked, 4);
    const A: FrameStatus = FrameStatus::Asleep;
    assert_eq!(statuses(&crowd), [D, D, D, D, A, T, T, T, T, D]);
    assert_eq!(
        report.behind,
        Behind {
            overdue: 5,
            frames: 2
        }
    );
    // Released, it is due again as a fresh member, queued behind those owed from before.
    assert!(crowd.release(ids[4]));
    let mut frames = 0;
    while crowd.get(ids[4]).unwrap().context().ticks == 0 {
        crowd.frame();
        frames += 1;
        assert!(frames <= 3, "{:?}", statuses(&crowd));
    }
    // Frame 2 ticks 9 and 0 to 2, frame 3 ticks 3 and the fresh ones from frame 2, 4 first.
    assert_eq!(frames, 2);
    assert!(crowd.iter().all(|m| !m.is_owed() || m.status() == D));
}

#[test]
fn a_budget_that_covers_the_frame_ticks_everyone_due() {
    let mut crowd = Crowd::new(ManualClock::new()).with_threads(2).unwrap();
    let bp = counter();
    for i in 0..3000 {
        crowd.add(bp.clone(), Walker::new(i));
    }
    crowd.set_budget(Some(3000));
    for _ in 0..3 {
        let report = crowd.frame();
        assert_eq!(
            (report.due, report.ticked, report.visits),
            (3000, 3000, 3000)
        );
        assert_eq!(report.behind, Behind::default());
    }
    // Over three chunks of slots, the budget ends inside the second.
    crowd.set_budget(Some(1500));
    let report = crowd.frame();
    assert_eq!((report.ticked, report.behind.overdue), (1500, 1500));
    let ticks: Vec<u32> = crowd.iter().map(|m| m.context().ticks).collect();
    assert!(ticks[..1500].iter().all(|t| *t == 4));
    assert!(ticks[1500..].iter().all(|t| *t == 3));
}

#[test]
fn removing_a_member_halts_its_running_action_once() {
    let mut crowd = Crowd::new(ManualClock::new()).with_threads(2).unwrap();
    let working = Blueprint::<Walker>::builder()
        .sequence("job", |s| s.stateful("work", || Work))
        .build_shared()
        .unwrap();
    let a = crowd.add(working.clone(), Walker::new(0));
    let b = crowd.add(working.clone(), Walker::new(1));
    let idle = crowd.add(counter(), Walker::new(2));
    for _ in 0..3 {
        crowd.frame();
    }
    assert_eq!(
        crowd.get(a).unwrap().status(),
        FrameStatus::Ticked(Status::Running)
    );
    let (tree, walker) = crowd.remove(a).unwrap();
    assert_eq!((walker.starts, walker.halts), (1, 1));
    assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    assert!(crowd.remove(a).is_none());
    assert!(crowd.get(a).is_none());
    // Its slot goes to the next member, under a new id.
    let c = crowd.add(counter(), Walker::new(3));
    assert_eq!(c.slot(), a.slot());
    assert_ne!(c, a);
    assert!(crowd.get(a).is_none());
    assert_eq!(crowd.len(), 3);
    crowd.frame();
    // The others went on, untouched by the removal.
    let bw = crowd.get(b).unwrap().context();
    assert_eq!((bw.starts, bw.halts), (1, 0));
    let (_, walker) = crowd.remove(idle).unwrap();
    assert_eq!((walker.ticks, walker.halts), (4, 0));
    // Halting all keeps the members and halts each running action once.
    crowd.halt_all();
    crowd.halt_all();
    let bw = crowd.get(b).unwrap().context();
    assert_eq!((bw.starts, bw.halts), (1, 1));
    assert_eq!(crowd.len(), 2);
}

#[test]
fn a_removed_member_owed_a_tick_leaves_the_queue() {
    let (mut crowd, ids) = counters(4);
    crowd.set_budget(Some(1));
    crowd.frame();
    assert_eq!(crowd.behind().overdue, 3);
    crowd.remove(ids[1]).unwrap();
    assert_eq!(crowd.behind().overdue, 2);
    // Member 2 is the oldest owed now.
    crowd.frame();
    let ticks: Vec<u32> = crowd.iter().map(|m| m.context().ticks).collect();
    assert_eq!(ticks, [1, 1, 0]);
}

#[test]
fn failures_and_errors_are_reported_per_member() {
    let mut crowd = Crowd::new(ManualClock::new()).with_threads(2).unwrap();
    struct Blocked;
    impl Action<Walker> for Blocked {
        fn tick(&self, h: &mut Handle<'_, Walker>) -> Status {
            h.fail_with(7, "blocked")
        }
    }
    let failing = Blueprint::<Walker>::builder()
        .sequence("go", |s| s.action_node("walk", Blocked))
        .build_shared()
        .unwrap();
    let broken = Blueprint::<Walker>::builder()
        .action("bad", |_: &mut Walker| Status::Running)
        .build_shared()
        .unwrap();
    let ok = crowd.add(counter(), Walker::new(0));
    let fails = crowd.add(failing, Walker::new(1));
    let errs = crowd.add(broken, Walker::new(2));
    let report = crowd.frame();
    assert_eq!((report.ticked, report.failures, report.errors), (3, 1, 1));
    assert_eq!(crowd.get(ok).unwrap().status(), T);
    let failed = crowd.get(fails).unwrap();
    assert_eq!(failed.status(), FrameStatus::Ticked(Status::Failure));
    let why = failed.tree().last_failure().unwrap();
    assert_eq!(why.leaf().path, "go/walk");
    assert_eq!(why.reason().unwrap().to_string(), "blocked (error 7)");
    let ids: Vec<MemberId> = crowd.failures().map(|m| m.id()).collect();
    assert_eq!(ids, [fails]);
    let erred = crowd.get(errs).unwrap();
    assert_eq!(erred.status(), FrameStatus::Error);
    assert!(matches!(erred.error(), Some(TickError::LeafRunning { .. })));
    assert_eq!(crowd.errors().count(), 1);
    // The error stays until the member's next tick.
    crowd.get_mut(errs).unwrap().set_interval(2);
    crowd.frame();
    assert_eq!(crowd.get(errs).unwrap().status(), N);
    assert!(crowd.get(errs).unwrap().error().is_some());
}

#[test]
fn tick_once_repeats_passes_and_charges_each() {
    let bp = Blueprint::<Walker>::builder()
        .repeat("thrice", 3, |r| {
            r.action("count", |w: &mut Walker| {
                w.ticks += 1;
                Status::Success
            })
        })
        .build_shared()
        .unwrap();
    let mut crowd = Crowd::new(ManualClock::new()).with_threads(1).unwrap();
    crowd.add(bp, Walker::new(0));
    assert_eq!(crowd.frame().visits, 2);
    assert_eq!(crowd.iter().next().unwrap().context().ticks, 1);
    crowd.set_tick_mode(TickMode::Once);
    // The Repeat's remaining two cycles and then three more: two nodes per pass.
    let report = crowd.frame();
    assert_eq!(crowd.iter().next().unwrap().context().ticks, 3);
    assert_eq!(report.visits, 4);
    assert_eq!(report.ticked, 1);
}

// --- The same results on any number of threads -------------------------------------

const WALK_XML: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Fallback>
      <Sequence>
        <Hungry/>
        <Script code="meals := meals + 1"/>
        <Eat/>
      </Sequence>
      <Sequence>
        <Wander/>
        <Sleep msec="30"/>
        <Script code="walks := walks + 1"/>
      </Sequence>
    </Fallback>
  </BehaviorTree>
</root>"#;

fn walk_blueprint() -> Arc<Blueprint<Walker>> {
    let mut registry = Registry::<Walker>::new();
    registry
        .register_condition("Hungry", vec![], |h| h.ctx().food < 30)
        .unwrap();
    registry
        .register_action("Eat", vec![], |h| {
            let w = h.ctx_mut();
            w.food += 50;
            w.note(1);
            Status::Success
        })
        .unwrap();
    registry
        .register_action("Wander", vec![], |h| {
            let w = h.ctx_mut();
            w.x += w.seed % 5 - 2;
            w.food -= 7;
            w.far = w.x.abs() > 6;
            w.note(2 + w.x.unsigned_abs());
            Status::from(w.x % 13 != 0)
        })
        .unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(WALK_XML, "walk.xml").unwrap();
    Arc::new(loader.build_main().unwrap())
}

fn work_blueprint() -> Arc<Blueprint<Walker>> {
    Blueprint::<Walker>::builder()
        .reactive_sequence("guarded", |s| {
            s.condition("fed", |w: &Walker| w.food > -40).timeout(
                "limit",
                Duration::from_millis(80),
                |t| t.stateful("work", || Work),
            )
        })
        .build_shared()
        .unwrap()
}

/// Everything observable of one run: every frame's report and statuses, and each
/// member's context, node statuses and blackboard at the end.
type Run = (Vec<(FrameReport, Vec<FrameStatus>)>, Vec<String>);

fn run(threads: usize, budget: Option<u64>) -> Run {
    run_driven(threads, budget, false)
}

/// How a run's frames deliver their events: not at all, through `for_each_mut` before the
/// frame, or with it through `frame_with`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Deliver {
    None,
    Before,
    With,
}

/// A frame whose members are visited one by one ([`Crowd::frame_in_place`]): the
/// second half of the slots, then the first, each backwards, on two threads at once.
fn frame_in_place(crowd: &mut Crowd<Walker>) -> FrameReport {
    let ids: Vec<MemberId> = crowd.iter().map(|m| m.id()).collect();
    let frame = crowd.frame_in_place().expect("no budget");
    let (first, second) = ids.split_at(ids.len() / 2);
    std::thread::scope(|s| {
        for half in [second, first] {
            let frame = &frame;
            s.spawn(move || {
                let mut visitor = frame.visitor();
                for &id in half.iter().rev() {
                    visitor.visit(id, |_| {});
                }
            });
        }
    });
    frame.finish()
}

fn run_driven(threads: usize, budget: Option<u64>, in_place: bool) -> Run {
    run_delivering(threads, budget, in_place, Deliver::None)
}

fn run_delivering(threads: usize, budget: Option<u64>, in_place: bool, deliver: Deliver) -> Run {
    let clock = ManualClock::new();
    let mut crowd = Crowd::new(clock.clone()).with_threads(threads).unwrap();
    assert_eq!(crowd.threads(), threads);
    let (walk, work) = (walk_blueprint(), work_blueprint());
    let add = |crowd: &mut Crowd<Walker>, i: i64| {
        let bp = if i % 3 == 0 { &work } else { &walk };
        let mut tree = Tree::with_shared_clock(bp.clone(), crowd.clock().clone());
        tree.blackboard_mut().set("meals", 0i64).unwrap();
        tree.blackboard_mut().set("walks", 0i64).unwrap();
        crowd.add_tree(tree, Walker::new(i))
    };
    let mut ids: Vec<MemberId> = (0..5000).map(|i| add(&mut crowd, i)).collect();
    crowd.set_level_of_detail(|w: &Walker| if w.far { 4 } else { 1 });
    crowd.set_budget(budget);
    let mut frames = Vec::new();
    for f in 0..120i64 {
        if f % 10 == 5 {
            // Leave and join between frames, the same way in every run.
            for k in 0..50 {
                let id = ids.remove((k * 37 + f as usize) % ids.len());
                crowd.remove(id).unwrap();
            }
            for k in 0..60 {
                ids.push(add(&mut crowd, 10_000 + f * 100 + k));
            }
        }
        // Every seventh member, a different seventh each frame, moves near or far (which
        // the level-of-detail hook reads) and has a meal written on its blackboard.
        let named: Vec<MemberId> = ids
            .iter()
            .copied()
            .filter(|id| id.slot() % 7 == f as usize % 7)
            .collect();
        let event = |mut m: neurotree::crowd::MemberMut<'_, Walker>| {
            let walker = m.context_mut();
            walker.far = !walker.far;
            m.tree_mut().blackboard_mut().set("meals", f).unwrap();
        };
        let report = match deliver {
            Deliver::None if in_place => frame_in_place(&mut crowd),
            Deliver::None => crowd.frame(),
            Deliver::Before => {
                crowd.for_each_mut(&named, event);
                crowd.frame()
            }
            Deliver::With => crowd.frame_with(&named, event),
        };
        frames.push((report, statuses(&crowd)));
        clock.advance(Duration::from_millis(10));
    }
    let ends = crowd
        .iter()
        .map(|m| {
            let bb = m.tree().blackboard();
            format!(
                "{:?} {:?} {:?} meals={:?} walks={:?}",
                m.id(),
                m.context(),
                m.tree().statuses(),
                bb.get::<i64>("meals"),
                bb.get::<i64>("walks"),
            )
        })
        .collect();
    (frames, ends)
}

#[test]
fn one_thread_or_several_give_the_same_results() {
    for budget in [None, Some(20_000)] {
        let one = run(1, budget);
        // The runs are worth comparing: work was done, deferred, failed, removed.
        let ticked: u64 = one.0.iter().map(|(r, _)| r.ticked).sum();
        let failures: u64 = one.0.iter().map(|(r, _)| r.failures).sum();
        assert!(ticked > 100_000 && failures > 0, "{ticked} {failures}");
        assert!(one.1.iter().any(|e| e.contains("halts: 1")));
        assert!(one.1.iter().any(|e| !e.contains("meals=Ok(0)")));
        if budget.is_some() {
            assert!(one.0.iter().any(|(r, _)| r.behind.overdue > 0));
        }
        for threads in [2, 3] {
            let many = run(threads, budget);
            assert_eq!(one.0.len(), many.0.len());
            for (f, (a, b)) in one.0.iter().zip(&many.0).enumerate() {
                assert_eq!(a, b, "frame {f} with {threads} threads, budget {budget:?}");
            }
            assert_eq!(one.1, many.1, "{threads} threads, budget {budget:?}");
        }
    }
}

#[test]
fn events_delivered_with_the_frame_give_what_events_delivered_before_it_give() {
    for budget in [None, Some(20_000)] {
        let before = run_delivering(1, budget, false, Deliver::Before);
        assert!(before.1.iter().any(|e| e.contains("meals=Ok(119)")));
        for threads in [1, 2, 3] {
            let with = run_delivering(threads, budget, false, Deliver::With);
            for (f, (a, b)) in before.0.iter().zip(&with.0).enumerate() {
                assert_eq!(a, b, "frame {f}, {threads} threads, budget {budget:?}");
            }
            assert_eq!(before.1, with.1, "{threads} threads, budget {budget:?}");
        }
    }
}

#[test]
fn members_visited_in_place_in_any_order_give_what_a_frame_gives() {
    let frame = run(1, None);
    let in_place = run_driven(1, None, true);
    assert!(frame.0.iter().map(|(r, _)| r.ticked).sum::<u64>() > 100_000);
    assert_eq!(frame.0.len(), in_place.0.len());
    for (f, (a, b)) in frame.0.iter().zip(&in_place.0).enumerate() {
        assert_eq!(a, b, "frame {f}");
    }
    assert_eq!(frame.1, in_place.1);
}

#[test]
fn an_in_place_frame_ticks_the_due_members_it_visits_once_and_loads_only_them() {
    let clock = ManualClock::new();
    let mut crowd = Crowd::new(clock.clone());
    let ids: Vec<MemberId> = (0..3)
        .map(|i| crowd.add(counter(), Walker::new(i)))
        .collect();
    crowd.get_mut(ids[2]).unwrap().set_interval(2);
    // Frame 0: member 2 (phase 2, interval 2) is due; member 1 is not visited.
    let frame = crowd.frame_in_place().unwrap();
    let mut loads = Vec::new();
    let mut visitor = frame.visitor();
    for id in [ids[2], ids[0], ids[0]] {
        let visit = visitor.visit(id, |w| {
            w.food = 1000;
            loads.push(w.seed);
        });
        if let Visit::Ticked(w, status) = visit {
            assert_eq!((w.ticks, w.food, status), (1, 1000, T));
        }
    }
    drop(visitor);
    let report = frame.finish();
    assert_eq!((report.due, report.ticked, report.visits), (2, 2, 2));
    assert_eq!(loads, [2, 0]);
    assert_eq!(statuses(&crowd), [T, N, T]);
    // Frame 1: member 2 is not due, so it is neither loaded nor ticked.
    let frame = crowd.frame_in_place().unwrap();
    let mut visitor = frame.visitor();
    let mut loads = Vec::new();
    for &id in &ids {
        visitor.visit(id, |w| loads.push(w.seed));
    }
    drop(visitor);
    assert_eq!(frame.finish().ticked, 2);
    assert_eq!(loads, [0, 1]);
    assert_eq!(statuses(&crowd), [T, T, N]);
    let ticks: Vec<u32> = crowd.iter().map(|m| m.context().ticks).collect();
    assert_eq!(ticks, [2, 1, 1]);
    // Under a budget, the crowd picks its members itself.
    crowd.set_budget(Some(10));
    assert!(crowd.frame_in_place().is_none());
}

#[test]
fn a_crowd_of_one_thread_of_its_own_ticks_on_the_callers_thread_others_on_their_pool() {
    // Which thread ticked the member, as a tree cannot name it otherwise.
    type Ticked = Option<std::thread::ThreadId>;
    let bp = Blueprint::<Ticked>::builder()
        .action("note", |t: &mut Ticked| {
            *t = Some(std::thread::current().id());
            Status::Success
        })
        .build_shared()
        .unwrap();
    let here = std::thread::current().id();
    // A pool given to the crowd is used whatever its size: its threads' settings apply.
    let given = Arc::new(
        rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap(),
    );
    for (threads, on_caller) in [(1, true), (2, false), (0, false)] {
        for budget in [None, Some(100)] {
            let crowd = Crowd::new(ManualClock::new());
            let mut crowd = match threads {
                0 => crowd.with_pool(Arc::clone(&given)),
                n => crowd.with_threads(n).unwrap(),
            };
            crowd.set_budget(budget);
            let id = crowd.add(Arc::clone(&bp), None);
            assert_eq!(crowd.frame().ticked, 1);
            let ticked = crowd.get(id).unwrap().context().unwrap();
            // A budget picks members over the whole crowd first, in the pool.
            let inline = on_caller && budget.is_none();
            assert_eq!(
                ticked == here,
                inline,
                "{threads} threads, budget {budget:?}"
            );
        }
    }
}
