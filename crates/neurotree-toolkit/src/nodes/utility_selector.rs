//! UtilitySelector: a control that ticks the child with the highest score.
//!
//! - **UtilitySelector(hysteresis=0)**: every child is a [Utility](super::utility)
//!   decorator whose `score` gives a number. On every tick the selector evaluates every
//!   score, in order, and ticks the child with the highest (on a tie, the first), returning
//!   that child's status. While a child is Running it stays chosen until another child's
//!   score beats its own by more than `hysteresis`; then the Running child is halted (once,
//!   with everything Running under it) and the new one ticked in the same tick. A child that
//!   completes is reset, and the next tick chooses afresh.
//! - A score that does not give a number (text, a boolean, NaN, a missing entry) is an error
//!   of the tick naming the Utility ([`TickError::Node`](neurotree_core::TickError::Node));
//!   so is a child that is not a Utility, naming the selector. The tree is halted, as after
//!   any tick error.
//! - `hysteresis` is a number ≥ 0, literal or `{key}` (read on every tick).
//!
//! Each score evaluated is told to the tree's observer
//! ([`Observer::on_node_score`](neurotree_core::Observer::on_node_score)) as the Utility's:
//! the studio shows it on the node.
//!
//! The tree may sleep while the selector runs (see [`sleep`](neurotree_core::tree::sleep)):
//! scores read only the blackboard, so a sleeping tree wakes when it is written.

use std::sync::{Arc, OnceLock};

use neurotree_core::{
    Arity, Category, CustomNode, CustomSpec, NodeCtx, NodeDecl, NodeKind, NodeStatus, Port,
    PortDecl, PortValue,
};

use super::utility::{Score, UTILITY};
use crate::registry::{MakerError, Registry};
use crate::script::{Enums, ScriptEnv, Value};
use neurotree_core::nodes::semantics::Semantics;

/// UtilitySelector's declaration: its name, family, children and ports.
pub const UTILITY_SELECTOR: NodeDecl = NodeDecl {
    name: "UtilitySelector",
    category: Category::Control,
    arity: Arity::AtLeast(1),
    ports: &[PortDecl::input(
        "hysteresis",
        "f64",
        "How much another child's score must beat the Running child's by to replace it.",
    )
    .or("0")],
    summary: "Ticks the Utility child with the highest score; switches away from a Running one only past `hysteresis`.",
    semantics: Semantics::ANY,
};

/// The children's scores, as their ports declare them: read from the blueprint on the
/// first tick of any instance, then shared by all instances of the blueprint.
type Scores = Arc<OnceLock<Result<Vec<Score>, String>>>;

/// One instance's UtilitySelector.
struct UtilitySelector {
    scores: Scores,
    enums: Arc<Enums>,
    /// `hysteresis` when literal; `None` when read from an entry on every tick.
    hysteresis: Option<f64>,
    /// The child that returned Running last.
    running: Option<usize>,
    /// The score of each child, as last evaluated (empty before the first tick).
    last: Vec<f64>,
}

impl UtilitySelector {
    /// `hysteresis`, literal or read now.
    fn hysteresis<C>(&self, node: &NodeCtx<'_, '_, C>) -> Result<f64, String> {
        let h = match self.hysteresis {
            Some(h) => h,
            None => node
                .input::<f64>("hysteresis")
                .map_err(|e| format!("hysteresis: {e}"))?,
        };
        check_hysteresis(h)
    }

    /// Evaluates every child's score into `self.last` and returns the best child: the
    /// first of the highest. On an error, the tick has been failed (naming who) and `None`
    /// is returned.
    fn evaluate<C>(&mut self, node: &mut NodeCtx<'_, '_, C>) -> Option<usize> {
        let n = node.child_count();
        let scores = Arc::clone(&self.scores);
        let scores = match scores.get_or_init(|| children_scores(node)) {
            Ok(scores) => scores,
            Err(message) => {
                node.fail(message.clone());
                return None;
            }
        };
        self.last.resize(n, 0.0);
        let mut best = 0;
        for (i, score) in scores.iter().enumerate() {
            match evaluate(score, node, i, &self.enums) {
                Ok(value) => {
                    self.last[i] = value;
                    node.report_child_score(i, value);
                }
                Err(message) => {
                    node.fail_child(i, message);
                    return None;
                }
            }
            if self.last[i] > self.last[best] {
                best = i;
            }
        }
        Some(best)
    }
}

