//! How the engine's built-in nodes are made from their ports, and read back into ports.
//!
//! What a built-in is (name, family, children, ports) is its declaration in its own module
//! ([`neurotree_core::nodes::BUILT_INS`]); the registry is built from those. What is left
//! here needs the tree's context type: making a [`NodeKind`] from the ports' values
//! ([`built_in_kind`]) and reading them back for the XML writer ([`built_in_ports`]).
//! [`BuiltIn`] names the kinds; `built_in_kinds_and_declarations_match` checks that every
//! declaration has one and every one a declaration.

use neurotree_core::nodes::{control, decorator, leaf, NodeDecl};
use neurotree_core::{FromPortStr, NodeKind, ParallelPolicy, Param};

/// The built-in nodes the loader knows how to build from their ports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BuiltIn {
    Sequence,
    SequenceWithMemory,
    ReactiveSequence,
    Fallback,
    ReactiveFallback,
    AsyncSequence,
    AsyncFallback,
    Parallel,
    ParallelAll,
    IfThenElse,
    WhileDoElse,
    TryCatch,
    Inverter,
    ForceSuccess,
    ForceFailure,
    Repeat,
    RetryUntilSuccessful,
    KeepRunningUntilFailure,
    Delay,
    Timeout,
    Cooldown,
    RunOnce,
    AlwaysSuccess,
    AlwaysFailure,
    Sleep,
}

impl BuiltIn {
    /// Every built-in kind.
    pub(crate) const ALL: [BuiltIn; 25] = [
        BuiltIn::Sequence,
        BuiltIn::SequenceWithMemory,
        BuiltIn::ReactiveSequence,
        BuiltIn::Fallback,
        BuiltIn::ReactiveFallback,
        BuiltIn::AsyncSequence,
        BuiltIn::AsyncFallback,
        BuiltIn::Parallel,
        BuiltIn::ParallelAll,
        BuiltIn::IfThenElse,
        BuiltIn::WhileDoElse,
        BuiltIn::TryCatch,
        BuiltIn::Inverter,
        BuiltIn::ForceSuccess,
        BuiltIn::ForceFailure,
        BuiltIn::Repeat,
        BuiltIn::RetryUntilSuccessful,
        BuiltIn::KeepRunningUntilFailure,
        BuiltIn::Delay,
        BuiltIn::Timeout,
        BuiltIn::Cooldown,
        BuiltIn::RunOnce,
        BuiltIn::AlwaysSuccess,
        BuiltIn::AlwaysFailure,
        BuiltIn::Sleep,
    ];

    /// The node's declaration, in its module.
    pub(crate) fn decl(self) -> &'static NodeDecl {
        match self {
            BuiltIn::Sequence => &control::sequence::SEQUENCE,
            BuiltIn::SequenceWithMemory => &control::sequence::SEQUENCE_WITH_MEMORY,
            BuiltIn::ReactiveSequence => &control::reactive::REACTIVE_SEQUENCE,
            BuiltIn::Fallback => &control::fallback::FALLBACK,
            BuiltIn::ReactiveFallback => &control::reactive::REACTIVE_FALLBACK,
            BuiltIn::AsyncSequence => &control::sequence::ASYNC_SEQUENCE,
            BuiltIn::AsyncFallback => &control::fallback::ASYNC_FALLBACK,
            BuiltIn::Parallel => &control::parallel::PARALLEL,
            BuiltIn::ParallelAll => &control::parallel_all::PARALLEL_ALL,
            BuiltIn::IfThenElse => &control::if_then_else::IF_THEN_ELSE,
            BuiltIn::WhileDoElse => &control::while_do_else::WHILE_DO_ELSE,
            BuiltIn::TryCatch => &control::try_catch::TRY_CATCH,
            BuiltIn::Inverter => &decorator::inverter::INVERTER,
            BuiltIn::ForceSuccess => &decorator::force::FORCE_SUCCESS,
            BuiltIn::ForceFailure => &decorator::force::FORCE_FAILURE,
            BuiltIn::Repeat => &decorator::repeat::REPEAT,
            BuiltIn::RetryUntilSuccessful => &decorator::retry::RETRY_UNTIL_SUCCESSFUL,
            BuiltIn::KeepRunningUntilFailure => {
                &decorator::keep_running::KEEP_RUNNING_UNTIL_FAILURE
            }
            BuiltIn::Delay => &decorator::delay::DELAY,
            BuiltIn::Timeout => &decorator::timeout::TIMEOUT,
            BuiltIn::Cooldown => &decorator::cooldown::COOLDOWN,
            BuiltIn::RunOnce => &decorator::run_once::RUN_ONCE,
            BuiltIn::AlwaysSuccess => &leaf::always::ALWAYS_SUCCESS,
            BuiltIn::AlwaysFailure => &leaf::always::ALWAYS_FAILURE,
            BuiltIn::Sleep => &leaf::sleep::SLEEP,
        }
    }

    /// The kind declared as `name`.
    pub(crate) fn named(name: &str) -> Option<BuiltIn> {
        BuiltIn::ALL.into_iter().find(|b| b.decl().name == name)
    }
}

