//! The path that failed, as every format marks it.

use neurotree_core::{Failure, NodeId};

/// The colour of the path that failed: the stroke of a failed node, so that the path reads
/// as failure's colour made bolder.
pub(crate) const PATH_COLOUR: &str = "#c92a2a";

/// The nodes on the path that failed in a tick (the root and its descendants down to the
/// node that decided it), each with its own reason in words when it gave one: what
/// [`Format::render_failed_path`](super::Format::render_failed_path) marks.
///
/// ```
/// use neurotree::render::FailedPath;
/// use neurotree::NodeId;
///
/// let mut path = FailedPath::new();
/// path.mark(NodeId(0), None);
/// path.mark(NodeId(2), Some("blocked (error 106)".into()));
/// assert!(path.contains(NodeId(2)) && !path.contains(NodeId(1)));
/// assert_eq!(path.reason(NodeId(2)), Some("blocked (error 106)"));
/// assert_eq!(path.reason(NodeId(0)), None);
/// ```
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FailedPath {
    /// By node id: `None` off the path; on it, the node's reason, if any.
    marks: Vec<Option<Option<String>>>,
}

impl FailedPath {
    /// No path: a picture drawn with it marks nothing.
    pub fn new() -> Self {
        Self::default()
    }

    /// The chain of [`Tree::last_failure`](neurotree_core::Tree::last_failure): each link's
    /// node, with its own reason as [`Reason`](neurotree_core::Reason)'s `Display` writes it.
    pub fn from_failure(failure: &Failure) -> Self {
        let mut path = Self::new();
        for link in &failure.links {
            path.mark(link.node, link.reason.as_ref().map(ToString::to_string));
        }
        path
    }

    /// Puts `node` on the path, with the reason it gave (replacing any it had).
    pub fn mark(&mut self, node: NodeId, reason: Option<String>) {
        let at = node.index();
        if self.marks.len() <= at {
            self.marks.resize(at + 1, None);
        }
        self.marks[at] = Some(reason);
    }

    /// Whether `node` is on the path.
    pub fn contains(&self, node: NodeId) -> bool {
        matches!(self.marks.get(node.index()), Some(Some(_)))
    }

    /// The reason `node` gave, if it is on the path and gave one.
    pub fn reason(&self, node: NodeId) -> Option<&str> {
        self.marks.get(node.index())?.as_ref()?.as_deref()
    }

    /// Whether no node is on the path.
    pub fn is_empty(&self) -> bool {
        self.marks.iter().all(Option::is_none)
    }

    /// The notes of the text drawings, by node id for `len` nodes: `failed`, or
    /// `failed: REASON`, on the path; empty off it.
    pub(crate) fn notes(&self, len: usize) -> Vec<String> {
        (0..len)
            .map(|i| match self.marks.get(i) {
                Some(Some(Some(reason))) => format!("failed: {reason}"),
                Some(Some(None)) => "failed".to_string(),
                _ => String::new(),
            })
            .collect()
    }

