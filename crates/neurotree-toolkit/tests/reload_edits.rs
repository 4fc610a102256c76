//! Reloading an XML tree whose attributes or scripts were edited: every node built from
//! something that changed (its own attributes, a child's that it reads at load, its
//! conditions) starts afresh, so that the run goes on exactly as a fresh load of the new
//! file would from the same state.

use std::fmt::Write as _;
use std::sync::Arc;
use std::time::Duration;

use neurotree::{Blueprint, ManualClock, NodeStatus, Status, Tree};
use proptest::prelude::*;

use crate::shared::load;

type Ctx = Vec<String>;

fn tree(text: &str, clock: &ManualClock) -> Tree<Ctx> {
    let bp: Arc<Blueprint<Ctx>> = Arc::new(load(text).unwrap());
    Tree::with_clock(bp, clock.clone())
}

fn utility_pair(score_a: u32) -> String {
    format!(
        r#"<root main_tree_to_execute="T"><BehaviorTree ID="T">
             <UtilitySelector>
               <Utility score="{score_a}"><Say message="A"/></Utility>
               <Utility score="2"><Say message="B"/></Utility>
             </UtilitySelector>
           </BehaviorTree></root>"#
    )
}

/// A UtilitySelector reads its Utilities' scores: a score changed by a reload is the one
/// the next tick weighs, as after a fresh load.
#[test]
fn a_reloaded_utility_score_is_the_one_weighed() {
    let clock = ManualClock::new();
    let mut t = tree(&utility_pair(1), &clock);
    let mut said = Vec::new();
    assert_eq!(t.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["B"]);
    let report = t
        .reload(Arc::new(load(&utility_pair(5)).unwrap()), &mut said)
        .unwrap();
    // The selector and the changed Utility start afresh; the other Utility and both
    // leaves keep their state.
    assert_eq!((report.kept, report.restarted), (3, 2));
    said.clear();
    assert_eq!(t.tick_once(&mut said), Ok(Status::Success));
    assert_eq!(said, ["A"]);
}

/// A node of the random trees, with its editable attributes: each is written from a
/// template in which `#` stands for a small number, which an edit changes.
#[derive(Clone, Debug)]
struct Node {
    tag: &'static str,
    attrs: Vec<(&'static str, &'static str, u8)>,
    children: Vec<Node>,
}

/// Conditions any node may carry.
const CONDITIONS: [(&str, &str); 3] = [
    ("_skipIf", "x == #"),
    ("_successIf", "x > # + 2"),
    ("_onSuccess", "x += #"),
];

fn leaf() -> impl Strategy<Value = Node> {
    prop_oneof![
        (0u8..4).prop_map(|n| ("Say", vec![("message", "m#", n)])),
        (1u8..4).prop_map(|n| ("Sleep", vec![("msec", "#0", n)])),
        (0u8..4).prop_map(|n| ("Script", vec![("code", "x := #", n)])),
        (0u8..4).prop_map(|n| ("Script", vec![("code", "x += #", n)])),
        (0u8..4).prop_map(|n| ("ScriptCondition", vec![("code", "x < #", n)])),
    ]
    .prop_map(|(tag, attrs)| Node {
        tag,
        attrs,
        children: Vec::new(),
    })
}

fn with_conditions(node: impl Strategy<Value = Node>) -> impl Strategy<Value = Node> {
    (node, prop::option::of((0..CONDITIONS.len(), 0u8..4))).prop_map(|(mut node, c)| {
        if let Some((c, n)) = c {
            let (name, template) = CONDITIONS[c];
            node.attrs.push((name, template, n));
        }
        node
    })
}