/// What a built-in node's port is bound to, as [`built_in_kind`] needs to know it.
pub(crate) enum Binding {
    /// Literal text, read now.
    Literal(String),
    /// A blackboard entry, read by the node when it runs.
    Entry,
    /// Not given (and no default).
    Missing,
}

/// The kind of a built-in node from its ports: a literal is read now (already checked to
/// convert), a port bound to an entry becomes a [`Param::Port`] the node reads when it runs.
pub(crate) fn built_in_kind<C>(
    b: BuiltIn,
    port: impl Fn(&str) -> Binding,
) -> Result<NodeKind<C>, String> {
    use std::time::Duration;
    let param = |name: &str| -> Result<Param<String>, String> {
        match port(name) {
            Binding::Literal(text) => Ok(Param::Value(text)),
            Binding::Entry => Ok(Param::Port),
            Binding::Missing => Err(format!("missing port `{name}`")),
        }
    };
    fn read<T: FromPortStr>(name: &str, text: Param<String>) -> Result<Param<T>, String> {
        match text {
            Param::Value(text) => T::from_port_str(&text)
                .map(Param::Value)
                .map_err(|()| format!("port `{name}`: cannot read `{text}`")),
            Param::Port => Ok(Param::Port),
        }
    }
    let num = |name: &str| -> Result<Param<i32>, String> { read(name, param(name)?) };
    let flag = |name: &str| -> Result<Param<bool>, String> { read(name, param(name)?) };
    let ms = |name: &str| -> Result<Param<Duration>, String> {
        Ok(match read::<u64>(name, param(name)?)? {
            Param::Value(ms) => Param::Value(Duration::from_millis(ms)),
            Param::Port => Param::Port,
        })
    };
    Ok(match b {
        BuiltIn::Sequence => NodeKind::Sequence,
        BuiltIn::SequenceWithMemory => NodeKind::SequenceWithMemory,
        BuiltIn::ReactiveSequence => NodeKind::ReactiveSequence,
        BuiltIn::Fallback => NodeKind::Fallback,
        BuiltIn::ReactiveFallback => NodeKind::ReactiveFallback,
        BuiltIn::AsyncSequence => NodeKind::AsyncSequence,
        BuiltIn::AsyncFallback => NodeKind::AsyncFallback,
        BuiltIn::Parallel => {
            let (success, failure) = (num("success_count")?, num("failure_count")?);
            NodeKind::Parallel(match (success, failure) {
                (Param::Value(success), Param::Value(failure)) => {
                    ParallelPolicy::Thresholds { success, failure }
                }
                (success, failure) => ParallelPolicy::Ports { success, failure },
            })
        }
        BuiltIn::ParallelAll => NodeKind::ParallelAll {
            max_failures: num("max_failures")?,
        },
        BuiltIn::IfThenElse => NodeKind::IfThenElse,
        BuiltIn::WhileDoElse => NodeKind::WhileDoElse,
        BuiltIn::TryCatch => NodeKind::TryCatch {
            catch_on_halt: flag("catch_on_halt")?,
        },
        BuiltIn::Inverter => NodeKind::Inverter,
        BuiltIn::ForceSuccess => NodeKind::ForceSuccess,
        BuiltIn::ForceFailure => NodeKind::ForceFailure,
        BuiltIn::Repeat => NodeKind::Repeat {
            num_cycles: num("num_cycles")?,
        },
        BuiltIn::RetryUntilSuccessful => NodeKind::RetryUntilSuccessful {
            num_attempts: num("num_attempts")?,
        },
        BuiltIn::KeepRunningUntilFailure => NodeKind::KeepRunningUntilFailure,
        BuiltIn::Delay => NodeKind::Delay(ms("delay_msec")?),
        BuiltIn::Timeout => NodeKind::Timeout(ms("msec")?),
        BuiltIn::Cooldown => NodeKind::Cooldown(ms("cooldown_msec")?),
        BuiltIn::RunOnce => NodeKind::RunOnce {
            then_skip: flag("then_skip")?,
        },
        BuiltIn::AlwaysSuccess => NodeKind::AlwaysSuccess,
        BuiltIn::AlwaysFailure => NodeKind::AlwaysFailure,
        BuiltIn::Sleep => NodeKind::Sleep(ms("msec")?),
    })
}

