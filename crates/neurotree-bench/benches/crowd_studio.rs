//! What the studio costs a crowd: a frame of 100,000 agents run plainly, and with the studio
//! watching one of them (`CrowdWatch` around the frame, the studio's observer on the agent
//! watched). Both crowds are the `crowd_sleeping` one: every agent waits, asleep, for an
//! alert, and 1% of them are alerted each frame.
//!
//! `cargo bench -p neurotree-bench --bench crowd_studio`

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use neurotree::crowd::{Crowd, MemberId};
use neurotree::crowd_studio::watched_frame;
use neurotree::studio::{Studio, StudioOptions};
use neurotree::{ManualClock, Registry};
use neurotree_bench::{sleepy_agent_crowd, Agent};

const AGENTS: usize = 100_000;

/// Alerts every 100th agent, from a phase that moves each frame.
fn alert(crowd: &mut Crowd<Agent>, ids: &[MemberId], frame: usize) {
    for id in ids.iter().skip(frame % 100).step_by(100) {
        if let Some(tree) = crowd.member_tree_mut(*id) {
            let _ = tree.blackboard_mut().set("alert", true);
        }
    }
}

fn crowd_studio(c: &mut Criterion) {
    let mut group = c.benchmark_group("crowd_studio");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(10))
        .throughput(Throughput::Elements(AGENTS as u64));
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());

    let clock = ManualClock::new();
    let mut crowd = sleepy_agent_crowd(AGENTS, threads, clock.clone());
    let ids: Vec<MemberId> = crowd.iter().map(|m| m.id()).collect();
    let mut frame = 0;
    group.bench_function("frame_100k_sleeping/plain", |b| {
        b.iter(|| {
            alert(&mut crowd, &ids, frame);
            frame += 1;
            clock.advance(Duration::from_millis(16));
            crowd.frame()
        })
    });

    let clock = ManualClock::new();
    let mut crowd = sleepy_agent_crowd(AGENTS, threads, clock.clone());
    let studio = Studio::serve(StudioOptions::default(), Registry::new).expect("the studio");
    let mut watch = studio.watch_crowd("agents");
    let mut frame = 0;
    group.bench_function("frame_100k_sleeping/watched", |b| {
        b.iter(|| {
            alert(&mut crowd, &ids, frame);
            frame += 1;
            clock.advance(Duration::from_millis(16));
            watched_frame(&mut crowd, &mut watch)
        })
    });
    group.finish();
}

criterion_group!(benches, crowd_studio);
criterion_main!(benches);
