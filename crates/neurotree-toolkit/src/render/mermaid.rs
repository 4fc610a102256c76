//! Mermaid export: a `flowchart TD` that GitHub, GitLab and most documentation tools draw
//! from a fenced ```` ```mermaid ```` block.
//!
//! One Mermaid node per tree node, with the id `n` followed by the
//! [`NodeId`](neurotree_core::NodeId), the label `name` over the type name in italics, and
//! the Mermaid shape closest to the family's: a rectangle for controls, a hexagon for
//! decorators, a stadium for conditions, a rounded rectangle for actions, a subroutine box
//! for subtrees. With statuses, each node gets the class of its status (`success`,
//! `failure`, `running`, `idle`, `skipped`), defined with the colours of the tables in
//! [`render`](super).
//!
//! Drawn with a [`FailedPath`](super::FailedPath), the nodes on the path also get the class
//! `failedpath` (a red border three pixels wide), the links between them a `linkStyle` of
//! the same red and width, and a node that gave a reason has it in bold as the last line of
//! its label.

use std::fmt::Write as _;

use neurotree_core::{Blueprint, NodeStatus};

use super::failed::{FailedPath, PATH_COLOUR};
use super::style::{node_views, paint, printable, status_word, NodeView, Shape, STATUSES};

/// The tree `bp` as a Mermaid flowchart; with `statuses` (by node id, Idle past the end)
/// each node is coloured by its status.
///
/// ```
/// use neurotree::render::render_mermaid;
/// use neurotree::{Blueprint, Status};
///
/// let bp = Blueprint::<()>::builder()
///     .fallback("door", |f| f.condition("is_open", |_: &()| false))
///     .build()
///     .unwrap();
/// let chart = render_mermaid(&bp, None);
/// assert!(chart.starts_with("flowchart TD\n"));
/// assert!(chart.contains(r#"n1(["is_open<br/><i>Condition</i>"])"#));
/// ```
pub fn render_mermaid<C>(bp: &Blueprint<C>, statuses: Option<&[NodeStatus]>) -> String {
    draw(bp, statuses, &FailedPath::new())
}

/// [`render_mermaid`] with `failed` marked.
pub(crate) fn draw<C>(
    bp: &Blueprint<C>,
    statuses: Option<&[NodeStatus]>,
    failed: &FailedPath,
) -> String {
    let mut out = String::from("flowchart TD\n");
    let views = node_views(bp, statuses);
    for view in &views {
        node_line(&mut out, view, failed.reason(view.id));
    }
    // Mermaid numbers links in the order they are written, from 0.
    let mut failed_links = Vec::new();
    let mut link = 0;
    for view in &views {
        if let Some(parent) = bp.parent(view.id) {
            if failed.joins(parent, view.id) {
                failed_links.push(link.to_string());
            }
            link += 1;
            // Writing into a String cannot fail.
            let _ = writeln!(out, "    n{} --> n{}", parent.0, view.id.0);
        }
    }
    for status in STATUSES {
        let ids: Vec<String> = views
            .iter()
            .filter(|v| v.status == Some(status))
            .map(|v| format!("n{}", v.id.0))
            .collect();
        if ids.is_empty() {
            continue;
        }
        let paint = paint(Some(status));
        let word = status_word(status);
        let _ = write!(
            out,
            "    classDef {word} fill:{},stroke:{},color:#212529",
            paint.fill, paint.stroke
        );
        if paint.dashed {
            out.push_str(",stroke-dasharray:4 3");
        }
        let _ = writeln!(out, ";\n    class {} {word};", ids.join(","));
    }
    let on_path: Vec<String> = views
        .iter()
        .filter(|v| failed.contains(v.id))
        .map(|v| format!("n{}", v.id.0))
        .collect();
    if !on_path.is_empty() {
        // After the status classes, so that its stroke wins over theirs.
        let _ = writeln!(
            out,
            "    classDef failedpath stroke:{PATH_COLOUR},stroke-width:3px;\n    \
             class {} failedpath;",
            on_path.join(",")
        );
    }
    if !failed_links.is_empty() {
        let _ = writeln!(
            out,
            "    linkStyle {} stroke:{PATH_COLOUR},stroke-width:3px;",
            failed_links.join(",")
        );
    }
    out
}

fn node_line(out: &mut String, view: &NodeView<'_>, reason: Option<&str>) {
    let mut label = escape(&view.title());
    if let Some(type_name) = &view.type_name {
        let _ = write!(label, "<br/><i>{}</i>", escape(type_name));
    }
    if let Some(reason) = reason {
        let _ = write!(label, "<br/><b>{}</b>", escape(&printable(reason)));
    }
    let (open, close) = match view.shape {
        Shape::Decorator => ("{{", "}}"),
        Shape::Condition => ("([", "])"),
        Shape::Action => ("(", ")"),
        Shape::SubTree => ("[[", "]]"),
        _ => ("[", "]"),
    };
    let _ = writeln!(out, "    n{}{open}\"{label}\"{close}", view.id.0);
}

/// Text for a quoted Mermaid label, which Mermaid reads as HTML after replacing its own
/// `#name;` entity codes: the characters that would end the label, open a tag or an entity,
/// or start a Markdown string become entity codes.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '"' => out.push_str("#quot;"),
            '#' => out.push_str("#35;"),
            '&' => out.push_str("#amp;"),
            '<' => out.push_str("#lt;"),
            '>' => out.push_str("#gt;"),
            '`' => out.push_str("#96;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn label_breakers_become_entity_codes() {
        assert_eq!(
            escape(r#"a "b" <c> & #d `e`"#),
            "a #quot;b#quot; #lt;c#gt; #amp; #35;d #96;e#96;"
        );
    }
}
