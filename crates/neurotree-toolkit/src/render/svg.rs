//! SVG drawn by NeuroTree itself: a tidy tree of shapes, no Graphviz needed.
//!
//! Each node is a box sized to its label, with the shape of its family and, when statuses
//! are given, the colours of its status and a badge (`✓`, `✗`, `▶`, `–`); see the tables in
//! [`render`](super). The boxes are placed by [`layout::tidy`](super::layout::tidy) and
//! joined parent to children by right-angled lines. Each node is a group with the id `n`
//! followed by its [`NodeId`](neurotree_core::NodeId), the classes of its family and
//! status, and a `<title>` (its path, type and status) that viewers show on hover. A legend
//! of the colours closes a picture drawn with statuses.
//!
//! Drawn with a [`FailedPath`](super::FailedPath), the nodes on the path get the class
//! `failed-path` and a red outline three pixels wide, the lines between them are drawn red
//! and as wide, over the others, with the class `failed-path`, and a node that gave a reason
//! shows it in red (class `reason`) under its name and type, and in its `<title>`.
//!
//! The output is plain XML with every text escaped and numbers rounded to a tenth, so the
//! same tree and statuses give the same bytes.

use std::fmt::Write as _;

use neurotree_core::{Blueprint, NodeId, NodeStatus};

use super::failed::{FailedPath, PATH_COLOUR};
use super::layout::{tidy, Layout, Placed, Size, Spacing};
use super::node_box::{
    box_size, direction_mark, direction_name, port_lines, ports_title, PortLine, FIRST_BASELINE,
    GLYPH_WIDTH, LINE_STEP, NAME_SIZE, NODE_HEIGHT, PORT_SIZE, SLANT, TYPE_SIZE,
};
use super::style::{node_views, paint, printable, status_word, NodeView, Paint, Shape, STATUSES};
use super::text_width::text_width;
use crate::xml::escape;

const MARGIN: f64 = 16.0;
const GLYPH_SIZE: f64 = 15.0;
const BADGE_RADIUS: f64 = 7.0;
const LEGEND_HEIGHT: f64 = 28.0;
const FONTS: &str = "Helvetica, Arial, 'DejaVu Sans', sans-serif";
const EDGE_COLOUR: &str = "#adb5bd";
/// A `{key}` binding's colour, apart from literal text.
const BINDING_COLOUR: &str = "#1864ab";
const PORT_NAME_COLOUR: &str = "#868e96";
/// The mark of a port's direction (`in`, `out`).
const DIRECTION_COLOUR: &str = "#5f3dc4";

/// The tree `bp` as a standalone SVG document; with `statuses` (by node id, Idle past the
/// end) each node is coloured by its status and a legend is added.
///
/// ```
/// use neurotree::render::render_svg;
/// use neurotree::{Blueprint, NodeStatus, Status};
///
/// let bp = Blueprint::<()>::builder()
///     .sequence("go", |s| s.action("step", |_: &mut ()| Status::Success))
///     .build()
///     .unwrap();
/// let svg = render_svg(&bp, Some(&[NodeStatus::Running, NodeStatus::Success]));
/// assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
/// assert!(svg.contains("class=\"node action success\""));
/// ```
pub fn render_svg<C>(bp: &Blueprint<C>, statuses: Option<&[NodeStatus]>) -> String {
    draw(bp, statuses, &FailedPath::new())
}

/// [`render_svg`] with `failed` marked.
pub(crate) fn draw<C>(
    bp: &Blueprint<C>,
    statuses: Option<&[NodeStatus]>,
    failed: &FailedPath,
) -> String {
    let words = STATUSES.map(|s| (s, status_word(s)));
    render_svg_with_legend(bp, statuses, &words, failed)
}