impl<C> CustomNode<C> for UtilitySelector {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(self.running,)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(running,)| self.running = running)
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        // Scores read only the blackboard: a tree may sleep until it is written.
        node.wake_on("score");
        node.set_running();
        let hysteresis = match self.hysteresis(node) {
            Ok(h) => h,
            Err(message) => {
                node.fail(message);
                return NodeStatus::Failure;
            }
        };
        let Some(best) = self.evaluate(node) else {
            return NodeStatus::Failure;
        };
        let chosen = match self.running {
            Some(running) if running != best => {
                if self.last[best] > self.last[running] + hysteresis {
                    node.halt_child(running);
                    best
                } else {
                    running
                }
            }
            _ => best,
        };
        let status = node.tick_child(chosen);
        self.running = (status == NodeStatus::Running).then_some(chosen);
        if status.is_completed() {
            node.reset_children();
        }
        status
    }

    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {
        self.running = None;
    }
}

/// `h` if it is a hysteresis: a number, not below zero.
fn check_hysteresis(h: f64) -> Result<f64, String> {
    if h >= 0.0 {
        Ok(h)
    } else {
        Err(format!(
            "hysteresis is {h}; write a number of at least 0 (0: always take the highest score)"
        ))
    }
}

/// Every child's declared score; an error naming the first child that is no Utility.
fn children_scores<C>(node: &NodeCtx<'_, '_, C>) -> Result<Vec<Score>, String> {
    (0..node.child_count())
        .map(|i| {
            let type_name = node.child_type_name(i);
            if type_name != UTILITY.name {
                return Err(format!(
                    "child {} is a {type_name}; every child of a UtilitySelector is a \
                     <Utility score=\"...\"> around the branch it scores",
                    i + 1
                ));
            }
            Score::from_ports(node.child_ports(i)).map_err(|e| e.into_parts().1)
        })
        .collect()
}

/// The value of child `i`'s `score`, or why it is not a number.
fn evaluate<C>(
    score: &Score,
    node: &mut NodeCtx<'_, '_, C>,
    i: usize,
    enums: &Enums,
) -> Result<f64, String> {
    let value = match score {
        Score::Entry => node
            .child_input::<f64>(i, "score")
            .map_err(|e| format!("score: {e}"))?,
        Score::Script(script) => {
            let (scope, stamp) = (node.scope(), node.now());
            let mut env = ScriptEnv {
                blackboard: node.blackboard(),
                scope,
                enums,
                stamp,
                max_string_len: crate::script::DEFAULT_MAX_STRING_LEN,
            };
            match script.eval(&mut env) {
                Ok(Value::Int(n)) => n as f64,
                Ok(Value::Real(r)) => r,
                Ok(other) => {
                    return Err(format!(
                        "score `{}` is `{other}`, not a number",
                        script.source()
                    ))
                }
                Err(e) => return Err(format!("score `{}`: {e}", e.excerpt(script.source()))),
            }
        }
    };
    if value.is_nan() {
        return Err(String::from("score is NaN, not a number"));
    }
    Ok(value)
}

/// A UtilitySelector's kind; `hysteresis` is `None` when read from an entry.
fn kind<C: 'static>(hysteresis: Option<f64>, enums: Arc<Enums>) -> CustomSpec<C> {
    let scores: Scores = Arc::new(OnceLock::new());
    CustomSpec::new(
        UTILITY_SELECTOR.name,
        UTILITY_SELECTOR.arity,
        Box::new(move || {
            Box::new(UtilitySelector {
                scores: Arc::clone(&scores),
                enums: Arc::clone(&enums),
                hysteresis,
                running: None,
                last: Vec::new(),
            })
        }),
    )
}

