//! The reference trees that NeuroTree's benchmarks and allocation tests tick.
//!
//! They are public so that anyone can reproduce the figures in `BENCHMARKS.md` from their own
//! code, and compare with other libraries on the same shapes.

#![forbid(unsafe_code)]

pub mod latency;

use std::sync::Arc;

use neurotree::{Blueprint, Builder, ParallelPolicy, Status};

/// Nodes a tick of [`tree1111`] visits: 1 root, 10 fallbacks, 100 sequences, 1000 leaves.
pub const TREE1111_NODES_PER_TICK: usize = 1111;

/// The shape of `tree1111.xml` (the benchmark tree shared with BehaviorTree.CPP): a root
/// Sequence of 10 Fallbacks, each of 10 Sequences of 10 condition leaves. In each Fallback
/// the first nine Sequences end with a failing leaf and the tenth succeeds, so one tick
/// visits every node and the root succeeds.
pub fn tree1111<C: 'static>() -> Arc<Blueprint<C>> {
    Builder::<C>::new()
        .sequence("root", |mut root| {
            for f in 0..10 {
                root = root.fallback(&format!("fallback_{f}"), |mut fb| {
                    for s in 0..10 {
                        fb = fb.sequence(&format!("sequence_{f}_{s}"), |mut seq| {
                            for leaf in 0..10 {
                                let fail = s < 9 && leaf == 9;
                                seq = if fail {
                                    seq.condition("Fail", |_: &C| false)
                                } else {
                                    seq.condition("Succ", |_: &C| true)
                                };
                            }
                            seq
                        });
                    }
                    fb
                });
            }
            root
        })
        .build_shared()
        .expect("tree1111 is a valid tree")
}

/// `tree1111.xml` as BehaviorTree.CPP's benchmark ships it (from this repository's corpus).
pub const TREE1111_XML: &str = include_str!("../tree1111.xml");

/// The registry that runs [`TREE1111_XML`]: its `Succ` and `Fail` leaves as registered
/// conditions, as a user would register them.
pub fn tree1111_registry<C: 'static>() -> neurotree::Registry<C> {
    let mut registry = neurotree::Registry::new();
    registry
        .register_condition("Succ", vec![], |_| true)
        .expect("a fresh registry has no Succ");
    registry
        .register_condition("Fail", vec![], |_| false)
        .expect("a fresh registry has no Fail");
    registry
}

/// [`tree1111`] as users run it: loaded from [`TREE1111_XML`] with [`tree1111_registry`].
pub fn tree1111_xml<C: 'static>() -> Arc<Blueprint<C>> {
    let registry = tree1111_registry::<C>();
    let mut loader = neurotree::XmlLoader::new(&registry);
    loader
        .load_str(TREE1111_XML, "tree1111.xml")
        .expect("tree1111.xml loads");
    Arc::new(loader.build_main().expect("tree1111.xml builds"))
}

/// The "agent" of the many-agents benchmark: a 50-node game-AI tree over [`Agent`] that
/// uses every family of node (reactive checks, memory sequences, a parallel, decorators and a
/// stateful action), so that an instance carries realistic per-node state.
pub fn agent_tree() -> Arc<Blueprint<Agent>> {
    agent_nodes(Builder::new())
        .build_shared()
        .expect("the agent tree is a valid tree")
}

