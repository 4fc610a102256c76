//! Ticks tree1111 a given number of times, for instruction counts under callgrind, which
//! are repeatable where wall-clock times are not:
//!
//! ```sh
//! cargo build --release -p neurotree-bench --example tick_loop
//! valgrind --tool=callgrind target/release/examples/tick_loop xml 110
//! valgrind --tool=callgrind target/release/examples/tick_loop xml 10
//! ```
//!
//! The difference of the two totals divided by 100 is the cost of one tick. `builder`
//! ticks the tree built in Rust (closure conditions), `xml` the one loaded from
//! `tree1111.xml` (registered conditions). `load N` loads `tree1111.xml` into a tickable
//! instance N times with one registry, as the `load/tree1111` benchmark does: the
//! difference of `load 11` and `load 1`, divided by 10, is the cost of one load.

use std::hint::black_box;

use std::sync::Arc;

use neurotree::{ManualClock, Status, Tree, XmlLoader};
use neurotree_bench::{tree1111, tree1111_registry, tree1111_xml, TREE1111_XML};

fn main() {
    let mut args = std::env::args().skip(1);
    let which = args.next().unwrap_or_else(|| "builder".into());
    let ticks: u32 = args.next().and_then(|n| n.parse().ok()).unwrap_or(100);
    if which == "load" {
        let registry = tree1111_registry::<()>();
        for _ in 0..ticks {
            let mut loader = XmlLoader::new(&registry);
            loader
                .load_str(black_box(TREE1111_XML), "tree1111.xml")
                .expect("tree1111.xml loads");
            let blueprint = loader.build_main().expect("tree1111.xml builds");
            black_box(Tree::with_clock(Arc::new(blueprint), ManualClock::new()));
        }
        return;
    }
    let blueprint = match which.as_str() {
        "builder" => tree1111::<()>(),
        "xml" => tree1111_xml(),
        other => {
            eprintln!("tick_loop: `{other}` is not a tree; use builder, xml or load");
            std::process::exit(2);
        }
    };
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    for _ in 0..ticks {
        let status = black_box(tree.tick_once(black_box(&mut ())));
        assert_eq!(status, Ok(Status::Success));
    }
}
