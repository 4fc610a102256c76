//! Ticking never allocates: a counting allocator watches ticks, halts and resets of
//! tree1111, the many-agents tree and a tree holding every built-in node kind.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use neurotree::{
    Action, Arity, Builder, Condition, CustomNode, CustomSpec, Handle, ManualClock, NodeCtx,
    NodeStatus, Observer, ParallelPolicy, StatefulAction, Status, StatusChange, SubTreeScope, Tree,
};
use neurotree_bench::{agent_tree, tree1111, Agent};

#[path = "../../neurotree-core/tests/support/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::allocations;

#[test]
fn the_counter_sees_allocations() {
    // Guards the guard: without this, a broken counter would make every test below pass.
    assert!(allocations(|| drop(std::hint::black_box(vec![1u8; 64]))) >= 1);
}

#[test]
fn tree1111_ticks_without_allocating() {
    let mut tree = Tree::with_clock(tree1111::<()>(), ManualClock::new());
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    let n = allocations(|| {
        for _ in 0..100 {
            assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
            assert_eq!(tree.tick_exactly_once(&mut ()), Ok(Status::Success));
        }
    });
    assert_eq!(n, 0);
}

#[test]
fn many_agents_tick_without_allocating() {
    let clock = ManualClock::new();
    let shared: Arc<dyn neurotree::Clock> = Arc::new(clock.clone());
    let bp = agent_tree();
    // An agent's Retry gives a reason when it gives up: with the record made up front, no
    // tick allocates, even the first that gives one.
    let mut trees: Vec<_> = (0..100)
        .map(|_| {
            let mut t = Tree::with_shared_clock(Arc::clone(&bp), Arc::clone(&shared));
            t.reserve_failure_record();
            t
        })
        .collect();
    let mut agents: Vec<_> = (0..100).map(Agent::new).collect();
    for (t, a) in trees.iter_mut().zip(agents.iter_mut()) {
        t.tick_once(a).unwrap();
    }
    let n = allocations(|| {
        for _ in 0..50 {
            clock.advance(Duration::from_millis(16));
            for (t, a) in trees.iter_mut().zip(agents.iter_mut()) {
                t.tick_once(a).unwrap();
            }
        }
        trees[0].halt(&mut agents[0]);
    });
    assert_eq!(n, 0);
}

/// The world of the every-node tree: a counter that leaves read and write.
#[derive(Default)]
struct World {
    ticks: u64,
    halts: u64,
    /// Ticks of the custom node, the root's last child.
    custom: u64,
}

struct Even;
impl Condition<World> for Even {
    fn check(&self, h: &Handle<'_, World>) -> bool {
        h.ctx().ticks % 2 == 0
    }
}

struct Count;
impl Action<World> for Count {
    fn tick(&self, h: &mut Handle<'_, World>) -> Status {
        h.ctx_mut().ticks += 1;
        // Writes an existing entry in place: no allocation after the first tick.
        let n = h.ctx().ticks;
        h.set("count", n)
            .map_or(Status::Failure, |_| Status::Success)
    }
}

/// Runs for three ticks.
#[derive(Default)]
struct Walk(u8);
impl StatefulAction<World> for Walk {
    fn on_start(&mut self, _h: &mut Handle<'_, World>) -> Status {
        self.0 = 0;
        Status::Running
    }
    fn on_running(&mut self, _h: &mut Handle<'_, World>) -> Status {
        self.0 += 1;
        if self.0 >= 3 {
            Status::Success
        } else {
            Status::Running
        }
    }
    fn on_halted(&mut self, h: &mut Handle<'_, World>) {
        h.ctx_mut().halts += 1;
    }
}

/// A custom control: ticks its children as a Sequence would.
struct MySequence;
impl CustomNode<World> for MySequence {
    fn tick(&mut self, node: &mut NodeCtx<'_, '_, World>) -> NodeStatus {
        node.ctx().custom += 1;
        for i in 0..node.child_count() {
            match node.tick_child(i) {
                NodeStatus::Success | NodeStatus::Skipped => {}
                other => return other,
            }
        }
        node.reset_children();
        NodeStatus::Success
    }
}

fn every_node() -> Arc<neurotree::Blueprint<World>> {
    let ms = Duration::from_millis;
    let custom = CustomSpec::new(
        "MySequence",
        Arity::AtLeast(1),
        Box::new(|| Box::new(MySequence)),
    );
    let scope = SubTreeScope {
        remap: vec![("inner_count".into(), "count".into())],
        autoremap: true,
        values: vec![],
    };
    Builder::<World>::new()
        .parallel_all("root", -1, |p| {
            p.sequence("seq", |s| {
                s.condition("always", |_: &World| true)
                    .action("count", |w: &mut World| {
                        w.ticks += 1;
                        Status::Success
                    })
                    .stateful("walk", Walk::default)
            })
            .sequence_with_memory("memory", |s| {
                s.always_success("a").stateful("walk", Walk::default)
            })
            .reactive_sequence("reactive", |s| {
                s.condition_node("even", Even)
                    .stateful("walk", Walk::default)
            })
            .fallback("fallback", |f| {
                f.always_failure("no").action_node("count_obj", Count)
            })
            .reactive_fallback("reactive_fb", |f| {
                f.inverter("not_even", |i| i.condition_node("even", Even))
                    .stateful("walk", Walk::default)
            })
            .async_sequence("async_seq", |s| s.always_success("a").always_success("b"))
            .async_fallback("async_fb", |s| s.always_failure("a").always_success("b"))
            .parallel_policy("require_one", ParallelPolicy::RequireOne, |p| {
                p.stateful("walk", Walk::default).sleep("nap", ms(50))
            })
            .parallel_all("all", 1, |p| p.always_success("a").sleep("nap", ms(30)))
            .if_then_else("ite", |i| {
                i.condition_node("even", Even)
                    .stateful("walk", Walk::default)
                    .always_failure("else")
            })
            .while_do_else("wde", |w| {
                w.condition_node("even", Even)
                    .stateful("walk", Walk::default)
                    .always_success("else")
            })
            .try_catch("try", false, |t| {
                t.always_failure("boom").always_success("catch")
            })
            .force_success("fs", |f| f.always_failure("x"))
            .force_failure("ff", |f| f.always_success("x"))
            .repeat("repeat", 3, |r| r.always_success("x"))
            .retry("retry", 3, |r| r.always_failure("x"))
            .keep_running_until_failure("krf", |k| k.condition_node("even", Even))
            .delay("delay", ms(20), |d| d.always_success("x"))
            .timeout("timeout", ms(25), |t| t.stateful("walk", Walk::default))
            .timeout("timeout_fires", ms(25), |t| t.sleep("nap", ms(40)))
            .cooldown("cooldown", ms(40), |c| c.always_success("x"))
            .run_once("once", true, |o| o.always_success("x"))
            .subtree("sub", scope, |s| s.action_node("count_obj", Count))
            .custom("custom", custom, |c| {
                c.always_success("a").condition_node("even", Even)
            })
        })
        .build_shared()
        .unwrap()
}

