//! What `neurotree lint` costs once the files are loaded: the analysis alone, on tree1111
//! (`corpus/bench`, 1,111 nodes) and on each of Nav2's trees (`corpus/nav2`, with Nav2's
//! controls and model and the entries its navigators write, as `--nav2` lints them).
//!
//! `cargo bench -p neurotree-bench --bench lint`

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use neurotree::lint::{lint, LintOptions};
use neurotree::nav2::{register_release, Nav2Release};
use neurotree::{Registry, XmlLoader};

fn corpus(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../corpus")
        .join(relative)
}

/// Validates every tree `loader` holds, as `neurotree lint` does before it lints.
fn validate(loader: &XmlLoader<'_, ()>) {
    let ids: Vec<String> = loader.tree_ids().map(String::from).collect();
    for id in ids {
        loader.validate(&id).expect("the corpus's trees validate");
    }
}

fn bench_lint(c: &mut Criterion) {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry).mock_unknown(true);
    loader
        .load_file(corpus("bench/tree1111.xml"))
        .expect("tree1111 loads");
    validate(&loader);
    let options = LintOptions::default();
    c.bench_function("lint/tree1111", |b| {
        b.iter(|| black_box(lint(&loader, &options)))
    });

    let mut nav2 = Registry::<()>::new();
    register_release(&mut nav2, Nav2Release::Main).expect("Nav2's names are free");
    let options = LintOptions::nav2();
    let mut files: Vec<PathBuf> = std::fs::read_dir(corpus("nav2"))
        .expect("corpus/nav2")
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "xml"))
        .filter(|p| !p.ends_with("nav2_tree_nodes.xml"))
        .collect();
    files.sort();
    for file in files {
        let mut loader = XmlLoader::new(&nav2);
        loader.load_file(&file).expect("Nav2's tree loads");
        validate(&loader);
        let name = file.file_stem().expect("a file name").to_string_lossy();
        c.bench_function(&format!("lint/nav2/{name}"), |b| {
            b.iter(|| black_box(lint(&loader, &options)))
        });
    }
}

criterion_group!(benches, bench_lint);
criterion_main!(benches);
