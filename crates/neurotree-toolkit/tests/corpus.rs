//! The trees written elsewhere (`corpus/btcpp`): every file is loaded, with mock
//! leaves for the node types no test registers and stand-ins for the two custom controls.
//! The files that do not load yet are listed with the reason, so that a change in either
//! direction shows. Every tree that loads is also saved and loaded back.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use neurotree::xml::{write_xml, SaveOptions, Substitute, Substitutions};
use neurotree::{Arity, Blueprint, CustomNode, NodeCtx, NodeStatus, PortSpec, Registry, XmlLoader};

use crate::signature as support;
use support::signature;

use crate::corpus_dir;

fn corpus() -> PathBuf {
    corpus_dir::corpus("btcpp")
}

fn xml_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            out.extend(xml_files(&path));
        } else if path.extension().is_some_and(|e| e == "xml") {
            out.push(path);
        }
    }
    out.sort();
    out
}

/// A stand-in for the examples' custom controls: ticks its children as a Sequence would.
struct StandIn;

impl CustomNode<()> for StandIn {
    fn tick(&mut self, node: &mut NodeCtx<'_, '_, ()>) -> NodeStatus {
        for i in 0..node.child_count() {
            match node.tick_child(i) {
                NodeStatus::Success | NodeStatus::Skipped => {}
                other => return other,
            }
        }
        node.reset_children();
        NodeStatus::Success
    }
}

/// Files that belong together: the tutorials split over several embedded documents.
fn group(file: &Path) -> String {
    let name = file.file_name().unwrap().to_string_lossy().to_string();
    match name.rsplit_once("__") {
        Some((stem, _))
            if name.starts_with("examples__t07") || name.starts_with("examples__t14") =>
        {
            stem.to_string()
        }
        _ => name,
    }
}

/// Building tree `id` of `files` the general way gives `bp`: a substitution rule that
/// matches no node keeps every element off the loader's path for plain elements (no
/// attributes, no rules), which must open each node exactly as the general path does.
fn general_path_agrees(registry: &Registry<()>, files: &[PathBuf], id: &str, bp: &Blueprint<()>) {
    let mut rules = Substitutions::new();
    rules.add_rule("NoNodeIsNamedSo", Substitute::Node("AlwaysSuccess".into()));
    let mut loader = XmlLoader::new(registry)
        .mock_unknown(true)
        .base_dir(corpus())
        .substitute(rules);
    for file in files {
        loader.load_file(file).unwrap();
    }
    let general = loader.build(id).unwrap();
    assert_eq!(signature(bp), signature(&general), "{files:?} {id}");
    assert_eq!(bp.structure_hash(), general.structure_hash());
}

/// Saving `bp` and loading the saved file gives the same blueprint.
fn saves_and_loads_back(registry: &Registry<()>, bp: &Blueprint<()>, id: &str) {
    let opts = SaveOptions {
        tree_id: id.to_string(),
        ..SaveOptions::default()
    };
    let saved = write_xml(bp, registry, &opts);
    let mut loader = XmlLoader::new(registry).mock_unknown(true);
    loader.load_str(&saved, "saved.xml").unwrap();
    let again = loader.build(id).unwrap();
    assert_eq!(signature(bp), signature(&again), "{saved}");
}

#[test]
fn every_corpus_file_loads_or_is_listed() {
    let mut registry = Registry::<()>::new();
    registry
        .register_custom(
            "ManualSelector",
            // The example nests an empty one as a menu entry.
            Arity::AtLeast(0),
            vec![PortSpec::input::<bool>("repeat_last_selection")],
            || Box::new(StandIn),
        )
        .unwrap();
    registry
        .register_custom(
            "LoopPose",
            Arity::One,
            vec![
                PortSpec::input::<String>("queue"),
                PortSpec::output::<String>("value"),
            ],
            || Box::new(StandIn),
        )
        .unwrap();
    let mut groups: BTreeMap<String, Vec<PathBuf>> = BTreeMap::new();
    for file in xml_files(&corpus()) {
        groups.entry(group(&file)).or_default().push(file);
    }
    let mut failures = BTreeMap::new();
    let mut loaded = 0;
    for files in groups.values() {
        let mut loader = XmlLoader::new(&registry)
            .mock_unknown(true)
            .base_dir(corpus());
        let result = files
            .iter()
            .try_for_each(|f| loader.load_file(f))
            .and_then(|()| {
                let ids: Vec<String> = loader.tree_ids().map(String::from).collect();
                ids.iter().try_for_each(|id| {
                    let bp = loader.build(id)?;
                    saves_and_loads_back(&registry, &bp, id);
                    general_path_agrees(&registry, files, id, &bp);
                    Ok(())
                })
            });
        match result {
            Ok(()) => loaded += files.len(),
            Err(e) => {
                let name = files[0].file_name().unwrap().to_string_lossy().to_string();
                failures.insert(name, e.message);
            }
        }
    }
    // The three fuzzing seeds are invalid for BehaviorTree.CPP 4 too (a port it does not
    // declare, a decorator without a child).
    let expected: BTreeMap<String, &str> = [
        ("corpus2.xml", "unknown port `timeout_ms` on `Timeout`"),
        ("corpus3.xml", "unknown port `key` on `SetBlackboard`"),
        (
            "corpus4.xml",
            "`ForceSuccess` takes exactly 1 child, found 0",
        ),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect();
    assert_eq!(
        failures.keys().collect::<Vec<_>>(),
        expected.keys().collect::<Vec<_>>(),
        "{failures:#?}"
    );
    for (file, message) in &failures {
        assert!(message.starts_with(expected[file]), "{file}: {message}");
    }
    assert_eq!(loaded, 44);
}