/// [`render_svg`] with the legend's entries given: each a status whose colours it shows
/// and the word that says what they mean in this picture.
pub(crate) fn render_svg_with_legend<C>(
    bp: &Blueprint<C>,
    statuses: Option<&[NodeStatus]>,
    legend_entries: &[(NodeStatus, &str)],
    failed: &FailedPath,
) -> String {
    let mut views = node_views(bp, statuses);
    // Under the name, the type as the file names it, as the studio's page draws it; the
    // shape already says what kind of node it is.
    for view in &mut views {
        let type_id = bp.type_id(view.id);
        view.type_name = (type_id != bp.name(view.id)).then(|| printable(type_id));
    }
    let ports: Vec<Vec<PortLine>> = views.iter().map(|v| port_lines(bp, v.id)).collect();
    let sizes: Vec<Size> = views
        .iter()
        .zip(&ports)
        .map(|(v, p)| box_size(v, p, failed.reason(v.id)))
        .collect();
    let children: Vec<Vec<usize>> = bp
        .ids()
        .map(|id| bp.children(id).iter().map(|c| c.index()).collect())
        .collect();
    // A blueprint is a tree rooted at node 0 with finite sizes, so the layout cannot fail;
    // an empty picture stands in should that ever change.
    let layout = tidy(&children, &sizes, Spacing::default()).unwrap_or_else(|_| Layout {
        nodes: Vec::new(),
        width: 0.0,
        height: 0.0,
    });
    let legend_width = if statuses.is_some() {
        legend_width(legend_entries)
    } else {
        0.0
    };
    let width = layout.width.max(legend_width) + 2.0 * MARGIN;
    let mut height = layout.height + 2.0 * MARGIN;
    if statuses.is_some() {
        height += LEGEND_HEIGHT;
    }
    let mut out = String::new();
    // Writing into a String cannot fail, here and below.
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         viewBox=\"0 0 {w} {h}\" font-family=\"{FONTS}\">",
        w = num(width),
        h = num(height),
    );
    let _ = writeln!(
        out,
        "<rect class=\"background\" width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>"
    );
    let placed: Vec<Placed> = layout
        .nodes
        .iter()
        .map(|p| Placed {
            x: p.x + MARGIN,
            y: p.y + MARGIN,
            size: p.size,
        })
        .collect();
    edges(&mut out, &placed, &children, failed);
    out.push_str("<g class=\"nodes\">\n");
    for ((view, p), ports) in views.iter().zip(&placed).zip(&ports) {
        node(&mut out, bp, view, p, ports, failed);
    }
    out.push_str("</g>\n");
    if statuses.is_some() {
        legend(
            &mut out,
            legend_entries,
            MARGIN,
            height - MARGIN - LEGEND_HEIGHT / 2.0,
        );
    }
    out.push_str("</svg>\n");
    out
}

/// Right-angled lines from each parent's bottom to its children's tops, bending halfway
/// between the rows, where no box is; those of the path that failed last, so that siblings'
/// lines, which share their first stretch, do not hide them.
fn edges(out: &mut String, nodes: &[Placed], children: &[Vec<usize>], failed: &FailedPath) {
    let _ = writeln!(
        out,
        "<g class=\"edges\" fill=\"none\" stroke=\"{EDGE_COLOUR}\" stroke-width=\"1.5\">"
    );
    let mut on_path = Vec::new();
    for (i, (parent, kids)) in nodes.iter().zip(children).enumerate() {
        let Some(&first) = kids.first() else {
            continue;
        };
        let bend = parent.bottom() + (nodes[first].y - parent.bottom()) / 2.0;
        for &c in kids {
            let child = &nodes[c];
            let d = format!(
                "M{} {}V{}H{}V{}",
                num(parent.x),
                num(parent.bottom()),
                num(bend),
                num(child.x),
                num(child.y)
            );
            // Node indices are node ids: the layout keeps the blueprint's order.
            if failed.joins(id_of(i), id_of(c)) {
                on_path.push(d);
            } else {
                let _ = writeln!(out, "<path d=\"{d}\"/>");
            }
        }
    }
    for d in on_path {
        let _ = writeln!(
            out,
            "<path class=\"failed-path\" d=\"{d}\" stroke=\"{PATH_COLOUR}\" stroke-width=\"3\"/>"
        );
    }
    out.push_str("</g>\n");
}

