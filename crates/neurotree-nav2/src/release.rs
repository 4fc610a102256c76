//! Nav2's releases: which node types each one has, and the names Nav2 changed.
//!
//! Nav2's node types change from release to release: Kilted added the route server's nodes
//! to Jazzy's, and main (the next release) added the following, stop and occupancy checks,
//! three controls, and renamed two conditions. A [`Nav2Release`] knows its model
//! (`nav2_tree_nodes.xml` as that release's branch ships it); [`register_release`] makes a
//! registry that knows exactly its types, so a file checked against Jazzy is refused if it
//! uses a node Jazzy does not have. With main, the names Nav2 changed ([`RENAMED`]) load
//! from older files as their new names, with a warning.
//!
//! The controls and decorators an older release has are NeuroTree's, which follow Nav2 main:
//! with Jazzy or Kilted, RoundRobin still takes `wrap_around` (added after Kilted) and runs
//! as main's does, and GoalUpdater takes `input_goals` / `output_goals` (added after Jazzy).
//! The other types of an older release are declared by its own model, with its ports.

use std::fmt;
use std::str::FromStr;

use neurotree_toolkit::{Registry, RegistryError};

/// A release of Nav2 whose node types NeuroTree knows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Nav2Release {
    /// Jazzy Jalisco (ROS 2 Jazzy, May 2024): 65 types.
    Jazzy,
    /// Kilted Kaiju (ROS 2 Kilted, May 2025): 70 types.
    Kilted,
    /// The main branch, the next release: 81 types.
    #[default]
    Main,
}

/// Nav2 Jazzy's model (`nav2_tree_nodes.xml` of the `jazzy` branch, commit f4108e5).
pub const NAV2_JAZZY_TREE_NODES_MODEL: &str = include_str!("models/nav2_tree_nodes_jazzy.xml");

/// Nav2 Kilted's model (`nav2_tree_nodes.xml` of the `kilted` branch, commit 71a1d84).
pub const NAV2_KILTED_TREE_NODES_MODEL: &str = include_str!("models/nav2_tree_nodes_kilted.xml");

/// The names Nav2 main changed, with the new name: IsPathValid became ValidatePath and
/// IsStopped became CheckStopStatus (nav2 PR #5991), each the same node under its new name.
pub const RENAMED: [(&str, &str); 2] = [
    ("IsPathValid", "ValidatePath"),
    ("IsStopped", "CheckStopStatus"),
];

impl Nav2Release {
    /// Every release, oldest first.
    pub const ALL: [Nav2Release; 3] = [Nav2Release::Jazzy, Nav2Release::Kilted, Nav2Release::Main];

    /// Its name, as `--nav2=NAME` takes it.
    pub fn name(self) -> &'static str {
        match self {
            Nav2Release::Jazzy => "jazzy",
            Nav2Release::Kilted => "kilted",
            Nav2Release::Main => "main",
        }
    }

    /// Its `TreeNodesModel`.
    pub fn model(self) -> &'static str {
        match self {
            Nav2Release::Jazzy => NAV2_JAZZY_TREE_NODES_MODEL,
            Nav2Release::Kilted => NAV2_KILTED_TREE_NODES_MODEL,
            Nav2Release::Main => crate::NAV2_TREE_NODES_MODEL,
        }
    }

    /// The names of the node types its model lists.
    pub fn types(self) -> impl Iterator<Item = &'static str> {
        self.model()
            .split(" ID=\"")
            .skip(1)
            .filter_map(|rest| rest.split('"').next())
    }

    /// The file name its model goes by in messages.
    pub fn model_file(self) -> String {
        format!("nav2_tree_nodes.xml ({})", self.name())
    }
}

impl fmt::Display for Nav2Release {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is not a release NeuroTree knows.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[error("`{0}` is not a Nav2 release NeuroTree knows (jazzy, kilted or main)")]
pub struct UnknownRelease(pub String);

neurotree_core::debug_shows_message!(struct UnknownRelease(name));

impl FromStr for Nav2Release {
    type Err = UnknownRelease;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Nav2Release::ALL
            .into_iter()
            .find(|r| r.name() == text.trim().to_ascii_lowercase())
            .ok_or_else(|| UnknownRelease(text.to_string()))
    }
}

