//! Utility: a decorator that gives its child a score, for a
//! [UtilitySelector](super::utility_selector) to choose by.
//!
//! - **Utility(score)**: `score` is a script expression (`hunger * 2 - fatigue`) or a
//!   blackboard entry (`{hunger}`), whose value must be a number. The UtilitySelector above
//!   it evaluates the score on every tick; the Utility itself ticks its child and returns
//!   the child's status, resetting it once it completes. Outside a UtilitySelector the score
//!   is not read and the Utility passes its child through.
//!
//! The script is parsed when the tree is loaded, so a score that does not parse is a load
//! error with its file position; one that does not give a number is an error of the tick
//! that evaluated it, naming the Utility.

use std::sync::Arc;

use neurotree_core::{
    Arity, Category, CustomNode, CustomSpec, NodeCtx, NodeDecl, NodeKind, NodeStatus, Port,
    PortDecl, PortValue,
};

use crate::registry::{MakerError, Registry};
use crate::script::Script;
use neurotree_core::nodes::semantics::{first, Order, Semantics, Statuses};

/// Utility's declaration: its name, family, children and ports.
pub const UTILITY: NodeDecl = NodeDecl {
    name: "Utility",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[PortDecl::input(
        "score",
        "String",
        "The child's score: a script expression or a {key}, giving a number.",
    )],
    summary: "Gives its child a score for the UtilitySelector above it; ticks it through.",
    semantics: Semantics::new(Order::in_turn(Statuses::ANY), |_, c| {
        first(c).or(Statuses::FAILURE)
    }),
};

/// Where a Utility's score comes from, as its `score` port is written.
#[derive(Clone)]
pub(crate) enum Score {
    /// `score="{key}"`: the entry, read as a number.
    Entry,
    /// `score="expression"`: the script, parsed at load.
    Script(Script),
}

impl Score {
    /// The score that `ports` (a Utility's) declare; an error if `score` is missing or its
    /// script does not parse.
    pub(crate) fn from_ports(ports: &[Port]) -> Result<Score, MakerError> {
        match ports.iter().find(|p| p.name == "score").map(|p| &p.value) {
            Some(PortValue::Entry(_)) => Ok(Score::Entry),
            Some(PortValue::Literal(code)) => Script::parse(code)
                .map(Score::Script)
                .map_err(|e| MakerError::Script(format!("in score `{}`: {e}", e.excerpt(code)))),
            None => Err(MakerError::MissingPort(String::from(
                "missing port `score`: write a script expression or a {key}",
            ))),
        }
    }
}

/// The decorator's tick: its child's status, the child reset once it completes.
struct Utility;

impl<C> CustomNode<C> for Utility {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(Vec::new())
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        // Its status is its child's: a tree may sleep while it runs.
        node.wakes_with_children();
        node.set_running();
        let status = node.tick_child(0);
        if status.is_completed() {
            node.reset_children();
        }
        status
    }
}

/// The kind a Utility is made of. The score is checked here, at load; the
/// UtilitySelector reads it again from the ports, as it evaluates it.
pub(crate) fn make<C: 'static>(ports: &[Port]) -> Result<NodeKind<C>, MakerError> {
    Score::from_ports(ports)?;
    Ok(NodeKind::Custom(Box::new(spec())))
}

/// A Utility's kind, for a builder: its score is the `score` port bound beside it.
pub fn spec<C: 'static>() -> CustomSpec<C> {
    CustomSpec::new(UTILITY.name, Arity::One, Box::new(|| Box::new(Utility)))
}

/// Adds Utility to `registry`.
pub(crate) fn register<C: 'static>(registry: &mut Registry<C>) {
    registry.register_declared(&UTILITY, Arc::new(|ports, _| make(ports)));
}