fn id_of(index: usize) -> NodeId {
    // A blueprint's ids are u32, so its indices fit.
    NodeId(u32::try_from(index).unwrap_or(u32::MAX))
}

fn node<C>(
    out: &mut String,
    bp: &Blueprint<C>,
    view: &NodeView<'_>,
    p: &Placed,
    ports: &[PortLine],
    failed: &FailedPath,
) {
    let on_path = failed.contains(view.id);
    let reason = failed.reason(view.id).map(printable);
    let mut paint = paint(view.status);
    let _ = write!(
        out,
        "<g id=\"n{}\" class=\"node {}",
        view.id.0,
        view.shape.family()
    );
    if let Some(status) = view.status {
        let _ = write!(out, " {}", status_word(status));
    }
    if on_path {
        out.push_str(" failed-path");
        paint.stroke = PATH_COLOUR;
    }
    out.push_str("\">");
    let mut title = super::style::printable(&bp.path(view.id)).into_owned();
    if let Some(type_name) = &view.type_name {
        let _ = write!(title, " ({type_name})");
    }
    if let Some(status) = view.status {
        let _ = write!(title, ": {}", status.as_str());
    }
    match &reason {
        Some(reason) => {
            let _ = write!(title, " -- failed: {reason}");
        }
        None if on_path => title.push_str(" -- failed"),
        None => {}
    }
    title.push_str(&ports_title(ports));
    let _ = write!(out, "<title>{}</title>", escape(&title));
    let width = if on_path { "3" } else { "1.5" };
    let (left, right) = outline(out, view.shape, p, paint, width);
    labels(out, view, p, (left + right) / 2.0, ports, reason.as_deref());
    if let Some(mark) = view.status.and_then(badge_mark) {
        badge(out, mark, view.shape, p, paint);
    }
    out.push_str("</g>\n");
}

/// Draws the node's shape (and a control's glyph); returns the horizontal span left for
/// the label.
fn outline(out: &mut String, shape: Shape, p: &Placed, paint: Paint, width: &str) -> (f64, f64) {
    let style = format!(
        "fill=\"{}\" stroke=\"{}\" stroke-width=\"{width}\"{}",
        paint.fill,
        paint.stroke,
        if paint.dashed {
            " stroke-dasharray=\"4 3\""
        } else {
            ""
        }
    );
    let (l, t, w, h) = (p.left(), p.y, p.size.width, p.size.height);
    match shape {
        Shape::Decorator => {
            let points = [
                (l, p.middle()),
                (l + SLANT, t),
                (l + w - SLANT, t),
                (l + w, p.middle()),
                (l + w - SLANT, t + h),
                (l + SLANT, t + h),
            ]
            .map(|(x, y)| format!("{},{}", num(x), num(y)))
            .join(" ");
            let _ = write!(out, "<polygon points=\"{points}\" {style}/>");
        }
        // Keep the label off the round ends.
        // Round ends of a two-line box's radius, however many lines it carries.
        Shape::Condition => {
            rect(out, p, NODE_HEIGHT / 2.0, &style);
            return (l + NODE_HEIGHT / 4.0, l + w - NODE_HEIGHT / 4.0);
        }
        Shape::Action => rect(out, p, 8.0, &style),
        Shape::SubTree => {
            rect(out, p, 2.0, &style);
            let inner = Placed {
                x: p.x,
                y: t + 3.0,
                size: Size::new(w - 6.0, h - 6.0),
            };
            let inner_style = format!(
                "fill=\"none\" stroke=\"{}\" stroke-width=\"1\"",
                paint.stroke
            );
            rect(out, &inner, 1.0, &inner_style);
        }
        Shape::Sequential | Shape::Alternative | Shape::Concurrent | Shape::Control => {
            rect(out, p, 2.0, &style);
        }
    }
    let Some(glyph) = shape.glyph() else {
        return (l, l + w);
    };
    let _ = write!(
        out,
        "<line x1=\"{x}\" y1=\"{}\" x2=\"{x}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"1\"/>\
         <text x=\"{}\" y=\"{}\" font-size=\"{GLYPH_SIZE}\" font-weight=\"bold\" \
         text-anchor=\"middle\" fill=\"#343a40\">{}</text>",
        num(t),
        num(t + h),
        paint.stroke,
        num(l + GLYPH_WIDTH / 2.0),
        num(p.middle() + GLYPH_SIZE * 0.35),
        escape(glyph),
        x = num(l + GLYPH_WIDTH),
    );
    (l + GLYPH_WIDTH, l + w)
}