/// The ports a built-in kind was made from, as [`built_in_kind`] reads them back: what a
/// saved file writes for the node, named as its declaration names them. `children` resolves
/// the Parallel shorthands the builder offers into BehaviorTree.CPP's thresholds.
pub(crate) fn built_in_ports<C>(
    kind: &NodeKind<C>,
    children: usize,
) -> Vec<(&'static str, String)> {
    // A parameter read from a port has no value here: such a node keeps its port
    // bindings, which the writer writes instead.
    fn text<T: ToString>(p: &Param<T>) -> Option<String> {
        match p {
            Param::Value(v) => Some(v.to_string()),
            Param::Port => None,
        }
    }
    let ms = |d: &Param<std::time::Duration>| match d {
        Param::Value(d) => Some(d.as_millis().to_string()),
        Param::Port => None,
    };
    // The values in the order of the declared ports.
    let values: Vec<Option<String>> = match kind {
        NodeKind::Parallel(policy) => {
            let n = children as i32;
            let (success, failure) = match *policy {
                ParallelPolicy::Thresholds { success, failure } => {
                    (Param::Value(success), Param::Value(failure))
                }
                ParallelPolicy::Ports { success, failure } => (success, failure),
                ParallelPolicy::RequireAll => (Param::Value(-1), Param::Value(1)),
                ParallelPolicy::RequireOne => (Param::Value(1), Param::Value(-1)),
                ParallelPolicy::RequireCount(m) => {
                    (Param::Value(m as i32), Param::Value(n - m as i32 + 1))
                }
            };
            vec![text(&success), text(&failure)]
        }
        NodeKind::ParallelAll { max_failures } => vec![text(max_failures)],
        NodeKind::TryCatch { catch_on_halt } => vec![text(catch_on_halt)],
        NodeKind::Repeat { num_cycles } => vec![text(num_cycles)],
        NodeKind::RetryUntilSuccessful { num_attempts } => vec![text(num_attempts)],
        NodeKind::Delay(d) | NodeKind::Timeout(d) | NodeKind::Sleep(d) | NodeKind::Cooldown(d) => {
            vec![ms(d)]
        }
        NodeKind::RunOnce { then_skip } => vec![text(then_skip)],
        _ => return Vec::new(),
    };
    let Some(built_in) = BuiltIn::named(kind.type_name()) else {
        return Vec::new();
    };
    let names = built_in.decl().ports.iter().map(|p| p.name);
    names
        .zip(values)
        .filter_map(|(name, value)| Some((name, value?)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::registry::{Make, Registry};

    #[test]
    fn built_in_kinds_and_declarations_match() {
        // Every declaration has a kind, and every kind a declaration in the list.
        for decl in neurotree_core::nodes::BUILT_INS {
            let b = BuiltIn::named(decl.name);
            assert!(b.is_some(), "{} is declared but has no BuiltIn", decl.name);
        }
        for b in BuiltIn::ALL {
            let listed = neurotree_core::nodes::BUILT_INS
                .iter()
                .any(|d| *d == b.decl());
            assert!(listed, "{b:?}'s declaration is not in BUILT_INS");
            // The kind made from the declared ports is what the declaration says.
            let decl = b.decl();
            let kind = built_in_kind::<()>(b, |p| match decl.port(p) {
                Some(port) => Binding::Literal(sample(port).into()),
                None => Binding::Missing,
            })
            .unwrap_or_else(|e| panic!("{}: {e}", decl.name));
            assert_eq!(kind.type_name(), decl.name);
            assert_eq!(kind.arity(), decl.arity, "{}", decl.name);
            assert_eq!(kind.category(), decl.category, "{}", decl.name);
        }
    }

    /// A literal of the port's type, other than its default and the smallest value, so
    /// that a swapped pair of ports would show.
    fn sample(port: &neurotree_core::PortDecl) -> &'static str {
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

    #[test]
    fn built_in_ports_read_back_into_the_same_kind() {
        let r = Registry::<()>::new();
        for t in r.types() {
            let Make::BuiltIn(b) = t.make else { continue };
            let decl = b.decl();
            // Only the declared names are given, so a kind reading another name fails.
            let kind = built_in_kind::<()>(b, |p| match decl.port(p) {
                Some(port) => Binding::Literal(sample(port).into()),
                None => Binding::Missing,
            })
            .unwrap();
            let ports = built_in_ports(&kind, 3);
            let again = built_in_kind::<()>(b, |p| match ports.iter().find(|(n, _)| *n == p) {
                Some((_, v)) => Binding::Literal(v.clone()),
                None => Binding::Missing,
            })
            .unwrap();
            assert_eq!(format!("{again:?}"), format!("{kind:?}"), "{}", t.name);
            let names: Vec<&str> = ports.iter().map(|(n, _)| *n).collect();
            let declared: Vec<&str> = decl.ports.iter().map(|p| p.name).collect();
            assert_eq!(names, declared, "{}", t.name);
        }
        let count = NodeKind::<()>::Parallel(ParallelPolicy::RequireCount(2));
        assert_eq!(
            built_in_ports(&count, 5),
            [("success_count", "2".into()), ("failure_count", "4".into())]
        );
    }

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
    fn built_in_kinds_read_their_ports() {
        let literal = |text: &str| {
            let text = text.to_string();
            move |p: &str| match p {
                "num_cycles" => Binding::Literal(text.clone()),
                _ => Binding::Missing,
            }
        };
        let kind = built_in_kind::<()>(BuiltIn::Repeat, literal("3"));
        assert!(matches!(
            kind,
            Ok(NodeKind::Repeat {
                num_cycles: Param::Value(3)
            })
        ));
        // An entry is read by the node when it runs; a Parallel with one goes by its ports.
        let kind = built_in_kind::<()>(BuiltIn::Repeat, |_| Binding::Entry);
        assert!(matches!(
            kind,
            Ok(NodeKind::Repeat {
                num_cycles: Param::Port
            })
        ));
        let kind = built_in_kind::<()>(BuiltIn::Parallel, |p| match p {
            "success_count" => Binding::Entry,
            _ => Binding::Literal("1".into()),
        });
        assert!(matches!(
            kind,
            Ok(NodeKind::Parallel(ParallelPolicy::Ports {
                success: Param::Port,
                failure: Param::Value(1)
            }))
        ));
        let missing = built_in_kind::<()>(BuiltIn::Timeout, |_| Binding::Missing);
        assert_eq!(missing.err().as_deref(), Some("missing port `msec`"));
    }
}