    /// Whether the edge from `parent` to `child` is on the path.
    pub(crate) fn joins(&self, parent: NodeId, child: NodeId) -> bool {
        self.contains(parent) && self.contains(child)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::Format;
    use neurotree_core::{Action, Blueprint, Handle, ManualClock, NodeStatus, Status, Tree};

    /// Fails with code 106, "blocked".
    struct Blocked;
    impl Action<()> for Blocked {
        fn tick(&self, h: &mut Handle<'_, ()>) -> Status {
            h.fail_with(106, "blocked")
        }
    }

    /// `mission` (0) runs `start` (1), then `reach` (2), a Fallback of `near` (3) and
    /// `follow` (4), which is blocked: the path is 0, 2, 4.
    fn failed() -> (std::sync::Arc<Blueprint<()>>, Vec<NodeStatus>, FailedPath) {
        let bp = Blueprint::<()>::builder()
            .sequence("mission", |s| {
                s.always_success("start").fallback("reach", |f| {
                    f.condition("near", |_: &()| false)
                        .action_node("follow", Blocked)
                })
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp.clone(), ManualClock::new());
        assert_eq!(tree.tick_once(&mut ()), Ok(Status::Failure));
        let path = FailedPath::from_failure(&tree.last_failure().unwrap());
        use NodeStatus::*;
        (bp, vec![Failure, Success, Failure, Failure, Failure], path)
    }

    #[test]
    fn a_failure_chain_marks_its_links_with_their_own_reasons() {
        let (_, _, path) = failed();
        let on: Vec<bool> = (0..5).map(|i| path.contains(NodeId(i))).collect();
        assert_eq!(on, [true, false, true, false, true]);
        let reasons: Vec<Option<&str>> = (0..5).map(|i| path.reason(NodeId(i))).collect();
        assert_eq!(
            reasons,
            [None, None, None, None, Some("blocked (error 106)")]
        );
        assert!(!path.is_empty());
        assert!(FailedPath::new().is_empty());
    }

    #[test]
    fn text_notes_each_node_on_the_path() {
        let (bp, statuses, path) = failed();
        assert_eq!(
            Format::Ascii.render_failed_path(&bp, &statuses, &path),
            "[F] mission (Sequence) -- failed\n\
             +-- [S] start (AlwaysSuccess)\n\
             \\-- [F] reach (Fallback) -- failed\n    \
             +-- [F] near (Condition)\n    \
             \\-- [F] follow (Action) -- failed: blocked (error 106)\n"
        );
        assert_eq!(
            Format::Unicode.render_failed_path(&bp, &statuses, &path),
            "[✗] mission (Sequence) -- failed\n\
             ├── [✓] start (AlwaysSuccess)\n\
             └── [✗] reach (Fallback) -- failed\n    \
             ├── [✗] near (Condition)\n    \
             └── [✗] follow (Action) -- failed: blocked (error 106)\n"
        );
    }

    #[test]
    fn dot_draws_the_path_red_and_wide_with_the_reason_in_the_label() {
        let (bp, statuses, path) = failed();
        assert_eq!(
            Format::Dot.render_failed_path(&bp, &statuses, &path),
            "digraph behavior_tree {\n  \
             graph [rankdir=TB, ordering=out, nodesep=0.25, ranksep=0.4, bgcolor=\"white\"];\n  \
             node [fontname=\"Helvetica,Arial,sans-serif\", fontsize=11, style=\"filled\", \
             fillcolor=\"#ffffff\", color=\"#495057\", penwidth=1.4];\n  \
             edge [color=\"#868e96\", arrowhead=none];\n  \
             n0 [label=\"→ mission\\nSequence\", shape=box, fillcolor=\"#ffe3e3\", \
             color=\"#c92a2a\", tooltip=\"FAILURE: failed\", penwidth=3];\n  \
             n1 [label=\"start\\nAlwaysSuccess\", shape=box, fillcolor=\"#d3f9d8\", \
             color=\"#2b8a3e\", tooltip=\"SUCCESS\", style=\"rounded,filled\"];\n  \
             n2 [label=\"? reach\\nFallback\", shape=box, fillcolor=\"#ffe3e3\", \
             color=\"#c92a2a\", tooltip=\"FAILURE: failed\", penwidth=3];\n  \
             n3 [label=\"near\\nCondition\", shape=ellipse, fillcolor=\"#ffe3e3\", \
             color=\"#c92a2a\", tooltip=\"FAILURE\"];\n  \
             n4 [label=\"follow\\nAction\\nblocked (error 106)\", shape=box, \
             fillcolor=\"#ffe3e3\", color=\"#c92a2a\", \
             tooltip=\"FAILURE: failed: blocked (error 106)\", penwidth=3, \
             style=\"rounded,filled\"];\n  \
             n0 -> n1;\n  \
             n0 -> n2 [color=\"#c92a2a\", penwidth=3];\n  \
             n2 -> n3;\n  \
             n2 -> n4 [color=\"#c92a2a\", penwidth=3];\n\
             }\n"
        );
    }

    #[test]
    fn mermaid_classes_the_path_and_styles_its_links() {
        let (bp, statuses, path) = failed();
        assert_eq!(
            Format::Mermaid.render_failed_path(&bp, &statuses, &path),
            "flowchart TD\n    \
             n0[\"→ mission<br/><i>Sequence</i>\"]\n    \
             n1(\"start<br/><i>AlwaysSuccess</i>\")\n    \
             n2[\"? reach<br/><i>Fallback</i>\"]\n    \
             n3([\"near<br/><i>Condition</i>\"])\n    \
             n4(\"follow<br/><i>Action</i><br/><b>blocked (error 106)</b>\")\n    \
             n0 --> n1\n    \
             n0 --> n2\n    \
             n2 --> n3\n    \
             n2 --> n4\n    \
             classDef success fill:#d3f9d8,stroke:#2b8a3e,color:#212529;\n    \
             class n1 success;\n    \
             classDef failure fill:#ffe3e3,stroke:#c92a2a,color:#212529;\n    \
             class n0,n2,n3,n4 failure;\n    \
             classDef failedpath stroke:#c92a2a,stroke-width:3px;\n    \
             class n0,n2,n4 failedpath;\n    \
             linkStyle 1,3 stroke:#c92a2a,stroke-width:3px;\n"
        );
    }

    /// The `<g>` element of node `id` in an SVG.
    fn group<'a>(svg: &'a str, id: &str) -> &'a str {
        let start = svg.find(&format!("<g id=\"{id}\"")).unwrap();
        let end = start + svg[start..].find("</g>").unwrap();
        &svg[start..end]
    }

