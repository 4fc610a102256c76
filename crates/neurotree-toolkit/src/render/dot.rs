//! Graphviz DOT export: `dot -Tsvg tree.dot > tree.svg` draws it.
//!
//! One DOT node per tree node, with the id `n` followed by the [`NodeId`](neurotree_core::NodeId)
//! (stable for a given tree), the label `name` over the type name, the shape of the node's
//! family and, when statuses are given, the colour of its status (see the tables in
//! [`render`](super)). Edges go from parent to child, children in order.
//!
//! Drawn with a [`FailedPath`](super::FailedPath), the nodes on the path and the edges
//! between them are red and three times as wide (`color="#c92a2a", penwidth=3`), and a node
//! that gave a reason has it as a third line of its label.

use std::fmt::Write as _;

use neurotree_core::{Blueprint, NodeStatus};

use super::failed::{FailedPath, PATH_COLOUR};
use super::style::{node_views, paint, printable, NodeView, Shape};

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
    draw(bp, statuses, &FailedPath::new())
}

/// [`render_dot`] with `failed` marked.
pub(crate) fn draw<C>(
    bp: &Blueprint<C>,
    statuses: Option<&[NodeStatus]>,
    failed: &FailedPath,
) -> String {
    let mut out = String::from(
        "digraph behavior_tree {\n  \
         graph [rankdir=TB, ordering=out, nodesep=0.25, ranksep=0.4, bgcolor=\"white\"];\n  \
         node [fontname=\"Helvetica,Arial,sans-serif\", fontsize=11, style=\"filled\", \
         fillcolor=\"#ffffff\", color=\"#495057\", penwidth=1.4];\n  \
         edge [color=\"#868e96\", arrowhead=none];\n",
    );
    let views = node_views(bp, statuses);
    for view in &views {
        node_line(&mut out, view, failed);
    }
    for view in &views {
        if let Some(parent) = bp.parent(view.id) {
            // Writing into a String cannot fail.
            let _ = write!(out, "  n{} -> n{}", parent.0, view.id.0);
            if failed.joins(parent, view.id) {
                let _ = write!(out, " [color=\"{PATH_COLOUR}\", penwidth=3]");
            }
            out.push_str(";\n");
        }
    }
    out.push_str("}\n");
    out
}

fn node_line(out: &mut String, view: &NodeView<'_>, failed: &FailedPath) {
    let mut label = escape(&view.title());
    if let Some(type_name) = &view.type_name {
        label.push_str("\\n");
        label.push_str(&escape(type_name));
    }
    let reason = failed.reason(view.id);
    if let Some(reason) = reason {
        label.push_str("\\n");
        label.push_str(&escape(&printable(reason)));
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
    let on_path = failed.contains(view.id);
    if let Some(status) = view.status {
        let paint = paint(Some(status));
        if paint.dashed {
            style.push("dashed");
        }
        let stroke = if on_path { PATH_COLOUR } else { paint.stroke };
        let _ = write!(
            out,
            ", fillcolor=\"{}\", color=\"{stroke}\", tooltip=\"{}",
            paint.fill,
            status.as_str()
        );
        match reason {
            Some(reason) => {
                let _ = write!(out, ": failed: {}", escape(&printable(reason)));
            }
            None if on_path => out.push_str(": failed"),
            None => {}
        }
        out.push('"');
    } else if on_path {
        let _ = write!(out, ", color=\"{PATH_COLOUR}\"");
    }
    if on_path {
        out.push_str(", penwidth=3");
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
