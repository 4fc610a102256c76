//! tree1111 benchmark for the `bonsai-bt` crate.
//!
//! Builds the tree of `tree1111.xml` (root Sequence -> 10 Fallbacks -> 10
//! Sequences -> 10 leaves) as a `bonsai_bt::Behavior` and times `BT::tick`.
//! The XML only contains `<Sequence>`, `<Fallback>`, `<Succ/>` and `<Fail/>`
//! tags, so a tiny tag scanner is enough to read it (no XML dependency).
//!
//! Semantics of bonsai-bt 0.14 (src/sequence.rs, src/bt.rs):
//! * `Sequence` / `Select` (the default, `memory(true)`) resume the running
//!   child on the next tick, like BT.CPP's `Sequence` / `Fallback`.
//!   `.memory(false)` gives reactive versions that restart from the first
//!   child every tick. With no RUNNING leaf (the case here) both variants
//!   visit exactly the same nodes.
//! * A memory `Sequence` only moves past a successful child within the same
//!   tick for *update* events; the only event type, `Event`, is always an
//!   update event (`Event::zero_dt_args()` = dt 0.0), so one tick walks the
//!   whole tree.
//! * Each time a composite moves to a child it does
//!   `State::new(child.clone())`: the child's `Behavior` (a whole subtree for
//!   composite children, with its `Vec`s) is cloned into the cursor. That
//!   per-visit cloning (and its heap allocations) is part of every tick and
//!   therefore part of the measurement.
//! * Once the root returns SUCCESS/FAILURE, `BT` is "finished" and `tick`
//!   returns `None` until `reset_bt()` is called. `reset_bt()` deep-clones the
//!   initial `Behavior` and rebuilds the state, so it is done outside the
//!   timed section: every tick is timed individually with `Instant` (clock
//!   overhead is ~tens of ns against a tick of tens of µs). The cost of
//!   `reset_bt()` is reported on stderr.
//!
//! Usage: bonsai-tree1111 [TREE_XML] [TICKS]
//! (TREE_XML defaults to $TREE1111, then to the repository's corpus/bench/tree1111.xml.)

use std::hint::black_box;
use std::time::{Duration, Instant};

use bonsai_bt::{ActionArgs, Behavior, Event, Failure, Select, Sequence, Status, Success, BT};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Leaf {
    Succ,
    Fail,
}

/// Node count of the tree (controls + leaves) and number of leaves.
#[derive(Default, Debug)]
struct Counts {
    nodes: usize,
    leaves: usize,
}

/// Parses the `<BehaviorTree>` body of tree1111.xml into a `Behavior`.
fn parse_tree(xml: &str, memory: bool, counts: &mut Counts) -> Behavior<Leaf> {
    // Collect tags as (name, kind) with kind: 0 = open, 1 = close, 2 = self-closing.
    let mut tags: Vec<(String, u8)> = Vec::new();
    let mut rest = xml;
    while let Some(start) = rest.find('<') {
        let end = rest[start..].find('>').expect("unterminated tag") + start;
        let body = rest[start + 1..end].trim();
        rest = &rest[end + 1..];
        if body.starts_with('?') || body.starts_with('!') {
            continue;
        }
        let (kind, body) = if let Some(b) = body.strip_prefix('/') {
            (1u8, b)
        } else if let Some(b) = body.strip_suffix('/') {
            (2u8, b)
        } else {
            (0u8, body)
        };
        let name = body.split_whitespace().next().unwrap_or("").to_string();
        tags.push((name, kind));
    }
    // Skip <root ...> and <BehaviorTree ...>; the tree is the first node after.
    let pos = tags
        .iter()
        .position(|(n, k)| n == "BehaviorTree" && *k == 0)
        .expect("no <BehaviorTree> element")
        + 1;
    let mut i = pos;
    let tree = build(&tags, &mut i, memory, counts);
    assert_eq!(tags[i].0, "BehaviorTree", "expected a single root node");
    tree
}

fn build(
    tags: &[(String, u8)],
    i: &mut usize,
    memory: bool,
    counts: &mut Counts,
) -> Behavior<Leaf> {
    let (name, kind) = (&tags[*i].0, tags[*i].1);
    *i += 1;
    counts.nodes += 1;
    match (name.as_str(), kind) {
        ("Succ", 2) => {
            counts.leaves += 1;
            Behavior::Action(Leaf::Succ)
        }
        ("Fail", 2) => {
            counts.leaves += 1;
            Behavior::Action(Leaf::Fail)
        }
        (ctrl @ ("Sequence" | "Fallback"), 0) => {
            let mut children = Vec::new();
            while tags[*i].1 != 1 {
                children.push(build(tags, i, memory, counts));
            }
            assert_eq!(&tags[*i].0, ctrl, "mismatched closing tag");
            *i += 1;
            assert!(!children.is_empty(), "empty {ctrl}");
            let node = if ctrl == "Sequence" {
                Sequence(children)
            } else {
                Select(children)
            };
            node.memory(memory)
        }
        other => panic!("unsupported node in tree1111.xml: {other:?}"),
    }
}

