//! The node catalog: one module per node, holding its semantics and its tests.
//!
//! - [`control`]: nodes with children that decide which to tick;
//! - [`decorator`]: nodes with one child that change its outcome or its timing;
//! - [`leaf`]: conditions, actions and the built-in leaves;
//! - [`custom`]: the door for user-defined controls and decorators;
//! - [`hooks`]: pre- and post-conditions around any node.
//!
//! Each built-in node is a type of its own in its module, which says everything about it:
//! its declaration as data ([`NodeDecl`]: BehaviorTree.CPP name, family, children, ports),
//! its semantics, what it can return, how it is made from its ports, its tick, its halt, its
//! builder method and its tests (see [`built_in`]). `with_built_ins!` is the one list of
//! them: it makes [`NodeKind`](crate::NodeKind)'s variants, the dispatch and every other
//! match over node kinds, and [`BUILT_INS`], from which the toolkit's registry, model
//! export, XML writer and the README's catalog are derived.
//!
//! A new built-in is its module and one line in `with_built_ins!` (and its module's line
//! in its family's `mod` list).

pub mod built_in;
pub mod control;
pub mod custom;
pub mod decl;
pub mod decorator;
pub mod hooks;
pub mod leaf;
pub mod semantics;

pub use decl::{NodeDecl, PortDecl, PortDirection, PORT_TYPES};
pub use semantics::{Literals, Order, Semantics, Statuses};

/// The one list of built-in nodes, in catalog order: `Name in module::path;`, where the
/// module under `nodes` defines the type `Name` implementing [`built_in::BuiltIn`] and the
/// engine's `Tick`. It hands the list to `$callback`, a macro that makes something for
/// every built-in: [`NodeKind`](crate::NodeKind) and its matches, the tick dispatch, the
/// halt, [`BUILT_INS`].
///
/// SubTree is not here: it is a reference to a tree, made by the loader, not a node type.
macro_rules! with_built_ins {
    ($callback:ident) => {
        $callback! {
            Sequence in control::sequence;
            SequenceWithMemory in control::sequence;
            ReactiveSequence in control::reactive;
            Fallback in control::fallback;
            ReactiveFallback in control::reactive;
            AsyncSequence in control::sequence;
            AsyncFallback in control::fallback;
            Parallel in control::parallel;
            ParallelAll in control::parallel_all;
            IfThenElse in control::if_then_else;
            WhileDoElse in control::while_do_else;
            TryCatch in control::try_catch;
            Service in control::service;
            Inverter in decorator::inverter;
            ForceSuccess in decorator::force;
            ForceFailure in decorator::force;
            Repeat in decorator::repeat;
            RetryUntilSuccessful in decorator::retry;
            KeepRunningUntilFailure in decorator::keep_running;
            Delay in decorator::delay;
            Timeout in decorator::timeout;
            Cooldown in decorator::cooldown;
            RunOnce in decorator::run_once;
            AlwaysSuccess in leaf::always;
            AlwaysFailure in leaf::always;
            Sleep in leaf::sleep;
        }
    };
}
pub(crate) use with_built_ins;

/// Makes [`BUILT_INS`] from the list.
macro_rules! declarations {
    ($($name:ident in $($module:ident)::+;)*) => {
        /// Every built-in node of the engine, as declared in its module, in catalog order.
        /// (SubTree is not here: it is a reference to a tree, made by the loader, not a node
        /// type.)
        pub const BUILT_INS: &[&NodeDecl] = &[
            $(<$($module::)+$name as built_in::Tick>::DECL,)*
        ];
    };
}
with_built_ins!(declarations);

/// Makes [`kinds`] from the list.
macro_rules! kinds {
    ($($name:ident in $($module:ident)::+;)*) => {
        /// Every built-in node's type under one roof, for building a [`NodeKind`] by hand:
        /// `NodeKind::Inverter(kinds::Inverter)`.
        ///
        /// [`NodeKind`]: crate::NodeKind
        pub mod kinds {
            $(pub use super::$($module::)+$name;)*
        }
    };
}
with_built_ins!(kinds);

/// A stand-in of a family: what the XML loader builds for a node it cannot make (one only
/// described by a model, or one with an error), so that its children are still checked.
pub fn stand_in<C>(category: crate::Category) -> crate::NodeKind<C> {
    use crate::{Category, NodeKind};
    match category {
        Category::Control => NodeKind::Sequence(control::sequence::Sequence),
        Category::Decorator | Category::SubTree => {
            NodeKind::Inverter(decorator::inverter::Inverter)
        }
        Category::Action | Category::Condition => {
            NodeKind::AlwaysSuccess(leaf::always::AlwaysSuccess)
        }
    }
}

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
