//! tree1111 ticked and loaded in-process, measured as `compare/btcpp_native` measures
//! BehaviorTree.CPP, for `compare/native.sh`, which runs both in one run:
//!
//! - tick: `tick_once` on the tree built with the builder (closure conditions) and on the
//!   one loaded from `tree1111.xml` (registered conditions); every tick visits all 1,111
//!   nodes and the root succeeds (checked on every tick);
//! - load: from the XML text to a tickable instance with one registry, and its drop.
//!
//! Each is the best of 5 timed rounds after one warm-up round.
//! `compare_native [TICKS] [LOADS]` prints one JSON line per measure.

use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

use neurotree::{ManualClock, Status, Tree, XmlLoader};
use neurotree_bench::{
    tree1111, tree1111_registry, tree1111_xml, TREE1111_NODES_PER_TICK, TREE1111_XML,
};

/// The best time per iteration, in seconds, of 5 rounds of `n` iterations of `f`, after a
/// warm-up round of `n / 10 + 1`.
fn best_of_5(n: u64, mut f: impl FnMut()) -> f64 {
    let mut best = f64::INFINITY;
    for round in 0..6 {
        let count = if round == 0 { n / 10 + 1 } else { n };
        let start = Instant::now();
        for _ in 0..count {
            f();
        }
        let per = start.elapsed().as_secs_f64() / count as f64;
        if round > 0 && per < best {
            best = per;
        }
    }
    best
}

fn main() {
    let mut args = std::env::args().skip(1);
    let ticks: u64 = args.next().and_then(|n| n.parse().ok()).unwrap_or(20_000);
    let loads: u64 = args.next().and_then(|n| n.parse().ok()).unwrap_or(200);

    let registry = tree1111_registry::<()>();
    let per_load = best_of_5(loads, || {
        let mut loader = XmlLoader::new(&registry);
        loader
            .load_str(black_box(TREE1111_XML), "tree1111.xml")
            .expect("tree1111.xml loads");
        let blueprint = loader.build_main().expect("tree1111.xml builds");
        black_box(Tree::with_clock(Arc::new(blueprint), ManualClock::new()));
    });
    println!(
        "{{\"name\":\"neurotree/load\",\"loads\":{loads},\"us_per_load\":{:.3}}}",
        per_load * 1e6
    );

    for (name, blueprint) in [("builder", tree1111::<()>()), ("xml", tree1111_xml())] {
        let mut tree = Tree::with_clock(blueprint, ManualClock::new());
        let per_tick = best_of_5(ticks, || {
            let status = tree.tick_once(black_box(&mut ()));
            assert_eq!(status, Ok(Status::Success), "the root of tree1111 succeeds");
        });
        let ns = per_tick * 1e9;
        println!(
            "{{\"name\":\"neurotree/tick/{name}\",\"ticks\":{ticks},\"ns_per_tick\":{ns:.1},\"ns_per_node\":{:.3}}}",
            ns / TREE1111_NODES_PER_TICK as f64
        );
    }
}