fn node() -> impl Strategy<Value = Node> {
    with_conditions(leaf()).prop_recursive(3, 16, 3, |inner| {
        let control = (
            prop_oneof![
                Just("Sequence"),
                Just("Fallback"),
                Just("ReactiveSequence"),
                Just("SequenceWithMemory"),
            ],
            prop::collection::vec(inner.clone(), 1..4),
        )
            .prop_map(|(tag, children)| Node {
                tag,
                attrs: Vec::new(),
                children,
            });
        let utility = prop::collection::vec(
            (
                prop_oneof![Just("#"), Just("x * #"), Just("# - x")],
                0u8..4,
                inner.clone(),
            ),
            1..4,
        )
        .prop_map(|children| Node {
            tag: "UtilitySelector",
            attrs: Vec::new(),
            children: children
                .into_iter()
                .map(|(template, n, child)| Node {
                    tag: "Utility",
                    attrs: vec![("score", template, n)],
                    children: vec![child],
                })
                .collect(),
        });
        let switch =
            (0u8..4, 0u8..4, prop::collection::vec(inner, 3)).prop_map(|(a, b, children)| Node {
                tag: "Switch2",
                attrs: vec![
                    ("variable", "{x}", 0),
                    ("case_1", "#", a),
                    ("case_2", "#", b),
                ],
                children,
            });
        with_conditions(prop_oneof![2 => control, 1 => utility, 1 => switch])
    })
}

impl Node {
    fn attrs(&self) -> usize {
        self.attrs.len() + self.children.iter().map(Node::attrs).sum::<usize>()
    }

    /// Sets the number of the `k`-th attribute (in document order) to `n`.
    fn edit(&mut self, k: &mut usize, n: u8) -> bool {
        if *k < self.attrs.len() {
            self.attrs[*k].2 = n;
            return true;
        }
        *k -= self.attrs.len();
        self.children.iter_mut().any(|c| c.edit(k, n))
    }

    fn write(&self, out: &mut String) {
        let _ = write!(out, "<{}", self.tag);
        for (name, template, n) in &self.attrs {
            let value = template.replace('#', &n.to_string());
            let value = value.replace('<', "&lt;").replace('>', "&gt;");
            let _ = write!(out, " {name}=\"{value}\"");
        }
        out.push('>');
        for c in &self.children {
            c.write(out);
        }
        let _ = write!(out, "</{}>", self.tag);
    }

    fn xml(&self) -> String {
        let mut out = String::from(
            "<root main_tree_to_execute=\"T\"><BehaviorTree ID=\"T\"><Sequence><Script code=\"x := 0\"/>",
        );
        // Forever, so that every tick after the reload has something to run.
        out.push_str("<KeepRunningUntilFailure><ForceSuccess>");
        self.write(&mut out);
        out.push_str("</ForceSuccess></KeepRunningUntilFailure></Sequence></BehaviorTree></root>");
        out
    }
}

/// What a tick did: its result, every node's status, `x` and what the leaves said.
type Seen = (Result<Status, String>, Vec<NodeStatus>, Option<i64>, Ctx);

fn tick(tree: &mut Tree<Ctx>) -> Seen {
    let mut said = Vec::new();
    let result = tree.tick_once(&mut said).map_err(|e| e.to_string());
    let x = tree.blackboard().get::<i64>("x").ok();
    (result, tree.statuses().to_vec(), x, said)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Random trees, random edits of their attributes and scripts, a reload mid-run: from
    /// then on, every tick is the tick of a fresh load of the edited file given the
    /// reloaded tree's state.
    #[test]
    fn a_reloaded_tree_runs_as_a_fresh_load_of_the_edited_file(
        root in node(),
        edits in prop::collection::vec((any::<prop::sample::Index>(), 0u8..4), 1..4),
        before in 0usize..8,
        after in 1usize..12,
    ) {
        let mut edited = root.clone();
        for (k, n) in &edits {
            let mut k = k.index(root.attrs().max(1));
            edited.edit(&mut k, *n);
        }
        let clock = ManualClock::new();
        let mut running = tree(&root.xml(), &clock);
        for _ in 0..before {
            let _ = tick(&mut running);
            clock.advance(Duration::from_millis(10));
        }
        let new = Arc::new(load(&edited.xml()).unwrap());
        prop_assume!(running.reload(new, &mut Vec::new()).is_ok());
        let state = running.save_state().unwrap();
        let mut fresh = tree(&edited.xml(), &clock);
        fresh.restore_state(&state).unwrap();
        for t in 0..after {
            let (a, b) = (tick(&mut running), tick(&mut fresh));
            prop_assert_eq!(a, b, "tick {} after the reload", t);
            clock.advance(Duration::from_millis(10));
        }
    }
}
