//! Crowd benchmarks: 1,000,000 instances of the 50-node agent tree, one frame each
//! iteration, on one thread and on every core, and with only one agent in eight due (by
//! intervals set once, with phases by slot or by blocks of slots, and by a level-of-detail
//! hook).
//!
//! `cargo bench -p neurotree-bench --bench crowd` (`RAYON_NUM_THREADS` does not apply: the
//! pools are sized here).

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use neurotree::ManualClock;
use neurotree_bench::{agent_crowd, crowd_bytes_per_member};

const AGENTS: usize = 1_000_000;

fn crowd(c: &mut Criterion) {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut group = c.benchmark_group("crowd");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(10))
        .throughput(Throughput::Elements(AGENTS as u64));
    let mut threads = vec![1];
    if cores > 1 {
        threads.push(cores);
    }
    for threads in threads {
        let clock = ManualClock::new();
        let mut crowd = agent_crowd(AGENTS, threads, clock.clone());
        if threads == 1 {
            eprintln!("bytes per member: {}", crowd_bytes_per_member(&crowd));
        }
        group.bench_function(format!("frame_1m/{threads}_threads"), |b| {
            b.iter(|| {
                clock.advance(Duration::from_millis(16));
                crowd.frame()
            })
        });
        // Every agent ticks every 8th frame, the phases spreading them: 125,000 per frame.
        // Set once, the intervals leave the trees of the agents not due untouched; chosen
        // by a level-of-detail hook, every agent's context is read every frame.
        for mut member in crowd.iter_mut() {
            member.set_interval(8);
        }
        group.bench_function(format!("frame_1m_eighth_due/{threads}_threads"), |b| {
            b.iter(|| {
                clock.advance(Duration::from_millis(16));
                let report = crowd.frame();
                debug_assert_eq!(report.ticked, AGENTS as u64 / 8);
                report
            })
        });
        // The same with phases by blocks of 1,024 slots: the members due together sit
        // together in memory.
        for mut member in crowd.iter_mut() {
            let phase = member.id().slot() / 1024;
            member.set_phase(phase as u32);
        }
        group.bench_function(
            format!("frame_1m_eighth_due_blocks/{threads}_threads"),
            |b| {
                b.iter(|| {
                    clock.advance(Duration::from_millis(16));
                    let report = crowd.frame();
                    debug_assert_eq!(report.ticked, AGENTS as u64 / 8);
                    report
                })
            },
        );
        crowd.set_level_of_detail(|_| 8);
        group.bench_function(format!("frame_1m_eighth_due_lod/{threads}_threads"), |b| {
            b.iter(|| {
                clock.advance(Duration::from_millis(16));
                let report = crowd.frame();
                debug_assert_eq!(report.ticked, AGENTS as u64 / 8);
                report
            })
        });
    }
    group.finish();
}

criterion_group!(benches, crowd);
criterion_main!(benches);
