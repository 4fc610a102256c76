//! The node types the commands know before they read a file.

use neurotree::{nav2, Registry};

/// `--nav2`, shared by `run`, `check` and `show`.
#[derive(clap::Args, Debug, Clone, Copy, Default)]
pub struct Nav2Args {
    /// Know every node type of Nav2 (its 81 types) without --model: the controls and
    /// decorators run as Nav2 runs them; the conditions and actions are declared by their
    /// ports, for --mock or --mock-unknown to replace.
    #[arg(long)]
    pub nav2: bool,
}

/// The built-in nodes and Nav2's controls, decorators and goal conditions, so that Nav2's
/// trees run with only their leaves mocked and check without a model for their controls;
/// with `nav2`, also the models of Nav2's other node types (its conditions and actions).
pub fn with_nav2_controls<C: 'static>(nav2: Nav2Args) -> Registry<C> {
    let mut registry = Registry::new();
    // A fresh registry holds only the built-in nodes, none of which has a Nav2 name, so
    // registering Nav2's cannot meet a taken name.
    nav2::register_controls(&mut registry).expect("Nav2's names are free in a fresh registry");
    if nav2.nav2 {
        // The model is part of the program, and the test below loads it.
        registry
            .add_model_str(nav2::NAV2_TREE_NODES_MODEL, "nav2_tree_nodes.xml")
            .expect("Nav2's model loads");
    }
    registry
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nav2_controls_are_known() {
        let registry = with_nav2_controls::<()>(Nav2Args::default());
        for name in [
            "PipelineSequence",
            "RecoveryNode",
            "RoundRobin",
            "RateController",
            "PersistentSequence",
            "SpeedController",
        ] {
            assert!(registry.get(name).is_some(), "{name}");
        }
        assert!(registry.get("ComputePathToPose").is_none());
    }

    #[test]
    fn with_nav2_every_one_of_its_81_types_is_known() {
        let plain = with_nav2_controls::<()>(Nav2Args::default());
        let registry = with_nav2_controls::<()>(Nav2Args { nav2: true });
        let added = registry.types().count() - plain.types().count();
        // 81 types, of which the 13 controls and decorators and the 2 goal conditions are
        // implemented already.
        assert_eq!(added, 81 - 15);
        for name in ["ComputePathToPose", "FollowPath", "IsBatteryLow", "Spin"] {
            assert!(registry.get(name).is_some(), "{name}");
        }
    }
}
