//! A built-in kind made from its declared ports, and the ports read back from a kind: the
//! two directions a file takes (the XML loader, the XML writer), for every built-in
//! [`NodeDecl`](crate::nodes::NodeDecl) that has ports.
//!
//! A literal is read when the kind is made (the loader has checked it converts); a port
//! bound to a blackboard entry becomes [`Param::Port`], which the node reads when it runs,
//! as BehaviorTree.CPP's `getInput` does.

use alloc::string::String;
use alloc::vec::Vec;

use super::NodeKind;
use crate::nodes::NodeDecl;

/// Why a built-in's ports do not make it: what the loader reports at the node.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PortBindingError {
    /// A port without a default is not given.
    #[error("missing port `{port}`")]
    Missing {
        /// The port's name.
        port: String,
    },
    /// A literal does not convert to the port's type.
    #[error("port `{port}`: cannot read `{text}`")]
    Unreadable {
        /// The port's name.
        port: String,
        /// The literal.
        text: String,
    },
}

crate::debug_shows_message!(enum PortBindingError {
    Missing { port },
    Unreadable { port, text },
});

/// What a port of a built-in node is bound to in a file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PortBinding {
    /// Literal text, read when the kind is made.
    Literal(String),
    /// A blackboard entry, read by the node when it runs.
    Entry,
    /// Not given, and no default.
    Missing,
}

impl<C> NodeKind<C> {
    /// The kind of the built-in `decl` with its ports bound by `port`; an error names the
    /// port that is missing or whose literal does not convert. `None` if `decl` is no
    /// built-in of the engine.
    pub fn from_declared(
        decl: &NodeDecl,
        port: &dyn Fn(&str) -> PortBinding,
    ) -> Option<Result<Self, PortBindingError>> {
        Self::make(decl.name, port).transpose()
    }

    /// The ports a built-in kind was made from, as [`from_declared`](Self::from_declared)
    /// reads them back: what a saved file writes for the node, named as its declaration
    /// names them, a parameter read from a port left out. `children` resolves the Parallel
    /// shorthands the builder offers into BehaviorTree.CPP's thresholds.
    pub fn declared_ports(&self, decl: &NodeDecl, children: usize) -> Vec<(&'static str, String)> {
        // The values in the order of the declared ports.
        let values = match self.built_in() {
            Some(node) => node.port_values(children),
            None => return Vec::new(),
        };
        decl.ports
            .iter()
            .map(|p| p.name)
            .zip(values)
            .filter_map(|(name, value)| Some((name, value?)))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nodes::{PortDecl, BUILT_INS};
    use crate::{ParallelPolicy, Param};
    use alloc::format;
    use alloc::string::ToString;

    /// A literal of the port's type, other than its default and the smallest value, so
    /// that a swapped pair of ports would show.
    fn sample(port: &PortDecl) -> &'static str {
        match (port.name, port.type_name) {
            ("failure_count", _) => "-1",
            (_, "i32") => "2",
            (_, "bool") => match port.default {
                Some("true") => "false",
                _ => "true",
            },
            _ => "7",
        }
    }

    fn samples(decl: &NodeDecl) -> impl Fn(&str) -> PortBinding + '_ {
        move |p| match decl.port(p) {
            Some(port) => PortBinding::Literal(sample(port).into()),
            None => PortBinding::Missing,
        }
    }

    #[test]
    fn every_declaration_makes_the_kind_it_declares() {
        for decl in BUILT_INS {
            let kind = NodeKind::<()>::from_declared(decl, &samples(decl))
                .unwrap_or_else(|| panic!("{} makes no kind", decl.name))
                .unwrap_or_else(|e| panic!("{}: {e}", decl.name));
            assert_eq!(kind.type_name(), decl.name);
            assert_eq!(kind.arity(), decl.arity, "{}", decl.name);
            assert_eq!(kind.category(), decl.category, "{}", decl.name);
        }
    }

    #[test]
    fn declared_ports_read_back_into_the_same_kind() {
        for decl in BUILT_INS {
            let kind = NodeKind::<()>::from_declared(decl, &samples(decl))
                .unwrap()
                .unwrap();
            let ports = kind.declared_ports(decl, 3);
            let names: Vec<&str> = ports.iter().map(|(n, _)| *n).collect();
            let declared: Vec<&str> = decl.ports.iter().map(|p| p.name).collect();
            assert_eq!(names, declared, "{}", decl.name);
            // Only the names written back are given, so a kind reading another name fails.
            let again = NodeKind::<()>::from_declared(decl, &|p| match ports
                .iter()
                .find(|(n, _)| *n == p)
            {
                Some((_, v)) => PortBinding::Literal(v.clone()),
                None => PortBinding::Missing,
            })
            .unwrap()
            .unwrap();
            assert_eq!(format!("{again:?}"), format!("{kind:?}"), "{}", decl.name);
        }
        let parallel = BUILT_INS.iter().find(|d| d.name == "Parallel").unwrap();
        let count = NodeKind::<()>::Parallel(crate::nodes::control::parallel::Parallel {
            policy: ParallelPolicy::RequireCount(2),
        });
        assert_eq!(
            count.declared_ports(parallel, 5),
            [("success_count", "2".into()), ("failure_count", "4".into())]
        );
    }

    #[test]
    fn entries_become_ports_read_at_run_time_and_bad_literals_are_named() {
        let repeat = BUILT_INS.iter().find(|d| d.name == "Repeat").unwrap();
        let entry = NodeKind::<()>::from_declared(repeat, &|_| PortBinding::Entry).unwrap();
        assert!(matches!(
            entry,
            Ok(NodeKind::Repeat(crate::nodes::decorator::repeat::Repeat {
                num_cycles: Param::Port
            }))
        ));
        assert!(entry.unwrap().declared_ports(repeat, 1).is_empty());
        let bad = NodeKind::<()>::from_declared(repeat, &|_| PortBinding::Literal("x".into()));
        assert_eq!(
            bad.unwrap().unwrap_err().to_string(),
            "port `num_cycles`: cannot read `x`"
        );
        let missing = NodeKind::<()>::from_declared(repeat, &|_| PortBinding::Missing);
        assert_eq!(
            missing.unwrap().unwrap_err(),
            PortBindingError::Missing {
                port: "num_cycles".into()
            }
        );
    }
}
