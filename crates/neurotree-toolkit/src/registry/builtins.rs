//! The built-in node types the engine implements, under their BehaviorTree.CPP names, with
//! their families and ports; and the conversion between a node kind and its port values.

use neurotree_core::{Category, FromPortStr, NodeKind, ParallelPolicy, Param};

use super::PortSpec;

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

/// The built-in nodes, their families and their ports, as BehaviorTree.CPP declares them.
pub(crate) fn built_ins() -> Vec<(&'static str, Category, BuiltIn, Vec<PortSpec>)> {
    use BuiltIn as B;
    use Category::{Action, Control, Decorator};
    let ms = |name: &str| vec![PortSpec::input::<u64>(name)];
    vec![
        ("Sequence", Control, B::Sequence, vec![]),
        ("SequenceWithMemory", Control, B::SequenceWithMemory, vec![]),
        ("ReactiveSequence", Control, B::ReactiveSequence, vec![]),
        ("Fallback", Control, B::Fallback, vec![]),
        ("ReactiveFallback", Control, B::ReactiveFallback, vec![]),
        ("AsyncSequence", Control, B::AsyncSequence, vec![]),
        ("AsyncFallback", Control, B::AsyncFallback, vec![]),
        (
            "Parallel",
            Control,
            B::Parallel,
            vec![
                PortSpec::input::<i32>("success_count").default_value("-1"),
                PortSpec::input::<i32>("failure_count").default_value("1"),
            ],
        ),
        (
            "ParallelAll",
            Control,
            B::ParallelAll,
            vec![PortSpec::input::<i32>("max_failures").default_value("1")],
        ),
        ("IfThenElse", Control, B::IfThenElse, vec![]),
        ("WhileDoElse", Control, B::WhileDoElse, vec![]),
        (
            "TryCatch",
            Control,
            B::TryCatch,
            vec![PortSpec::input::<bool>("catch_on_halt").default_value("false")],
        ),
        ("Inverter", Decorator, B::Inverter, vec![]),
        ("ForceSuccess", Decorator, B::ForceSuccess, vec![]),
        ("ForceFailure", Decorator, B::ForceFailure, vec![]),
        (
            "Repeat",
            Decorator,
            B::Repeat,
            vec![PortSpec::input::<i32>("num_cycles")],
        ),
        (
            "RetryUntilSuccessful",
            Decorator,
            B::RetryUntilSuccessful,
            vec![PortSpec::input::<i32>("num_attempts")],
        ),
        (
            "KeepRunningUntilFailure",
            Decorator,
            B::KeepRunningUntilFailure,
            vec![],
        ),
        ("Delay", Decorator, B::Delay, ms("delay_msec")),
        ("Timeout", Decorator, B::Timeout, ms("msec")),
        ("Cooldown", Decorator, B::Cooldown, ms("cooldown_msec")),
        (
            "RunOnce",
            Decorator,
            B::RunOnce,
            vec![PortSpec::input::<bool>("then_skip").default_value("true")],
        ),
        ("AlwaysSuccess", Action, B::AlwaysSuccess, vec![]),
        ("AlwaysFailure", Action, B::AlwaysFailure, vec![]),
        ("Sleep", Action, B::Sleep, ms("msec")),
    ]
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
/// saved file writes for the node. `children` resolves the Parallel shorthands the builder
/// offers into BehaviorTree.CPP's thresholds.
pub(crate) fn built_in_ports<C>(
    kind: &NodeKind<C>,
    children: usize,
) -> Vec<(&'static str, String)> {
    // A parameter read from a port has no value here: such a node keeps its port
    // bindings, which the writer writes instead.
    fn text<T: ToString>(name: &'static str, p: &Param<T>) -> Option<(&'static str, String)> {
        match p {
            Param::Value(v) => Some((name, v.to_string())),
            Param::Port => None,
        }
    }
    let ms = |name: &'static str, d: &Param<std::time::Duration>| match d {
        Param::Value(d) => Some((name, d.as_millis().to_string())),
        Param::Port => None,
    };
    let ports: Vec<Option<(&'static str, String)>> = match kind {
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
            vec![
                text("success_count", &success),
                text("failure_count", &failure),
            ]
        }
        NodeKind::ParallelAll { max_failures } => vec![text("max_failures", max_failures)],
        NodeKind::TryCatch { catch_on_halt } => vec![text("catch_on_halt", catch_on_halt)],
        NodeKind::Repeat { num_cycles } => vec![text("num_cycles", num_cycles)],
        NodeKind::RetryUntilSuccessful { num_attempts } => {
            vec![text("num_attempts", num_attempts)]
        }
        NodeKind::Delay(d) => vec![ms("delay_msec", d)],
        NodeKind::Timeout(d) | NodeKind::Sleep(d) => vec![ms("msec", d)],
        NodeKind::Cooldown(d) => vec![ms("cooldown_msec", d)],
        NodeKind::RunOnce { then_skip } => vec![text("then_skip", then_skip)],
        _ => Vec::new(),
    };
    ports.into_iter().flatten().collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::registry::{Make, Registry};

    #[test]
    fn built_in_ports_read_back_into_the_same_kind() {
        let r = Registry::<()>::new();
        for t in r.types() {
            let Make::BuiltIn(b) = t.make else { continue };
            // Every port at a value other than the smallest, so a swapped pair would show.
            let kind = built_in_kind::<()>(b, |p| {
                Binding::Literal(match p {
                    "success_count" => "2".into(),
                    "failure_count" => "-1".into(),
                    "catch_on_halt" | "then_skip" => "true".into(),
                    _ => "7".into(),
                })
            })
            .unwrap();
            let ports = built_in_ports(&kind, 3);
            let again = built_in_kind::<()>(b, |p| match ports.iter().find(|(n, _)| *n == p) {
                Some((_, v)) => Binding::Literal(v.clone()),
                None => Binding::Missing,
            })
            .unwrap();
            assert_eq!(format!("{again:?}"), format!("{kind:?}"), "{}", t.name);
            assert_eq!(ports.len(), t.ports.len(), "{}", t.name);
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
        assert_eq!(repeat.category, Category::Decorator);
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