/// The nodes of [`agent_tree`], added to `b`.
fn agent_nodes(b: Builder<Agent>) -> Builder<Agent> {
    use std::time::Duration;
    b.reactive_fallback("agent", |root| {
        root.sequence("flee", |s| {
            s.condition("threatened", |a: &Agent| a.threat > 70)
                .condition("can_run", |a: &Agent| a.stamina > 10)
                .action("run_away", |a: &mut Agent| {
                    a.x -= 2;
                    a.stamina -= 1;
                    Status::Success
                })
        })
        .reactive_sequence("fight", |s| {
            s.condition("enemy_near", |a: &Agent| a.threat > 30)
                .inverter("not_wounded", |i| {
                    i.condition("wounded", |a: &Agent| a.health < 20)
                })
                .parallel_policy("attack", ParallelPolicy::RequireOne, |p| {
                    p.action("strike", |a: &mut Agent| {
                        a.threat = a.threat.saturating_sub(3);
                        Status::from(a.threat < 40)
                    })
                    .stateful("dodge", Dodge::default)
                    .force_failure("taunt", |f| {
                        f.action("shout", |_: &mut Agent| Status::Success)
                    })
                })
        })
        .sequence_with_memory("forage", |s| {
            s.condition("hungry", |a: &Agent| a.food < 50)
                .fallback("find_food", |f| {
                    f.condition("food_here", |a: &Agent| a.x % 7 == 0)
                        .retry("search", 3, |r| {
                            r.action("step", |a: &mut Agent| {
                                a.x += 1;
                                Status::from(a.x % 7 == 0)
                            })
                        })
                })
                .action("eat", |a: &mut Agent| {
                    a.food += 20;
                    Status::Success
                })
        })
        .sequence("socialize", |s| {
            s.condition("friend_near", |a: &Agent| a.threat < 10)
                .run_once("introduce", true, |r| {
                    r.action("wave", |_: &mut Agent| Status::Success)
                })
                .delay("pause", Duration::from_millis(100), |d| {
                    d.action("chat", |a: &mut Agent| {
                        a.threat += 1;
                        Status::Success
                    })
                })
                .parallel_all("share", 1, |p| {
                    p.action("give", |a: &mut Agent| {
                        a.food = a.food.saturating_sub(5);
                        Status::Success
                    })
                    .action("take", |a: &mut Agent| {
                        a.food += 5;
                        Status::Success
                    })
                    .sleep("linger", Duration::from_millis(50))
                })
        })
        .sequence("patrol", |s| {
            s.fallback("waypoint", |f| {
                f.condition("at_a", |a: &Agent| a.x == 0)
                    .condition("at_b", |a: &Agent| a.x == 10)
                    .force_success("walk", |w| {
                        w.action("walk", |a: &mut Agent| {
                            a.x = (a.x + 1) % 11;
                            Status::Success
                        })
                    })
            })
            .cooldown("look_around_cd", Duration::from_millis(500), |c| {
                c.action("look_around", |a: &mut Agent| {
                    a.threat = (a.threat + 13) % 100;
                    Status::Success
                })
            })
            .timeout("rest_limit", Duration::from_secs(2), |t| {
                t.if_then_else("rest_if_tired", |i| {
                    i.condition("tired", |a: &Agent| a.stamina < 30)
                        .action("rest", |a: &mut Agent| {
                            a.stamina += 5;
                            Status::Success
                        })
                        .always_success("not_tired")
                })
            })
            .repeat("breathe", 2, |r| r.always_success("breath"))
            .action("age", |a: &mut Agent| {
                a.food = a.food.saturating_sub(1);
                a.health = (a.health + 1).min(100);
                Status::Success
            })
            .keep_running_until_failure("idle", |k| {
                k.inverter("idle_once", |i| i.always_success("done"))
            })
        })
    })
}

/// [`agent_tree`] behind a leaf that waits, asleep, for its blackboard entry `alert`:
/// `Sequence(wait_for_alert, agent)`. An alert (a write of `true`) wakes the agent, which
/// runs the agent tree until it completes, then sleeps again. The tree of the
/// `crowd_sleeping` benchmark.
pub fn sleepy_agent_tree() -> Arc<Blueprint<Agent>> {
    Builder::<Agent>::new()
        .sequence("sleepy_agent", |s| {
            agent_nodes(s.stateful("wait_for_alert", || WaitForAlert))
        })
        .build_shared()
        .expect("the sleepy agent tree is a valid tree")
}

/// Waits for the entry `alert` to be true, saying so, so that the tree sleeps meanwhile;
/// then clears it and succeeds.
struct WaitForAlert;

