//! What watching a tree costs: the loggers of `neurotree::observe` on a tree whose every
//! node changes status twice or more per tick, writing to `io::sink()` so that only the
//! logging itself is measured. Throughput is in status changes, so time per element is
//! the cost of one change (the tick itself included: compare with `no_observer`).
//!
//! `cargo bench -p neurotree-bench --bench observe`

use std::hint::black_box;
use std::io;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use neurotree::observe::{BtlogWriter, ConsoleLogger, JsonlTrace, Statistics};
use neurotree::{Blueprint, ManualClock, Observer, Registry, Status, StatusChange, Tree};

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
}

criterion_group!(benches, observers);
criterion_main!(benches);
