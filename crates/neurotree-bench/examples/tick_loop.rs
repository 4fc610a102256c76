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
//! `tree1111.xml` (registered conditions).

use std::hint::black_box;

use neurotree::{ManualClock, Status, Tree};
use neurotree_bench::{tree1111, tree1111_xml};

fn main() {
    let mut args = std::env::args().skip(1);
    let which = args.next().unwrap_or_else(|| "builder".into());
    let ticks: u32 = args.next().and_then(|n| n.parse().ok()).unwrap_or(100);
    let blueprint = match which.as_str() {
        "builder" => tree1111::<()>(),
        "xml" => tree1111_xml(),
        other => {
            eprintln!("tick_loop: `{other}` is not a tree; use builder or xml");
            std::process::exit(2);
        }
    };
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    for _ in 0..ticks {
        let status = black_box(tree.tick_once(black_box(&mut ())));
        assert_eq!(status, Ok(Status::Success));
    }
}