    /// The first number of attribute `name` in `element`.
    fn attr(element: &str, name: &str) -> f64 {
        let at = element.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        let len = element[at..].find('"').unwrap();
        element[at..at + len].parse().unwrap()
    }

    #[test]
    fn svg_outlines_the_path_and_its_lines_red_and_writes_the_reason() {
        let (bp, statuses, path) = failed();
        let svg = Format::Svg.render_failed_path(&bp, &statuses, &path);
        let classes: Vec<&str> = (0..5)
            .map(|i| {
                let g = group(&svg, &format!("n{i}"));
                &g[g.find("class=\"").unwrap() + 7..g.find("\">").unwrap()]
            })
            .collect();
        assert_eq!(
            classes,
            [
                "node control failure failed-path",
                "node action success",
                "node control failure failed-path",
                "node condition failure",
                "node action failure failed-path",
            ]
        );
        for i in 0..5 {
            let outline = attr(group(&svg, &format!("n{i}")), "stroke-width");
            assert_eq!(outline, if path.contains(NodeId(i)) { 3.0 } else { 1.5 });
        }
        assert_eq!(
            group(&svg, "n4")
                .split("<title>")
                .nth(1)
                .and_then(|t| t.split("</title>").next()),
            Some("mission/reach/follow (Action): FAILURE -- failed: blocked (error 106)")
        );
        let reason = "<text class=\"reason\" x=\"229.5\" y=\"213\" font-size=\"10\" \
                      font-weight=\"bold\" text-anchor=\"middle\" fill=\"#c92a2a\">\
                      blocked (error 106)</text>";
        assert_eq!(svg.matches("class=\"reason\"").count(), 1);
        assert!(group(&svg, "n4").contains(reason));
        // Each red line runs from the bottom middle of a node on the path to the top
        // middle of its child on the path; the other lines keep the edge colour.
        let rect = |id: &str| {
            let g = group(&svg, id);
            let r = &g[g.find("<rect").unwrap()..];
            (
                attr(r, "x"),
                attr(r, "y"),
                attr(r, "width"),
                attr(r, "height"),
            )
        };
        let red: Vec<(f64, f64, f64, f64)> = svg
            .lines()
            .filter(|l| l.starts_with("<path class=\"failed-path\""))
            .map(|l| {
                assert!(l.ends_with("stroke=\"#c92a2a\" stroke-width=\"3\"/>"));
                let d = &l[l.find(" d=\"M").unwrap() + 5..];
                let d = &d[..d.find('"').unwrap()];
                let n: Vec<f64> = d
                    .split(['V', 'H', ' '])
                    .map(|v| v.parse().unwrap())
                    .collect();
                (n[0], n[1], n[3], n[4])
            })
            .collect();
        let link = |parent: &str, child: &str| {
            let (px, py, pw, ph) = rect(parent);
            let (cx, cy, cw, _) = rect(child);
            (px + pw / 2.0, py + ph, cx + cw / 2.0, cy)
        };
        assert_eq!(red, [link("n0", "n2"), link("n2", "n4")]);
        assert_eq!(svg.matches("<path d=").count(), 2);
    }

    #[test]
    fn reasons_are_escaped_in_every_format() {
        let (bp, statuses, _) = failed();
        let mut path = FailedPath::new();
        path.mark(NodeId(0), Some("say \"no\" <now> & #1".into()));
        let drawn = |f: Format| f.render_failed_path(&bp, &statuses, &path);
        assert!(drawn(Format::Dot).contains("\\nsay \\\"no\\\" <now> & #1\", shape=box"));
        assert!(drawn(Format::Mermaid)
            .contains("<br/><b>say #quot;no#quot; #lt;now#gt; #amp; #35;1</b>"));
        assert!(drawn(Format::Svg).contains(">say &quot;no&quot; &lt;now&gt; &amp; #1</text>"));
        assert!(drawn(Format::Ascii)
            .starts_with("[F] mission (Sequence) -- failed: say \"no\" <now> & #1\n"));
    }

    #[test]
    fn an_empty_path_draws_as_without_one() {
        let (bp, statuses, _) = failed();
        for format in Format::ALL {
            assert_eq!(
                format.render_failed_path(&bp, &statuses, &FailedPath::new()),
                format.render(&bp, Some(&statuses)),
                "{format}"
            );
        }
    }
}
