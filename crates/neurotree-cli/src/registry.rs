//! The node types the commands know before they read a file.

use neurotree::{nav2, Registry};

/// The built-in nodes and Nav2's control nodes (PipelineSequence, RecoveryNode,
/// RoundRobin, RateController and the goal nodes), so that Nav2's trees run with only
/// their leaves mocked and check without a model for their controls.
pub fn with_nav2_controls<C: 'static>() -> Registry<C> {
    let mut registry = Registry::new();
    // A fresh registry holds only the built-in nodes, none of which has a Nav2 name, so
    // registering Nav2's cannot meet a taken name.
    nav2::register_controls(&mut registry).expect("Nav2's names are free in a fresh registry");
    registry
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nav2_controls_are_known() {
        let registry = with_nav2_controls::<()>();
        for name in [
            "PipelineSequence",
            "RecoveryNode",
            "RoundRobin",
            "RateController",
        ] {
            assert!(registry.get(name).is_some(), "{name}");
        }
    }
}