impl WaitForAlert {
    fn check(h: &mut neurotree::Handle<'_, Agent>) -> Status {
        if h.blackboard().get::<bool>("alert").unwrap_or(false) {
            // Written on the tree's own clock, as the tree stamps its writes.
            let (scope, now) = (h.scope(), h.now());
            h.blackboard_mut().replace_in(scope, "alert", false, now);
            return Status::Success;
        }
        h.wake_on("alert");
        Status::Running
    }
}

impl neurotree::StatefulAction<Agent> for WaitForAlert {
    fn on_start(&mut self, h: &mut neurotree::Handle<'_, Agent>) -> Status {
        Self::check(h)
    }
    fn on_running(&mut self, h: &mut neurotree::Handle<'_, Agent>) -> Status {
        Self::check(h)
    }
}

/// A crowd of `agents` instances of [`sleepy_agent_tree`], as [`agent_crowd`] makes one of
/// [`agent_tree`]. Each blackboard holds `alert` (false) from the start, as an entry a port
/// names is declared when its tree is made: an alert then writes an entry that exists, as
/// every alert after a member's first does in a crowd that runs for longer than a bench.
pub fn sleepy_agent_crowd(
    agents: usize,
    threads: usize,
    clock: neurotree::ManualClock,
) -> neurotree::crowd::Crowd<Agent> {
    let blueprint = sleepy_agent_tree();
    let mut crowd = neurotree::crowd::Crowd::new(clock)
        .with_threads(threads)
        .expect("rayon starts its threads");
    for i in 0..agents {
        let clock = Arc::clone(crowd.clock());
        let mut tree = neurotree::Tree::with_shared_clock(Arc::clone(&blueprint), clock);
        tree.blackboard_mut()
            .set("alert", false)
            .expect("a fresh blackboard takes any entry");
        crowd.add_tree(tree, Agent::new(i as u32));
    }
    crowd
}

/// A crowd of `agents` instances of [`agent_tree`] on `clock`, each with its own
/// [`Agent::new`] context, running its frames in a pool of `threads` threads (0: rayon's
/// default, `RAYON_NUM_THREADS` or every core).
pub fn agent_crowd(
    agents: usize,
    threads: usize,
    clock: neurotree::ManualClock,
) -> neurotree::crowd::Crowd<Agent> {
    let blueprint = agent_tree();
    let mut crowd = neurotree::crowd::Crowd::new(clock)
        .with_threads(threads)
        .expect("rayon starts its threads");
    for i in 0..agents {
        crowd.add(Arc::clone(&blueprint), Agent::new(i as u32));
    }
    crowd
}

/// Bytes a member of [`agent_crowd`] takes: its slot in the crowd
/// ([`Crowd::slot_bytes`](neurotree::crowd::Crowd::slot_bytes): the `Tree` struct with its
/// blackboard, the [`Agent`] and its schedule) and its tree's node state on
/// the heap ([`Tree::state_bytes`](neurotree::Tree::state_bytes): statuses, slots, failure
/// bits and the stateful leaves' object pointers in one block, and the failure record once
/// a node gave a reason), for the member that takes the least: what every member takes,
/// whatever its tree did; [`crowd_bytes_per_member_mean`] counts the records others made.
///
/// Every byte such a member holds that grows with the crowd and that these members
/// allocate is counted, but two: the stateful leaves' own objects and the blackboard's
/// entries, which depend on the leaves and on what the program writes. The fields a member
/// leaves unset (an observer, a wake signal, its own pass bound, a reload in progress) take
/// one pointer between them until one is set, and so count as that pointer.
pub fn crowd_bytes_per_member(crowd: &neurotree::crowd::Crowd<Agent>) -> usize {
    let least = crowd.iter().map(|m| m.tree().state_bytes()).min();
    crowd.slot_bytes() + least.unwrap_or(0)
}