/// A UtilitySelector's kind for a builder, with a literal `hysteresis` (see
/// [`UtilityBuilder`]).
pub fn spec<C: 'static>(hysteresis: f64) -> CustomSpec<C> {
    kind(Some(hysteresis), Arc::new(Enums::new()))
}

/// The kind made from a file's ports.
fn make<C: 'static>(ports: &[Port], enums: &Arc<Enums>) -> Result<NodeKind<C>, MakerError> {
    let hysteresis = match ports
        .iter()
        .find(|p| p.name == "hysteresis")
        .map(|p| &p.value)
    {
        None => Some(0.0),
        Some(PortValue::Entry(_)) => None,
        Some(PortValue::Literal(text)) => {
            let h = text.trim().parse::<f64>().map_err(|_| {
                MakerError::BadValue(format!("hysteresis `{text}` is not a number"))
            })?;
            Some(check_hysteresis(h).map_err(MakerError::BadValue)?)
        }
    };
    Ok(NodeKind::Custom(Box::new(kind(
        hysteresis,
        Arc::clone(enums),
    ))))
}

/// Adds UtilitySelector to `registry`.
pub(crate) fn register<C: 'static>(registry: &mut Registry<C>) {
    registry.register_declared(
        &UTILITY_SELECTOR,
        Arc::new(|ports, enums| make(ports, enums)),
    );
}

/// Builder methods for scored choice: [`utility_selector`](Self::utility_selector) and
/// the [`utility`](Self::utility) decorators under it.
///
/// ```
/// use neurotree_toolkit::{Blueprint, ManualClock, Status, Tree, UtilityBuilder};
///
/// let bp = Blueprint::<Vec<&str>>::builder()
///     .utility_selector("choose", 0.0, |c| {
///         c.utility("eat", "{hunger}", |u| {
///             u.action("Eat", |log: &mut Vec<&str>| { log.push("eat"); Status::Success })
///         })
///         .utility("work", "5", |u| {
///             u.action("Work", |log: &mut Vec<&str>| { log.push("work"); Status::Success })
///         })
///     })
///     .build_shared()
///     .unwrap();
/// let mut tree = Tree::with_clock(bp, ManualClock::new());
/// tree.blackboard_mut().set("hunger", 9.0).unwrap();
/// let mut log = Vec::new();
/// assert_eq!(tree.tick_once(&mut log), Ok(Status::Success));
/// tree.blackboard_mut().set("hunger", 1.0).unwrap();
/// assert_eq!(tree.tick_once(&mut log), Ok(Status::Success));
/// assert_eq!(log, ["eat", "work"]);
/// ```
pub trait UtilityBuilder: Sized {
    /// A UtilitySelector with a literal `hysteresis`; `children` adds its Utility children.
    fn utility_selector(
        self,
        name: &str,
        hysteresis: f64,
        children: impl FnOnce(Self) -> Self,
    ) -> Self;

    /// A Utility whose `score` is a script expression, or an entry written `{key}`;
    /// `child` adds the branch it scores.
    fn utility(self, name: &str, score: &str, child: impl FnOnce(Self) -> Self) -> Self;
}