/// The name in bold, over the type name when the two differ, over the ports, over the
/// reason the node gave, if any, all centred on `centre`.
fn labels(
    out: &mut String,
    view: &NodeView<'_>,
    p: &Placed,
    centre: f64,
    ports: &[PortLine],
    reason: Option<&str>,
) {
    let centre = num(centre);
    let alone = view.type_name.is_none() && ports.is_empty() && reason.is_none();
    let name_y = if alone {
        p.middle() + NAME_SIZE * 0.35
    } else {
        p.y + FIRST_BASELINE
    };
    let _ = write!(
        out,
        "<text x=\"{centre}\" y=\"{}\" font-size=\"{NAME_SIZE}\" font-weight=\"bold\" \
         text-anchor=\"middle\" fill=\"#212529\">{}</text>",
        num(name_y),
        escape(&view.name)
    );
    let mut baseline = p.y + FIRST_BASELINE;
    if let Some(type_name) = &view.type_name {
        baseline += LINE_STEP;
        let _ = write!(
            out,
            "<text x=\"{centre}\" y=\"{}\" font-size=\"{TYPE_SIZE}\" text-anchor=\"middle\" \
             fill=\"#495057\">{}</text>",
            num(baseline),
            escape(type_name)
        );
    }
    for port in ports {
        baseline += LINE_STEP;
        let (class, colour) = if port.binding {
            ("binding", BINDING_COLOUR)
        } else {
            ("literal", "#212529")
        };
        // Which way the port carries data, when its type says: set apart from its name.
        let (direction, mark) = match port.direction {
            Some(d) => (
                format!(" data-direction=\"{}\"", direction_name(d)),
                format!(
                    "<tspan class=\"direction\" fill=\"{DIRECTION_COLOUR}\">{}</tspan>",
                    direction_mark(port.direction)
                ),
            ),
            None => (String::new(), String::new()),
        };
        let _ = write!(
            out,
            "<text class=\"port\"{direction} x=\"{centre}\" y=\"{}\" font-size=\"{PORT_SIZE}\" \
             text-anchor=\"middle\">{mark}<tspan fill=\"{PORT_NAME_COLOUR}\">{}: </tspan>\
             <tspan class=\"{class}\" fill=\"{colour}\">{}</tspan></text>",
            num(baseline),
            escape(&port.name),
            escape(&port.value)
        );
    }
    if let Some(reason) = reason {
        baseline += LINE_STEP;
        let _ = write!(
            out,
            "<text class=\"reason\" x=\"{centre}\" y=\"{}\" font-size=\"{TYPE_SIZE}\" \
             font-weight=\"bold\" text-anchor=\"middle\" fill=\"{PATH_COLOUR}\">{}</text>",
            num(baseline),
            escape(reason)
        );
    }
}

