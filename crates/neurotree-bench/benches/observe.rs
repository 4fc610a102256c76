//! What watching a tree costs: the loggers of `neurotree::observe` on a tree whose every
//! node changes status twice or more per tick, writing to `io::sink()` so that only the
//! logging itself is measured. Throughput is in status changes, so time per element is
//! the cost of one change (the tick itself included: compare with `no_observer`).
//!
//! The `nav2_*` benchmarks tick Nav2's navigator (`corpus/nav2/`, leaves mocked as
//! `neurotree run --mock-unknown --mock FollowPath=RUNNING` mocks them, the clock stepping
//! 100 ms a tick as the CLI's does) bare and with a `SqliteLogger` writing to a file: its
//! time per tick is what `--sqlite` adds to a tick.
//!
//! `cargo bench -p neurotree-bench --bench observe`

use std::hint::black_box;
use std::io;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use neurotree::observe::{BtlogWriter, ConsoleLogger, JsonlTrace, SqliteLogger, Statistics};
use neurotree::{
    Blueprint, ManualClock, Observer, Registry, Status, StatusChange, Tree, XmlLoader,
};

/// A sequence of ten leaves that all succeed: each tick, the sequence goes Idle, Running,
/// Success, Idle and each leaf Idle, Success, Idle.
fn blueprint() -> Arc<Blueprint<()>> {
    Blueprint::<()>::builder()
        .sequence("all", |mut s| {
            for i in 0..10 {
                s = s.always_success(&format!("leaf{i}"));
            }
            s
        })
        .build_shared()
        .expect("a valid tree")
}

/// Counts status changes, to size the throughput (and as the cheapest observer).
#[derive(Clone, Default)]
struct Count(Arc<AtomicU64>);

impl Observer for Count {
    fn on_status_change(&mut self, _change: StatusChange) {
        self.0.fetch_add(1, Ordering::Relaxed);
    }
}

fn changes_per_tick() -> u64 {
    let mut tree = Tree::with_clock(blueprint(), ManualClock::new());
    let count = Count::default();
    tree.set_observer(count.clone());
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    count.0.load(Ordering::Relaxed)
}

fn bench_observer<O: Observer + 'static>(
    c: &mut Criterion,
    name: &str,
    make: impl FnOnce(&Tree<()>) -> O,
) {
    let mut group = c.benchmark_group("observe");
    group.throughput(Throughput::Elements(changes_per_tick()));
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(blueprint(), clock.clone());
    let observer = make(&tree);
    tree.set_observer(observer);
    group.bench_function(name, |b| {
        b.iter(|| {
            clock.advance(std::time::Duration::from_micros(1));
            black_box(tree.tick_once(black_box(&mut ())))
        })
    });
    group.finish();
}

fn observers(c: &mut Criterion) {
    let mut group = c.benchmark_group("observe");
    group.throughput(Throughput::Elements(changes_per_tick()));
    let mut tree = Tree::with_clock(blueprint(), ManualClock::new());
    group.bench_function("no_observer", |b| {
        b.iter(|| black_box(tree.tick_once(black_box(&mut ()))))
    });
    group.finish();

    bench_observer(c, "count", |_| Count::default());
    bench_observer(c, "console_sink", |t| {
        ConsoleLogger::new(t.blueprint(), io::sink())
    });
    bench_observer(c, "console_sink_colored", |t| {
        ConsoleLogger::new(t.blueprint(), io::sink()).colored(true)
    });
    bench_observer(c, "jsonl_sink", |t| {
        JsonlTrace::new(t.blueprint(), io::sink())
    });
    bench_observer(c, "statistics", |t| Statistics::new(t.blueprint()));
    bench_observer(c, "btlog_sink", |t| {
        BtlogWriter::new(io::sink(), t, &Registry::new()).expect("writing to a sink")
    });
    // The studio's observer with its server up and no page attached: what `--studio`
    // costs a run nobody watches yet (statuses into shared bytes, a wake-up per tick).
    let dir = tempfile::tempdir().expect("a temporary directory");
    let options = neurotree::studio::StudioOptions {
        root: dir.path().to_path_buf(),
        ..Default::default()
    };
    let studio = neurotree::studio::Studio::serve(options, Registry::new).expect("a studio");
    bench_observer(c, "studio_no_page", |t| studio.attach(t, "bench").0);
}

const NAV2_NAVIGATOR: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../corpus/nav2/navigate_to_pose_w_replanning_and_recovery.xml"
));

/// Nav2's navigator with its leaves mocked (FollowPath running, the rest succeeding), the
/// registry that built it, and its clock.
fn nav2_navigator() -> (Tree<()>, Registry<()>, ManualClock) {
    let mut registry = Registry::new();
    neurotree::nav2::register_controls(&mut registry).expect("a fresh registry");
    let mut loader = XmlLoader::new(&registry)
        .mock_unknown(true)
        .mock("FollowPath", vec![Status::Running]);
    loader
        .load_str(
            NAV2_NAVIGATOR,
            "navigate_to_pose_w_replanning_and_recovery.xml",
        )
        .expect("the corpus file loads");
    let blueprint = loader.build_main().expect("the navigator builds");
    drop(loader);
    let clock = ManualClock::new();
    let tree = Tree::with_clock(Arc::new(blueprint), clock.clone());
    (tree, registry, clock)
}

fn nav2(c: &mut Criterion) {
    let mut group = c.benchmark_group("observe");
    let step = Duration::from_millis(100);
    let (mut tree, _, clock) = nav2_navigator();
    group.bench_function("nav2_no_observer", |b| {
        b.iter(|| {
            clock.advance(step);
            black_box(tree.tick_once(black_box(&mut ())))
        })
    });

    let dir = tempfile::tempdir().expect("a temporary directory");
    // The defaults write every 10 ticks here, when 1 s of the clock has passed; by the count
    // of changes alone, every 1024 changes (some 450 ticks); every tick, as before batches.
    let batches = [
        ("nav2_sqlite", None),
        (
            "nav2_sqlite_1024_changes",
            Some((SqliteLogger::DEFAULT_MAX_CHANGES, Duration::MAX)),
        ),
        (
            "nav2_sqlite_commit_every_tick",
            Some((1, SqliteLogger::DEFAULT_MAX_INTERVAL)),
        ),
    ];
    for (name, batch) in batches {
        let (mut tree, registry, clock) = nav2_navigator();
        let mut log = SqliteLogger::open(
            dir.path().join(format!("{name}.db3")),
            &tree,
            &registry,
            false,
        )
        .expect("a database in the temporary directory");
        if let Some((max_changes, max_interval)) = batch {
            log = log.batch(max_changes, max_interval);
        }
        tree.set_observer(log.clone());
        group.bench_function(name, |b| {
            b.iter(|| {
                clock.advance(step);
                black_box(tree.tick_once(black_box(&mut ())))
            })
        });
        log.flush().expect("the batches are written");
    }
    group.finish();
}

criterion_group!(benches, observers, nav2);
criterion_main!(benches);