/// What [`crowd_bytes_per_member`] counts, over every member, divided by their number:
/// with the record of failure reasons (80 bytes, 144 once a tick noted more than 16 words)
/// of each member whose tree has given a reason, which 17.5 % of the members of a 20,000
/// [`agent_crowd`] have after 30 frames and 25.6 % after 300, and no more after 1,000.
/// Rounded up.
pub fn crowd_bytes_per_member_mean(crowd: &neurotree::crowd::Crowd<Agent>) -> usize {
    let state: usize = crowd.iter().map(|m| m.tree().state_bytes()).sum();
    crowd.slot_bytes() + state.div_ceil(crowd.len().max(1))
}

/// Frames [`wake_each_once`] runs at most for the members to fall asleep again: an
/// alerted sleepy agent stays awake for a few frames.
pub const WAKE_EACH_ONCE_FRAMES: u32 = 64;

/// Alerts every member of a [`sleepy_agent_crowd`] once (a write of `alert`, delivered
/// with [`frame_with`](neurotree::crowd::Crowd::frame_with)), then runs frames, the
/// clock advancing `frame` before each, until every member sleeps again (at most
/// [`WAKE_EACH_ONCE_FRAMES`]). Returns the frames run, the first included.
///
/// What a member's first wake costs is paid once: its tree's first reason for a failure
/// makes the tree's record of reasons, on fresh memory. A crowd that has run for a while
/// has paid it for every member it woke; a benchmark that times the frames after this
/// measures what each later wake costs, as at 100,000 members its alerts, cycling through
/// every member in a few hundred frames, would reach by themselves.
pub fn wake_each_once(
    crowd: &mut neurotree::crowd::Crowd<Agent>,
    clock: &neurotree::ManualClock,
    frame: std::time::Duration,
) -> u32 {
    let ids: Vec<_> = crowd.iter().map(|m| m.id()).collect();
    clock.advance(frame);
    crowd.frame_with(&ids, |mut m| {
        let _ = m.tree_mut().blackboard_mut().set("alert", true);
    });
    let mut frames = 1;
    while crowd.asleep() < crowd.len() && frames < WAKE_EACH_ONCE_FRAMES {
        clock.advance(frame);
        crowd.frame();
        frames += 1;
    }
    frames
}

/// The world state of one agent in [`agent_tree`].
#[derive(Clone, Debug)]
pub struct Agent {
    /// Position on a line.
    pub x: i32,
    /// 0..100: how dangerous the surroundings are.
    pub threat: u32,
    /// 0..100.
    pub health: u32,
    /// 0..100.
    pub stamina: u32,
    /// 0..100.
    pub food: u32,
}

impl Agent {
    /// A varied starting state, so that agents take different branches.
    pub fn new(seed: u32) -> Self {
        Self {
            x: (seed % 11) as i32,
            threat: seed.wrapping_mul(37) % 100,
            health: 20 + seed % 80,
            stamina: 10 + seed % 90,
            food: seed.wrapping_mul(13) % 100,
        }
    }
}

/// A dodge that takes two ticks.
#[derive(Default)]
struct Dodge {
    ticks: u8,
}

