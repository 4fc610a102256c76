//! One member held still (as the studio holds the agent it watches when paused): the
//! other members are ticked exactly as without the hold, and the held one not at all,
//! whatever wakes it, until released; an observer set on one member leaves its ticks as
//! an unobserved run's.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree::crowd::{Crowd, FrameStatus, MemberId};
use neurotree::prelude::*;
use neurotree::{NodeStatus, Observer, StatusChange};

/// Counts a member's leg ticks and what it saw, folded in order.
#[derive(Clone, Debug, Default, PartialEq)]
struct Walker {
    ticks: u32,
    trace: u64,
}

/// A leg of `2 + seed % 3` ticks (awake), then a pause of 100 ms (asleep).
fn walk(seed: u64) -> Arc<Blueprint<Walker>> {
    let legs = 2 + (seed % 3) as u32;
    Blueprint::<Walker>::builder()
        .keep_running_until_failure("forever", |k| {
            k.sequence("round", |s| {
                s.stateful("leg", move || Leg { legs })
                    .sleep("pause", Duration::from_millis(100))
            })
        })
        .build_shared()
        .unwrap()
}

struct Leg {
    legs: u32,
}

impl StatefulAction<Walker> for Leg {
    fn on_start(&mut self, h: &mut Handle<'_, Walker>) -> Status {
        self.on_running(h)
    }
    fn on_running(&mut self, h: &mut Handle<'_, Walker>) -> Status {
        let w = h.ctx_mut();
        w.ticks += 1;
        w.trace = w.trace.wrapping_mul(31).wrapping_add(u64::from(w.ticks));
        if w.ticks.is_multiple_of(self.legs) {
            Status::Success
        } else {
            Status::Running
        }
    }
    fn on_halted(&mut self, _h: &mut Handle<'_, Walker>) {}
}

/// Per frame, each member's status, context and node statuses.
type Frames = Vec<Vec<(FrameStatus, Walker, Vec<NodeStatus>)>>;

/// 12 walkers over 60 frames of 20 ms. `hold`: member `m` held from frame `a` to frame `b`
/// (released before it), woken every frame meanwhile. `observe`: member 5 carries an
/// observer that records its status changes.
fn run(hold: Option<(usize, usize, usize)>, observe: bool) -> (Frames, Vec<u64>, usize) {
    run_with(hold, observe, false)
}

/// [`run`], its frames in place (as the Bevy plugin runs them) when `in_place`.
fn run_with(
    hold: Option<(usize, usize, usize)>,
    observe: bool,
    in_place: bool,
) -> (Frames, Vec<u64>, usize) {
    let clock = ManualClock::new();
    let mut crowd = Crowd::new(clock.clone()).with_threads(2).unwrap();
    let ids: Vec<MemberId> = (0..12)
        .map(|i| crowd.add(walk(i as u64), Walker::default()))
        .collect();
    let seen = Arc::new(Mutex::new(Vec::new()));
    if observe {
        let before = crowd.set_observer(ids[5], Some(Box::new(Recorder(Arc::clone(&seen)))));
        assert!(before.is_none());
    }
    let mut frames = Vec::new();
    let mut ticked = Vec::new();
    for f in 0..60 {
        if let Some((m, a, b)) = hold {
            if f == a {
                assert!(crowd.hold(ids[m]));
                assert!(crowd.is_held(ids[m]));
            }
            if f == b {
                assert!(crowd.release(ids[m]));
                assert!(!crowd.is_held(ids[m]));
            }
            if (a..b).contains(&f) {
                // Wakes, and a blackboard written, do not tick a held member.
                assert!(crowd.wake(ids[m]));
                crowd
                    .member_tree_mut(ids[m])
                    .unwrap()
                    .blackboard_mut()
                    .set("poke", f as i64)
                    .unwrap();
            }
        }
        let report = crate::crowd_sleeping::frame(&mut crowd, &ids, in_place);
        ticked.push(report.ticked);
        frames.push(
            crowd
                .iter()
                .map(|m| {
                    (
                        m.status(),
                        m.context().clone(),
                        m.tree().statuses().to_vec(),
                    )
                })
                .collect(),
        );
        clock.advance(Duration::from_millis(20));
    }
    let changes = seen.lock().unwrap().len();
    (frames, ticked, changes)
}

struct Recorder(Arc<Mutex<Vec<StatusChange>>>);

impl Observer for Recorder {
    fn on_status_change(&mut self, change: StatusChange) {
        self.0.lock().unwrap().push(change);
    }
    // As the studio's observer of a crowd's agent.
    fn lets_tree_sleep(&self) -> bool {
        true
    }
}

#[test]
fn a_held_member_is_not_ticked_and_the_others_tick_as_without_the_hold() {
    let (free, free_ticked, _) = run(None, false);
    let (held, held_ticked, _) = run(Some((3, 10, 30)), false);
    for (f, (a, b)) in free.iter().zip(&held).enumerate() {
        for m in (0..12).filter(|&m| m != 3) {
            assert_eq!(a[m], b[m], "frame {f}, member {m}");
        }
    }
    // Held from frame 10 to 29: its context stands as it was after frame 9.
    let before = held[9][3].1.clone();
    for (f, frame) in held.iter().enumerate().take(30).skip(10) {
        assert_eq!(frame[3].1, before, "frame {f}: the held member was ticked");
        assert_eq!(frame[3].0, FrameStatus::Asleep, "frame {f}");
    }
    // Released, it walks on from where it stood.
    assert!(held[59][3].1.ticks > before.ticks);
    // While it is held, the frames count exactly its ticks fewer.
    for f in 10..30 {
        let its = u64::from(matches!(free[f][3].0, FrameStatus::Ticked(_)));
        assert_eq!(free_ticked[f], held_ticked[f] + its, "frame {f}");
    }
    assert!((10..30).any(|f| matches!(free[f][3].0, FrameStatus::Ticked(_))));
}

#[test]
fn a_member_held_in_frames_in_place_is_not_ticked_either() {
    let (free, _, _) = run_with(None, false, true);
    let (held, _, _) = run_with(Some((7, 5, 25)), false, true);
    for (f, (a, b)) in free.iter().zip(&held).enumerate() {
        for m in (0..12).filter(|&m| m != 7) {
            assert_eq!(a[m], b[m], "frame {f}, member {m}");
        }
    }
    let before = held[4][7].1.clone();
    for frame in &held[5..25] {
        assert_eq!(frame[7].1, before);
    }
    assert!(held[59][7].1.ticks > before.ticks);
    // In place or not, the same frames.
    assert_eq!(run(None, false).0, free);
}

#[test]
fn an_observed_member_ticks_as_an_unobserved_one() {
    let (plain, _, _) = run(None, false);
    let (observed, _, changes) = run(None, true);
    assert_eq!(plain, observed);
    // It slept as the unobserved did, and its observer saw its passes.
    assert!(observed.iter().any(|f| f[5].0 == FrameStatus::Asleep));
    assert!(changes > 20, "{changes}");
}

#[test]
fn membership_changes_with_each_join_and_leave_and_slots_name_members() {
    let clock = ManualClock::new();
    let mut crowd = Crowd::new(clock);
    let a = crowd.add(walk(0), Walker::default());
    let m1 = crowd.membership();
    let b = crowd.add(walk(1), Walker::default());
    let m2 = crowd.membership();
    assert!(m2 > m1);
    crowd.remove(a).unwrap();
    let m3 = crowd.membership();
    assert!(m3 > m2);
    assert_eq!(crowd.id_at(a.slot()), None);
    assert_eq!(crowd.id_at(b.slot()), Some(b));
    let c = crowd.add(walk(2), Walker::default());
    assert!(crowd.membership() > m3);
    // The slot is reused by another member, with another id.
    assert_eq!(crowd.id_at(a.slot()), Some(c));
    assert_ne!(c, a);
    assert!(!crowd.hold(a));
    // A held member that leaves is no longer held.
    assert!(crowd.hold(b));
    crowd.remove(b).unwrap();
    assert!(!crowd.is_held(b));
    assert!(crowd.set_observer(a, None).is_none());
}

/// The studio watching the crowd (its observer on one member, then on another, a page's
/// view of them kept up to date): every member ticks as in a run nobody watches.
#[test]
fn a_crowd_watched_in_the_studio_ticks_as_one_unwatched() {
    use neurotree::crowd_studio::watched_frame;
    use neurotree::studio::{Studio, StudioOptions};

    let (plain, _, _) = run(None, false);
    let clock = ManualClock::new();
    let mut crowd = Crowd::new(clock.clone()).with_threads(2).unwrap();
    for i in 0..12 {
        crowd.add(walk(i as u64), Walker::default());
    }
    let studio = Studio::serve(StudioOptions::default(), Registry::new).unwrap();
    let mut watch = studio.watch_crowd("walkers");
    let mut frames = Vec::new();
    for f in 0..60 {
        if f == 20 {
            assert!(watch.watch(&mut crowd, "5"));
        }
        let report = watched_frame(&mut crowd, &mut watch).expect("no page stands it still");
        assert_eq!(report.errors, 0);
        frames.push(
            crowd
                .iter()
                .map(|m| {
                    (
                        m.status(),
                        m.context().clone(),
                        m.tree().statuses().to_vec(),
                    )
                })
                .collect::<Vec<_>>(),
        );
        clock.advance(Duration::from_millis(20));
        if f == 0 {
            assert_eq!(watch.watched(), Some("0"), "the first member watched");
        }
    }
    assert_eq!(watch.watched(), Some("5"));
    assert_eq!(frames, plain);
}

/// The member the studio watches leaves and another takes its slot: the newcomer is
/// another agent, so the studio watches the first member again, with its observer there,
/// and none is left thought to be on the newcomer.
#[test]
fn a_member_taking_the_slot_of_the_one_watched_is_not_taken_for_it() {
    use neurotree::crowd_studio::watched_frame;
    use neurotree::studio::{Studio, StudioOptions};

    let mut crowd = Crowd::new(ManualClock::new());
    let ids: Vec<MemberId> = (0..3)
        .map(|i| crowd.add(walk(i), Walker::default()))
        .collect();
    let studio = Studio::serve(StudioOptions::default(), Registry::new).unwrap();
    let mut watch = studio.watch_crowd("walkers");
    watched_frame(&mut crowd, &mut watch).unwrap();
    assert!(watch.watch(&mut crowd, "1"));
    watched_frame(&mut crowd, &mut watch).unwrap();
    crowd.remove(ids[1]).unwrap();
    let newcomer = crowd.add(walk(7), Walker::default());
    assert_eq!(newcomer.slot(), 1);
    watched_frame(&mut crowd, &mut watch).unwrap();
    assert_eq!(watch.watched(), Some("0"));
    assert!(
        crowd.set_observer(newcomer, None).is_none(),
        "no observer on the newcomer"
    );
    assert!(
        crowd.set_observer(ids[0], None).is_some(),
        "the studio's observer on the member watched"
    );
}