/// Action handler: `Succ` -> SUCCESS, `Fail` -> FAILURE (zero time used).
#[inline]
fn leaf(args: ActionArgs<Event, Leaf>, visited: &mut u64) -> (Status, f64) {
    *visited += 1;
    match *args.action {
        Leaf::Succ => (Success, args.dt),
        Leaf::Fail => (Failure, args.dt),
    }
}

struct Measure {
    ticks: u64,
    tick_time: Duration,
    reset_time: Duration,
}

fn run(tree: &Behavior<Leaf>, leaves: u64, warmup: u64, ticks: u64) -> Measure {
    let mut bt = BT::new(tree.clone(), 0u64);
    let ev = Event::zero_dt_args();
    let mut handler = |args: ActionArgs<Event, Leaf>, bb: &mut u64| leaf(args, bb);

    // Warm-up + check: every tick returns SUCCESS and runs every leaf.
    for _ in 0..warmup {
        *bt.blackboard_mut() = 0;
        let r = bt.tick(&ev, &mut handler);
        match r {
            Some((Success, _)) => {}
            other => {
                eprintln!("bonsai: root returned {other:?}, expected SUCCESS");
                std::process::exit(1);
            }
        }
        if *bt.blackboard() != leaves {
            eprintln!(
                "bonsai: visited {} leaves, expected {leaves}",
                bt.blackboard()
            );
            std::process::exit(1);
        }
        bt.reset_bt();
    }

    *bt.blackboard_mut() = 0;
    let mut tick_time = Duration::ZERO;
    let mut reset_time = Duration::ZERO;
    for _ in 0..ticks {
        let t0 = Instant::now();
        let r = black_box(bt.tick(black_box(&ev), &mut handler));
        let t1 = Instant::now();
        if !matches!(r, Some((Success, _))) {
            eprintln!("bonsai: root returned {r:?}, expected SUCCESS");
            std::process::exit(1);
        }
        bt.reset_bt();
        let t2 = Instant::now();
        tick_time += t1 - t0;
        reset_time += t2 - t1;
    }
    if *bt.blackboard() != leaves * ticks {
        eprintln!("bonsai: wrong number of leaf visits");
        std::process::exit(1);
    }
    Measure {
        ticks,
        tick_time,
        reset_time,
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .or_else(|| std::env::var("TREE1111").ok())
        .unwrap_or_else(|| {
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../../../../corpus/bench/tree1111.xml"
            )
            .to_string()
        });
    let ticks: u64 = args
        .next()
        .map(|s| s.parse().expect("TICKS must be an integer"))
        .unwrap_or(20_000);
    let xml = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        eprintln!("bonsai: cannot read {path}: {e}");
        std::process::exit(2);
    });

    let mut counts = Counts::default();
    let tree_mem = parse_tree(&xml, true, &mut counts);
    let mut c2 = Counts::default();
    let tree_reactive = parse_tree(&xml, false, &mut c2);
    let nodes = counts.nodes;
    let leaves = counts.leaves as u64;

    let warmup = (ticks / 10).max(100);
    // Reported variant: default (memory) Sequence/Select, the counterpart of
    // BT.CPP's Sequence/Fallback. The reactive variant goes to stderr.
    let m = run(&tree_mem, leaves, warmup, ticks);
    let r = run(&tree_reactive, leaves, warmup, ticks);

    let per_tick = |d: Duration, n: u64| d.as_nanos() as f64 / n as f64;
    let ns_tick = per_tick(m.tick_time, m.ticks);
    eprintln!(
        "bonsai: memory(true):  {:.0} ns/tick ({:.2} ns/node); reset_bt() {:.0} ns",
        ns_tick,
        ns_tick / nodes as f64,
        per_tick(m.reset_time, m.ticks)
    );
    let rt = per_tick(r.tick_time, r.ticks);
    eprintln!(
        "bonsai: memory(false): {:.0} ns/tick ({:.2} ns/node); reset_bt() {:.0} ns",
        rt,
        rt / nodes as f64,
        per_tick(r.reset_time, r.ticks)
    );
    println!(
        "{{\"name\":\"bonsai-bt\",\"ticks\":{},\"ns_per_tick\":{:.1},\"nodes_per_tick\":{},\"ns_per_node\":{:.3}}}",
        m.ticks,
        ns_tick,
        nodes,
        ns_tick / nodes as f64
    );
}
