//! What makes `neurotree run` a test bench: substitution rules, blackboard values written
//! at a given tick, scripting enums, and every blackboard in the summary. `neurotree test`
//! runs scenario files, which say the same, through the library's `ScenarioBench`.

use std::path::PathBuf;

use neurotree::blackboard_json::scope_json;
use neurotree::xml::Substitutions;
use neurotree::{Blackboard, Registry, Tree, XmlLoader};
use serde_json::{Map, Value};

/// The test bench's flags of `neurotree run`.
#[derive(clap::Args, Debug, Default, Clone)]
pub struct TestbenchArgs {
    /// Apply BehaviorTree.CPP's substitution rules JSON (`TestNodeConfigs`,
    /// `SubstitutionRules`): the nodes a rule matches (by name, type, or a wildcard path)
    /// become test nodes or another registered type, and need no registration. Repeatable.
    #[arg(long = "substitute", value_name = "FILE")]
    pub substitutes: Vec<PathBuf>,
    /// TICK:KEY=VALUE written to the root blackboard just before tick TICK (value read as
    /// --set reads it); `--set` is tick 1.
    #[arg(long = "set-at", value_name = "TICK:KEY=VALUE", value_parser = tick_key_value)]
    pub set_at: Vec<(u32, String, String)>,
    /// NAME=VALUE: a scripting enum (BehaviorTree.CPP's registerScriptingEnum), for scripts
    /// and for ports that take a number.
    #[arg(long = "enum", value_name = "NAME=VALUE", value_parser = enum_value)]
    pub enums: Vec<(String, i64)>,
    /// Print every SubTree's blackboard in the summary too (`blackboards`, by the SubTree
    /// node's path), not only the root's.
    #[arg(long)]
    pub all_blackboards: bool,
}

/// A `TICK:KEY=VALUE` of `--set-at`.
fn tick_key_value(text: &str) -> Result<(u32, String, String), String> {
    let wrong = || format!("`{text}` should be TICK:KEY=VALUE, TICK a tick from 1");
    let (tick, rest) = text.split_once(':').ok_or_else(wrong)?;
    let (key, value) = rest.split_once('=').ok_or_else(wrong)?;
    match tick.trim().parse::<u32>() {
        Ok(tick) if tick >= 1 && !key.is_empty() => Ok((tick, key.to_string(), value.to_string())),
        _ => Err(wrong()),
    }
}

/// A `NAME=VALUE` of `--enum`.
fn enum_value(text: &str) -> Result<(String, i64), String> {
    let (name, value) = text
        .split_once('=')
        .ok_or_else(|| format!("`{text}` should be NAME=VALUE, VALUE an integer"))?;
    let value = value
        .trim()
        .parse::<i64>()
        .map_err(|_| format!("`{text}`: the value of an enum is an integer"))?;
    Ok((name.trim().to_string(), value))
}

impl TestbenchArgs {
    /// Registers the `--enum`s.
    pub fn register_enums<C: 'static>(&self, registry: &mut Registry<C>) -> Result<(), String> {
        for (name, value) in &self.enums {
            registry
                .register_enum(name, *value)
                .map_err(|e| format!("--enum {name}={value}: {e}"))?;
        }
        Ok(())
    }

    /// The loader with the `--substitute` files' rules applied.
    pub fn substitute<'r, C: 'static>(
        &self,
        mut loader: XmlLoader<'r, C>,
    ) -> Result<XmlLoader<'r, C>, String> {
        for file in &self.substitutes {
            let rules = Substitutions::read(file).map_err(|e| e.to_string())?;
            loader = loader.substitute(rules);
        }
        Ok(loader)
    }

    /// Writes the `--set-at` values of the ticks after `done` up to `upto`: those due
    /// before the coming tick, and any a tick of several passes went past.
    pub fn set_due(&self, done: u32, upto: u32, bb: &mut Blackboard) {
        for (tick, key, value) in &self.set_at {
            if *tick > done && *tick <= upto {
                neurotree::scenario::write_text(bb, key, value);
            }
        }
    }

    /// The blackboards of the summary beyond the root's, if asked for: each SubTree's own
    /// entries by the SubTree's path.
    pub fn blackboards(&self, tree: &Tree<()>) -> Option<Value> {
        self.all_blackboards
            .then(|| Value::Object(blackboards(tree)))
    }
}

/// Every blackboard of the tree: `"/"` for the root's, then each SubTree's own entries by
/// the SubTree node's path.
pub fn blackboards(tree: &Tree<()>) -> Map<String, Value> {
    let bp = tree.blueprint();
    let paths = bp.paths();
    let mut all = Map::new();
    all.insert(
        "/".into(),
        Value::Object(scope_json(tree.blackboard(), neurotree::ScopeId::ROOT)),
    );
    for id in bp.ids() {
        if let Some(scope) = tree.subtree_scope(id) {
            all.insert(
                paths[id.index()].clone(),
                Value::Object(scope_json(tree.blackboard(), scope)),
            );
        }
    }
    all
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_parse_and_refuse_with_the_form_to_write() {
        assert_eq!(
            tick_key_value("3:goal=dock"),
            Ok((3, "goal".into(), "dock".into()))
        );
        assert!(tick_key_value("0:goal=dock").is_err());
        assert!(tick_key_value("goal=dock")
            .unwrap_err()
            .contains("TICK:KEY=VALUE"));
        assert_eq!(enum_value("DOCKING=2"), Ok(("DOCKING".into(), 2)));
        assert!(enum_value("DOCKING=x").unwrap_err().contains("integer"));
    }
}