/// Makes `registry` know the node types of `release`, and only those of Nav2: Nav2's
/// controls and decorators and its two goal conditions ([`register_controls`](crate::register_controls))
/// when the release has them, and the release's other types as its model declares them
/// (types already registered, such as simulated leaves, stay as they are). With
/// [`Nav2Release::Main`], Nav2's old names ([`RENAMED`]) load as the new ones, with a
/// warning. Fails if one of Nav2's control names is taken.
pub fn register_release<C: 'static>(
    registry: &mut Registry<C>,
    release: Nav2Release,
) -> Result<(), RegistryError> {
    crate::register_controls(registry)?;
    let types: Vec<&str> = release.types().collect();
    for name in crate::CONTROLS {
        if !types.contains(&name) {
            registry.remove(name);
        }
    }
    // The model is part of the program; its test loads it.
    let _ = registry.add_model_str(release.model(), &release.model_file());
    if release == Nav2Release::Main {
        for (old, new) in RENAMED {
            registry.add_renamed(old, new, "renamed in Nav2 after Kilted");
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_toolkit::XmlLoader;

    #[test]
    fn each_release_knows_its_count_of_types() {
        let counts: Vec<(Nav2Release, usize)> =
            Nav2Release::ALL.map(|r| (r, r.types().count())).to_vec();
        assert_eq!(
            counts,
            [
                (Nav2Release::Jazzy, 65),
                (Nav2Release::Kilted, 70),
                (Nav2Release::Main, 81)
            ]
        );
        for release in Nav2Release::ALL {
            let mut registry = Registry::<()>::new();
            let plain = registry.types().count();
            register_release(&mut registry, release).unwrap();
            assert_eq!(
                registry.types().count() - plain,
                release.types().count(),
                "{release}"
            );
            for name in release.types() {
                assert!(registry.get(name).is_some(), "{release}: {name}");
            }
        }
        assert_eq!("Kilted".parse(), Ok(Nav2Release::Kilted));
        assert_eq!(
            "rolling".parse::<Nav2Release>().unwrap_err().to_string(),
            "`rolling` is not a Nav2 release NeuroTree knows (jazzy, kilted or main)"
        );
    }

    fn load(release: Nav2Release, body: &str) -> Result<Vec<String>, String> {
        let mut registry = Registry::<()>::new();
        register_release(&mut registry, release).unwrap();
        let mut loader = XmlLoader::new(&registry);
        let xml =
            format!(r#"<root BTCPP_format="4"><BehaviorTree ID="T">{body}</BehaviorTree></root>"#);
        loader.load_str(&xml, "t.xml").map_err(|e| e.to_string())?;
        loader.validate("T").map_err(|e| e.to_string())?;
        Ok(loader.warnings().iter().map(ToString::to_string).collect())
    }

    #[test]
    fn old_names_load_on_main_with_a_warning_and_new_ones_are_refused_by_older_releases() {
        let warnings = load(Nav2Release::Main, r#"<IsPathValid path="{path}"/>"#).unwrap();
        assert_eq!(
            warnings,
            ["t.xml:1:45: warning: `IsPathValid` is `ValidatePath` now (renamed in Nav2 after Kilted); it loads as `ValidatePath`, write that"]
        );
        let warnings = load(Nav2Release::Main, r#"<IsStopped duration_stopped="500"/>"#).unwrap();
        assert!(
            warnings[0].contains("`IsStopped` is `CheckStopStatus` now"),
            "{warnings:?}"
        );
        assert_eq!(load(Nav2Release::Kilted, r#"<IsStopped/>"#), Ok(vec![]));
        assert!(load(Nav2Release::Kilted, r#"<CheckStopStatus/>"#).is_err());
        // Jazzy has no PersistentSequence, so it refuses it even though NeuroTree has one.
        let refused = load(
            Nav2Release::Jazzy,
            r#"<PersistentSequence><AlwaysSuccess/></PersistentSequence>"#,
        );
        assert!(refused.unwrap_err().contains("PersistentSequence"));
        assert!(load(
            Nav2Release::Main,
            r#"<PersistentSequence><AlwaysSuccess/></PersistentSequence>"#
        )
        .is_ok());
    }
}
