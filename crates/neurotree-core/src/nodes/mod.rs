//! The node catalog: one module per node, holding its semantics and its tests.
//!
//! - [`control`]: nodes with children that decide which to tick;
//! - [`decorator`]: nodes with one child that change its outcome or its timing;
//! - [`leaf`]: conditions, actions and the built-in leaves;
//! - [`custom`]: the door for user-defined controls and decorators;
//! - [`hooks`]: pre- and post-conditions around any node.
//!
//! Each built-in node's module also declares it as data ([`NodeDecl`]: BehaviorTree.CPP
//! name, family, children, ports), and [`BUILT_INS`] lists those declarations: the one list
//! a new built-in joins. The toolkit's registry, model export, XML writer and the README's
//! catalog are derived from it; the tick goes through [`NodeKind`](crate::NodeKind) only.
//!
//! A new built-in is its module (declaration, tick, halt, tests) and one line in each of:
//! [`BUILT_INS`], its family's module list, [`NodeKind`](crate::NodeKind) (the variant, its
//! name and its number of children), the dispatch in `tree::ticker`, the making of its kind
//! from its ports ([`NodeKind::from_declared`](crate::NodeKind::from_declared)), and the
//! README's catalog (its test prints the row).

pub mod control;
pub mod custom;
pub mod decl;
pub mod decorator;
pub mod hooks;
pub mod leaf;

pub use decl::{NodeDecl, PortDecl, PortDirection, PORT_TYPES};

/// Every built-in node of the engine, as declared in its module, in catalog order.
/// (SubTree is not here: it is a reference to a tree, made by the loader, not a node type.)
pub const BUILT_INS: &[&NodeDecl] = &[
    &control::sequence::SEQUENCE,
    &control::sequence::SEQUENCE_WITH_MEMORY,
    &control::reactive::REACTIVE_SEQUENCE,
    &control::fallback::FALLBACK,
    &control::reactive::REACTIVE_FALLBACK,
    &control::sequence::ASYNC_SEQUENCE,
    &control::fallback::ASYNC_FALLBACK,
    &control::parallel::PARALLEL,
    &control::parallel_all::PARALLEL_ALL,
    &control::if_then_else::IF_THEN_ELSE,
    &control::while_do_else::WHILE_DO_ELSE,
    &control::try_catch::TRY_CATCH,
    &decorator::inverter::INVERTER,
    &decorator::force::FORCE_SUCCESS,
    &decorator::force::FORCE_FAILURE,
    &decorator::repeat::REPEAT,
    &decorator::retry::RETRY_UNTIL_SUCCESSFUL,
    &decorator::keep_running::KEEP_RUNNING_UNTIL_FAILURE,
    &decorator::delay::DELAY,
    &decorator::timeout::TIMEOUT,
    &decorator::cooldown::COOLDOWN,
    &decorator::run_once::RUN_ONCE,
    &leaf::always::ALWAYS_SUCCESS,
    &leaf::always::ALWAYS_FAILURE,
    &leaf::sleep::SLEEP,
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Arity, Category};

    #[test]
    fn declarations_are_distinct_and_consistent() {
        for (i, d) in BUILT_INS.iter().enumerate() {
            assert!(
                BUILT_INS[..i].iter().all(|e| e.name != d.name),
                "{} is declared twice",
                d.name
            );
            // The family follows from the number of children, as BehaviorTree.CPP's does.
            let family_fits = match d.category {
                Category::Control => matches!(d.arity, Arity::Range { .. } | Arity::AtLeast(_)),
                Category::Decorator | Category::SubTree => d.arity == Arity::One,
                Category::Action | Category::Condition => d.arity == Arity::Leaf,
            };
            assert!(family_fits, "{}: {:?} with {}", d.name, d.category, d.arity);
            assert!(!d.summary.is_empty(), "{} has no summary", d.name);
            for (j, p) in d.ports.iter().enumerate() {
                assert!(PORT_TYPES.contains(&p.type_name), "{}.{}", d.name, p.name);
                assert!(!p.description.is_empty(), "{}.{}", d.name, p.name);
                assert!(
                    d.ports[..j].iter().all(|q| q.name != p.name),
                    "{}.{} twice",
                    d.name,
                    p.name
                );
                assert_eq!(d.port(p.name), Some(p));
            }
        }
    }
}
