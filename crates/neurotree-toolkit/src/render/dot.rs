//! Graphviz DOT export: `dot -Tsvg tree.dot > tree.svg` draws it.
//!
//! One DOT node per tree node, with the id `n` followed by the [`NodeId`](neurotree_core::NodeId)
//! (stable for a given tree), the label `name` over the type name, the shape of the node's
//! family and, when statuses are given, the colour of its status (see the tables in
//! [`render`](super)). Edges go from parent to child, children in order.

use std::fmt::Write as _;

use neurotree_core::{Blueprint, NodeStatus};

use super::style::{node_views, paint, NodeView, Shape};

/// The tree `bp` as a Graphviz `digraph`; with `statuses` (by node id, Idle past the end)
/// each node is coloured by its status.
///
/// ```
/// use neurotree::render::render_dot;
/// use neurotree::{Blueprint, NodeStatus, Status};
///
/// let bp = Blueprint::<()>::builder()
///     .sequence("go", |s| s.action("step", |_: &mut ()| Status::Success))
///     .build()
///     .unwrap();
/// let dot = render_dot(&bp, Some(&[NodeStatus::Running, NodeStatus::Success]));
/// assert!(dot.starts_with("digraph behavior_tree {"));
/// assert!(dot.contains("n0 -> n1;"));
/// ```
pub fn render_dot<C>(bp: &Blueprint<C>, statuses: Option<&[NodeStatus]>) -> String {
    let mut out = String::from(
        "digraph behavior_tree {\n  \
         graph [rankdir=TB, ordering=out, nodesep=0.25, ranksep=0.4, bgcolor=\"white\"];\n  \
         node [fontname=\"Helvetica,Arial,sans-serif\", fontsize=11, style=\"filled\", \
         fillcolor=\"#ffffff\", color=\"#495057\", penwidth=1.4];\n  \
         edge [color=\"#868e96\", arrowhead=none];\n",
    );
    let views = node_views(bp, statuses);
    for view in &views {
        node_line(&mut out, view);
    }
    for view in &views {
        if let Some(parent) = bp.parent(view.id) {
            // Writing into a String cannot fail.
            let _ = writeln!(out, "  n{} -> n{};", parent.0, view.id.0);
        }
    }
    out.push_str("}\n");
    out
}

fn node_line(out: &mut String, view: &NodeView<'_>) {
    let mut label = escape(&view.title());
    if let Some(type_name) = &view.type_name {
        label.push_str("\\n");
        label.push_str(&escape(type_name));
    }
    let (shape, mut style) = match view.shape {
        Shape::Decorator => ("hexagon", vec!["filled"]),
        Shape::Condition => ("ellipse", vec!["filled"]),
        Shape::Action => ("box", vec!["rounded", "filled"]),
        _ => ("box", vec!["filled"]),
    };
    let _ = write!(out, "  n{} [label=\"{label}\", shape={shape}", view.id.0);
    if view.shape == Shape::SubTree {
        out.push_str(", peripheries=2");
    }
    if let Some(status) = view.status {
        let paint = paint(Some(status));
        if paint.dashed {
            style.push("dashed");
        }
        let _ = write!(
            out,
            ", fillcolor=\"{}\", color=\"{}\", tooltip=\"{}\"",
            paint.fill,
            paint.stroke,
            status.as_str()
        );
    }
    if style != ["filled"] {
        let _ = write!(out, ", style=\"{}\"", style.join(","));
    }
    out.push_str("];\n");
}

/// Text for the inside of a DOT double-quoted string: quotes and backslashes escaped (a
/// backslash would otherwise start one of Graphviz's `\N`, `\l` escapes).
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quotes_and_backslashes_are_escaped() {
        assert_eq!(escape(r#"say "hi" \N"#), r#"say \"hi\" \\N"#);
    }
}
