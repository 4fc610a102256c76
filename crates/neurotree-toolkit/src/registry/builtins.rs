//! The built-in node types the engine implements, under their BehaviorTree.CPP names, with
//! their families and ports; and the conversion between a node kind and its port values.

use neurotree_core::{Category, FromPortStr, NodeKind, ParallelPolicy};

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

/// The kind of a built-in node from its ports' values (already checked to convert).
pub(crate) fn built_in_kind<C>(
    b: BuiltIn,
    port: impl Fn(&str) -> Option<String>,
) -> Result<NodeKind<C>, String> {
    use std::time::Duration;
    fn num<T: FromPortStr>(name: &str, text: Option<String>) -> Result<T, String> {
        let text = text.ok_or_else(|| format!("missing port `{name}`"))?;
        T::from_port_str(&text).map_err(|()| format!("port `{name}`: cannot read `{text}`"))
    }
    let ms = |name: &str| num::<u64>(name, port(name)).map(Duration::from_millis);
    Ok(match b {
        BuiltIn::Sequence => NodeKind::Sequence,
        BuiltIn::SequenceWithMemory => NodeKind::SequenceWithMemory,
        BuiltIn::ReactiveSequence => NodeKind::ReactiveSequence,
        BuiltIn::Fallback => NodeKind::Fallback,
        BuiltIn::ReactiveFallback => NodeKind::ReactiveFallback,
        BuiltIn::AsyncSequence => NodeKind::AsyncSequence,
        BuiltIn::AsyncFallback => NodeKind::AsyncFallback,
        BuiltIn::Parallel => NodeKind::Parallel(ParallelPolicy::Thresholds {
            success: num("success_count", port("success_count"))?,
            failure: num("failure_count", port("failure_count"))?,
        }),
        BuiltIn::ParallelAll => NodeKind::ParallelAll {
            max_failures: num("max_failures", port("max_failures"))?,
        },
        BuiltIn::IfThenElse => NodeKind::IfThenElse,
        BuiltIn::WhileDoElse => NodeKind::WhileDoElse,
        BuiltIn::TryCatch => NodeKind::TryCatch {
            catch_on_halt: num("catch_on_halt", port("catch_on_halt"))?,
        },
        BuiltIn::Inverter => NodeKind::Inverter,
        BuiltIn::ForceSuccess => NodeKind::ForceSuccess,
        BuiltIn::ForceFailure => NodeKind::ForceFailure,
        BuiltIn::Repeat => NodeKind::Repeat {
            num_cycles: num("num_cycles", port("num_cycles"))?,
        },
        BuiltIn::RetryUntilSuccessful => NodeKind::RetryUntilSuccessful {
            num_attempts: num("num_attempts", port("num_attempts"))?,
        },
        BuiltIn::KeepRunningUntilFailure => NodeKind::KeepRunningUntilFailure,
        BuiltIn::Delay => NodeKind::Delay(ms("delay_msec")?),
        BuiltIn::Timeout => NodeKind::Timeout(ms("msec")?),
        BuiltIn::Cooldown => NodeKind::Cooldown(ms("cooldown_msec")?),
        BuiltIn::RunOnce => NodeKind::RunOnce {
            then_skip: num("then_skip", port("then_skip"))?,
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
    let ms = |d: &std::time::Duration| d.as_millis().to_string();
    match kind {
        NodeKind::Parallel(policy) => {
            let n = children as i32;
            let (success, failure) = match *policy {
                ParallelPolicy::Thresholds { success, failure } => (success, failure),
                ParallelPolicy::RequireAll => (-1, 1),
                ParallelPolicy::RequireOne => (1, -1),
                ParallelPolicy::RequireCount(m) => (m as i32, n - m as i32 + 1),
            };
            vec![
                ("success_count", success.to_string()),
                ("failure_count", failure.to_string()),
            ]
        }
        NodeKind::ParallelAll { max_failures } => vec![("max_failures", max_failures.to_string())],
        NodeKind::TryCatch { catch_on_halt } => vec![("catch_on_halt", catch_on_halt.to_string())],
        NodeKind::Repeat { num_cycles } => vec![("num_cycles", num_cycles.to_string())],
        NodeKind::RetryUntilSuccessful { num_attempts } => {
            vec![("num_attempts", num_attempts.to_string())]
        }
        NodeKind::Delay(d) => vec![("delay_msec", ms(d))],
        NodeKind::Timeout(d) | NodeKind::Sleep(d) => vec![("msec", ms(d))],
        NodeKind::Cooldown(d) => vec![("cooldown_msec", ms(d))],
        NodeKind::RunOnce { then_skip } => vec![("then_skip", then_skip.to_string())],
        _ => Vec::new(),
    }
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
                Some(match p {
                    "success_count" => "2".into(),
                    "failure_count" => "-1".into(),
                    "catch_on_halt" | "then_skip" => "true".into(),
                    _ => "7".into(),
                })
            })
            .unwrap();
            let ports = built_in_ports(&kind, 3);
            let again = built_in_kind::<()>(b, |p| {
                ports.iter().find(|(n, _)| *n == p).map(|(_, v)| v.clone())
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
        let kind =
            built_in_kind::<()>(BuiltIn::Repeat, |p| (p == "num_cycles").then(|| "3".into()));
        assert!(matches!(kind, Ok(NodeKind::Repeat { num_cycles: 3 })));
        let missing = built_in_kind::<()>(BuiltIn::Timeout, |_| None);
        assert_eq!(missing.err().as_deref(), Some("missing port `msec`"));
    }
}
