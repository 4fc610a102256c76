//! The ports an engine built-in's kind was made from, for the XML writer.
//!
//! What a built-in is (name, family, children, ports) is its declaration in its own module
//! ([`neurotree_core::nodes::BUILT_INS`]), and the engine makes its kind from its ports and
//! reads them back ([`NodeKind::from_declared`], [`NodeKind::declared_ports`]); the
//! registry is built from those declarations.

use neurotree_core::nodes::BUILT_INS;
use neurotree_core::NodeKind;

/// The ports a built-in kind was made from, named as its declaration names them; empty for
/// a kind that is no engine built-in. `children` resolves the Parallel shorthands the
/// builder offers into BehaviorTree.CPP's thresholds.
pub(crate) fn built_in_ports<C>(
    kind: &NodeKind<C>,
    children: usize,
) -> Vec<(&'static str, String)> {
    match BUILT_INS.iter().find(|d| d.name == kind.type_name()) {
        Some(decl) => kind.declared_ports(decl, children),
        None => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::registry::{Make, Registry};
    use neurotree_core::ParallelPolicy;

    #[test]
    fn built_ins_are_registered_with_their_ports() {
        let r = Registry::<()>::new();
        let repeat = r.get("Repeat").unwrap();
        assert_eq!(repeat.category, neurotree_core::Category::Decorator);
        assert_eq!(repeat.ports[0].name, "num_cycles");
        assert!(repeat.ports[0].accepts("3"));
        assert!(!repeat.ports[0].accepts("three"));
        assert_eq!(r.get("Parallel").unwrap().ports.len(), 2);
        assert!(r.get("MoveBase").is_none());
    }

    #[test]
    fn every_built_in_is_registered_as_declared() {
        let r = Registry::<()>::new();
        for decl in BUILT_INS {
            let t = r.get(decl.name).unwrap();
            assert!(
                matches!(t.make, Make::BuiltIn(d) if d == *decl),
                "{}",
                decl.name
            );
        }
        // The writer names a Parallel's thresholds as declared.
        let count = NodeKind::<()>::Parallel(neurotree_core::nodes::kinds::Parallel {
            policy: ParallelPolicy::RequireCount(2),
        });
        assert_eq!(
            built_in_ports(&count, 5),
            [("success_count", "2".into()), ("failure_count", "4".into())]
        );
        assert!(built_in_ports(
            &NodeKind::<()>::Sequence(neurotree_core::nodes::kinds::Sequence),
            2
        )
        .is_empty());
    }
}
