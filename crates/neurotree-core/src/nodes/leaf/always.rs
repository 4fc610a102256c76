//! AlwaysSuccess and AlwaysFailure: leaves with a fixed outcome, for stubs and tests.
//!
//! - **AlwaysSuccess**: Success, every tick.
//! - **AlwaysFailure**: Failure, every tick.

use crate::nodes::decl::NodeDecl;
use crate::{Arity, Category};

/// AlwaysSuccess's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const ALWAYS_SUCCESS: NodeDecl = NodeDecl {
    name: "AlwaysSuccess",
    category: Category::Action,
    arity: Arity::Leaf,
    ports: &[],
    summary: "Success, every tick.",
};

/// AlwaysFailure's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const ALWAYS_FAILURE: NodeDecl = NodeDecl {
    name: "AlwaysFailure",
    category: Category::Action,
    arity: Arity::Leaf,
    ports: &[],
    summary: "Failure, every tick.",
};

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn fixed_outcomes() {
        let (mut tree, _) = build(|b| b.always_success("s"));
        assert_eq!(tick(&mut tree), Ok(Status::Success));
        let (mut tree, _) = build(|b| b.always_failure("f"));
        assert_eq!(tick(&mut tree), Ok(Status::Failure));
    }
}