impl<C: 'static> UtilityBuilder for neurotree_core::Builder<C> {
    fn utility_selector(
        self,
        name: &str,
        hysteresis: f64,
        children: impl FnOnce(Self) -> Self,
    ) -> Self {
        self.custom(name, spec(hysteresis), |c| {
            children(c.ports([Port::literal("hysteresis", &hysteresis.to_string())]))
        })
    }

    fn utility(self, name: &str, score: &str, child: impl FnOnce(Self) -> Self) -> Self {
        let trimmed = score.trim();
        let port = match trimmed.strip_prefix('{').and_then(|s| s.strip_suffix('}')) {
            Some(key) => Port::entry("score", key),
            None => Port::literal("score", score),
        };
        self.custom(name, super::utility::spec(), |c| child(c.ports([port])))
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    /// Three Utility children scored by the entries `a`, `b`, `c` over the leaves L0..L2.
    const ABC: &str = r#"<UtilitySelector hysteresis="{h}">
        <Utility score="{a}"><L0/></Utility>
        <Utility score="{b}"><L1/></Utility>
        <Utility score="{c}"><L2/></Utility>
    </UtilitySelector>"#;

    fn scores(tree: &mut Tree<Lab>, a: f64, b: f64, c: f64) {
        let bb = tree.blackboard_mut();
        bb.set("a", a).unwrap();
        bb.set("b", b).unwrap();
        bb.set("c", c).unwrap();
    }

    fn abc(scripts: &[&[Status]], hysteresis: f64) -> (Lab, Tree<Lab>) {
        let lab = Lab::new(scripts);
        let mut tree = lab.tree(ABC);
        tree.blackboard_mut().set("h", hysteresis).unwrap();
        (lab, tree)
    }

    #[test]
    fn the_highest_score_is_ticked_and_its_status_returned() {
        let (mut lab, mut tree) = abc(&[&[S], &[F], &[S]], 0.0);
        scores(&mut tree, 1.0, 5.0, 2.0);
        assert_eq!(lab.tick(&mut tree), Ok(F));
        scores(&mut tree, 1.0, 5.0, 7.5);
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(lab.ticks, [0, 1, 1]);
        assert_eq!(lab.halts, [0, 0, 0]);
    }

    #[test]
    fn a_tie_goes_to_the_first_child() {
        let (mut lab, mut tree) = abc(&[&[S], &[S], &[S]], 0.0);
        scores(&mut tree, 1.0, 4.0, 4.0);
        assert_eq!(lab.tick(&mut tree), Ok(S));
        scores(&mut tree, 4.0, 4.0, 4.0);
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(lab.ticks, [1, 1, 0]);
    }

    #[test]
    fn a_running_child_is_halted_once_when_beaten_and_the_new_one_ticked_in_the_same_tick() {
        let (mut lab, mut tree) = abc(&[&[R], &[R], &[R]], 0.0);
        scores(&mut tree, 1.0, 5.0, 2.0);
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(
            (lab.ticks.clone(), lab.halts.clone()),
            (vec![0, 2, 0], vec![0, 0, 0])
        );
        tree.blackboard_mut().set("c", 9.0).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(
            (lab.ticks.clone(), lab.halts.clone()),
            (vec![0, 2, 1], vec![0, 1, 0])
        );
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(
            (lab.ticks.clone(), lab.halts.clone()),
            (vec![0, 2, 2], vec![0, 1, 0])
        );
        // Halting the tree halts the Running child once more, and only it.
        tree.halt(&mut lab);
        assert_eq!(lab.halts, [0, 1, 1]);
    }

    #[test]
    fn hysteresis_keeps_a_running_child_until_it_is_beaten_by_more() {
        let (mut lab, mut tree) = abc(&[&[R], &[R], &[R]], 2.0);
        scores(&mut tree, 1.0, 5.0, 2.0);
        assert_eq!(lab.tick(&mut tree), Ok(R));
        // 7 beats 5 by 2: not by more than the hysteresis.
        tree.blackboard_mut().set("c", 7.0).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(
            (lab.ticks.clone(), lab.halts.clone()),
            (vec![0, 2, 0], vec![0, 0, 0])
        );
        tree.blackboard_mut().set("c", 7.5).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(
            (lab.ticks.clone(), lab.halts.clone()),
            (vec![0, 2, 1], vec![0, 1, 0])
        );
        // Once the child completes, the next tick chooses afresh without hysteresis.
        lab.scripts[2] = vec![S];
        assert_eq!(lab.tick(&mut tree), Ok(S));
        tree.blackboard_mut().set("b", 7.6).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(
            (lab.ticks.clone(), lab.halts.clone()),
            (vec![0, 3, 2], vec![0, 1, 0])
        );
    }

    /// Each score the observer is told: `(node, score)`.
    #[derive(Clone, Default)]
    struct Scores(std::sync::Arc<std::sync::Mutex<Vec<(u32, f64)>>>);

    impl neurotree_core::Observer for Scores {
        fn on_node_score(&mut self, node: neurotree_core::NodeId, score: f64) {
            self.0.lock().unwrap().push((node.0, score));
        }
    }

    #[test]
    fn every_score_evaluated_is_told_to_the_observer_as_its_utilitys() {
        let (mut lab, mut tree) = abc(&[&[R], &[R], &[R]], 0.0);
        let seen = Scores::default();
        tree.set_observer(seen.clone());
        scores(&mut tree, 1.0, 5.0, 2.0);
        assert_eq!(lab.tick(&mut tree), Ok(R));
        // The Utilities are nodes 1, 3 and 5 (each over its leaf).
        assert_eq!(*seen.0.lock().unwrap(), [(1, 1.0), (3, 5.0), (5, 2.0)]);
        tree.blackboard_mut().set("c", 9.0).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        assert_eq!(seen.0.lock().unwrap()[3..], [(1, 1.0), (3, 5.0), (5, 9.0)]);
    }

    #[test]
    fn scores_are_script_expressions_over_the_blackboard() {
        let mut lab = Lab::new(&[&[S], &[S]]);
        let mut tree = lab.tree(
            r#"<UtilitySelector>
                <Utility score="hunger * 2 - 1"><L0/></Utility>
                <Utility score="fatigue + 0.5"><L1/></Utility>
            </UtilitySelector>"#,
        );
        tree.blackboard_mut().set("hunger", 3_i64).unwrap();
        tree.blackboard_mut().set("fatigue", 5.0).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(S));
        tree.blackboard_mut().set("fatigue", 4.0).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(S));
        assert_eq!(lab.ticks, [1, 1]);
    }

    #[test]
    fn a_score_that_is_no_number_is_a_tick_error_naming_the_utility() {
        let mut lab = Lab::new(&[&[R], &[S]]);
        let mut tree = lab.tree(
            r#"<UtilitySelector>
                <Utility score="1"><L0/></Utility>
                <Utility name="chatty" score="'high'"><L1/></Utility>
            </UtilitySelector>"#,
        );
        match lab.tick(&mut tree) {
            Err(TickError::Node { path, message, .. }) => {
                assert!(path.ends_with("chatty"), "{path}");
                assert!(message.contains("not a number"), "{message}");
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(lab.ticks, [0, 0]);
        // A missing entry names the Utility too, and the Running child is halted once.
        let mut lab = Lab::new(&[&[R], &[S]]);
        let mut tree = lab.tree(ABC.replace("<L2/>", "<L1/>").as_str());
        scores(&mut tree, 5.0, 1.0, 1.0);
        tree.blackboard_mut().set("h", 0.0).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(R));
        tree.blackboard_mut().unset("a");
        match lab.tick(&mut tree) {
            Err(TickError::Node { path, message, .. }) => {
                assert!(path.contains("Utility"), "{path}");
                assert!(message.contains("score"), "{message}");
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(
            (lab.ticks.clone(), lab.halts.clone()),
            (vec![1, 0], vec![1, 0])
        );
    }

    #[test]
    fn bad_files_are_load_errors_and_a_stray_child_a_tick_error() {
        let lab = Lab::new(&[&[S]]);
        let wrap = |body: &str| {
            format!(
                r#"<root BTCPP_format="4" main_tree_to_execute="T"><BehaviorTree ID="T">{body}</BehaviorTree></root>"#
            )
        };
        let Err(err) = lab.load(&wrap(
            r#"<UtilitySelector><Utility score="1 +"><L0/></Utility></UtilitySelector>"#,
        )) else {
            panic!("a score that does not parse loads");
        };
        assert!(err.to_string().contains("score"), "{err}");
        let Err(err) = lab.load(&wrap(
            r#"<UtilitySelector hysteresis="-1"><Utility score="1"><L0/></Utility></UtilitySelector>"#,
        )) else {
            panic!("a negative hysteresis loads");
        };
        assert!(err.to_string().contains("hysteresis"), "{err}");
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(r#"<UtilitySelector><L0/></UtilitySelector>"#);
        match lab.tick(&mut tree) {
            Err(TickError::Node { message, .. }) => {
                assert!(message.contains("Utility"), "{message}")
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(lab.ticks, [0]);
    }
}