impl neurotree::StatefulAction<Agent> for Dodge {
    fn on_start(&mut self, _h: &mut neurotree::Handle<'_, Agent>) -> Status {
        self.ticks = 0;
        Status::Running
    }
    fn on_running(&mut self, h: &mut neurotree::Handle<'_, Agent>) -> Status {
        self.ticks += 1;
        if self.ticks >= 2 {
            h.ctx_mut().stamina = h.ctx().stamina.saturating_sub(1);
            Status::Success
        } else {
            Status::Running
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree::{ManualClock, Tree};

    #[test]
    fn tree1111_visits_every_node_and_succeeds() {
        let bp = tree1111::<()>();
        assert_eq!(bp.len(), TREE1111_NODES_PER_TICK);
        use std::sync::atomic::{AtomicUsize, Ordering};
        struct Count(Arc<AtomicUsize>);
        impl neurotree::Observer for Count {
            fn on_status_change(&mut self, c: neurotree::StatusChange) {
                if c.from == neurotree::NodeStatus::Idle {
                    self.0.fetch_add(1, Ordering::Relaxed);
                }
            }
        }
        let left_idle = Arc::new(AtomicUsize::new(0));
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        tree.set_observer(Count(Arc::clone(&left_idle)));
        assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
        // Every node left Idle exactly once during the tick.
        assert_eq!(left_idle.load(Ordering::Relaxed), TREE1111_NODES_PER_TICK);
        assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
        assert_eq!(
            left_idle.load(Ordering::Relaxed),
            2 * TREE1111_NODES_PER_TICK
        );
    }

    #[test]
    fn waking_each_member_once_runs_every_agent_and_all_sleep_again() {
        const FRAME: std::time::Duration = std::time::Duration::from_millis(16);
        let clock = ManualClock::new();
        // More than a word of 64 slots, on two threads: the alerts are shared out.
        let mut crowd = sleepy_agent_crowd(300, 2, clock.clone());
        for _ in 0..3 {
            clock.advance(FRAME);
            crowd.frame();
        }
        assert_eq!(crowd.asleep(), 300);
        let writes: Vec<u64> = crowd
            .iter()
            .map(|m| m.tree().blackboard().writes())
            .collect();
        let mean_before = crowd_bytes_per_member_mean(&crowd);
        let frames = wake_each_once(&mut crowd, &clock, FRAME);
        assert!(
            frames > 1 && frames < WAKE_EACH_ONCE_FRAMES,
            "{frames} frames"
        );
        assert_eq!(crowd.asleep(), 300);
        // Each blackboard written twice: the alert, and the waiting leaf clearing it once
        // it saw it (the agent tree ran after it).
        for (m, before) in crowd.iter().zip(writes) {
            assert_eq!(m.tree().blackboard().writes(), before + 2);
            assert_eq!(m.tree().blackboard().get::<bool>("alert"), Ok(false));
        }
        // Some agents' trees gave a failure reason and made their record; the first did not.
        let least = crowd_bytes_per_member(&crowd);
        let mean = crowd_bytes_per_member_mean(&crowd);
        assert_eq!(mean_before, least);
        assert!(mean > least, "{mean} against {least}");
    }

    #[test]
    fn a_crowd_member_takes_at_most_400_bytes() {
        let crowd = agent_crowd(4, 1, ManualClock::new());
        let bytes = crowd_bytes_per_member(&crowd);
        assert!(bytes <= 400, "{bytes} bytes per member");
        // The node state is counted: at least a status byte and a failure bit per node, a
        // 32-bit slot per control, and the stateful leaf's object.
        let state = crowd.iter().next().unwrap().tree().state_bytes();
        assert!(state >= 50 + 8 + 4 * 17 + 24, "{state} bytes of node state");
        assert_eq!(bytes, crowd.slot_bytes() + state);
    }

    #[test]
    fn a_crowd_member_takes_at_most_400_bytes_on_average_once_a_quarter_keep_records() {
        const FRAME: std::time::Duration = std::time::Duration::from_millis(16);
        let clock = ManualClock::new();
        let mut crowd = agent_crowd(2_000, 1, clock.clone());
        for _ in 0..300 {
            clock.advance(FRAME);
            crowd.frame();
        }
        let least = crowd_bytes_per_member(&crowd);
        let with_record = crowd
            .iter()
            .filter(|m| m.tree().state_bytes() > least - crowd.slot_bytes())
            .count();
        // About a quarter of the members have given a reason and keep their record.
        assert!((400..600).contains(&with_record), "{with_record} records");
        let mean = crowd_bytes_per_member_mean(&crowd);
        assert!(
            mean > least && mean <= 400,
            "{mean} bytes per member on average"
        );
    }

    #[test]
    fn agent_tree_has_fifty_nodes_and_runs() {
        let bp = agent_tree();
        assert_eq!(bp.len(), 50);
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut agent = Agent::new(7);
        for _ in 0..100 {
            assert!(tree.tick_once(&mut agent).is_ok());
        }
    }
}
