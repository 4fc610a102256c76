//! `neurotree models`: the `TreeNodesModel` of the node types NeuroTree has, as
//! BehaviorTree.CPP's `writeTreeNodesModelXML` writes a factory's, for Groot2 and the
//! studio to know them.
//!
//! With `--nav2[=RELEASE]`, Nav2's node types of that release (main when none is given).
//! For main: its controls and decorators, and its conditions and actions as the simulator
//! implements them (their ports, defaults and descriptions), the one it cannot give a
//! meaning (AssistedTeleop) as Nav2's model declares it. For Jazzy and Kilted: the types as
//! their own models declare them (NeuroTree's nodes have main's ports). The document is BehaviorTree.CPP format 4:
//! one `<Action>`, `<Condition>`, `<Control>` or `<Decorator>` per type, by name, with its
//! `input_port`, `output_port` and `inout_port` elements (name, type, default, description).
//! Port types are the Rust types the ports convert to, as BehaviorTree.CPP writes the
//! demangled C++ types.

use std::io::{self, Write};
use std::path::PathBuf;

use neurotree::nav2::{register_release, Nav2Release};
use neurotree::sim::nav2::{register_nav2_leaves, Nav2Sim};
use neurotree::Registry;

use crate::Outcome;

/// What `neurotree models` was asked to write.
#[derive(clap::Args, Debug)]
pub struct ModelsArgs {
    /// Nav2's node types, of a release: jazzy, kilted or main (main when none is given).
    #[arg(
        long,
        value_name = "RELEASE",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "main",
        required = true
    )]
    pub nav2: Option<Nav2Release>,
    /// Write the model to FILE instead of standard output.
    #[arg(long, short, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

/// The `TreeNodesModel` document of Nav2's node types of `release`: for main, as NeuroTree
/// implements them (its controls and simulated leaves, AssistedTeleop as Nav2 declares it);
/// for an older release, as that release's model declares them, since NeuroTree's nodes
/// have main's ports.
pub fn nav2_model(release: Nav2Release) -> String {
    let mut registry = Registry::<Nav2Sim>::new();
    if release == Nav2Release::Main {
        // A fresh registry holds only the built-ins, none of which has a Nav2 name.
        register_nav2_leaves(&mut registry).expect("Nav2's names are free in a fresh registry");
        register_release(&mut registry, release).expect("Nav2's names are free but for its leaves");
    } else {
        // The model is part of the program; the test below loads it.
        let _ = registry.add_model_str(release.model(), &release.model_file());
    }
    registry.tree_nodes_model()
}

/// Writes the model to the output file or `out`: Done, or Refused when the file cannot be
/// written (the error is on `err`).
pub fn execute(
    args: &ModelsArgs,
    out: &mut impl Write,
    err: &mut impl Write,
) -> io::Result<Outcome> {
    let release = args.nav2.unwrap_or_default();
    let model = nav2_model(release);
    match &args.output {
        None => {
            out.write_all(model.as_bytes())?;
            Ok(Outcome::Done)
        }
        Some(path) => match std::fs::write(path, model) {
            Ok(()) => Ok(Outcome::Done),
            Err(e) => {
                writeln!(
                    err,
                    "{}: error: cannot write the model: {e}",
                    path.display()
                )?;
                Ok(Outcome::Refused)
            }
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_releases_model_lists_its_types_and_loads_back() {
        for (release, count) in [
            (Nav2Release::Jazzy, 65),
            (Nav2Release::Kilted, 70),
            (Nav2Release::Main, 81),
        ] {
            let model = nav2_model(release);
            assert_eq!(model.matches(" ID=\"").count(), count, "{release}");
            let mut registry = Registry::<()>::new();
            let added = registry.add_model_str(&model, "model.xml").unwrap();
            assert_eq!(added, count, "{release}");
            for name in release.types() {
                assert!(registry.get(name).is_some(), "{release}: {name}");
            }
        }
    }
}
