//! Times frames of a crowd of agent trees, for a quick look at how a crowd scales with
//! threads and members outside criterion.
//!
//! `crowd_frames AGENTS THREADS [FRAMES] [INTERVAL] [BLOCK]`: prints milliseconds per
//! frame; with `BLOCK`, members take their phases by blocks of that many slots (the member
//! in slot `s` gets phase `s / BLOCK`), so that the members due together sit together. With
//! `THREADS` 0 it times the plain loop of the many-agents benchmark instead (every tree
//! ticked in turn on this thread), the baseline a crowd's bookkeeping adds to.

use std::time::{Duration, Instant};

use neurotree::ManualClock;
use neurotree_bench::agent_crowd;

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| {
            a.parse()
                .expect("numbers: AGENTS THREADS [FRAMES] [INTERVAL]")
        })
        .collect();
    let (agents, threads) = (args[0], args[1]);
    let frames = args.get(2).copied().unwrap_or(20);
    let interval = args.get(3).copied().unwrap_or(1) as u32;
    let block = args.get(4).copied();
    let clock = ManualClock::new();
    if threads == 0 {
        plain_loop(agents, frames, clock);
        return;
    }
    let mut crowd = agent_crowd(agents, threads, clock.clone());
    for mut member in crowd.iter_mut() {
        member.set_interval(interval);
        if let Some(block) = block {
            let phase = member.id().slot() / block.max(1);
            member.set_phase(phase as u32);
        }
    }
    let mut run = |n: usize| {
        for _ in 0..n {
            clock.advance(Duration::from_millis(16));
            crowd.frame();
        }
    };
    run(2);
    let start = Instant::now();
    run(frames);
    let ms = start.elapsed().as_secs_f64() * 1e3 / frames as f64;
    let block = block.map_or(String::new(), |b| format!(" block {b}"));
    println!("agents {agents} threads {threads} interval {interval}{block}: {ms:.3} ms per frame");
    let state = crowd.iter().next().map_or(0, |m| m.tree().state_bytes());
    println!(
        "bytes per member: {} = slot {} (Tree {}, Agent {}, schedule) + node state {}",
        neurotree_bench::crowd_bytes_per_member(&crowd),
        crowd.slot_bytes(),
        std::mem::size_of::<neurotree::Tree<neurotree_bench::Agent>>(),
        std::mem::size_of::<neurotree_bench::Agent>(),
        state,
    );
}

fn plain_loop(agents: usize, frames: usize, clock: ManualClock) {
    use std::sync::Arc;
    let blueprint = neurotree_bench::agent_tree();
    let shared: Arc<dyn neurotree::Clock> = Arc::new(clock.clone());
    let mut trees: Vec<_> = (0..agents)
        .map(|_| neurotree::Tree::with_shared_clock(Arc::clone(&blueprint), Arc::clone(&shared)))
        .collect();
    let mut contexts: Vec<_> = (0..agents as u32)
        .map(neurotree_bench::Agent::new)
        .collect();
    let mut run = |n: usize| {
        for _ in 0..n {
            clock.advance(Duration::from_millis(16));
            for (tree, ctx) in trees.iter_mut().zip(contexts.iter_mut()) {
                let _ = std::hint::black_box(tree.tick_exactly_once(ctx));
            }
        }
    };
    run(2);
    let start = Instant::now();
    run(frames);
    let ms = start.elapsed().as_secs_f64() * 1e3 / frames as f64;
    println!("agents {agents} plain loop: {ms:.3} ms per frame");
}
