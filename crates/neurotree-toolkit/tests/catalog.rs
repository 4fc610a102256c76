//! The guide's node catalog (docs/guide/catalog.md) is made from the built-in nodes' declarations, so that it
//! cannot drift from them: a node added, renamed or given a port changes the table, and this
//! test shows the table the guide must carry.

use neurotree::nodes::built_ins;
use neurotree::{NodeDecl, PortDecl, PortDirection};

const CATALOG: &str = include_str!("../../../docs/guide/catalog.md");

/// One port, as the catalog shows it: `` `name` i32 = default ``, with an arrow for what
/// the node writes.
fn port_cell(p: &PortDecl) -> String {
    let arrow = match p.direction {
        PortDirection::Input => "",
        PortDirection::Output => "→ ",
        PortDirection::InOut => "↔ ",
    };
    let default = p.default.map(|d| format!(" = {d}")).unwrap_or_default();
    format!("{arrow}`{}` {}{default}", p.name, p.type_name)
}

fn row(d: &NodeDecl) -> String {
    let ports: Vec<String> = d.ports.iter().map(port_cell).collect();
    let ports = if ports.is_empty() {
        "—".to_string()
    } else {
        ports.join(", ")
    };
    format!(
        "| {} | {} | {} | {} | {} |\n",
        d.name,
        d.category.as_str(),
        d.arity,
        ports,
        d.summary
    )
}

/// The catalog table of every built-in node, in declaration order.
fn catalog() -> String {
    let mut table = String::from("| node | family | children | ports | in short |\n");
    table.push_str("|---|---|---|---|---|\n");
    for d in built_ins() {
        table.push_str(&row(d));
    }
    table
}

#[test]
fn the_readme_catalog_is_the_declarations() {
    let section = CATALOG
        .split("# Node catalog\n")
        .nth(1)
        .expect("the guide's catalog has its `# Node catalog` title")
        .split("\n## ")
        .next()
        .unwrap_or_default();
    let table = catalog();
    assert!(
        section.contains(&format!("\n{table}\n")),
        "The guide's node catalog (docs/guide/catalog.md) differs from the declarations; put this table there:\n\n{table}"
    );
}
