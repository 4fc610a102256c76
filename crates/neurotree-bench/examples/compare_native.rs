//! tree1111 ticked and loaded in-process, measured as `compare/btcpp_native` measures
//! BehaviorTree.CPP, for `compare/native.sh`, which runs both in one run:
//!
//! - tick: `tick_once` on the tree built with the builder (closure conditions) and on the
//!   one loaded from `tree1111.xml` (registered conditions); every tick visits all 1,111
//!   nodes and the root succeeds (checked on every tick);
//! - tick times: 100,000 ticks of the tree loaded from XML, each timed alone: p50, p99,
//!   p99.9 and the slowest;
//! - load: from the XML text to a tickable instance with one registry, and its drop.
//!
//! Each is the fastest of ROUNDS rounds (default 300) of about 2 ms each (the number of
//! ticks or loads per round is doubled from 1 until a round takes 2 ms): on a machine shared
//! with other work, a round that nothing interrupted is what the code costs.
//! `compare_native [ROUNDS]` prints one JSON line per measure.

use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

use neurotree::{ManualClock, Status, Tree, XmlLoader};
use neurotree_bench::latency::TickTimes;
use neurotree_bench::{
    tree1111, tree1111_registry, tree1111_xml, TREE1111_NODES_PER_TICK, TREE1111_XML,
};

/// Ticks timed one by one for the tick-time percentiles, after the timed rounds.
const TIMED_TICKS: usize = 100_000;

/// The fastest time per call of `f`, in seconds, over `rounds` rounds of about 2 ms, and
/// the calls per round.
fn fastest(rounds: u32, mut f: impl FnMut()) -> (f64, u64) {
    let mut n = 1u64;
    loop {
        let start = Instant::now();
        for _ in 0..n {
            f();
        }
        if start.elapsed().as_secs_f64() >= 0.002 || n >= 1 << 30 {
            break;
        }
        n *= 2;
    }
    let mut best = f64::INFINITY;
    for _ in 0..rounds {
        let start = Instant::now();
        for _ in 0..n {
            f();
        }
        best = best.min(start.elapsed().as_secs_f64() / n as f64);
    }
    (best, n)
}

fn main() {
    let rounds: u32 = std::env::args()
        .nth(1)
        .and_then(|n| n.parse().ok())
        .unwrap_or(300);

    let registry = tree1111_registry::<()>();
    let (per_load, n) = fastest(rounds, || {
        let mut loader = XmlLoader::new(&registry);
        loader
            .load_str(black_box(TREE1111_XML), "tree1111.xml")
            .expect("tree1111.xml loads");
        let blueprint = loader.build_main().expect("tree1111.xml builds");
        black_box(Tree::with_clock(Arc::new(blueprint), ManualClock::new()));
    });
    println!(
        "{{\"name\":\"neurotree/load\",\"per_round\":{n},\"us_per_load\":{:.3}}}",
        per_load * 1e6
    );

    for (name, blueprint) in [("builder", tree1111::<()>()), ("xml", tree1111_xml())] {
        let mut tree = Tree::with_clock(blueprint, ManualClock::new());
        let (per_tick, n) = fastest(rounds, || {
            let status = tree.tick_once(black_box(&mut ()));
            assert_eq!(status, Ok(Status::Success), "the root of tree1111 succeeds");
        });
        let ns = per_tick * 1e9;
        println!(
            "{{\"name\":\"neurotree/tick/{name}\",\"per_round\":{n},\"ns_per_tick\":{ns:.1},\"ns_per_node\":{:.3}}}",
            ns / TREE1111_NODES_PER_TICK as f64
        );
        if name == "xml" {
            let mut times = TickTimes::with_capacity(TIMED_TICKS);
            for _ in 0..TIMED_TICKS {
                let status = times.time(|| tree.tick_once(black_box(&mut ())));
                assert_eq!(status, Ok(Status::Success), "the root of tree1111 succeeds");
            }
            let p = times.percentiles();
            println!(
                "{{\"name\":\"neurotree/tick_times/xml\",\"ticks\":{},\"p50_ns\":{},\"p99_ns\":{},\"p999_ns\":{},\"max_ns\":{}}}",
                p.ticks, p.p50, p.p99, p.p999, p.max
            );
        }
    }
}