/// Warms the tree up (the first ticks create the blackboard entries), then counts the
/// allocations of 200 ticks mixing `tick_once`, `tick_exactly_once` and halts, 10 ms apart.
fn run_every_node(tree: &mut Tree<World>, clock: &ManualClock, world: &mut World) -> usize {
    for _ in 0..5 {
        clock.advance(Duration::from_millis(10));
        tree.tick_once(world).unwrap();
    }
    allocations(|| {
        for i in 0..200 {
            clock.advance(Duration::from_millis(10));
            let s = if i % 2 == 0 {
                tree.tick_once(world)
            } else {
                tree.tick_exactly_once(world)
            };
            assert!(s.is_ok());
            if i % 37 == 0 {
                tree.halt(world);
            }
        }
    })
}

#[test]
fn every_node_kind_ticks_and_halts_without_allocating() {
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(every_node(), clock.clone());
    let mut world = World::default();
    let n = run_every_node(&mut tree, &clock, &mut world);
    assert_eq!(n, 0);
    // The run did real work: actions ran, running nodes were halted, the root's last child
    // (the custom node) was reached, and blackboard entries were rewritten in place.
    assert!(world.ticks > 100, "actions ran {} times", world.ticks);
    assert!(world.halts > 10, "{} halts", world.halts);
    assert!(
        world.custom > 40,
        "custom node ticked {} times",
        world.custom
    );
    assert!(tree.blackboard().info("count").unwrap().sequence > 50);
}

/// Counts, per node, the changes into each status. Preallocated: observing allocates nothing.
#[derive(Clone)]
struct Tally(Arc<Mutex<Vec<[u32; 5]>>>);

impl Observer for Tally {
    fn on_status_change(&mut self, c: StatusChange) {
        self.0.lock().unwrap()[c.node.index()][c.to as usize] += 1;
    }
}

/// The same run with an observer attached (the controls' observed loops are compiled apart),
/// and proof that the run exercised the nodes: every node was ticked, the timers fired.
#[test]
fn every_node_kind_observed_without_allocating() {
    let clock = ManualClock::new();
    let bp = every_node();
    let tally = Tally(Arc::new(Mutex::new(vec![[0; 5]; bp.len()])));
    let mut tree = Tree::with_clock(Arc::clone(&bp), clock.clone());
    tree.set_observer(tally.clone());
    let mut world = World::default();
    let n = run_every_node(&mut tree, &clock, &mut world);
    assert_eq!(n, 0);

    let seen = tally.0.lock().unwrap();
    let count = |path: &str, to: NodeStatus| {
        let id = bp.find(path).unwrap_or_else(|| panic!("no node {path}"));
        seen[id.index()][to as usize]
    };
    for id in bp.ids() {
        let [_, running, success, failure, _] = seen[id.index()];
        assert!(
            running + success + failure > 0,
            "{} was never ticked",
            bp.path(id)
        );
    }
    // Delay waits (Running) then lets its child through; a Timeout of 25 ms fires on a
    // 40 ms nap and halts it; Cooldown blocks (Failure) between successes; naps end.
    assert!(count("root/delay", NodeStatus::Running) > 5);
    assert!(count("root/delay", NodeStatus::Success) > 5);
    assert!(count("root/timeout/walk", NodeStatus::Success) > 5);
    assert!(count("root/timeout_fires", NodeStatus::Failure) > 5);
    assert_eq!(count("root/timeout_fires", NodeStatus::Success), 0);
    assert!(count("root/timeout_fires/nap", NodeStatus::Running) > 5);
    assert_eq!(count("root/timeout_fires/nap", NodeStatus::Success), 0);
    assert!(count("root/cooldown", NodeStatus::Success) > 2);
    assert!(count("root/cooldown", NodeStatus::Failure) > 2);
    assert!(count("root/require_one/nap", NodeStatus::Running) > 5);
    assert!(count("root/all/nap", NodeStatus::Success) > 5);
    // Stateful walks complete as well as being halted.
    assert!(count("root/seq/walk", NodeStatus::Success) > 5);
    assert_eq!(count("root/once", NodeStatus::Success), 1);
    assert!(world.halts > 10, "{} halts", world.halts);
}