/// A disc with the status mark on the top edge, near the right end where the shape has
/// an edge to sit on.
fn badge(out: &mut String, mark: &str, shape: Shape, p: &Placed, paint: Paint) {
    let inset = match shape {
        Shape::Condition => NODE_HEIGHT / 2.0,
        Shape::Decorator => SLANT + 4.0,
        _ => 12.0,
    };
    let (cx, cy) = (p.right() - inset, p.y);
    let _ = write!(
        out,
        "<circle cx=\"{}\" cy=\"{}\" r=\"{BADGE_RADIUS}\" fill=\"{}\"/>\
         <text x=\"{}\" y=\"{}\" font-size=\"9\" font-weight=\"bold\" text-anchor=\"middle\" \
         fill=\"#ffffff\">{mark}</text>",
        num(cx),
        num(cy),
        paint.stroke,
        num(cx),
        num(cy + 3.2),
    );
}

fn rect(out: &mut String, p: &Placed, radius: f64, paint: &str) {
    let _ = write!(
        out,
        "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" rx=\"{}\" {paint}/>",
        num(p.left()),
        num(p.y),
        num(p.size.width),
        num(p.size.height),
        num(radius)
    );
}

/// The mark on a node's badge; Idle nodes have none.
fn badge_mark(status: NodeStatus) -> Option<&'static str> {
    match status {
        NodeStatus::Success => Some("✓"),
        NodeStatus::Failure => Some("✗"),
        NodeStatus::Running => Some("▶"),
        NodeStatus::Skipped => Some("–"),
        NodeStatus::Idle => None,
    }
}

const SWATCH: f64 = 12.0;
const LEGEND_GAP: f64 = 16.0;
const LEGEND_SIZE: f64 = 11.0;

fn legend_width(entries: &[(NodeStatus, &str)]) -> f64 {
    entries
        .iter()
        .map(|(_, word)| SWATCH + 5.0 + text_width(word, LEGEND_SIZE, false) + LEGEND_GAP)
        .sum::<f64>()
        - LEGEND_GAP
}

fn legend(out: &mut String, entries: &[(NodeStatus, &str)], left: f64, middle: f64) {
    out.push_str("<g class=\"legend\">");
    let mut x = left;
    for &(status, word) in entries {
        let paint = paint(Some(status));
        let _ = write!(
            out,
            "<rect x=\"{}\" y=\"{}\" width=\"{SWATCH}\" height=\"{SWATCH}\" rx=\"2\" fill=\"{}\" \
             stroke=\"{}\"{}/><text x=\"{}\" y=\"{}\" font-size=\"{LEGEND_SIZE}\" \
             fill=\"#495057\">{word}</text>",
            num(x),
            num(middle - SWATCH / 2.0),
            paint.fill,
            paint.stroke,
            if paint.dashed {
                " stroke-dasharray=\"3 2\""
            } else {
                ""
            },
            num(x + SWATCH + 5.0),
            num(middle + LEGEND_SIZE * 0.35),
        );
        x += SWATCH + 5.0 + text_width(word, LEGEND_SIZE, false) + LEGEND_GAP;
    }
    out.push_str("</g>\n");
}

/// A coordinate rounded to a tenth, without a trailing `.0`: short, and the same bytes for
/// the same value.
pub(crate) fn num(v: f64) -> String {
    let tenths = (v * 10.0).round();
    // Rounding can leave -0, which should print as 0.
    let tenths = if tenths == 0.0 { 0.0 } else { tenths };
    if tenths % 10.0 == 0.0 {
        format!("{}", tenths / 10.0)
    } else {
        format!("{:.1}", tenths / 10.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_stable() {
        assert_eq!(num(3.0), "3");
        assert_eq!(num(3.04), "3");
        assert_eq!(num(3.06), "3.1");
        assert_eq!(num(-0.01), "0");
        assert_eq!(num(120.25), "120.3");
    }

    #[test]
    fn markup_characters_are_escaped() {
        assert_eq!(
            escape(r#"<a & 'b' "c">"#),
            "&lt;a &amp; &apos;b&apos; &quot;c&quot;&gt;"
        );
    }
}
