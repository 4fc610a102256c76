//! Tick benchmarks: tree1111 (BehaviorTree.CPP's benchmark shape) and many agents.
//!
//! `cargo bench -p neurotree-bench --bench tick`

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use neurotree::{ManualClock, Status, Tree};
use neurotree_bench::{
    agent_tree, tree1111, tree1111_registry, tree1111_xml, Agent, TREE1111_NODES_PER_TICK,
    TREE1111_XML,
};

/// tree1111 built with the builder (closure conditions), then loaded from XML (registered
/// conditions), as users run it.
fn tick_tree1111(c: &mut Criterion) {
    let mut group = c.benchmark_group("tree1111");
    group.throughput(Throughput::Elements(TREE1111_NODES_PER_TICK as u64));
    for (name, blueprint) in [
        ("tick_once", tree1111::<()>()),
        ("xml/tick_once", tree1111_xml()),
    ] {
        let mut tree = Tree::with_clock(blueprint, ManualClock::new());
        group.bench_function(name, |b| {
            b.iter(|| {
                let s = tree.tick_once(black_box(&mut ()));
                debug_assert_eq!(s, Ok(Status::Success));
                s
            })
        });
    }
    group.finish();
}

fn many_agents(c: &mut Criterion) {
    const AGENTS: usize = 100_000;
    let blueprint = agent_tree();
    let clock = ManualClock::new();
    let shared: std::sync::Arc<dyn neurotree::Clock> = std::sync::Arc::new(clock.clone());
    let mut group = c.benchmark_group("many_agents");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(8));
    group.throughput(Throughput::Elements(AGENTS as u64));
    group.bench_function("instantiate_100k", |b| {
        b.iter_batched(
            || (),
            |_| {
                (0..AGENTS)
                    .map(|_| Tree::with_shared_clock(blueprint.clone(), shared.clone()))
                    .collect::<Vec<_>>()
            },
            BatchSize::PerIteration,
        )
    });
    let mut trees: Vec<Tree<Agent>> = (0..AGENTS)
        .map(|_| Tree::with_shared_clock(blueprint.clone(), shared.clone()))
        .collect();
    let mut agents: Vec<Agent> = (0..AGENTS as u32).map(Agent::new).collect();
    // One pass per agent per frame (`tick_exactly_once`), as a game loop ticks its agents.
    group.bench_function("frame_100k", |b| {
        b.iter(|| {
            clock.advance(Duration::from_millis(16));
            for (tree, agent) in trees.iter_mut().zip(agents.iter_mut()) {
                let _ = black_box(tree.tick_exactly_once(agent));
            }
        })
    });
    group.finish();
}

/// From XML text to a tickable instance: parse, check, build the blueprint, instantiate,
/// and drop it again (so that each iteration starts from the same heap); `drop/tree1111`
/// times the drop alone.
fn load_tree1111(c: &mut Criterion) {
    let registry = tree1111_registry::<()>();
    let load = || {
        let mut loader = neurotree::XmlLoader::new(&registry);
        loader
            .load_str(black_box(TREE1111_XML), "tree1111.xml")
            .unwrap();
        let bp = loader.build_main().unwrap();
        Tree::with_clock(std::sync::Arc::new(bp), ManualClock::new())
    };
    c.bench_function("load/tree1111", |b| b.iter(load));
    c.bench_function("drop/tree1111", |b| {
        b.iter_batched(load, drop, criterion::BatchSize::SmallInput)
    });
}

/// Saving tree1111's state, restoring it into a fresh instance, and reloading the same
/// blueprint under a running instance: what checkpoints, resumes and `--watch` cost.
fn state_tree1111(c: &mut Criterion) {
    let blueprint = tree1111_xml::<()>();
    let mut tree = Tree::with_clock(blueprint.clone(), ManualClock::new());
    tree.tick_once(&mut ()).unwrap();
    let saved = tree.save_state().unwrap();
    c.bench_function("state/save/tree1111", |b| {
        b.iter(|| black_box(&tree).save_state().unwrap())
    });
    let mut fresh = Tree::with_clock(blueprint.clone(), ManualClock::new());
    c.bench_function("state/restore/tree1111", |b| {
        b.iter(|| fresh.restore_state(black_box(&saved)).unwrap())
    });
    c.bench_function("state/reload/tree1111", |b| {
        b.iter(|| tree.reload(black_box(blueprint.clone()), &mut ()).unwrap())
    });
}

criterion_group!(
    benches,
    tick_tree1111,
    many_agents,
    load_tree1111,
    state_tree1111
);
criterion_main!(benches);
