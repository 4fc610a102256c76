//! The random cases of the differential test: seeded trees of the built-in nodes that
//! NeuroTree and BehaviorTree.CPP 4.8.2 both have, written as XML, and the steps to run.

use std::collections::BTreeMap;
use std::fmt::Write as _;

/// SplitMix64: small, seedable, and the same on every platform and version.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// In `lo..=hi`.
    fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next() % (hi - lo + 1) as u64) as i64
    }
    /// An index into `weights`, drawn in proportion to them.
    fn weighted(&mut self, weights: &[u32]) -> usize {
        let total: u32 = weights.iter().sum();
        let mut x = (self.next() % u64::from(total)) as u32;
        for (i, w) in weights.iter().enumerate() {
            if x < *w {
                return i;
            }
            x -= w;
        }
        unreachable!("x < total")
    }
}

/// A tree: XML element name, attributes, children; a scripted leaf has its script.
#[derive(Clone, Debug)]
struct Spec {
    tag: &'static str,
    attrs: Vec<(&'static str, String)>,
    script: Option<String>,
    children: Vec<Spec>,
}

impl Spec {
    fn node(tag: &'static str, children: Vec<Spec>) -> Self {
        Spec {
            tag,
            attrs: Vec::new(),
            script: None,
            children,
        }
    }
    fn attr(mut self, name: &'static str, value: impl ToString) -> Self {
        self.attrs.push((name, value.to_string()));
        self
    }
}

fn script(rng: &mut Rng, running: bool) -> String {
    let len = rng.range(1, 4);
    (0..len)
        .map(
            |_| match rng.weighted(&[2, 2, if running { 3 } else { 0 }]) {
                0 => 'S',
                1 => 'F',
                _ => 'R',
            },
        )
        .collect()
}

fn leaf(rng: &mut Rng) -> Spec {
    let (tag, script) = match rng.weighted(&[6, 2, 2, 1, 1]) {
        0 => ("Act", Some(script(rng, true))),
        1 => ("Sync", Some(script(rng, false))),
        2 => ("Cond", Some(script(rng, false))),
        3 => ("AlwaysSuccess", None),
        _ => ("AlwaysFailure", None),
    };
    Spec {
        script,
        ..Spec::node(tag, Vec::new())
    }
}

fn children(rng: &mut Rng, depth: u32, lo: i64, hi: i64) -> Vec<Spec> {
    (0..rng.range(lo, hi))
        .map(|_| tree(rng, depth + 1))
        .collect()
}

/// A random tree: depth at most 4, at most 4 children a node.
fn tree(rng: &mut Rng, depth: u32) -> Spec {
    if depth >= 4 || (depth > 0 && rng.weighted(&[2, 3]) == 0) {
        return leaf(rng);
    }
    match rng.weighted(&[7, 2, 1, 2, 6]) {
        0 => {
            let tags = [
                "Sequence",
                "SequenceWithMemory",
                "ReactiveSequence",
                "Fallback",
                "ReactiveFallback",
                "AsyncSequence",
                "AsyncFallback",
            ];
            let tag = tags[rng.range(0, tags.len() as i64 - 1) as usize];
            Spec::node(tag, children(rng, depth, 1, 4))
        }
        1 => {
            let kids = children(rng, depth, 1, 4);
            let n = kids.len() as i64;
            // Thresholds BehaviorTree.CPP accepts: resolved, at most the children.
            let success = rng.range(-(n + 1), n);
            let failure = rng.range(-(n + 1), n);
            Spec::node("Parallel", kids)
                .attr("success_count", success)
                .attr("failure_count", failure)
        }
        2 => {
            let kids = children(rng, depth, 1, 4);
            let n = kids.len() as i64;
            let max_failures = rng.range(-(n + 1), n);
            Spec::node("ParallelAll", kids).attr("max_failures", max_failures)
        }
        3 => {
            let tag = ["IfThenElse", "WhileDoElse"][rng.range(0, 1) as usize];
            Spec::node(tag, children(rng, depth, 2, 3))
        }
        _ => {
            let kid = vec![tree(rng, depth + 1)];
            // -1 (forever) now and then.
            let count = |rng: &mut Rng| {
                if rng.weighted(&[1, 9]) == 0 {
                    -1
                } else {
                    rng.range(0, 3)
                }
            };
            match rng.range(0, 6) {
                0 => Spec::node("Inverter", kid),
                1 => Spec::node("ForceSuccess", kid),
                2 => Spec::node("ForceFailure", kid),
                3 => Spec::node("Repeat", kid).attr("num_cycles", count(rng)),
                4 => Spec::node("RetryUntilSuccessful", kid).attr("num_attempts", count(rng)),
                5 => Spec::node("KeepRunningUntilFailure", kid),
                _ => Spec::node("RunOnce", kid).attr("then_skip", rng.range(0, 1) == 1),
            }
        }
    }
}

/// One step of a case.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    TickOnce,
    TickExactlyOnce,
    Halt,
}

impl Op {
    pub fn letter(self) -> char {
        match self {
            Op::TickOnce => 'T',
            Op::TickExactlyOnce => 'E',
            Op::Halt => 'H',
        }
    }
}

fn ops(rng: &mut Rng) -> Vec<Op> {
    (0..rng.range(1, 10))
        .map(|_| match rng.weighted(&[4, 3, 1]) {
            0 => Op::TickOnce,
            1 => Op::TickExactlyOnce,
            _ => Op::Halt,
        })
        .collect()
}

/// One case: the XML, the leaves' scripts by node name, the steps.
pub struct Case {
    pub id: usize,
    pub seed: u64,
    pub xml: String,
    /// The scripted leaves' scripts (letters S, F, R), by node name.
    pub scripts: BTreeMap<String, String>,
    /// Each node's element name, by node name.
    pub tags: BTreeMap<String, &'static str>,
    pub ops: Vec<Op>,
}

/// Writes `spec` as XML, naming every node `n<i>` (its pre-order index).
fn write_xml(spec: &Spec, next: &mut usize, case: &mut Case) {
    let name = format!("n{next}");
    *next += 1;
    case.tags.insert(name.clone(), spec.tag);
    let out = &mut case.xml;
    let _ = write!(out, "<{} name=\"{name}\"", spec.tag);
    for (k, v) in &spec.attrs {
        let _ = write!(out, " {k}=\"{v}\"");
    }
    if let Some(s) = &spec.script {
        case.scripts.insert(name, s.clone());
    }
    if spec.children.is_empty() {
        out.push_str("/>");
    } else {
        out.push('>');
        for c in &spec.children {
            write_xml(c, next, case);
        }
        let _ = write!(case.xml, "</{}>", spec.tag);
    }
}

pub fn case(id: usize, seed: u64) -> Case {
    let mut rng = Rng(seed);
    let spec = tree(&mut rng, 0);
    let mut case = Case {
        id,
        seed,
        xml: String::from(
            "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\"><BehaviorTree ID=\"Main\">",
        ),
        scripts: BTreeMap::new(),
        tags: BTreeMap::new(),
        ops: Vec::new(),
    };
    write_xml(&spec, &mut 0, &mut case);
    case.xml.push_str("</BehaviorTree></root>");
    case.ops = ops(&mut rng);
    case
}
