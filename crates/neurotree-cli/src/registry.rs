//! The node types the commands know before they read a file.

use neurotree::nav2::{self, Nav2Release};
use neurotree::Registry;

/// `--nav2[=RELEASE]`, shared by `run`, `check` and `show`.
#[derive(clap::Args, Debug, Clone, Copy, Default)]
pub struct Nav2Args {
    /// Know every node type of a Nav2 release (jazzy, kilted or main; main when none is
    /// given: its 81 types) without --model, and only those of Nav2: the controls and
    /// decorators run as Nav2 runs them; the conditions and actions are declared by their
    /// ports, for --mock or --mock-unknown to replace. With main, the names Nav2 changed
    /// (IsPathValid, IsStopped) load as the new ones, with a warning.
    #[arg(
        long,
        value_name = "RELEASE",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "main"
    )]
    pub nav2: Option<Nav2Release>,
}

/// The built-in nodes and Nav2's controls, decorators and goal conditions, so that Nav2's
/// trees run with only their leaves mocked and check without a model for their controls;
/// with `--nav2`, exactly the types of the release asked for (see
/// [`nav2::register_release`]).
pub fn with_nav2_controls<C: 'static>(nav2: Nav2Args) -> Registry<C> {
    let mut registry = Registry::new();
    // A fresh registry holds only the built-in nodes, none of which has a Nav2 name, so
    // registering Nav2's cannot meet a taken name.
    let registered = match nav2.nav2 {
        Some(release) => nav2::register_release(&mut registry, release),
        None => nav2::register_controls(&mut registry),
    };
    registered.expect("Nav2's names are free in a fresh registry");
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
        let registry = with_nav2_controls::<()>(Nav2Args {
            nav2: Some(Nav2Release::Main),
        });
        let added = registry.types().count() - plain.types().count();
        // 81 types, of which the 13 controls and decorators and the 2 goal conditions are
        // implemented already.
        assert_eq!(added, 81 - 15);
        for name in ["ComputePathToPose", "FollowPath", "IsBatteryLow", "Spin"] {
            assert!(registry.get(name).is_some(), "{name}");
        }
    }

    #[test]
    fn an_older_release_knows_its_own_types_only() {
        let plain = with_nav2_controls::<()>(Nav2Args::default());
        for (release, count) in [(Nav2Release::Jazzy, 65), (Nav2Release::Kilted, 70)] {
            let registry = with_nav2_controls::<()>(Nav2Args {
                nav2: Some(release),
            });
            // Nav2's 15 controls and goal conditions are in the plain registry too, but
            // the release lacks some of them: they are gone.
            let nav2_types = registry.types().count() + 15 - plain.types().count();
            assert_eq!(nav2_types, count, "{release}");
            assert!(registry.get("PersistentSequence").is_none(), "{release}");
            assert!(registry.get("IsPathValid").is_some(), "{release}");
        }
    }
}
