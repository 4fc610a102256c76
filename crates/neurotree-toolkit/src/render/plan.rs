//! A tree's drawing planned for a drawer elsewhere (the studio's page): each node's box as
//! the SVG draws it (shape, glyph, lines, size) and where it goes, by the same layout, so
//! that the page and `neurotree show --format svg` draw one tree in one shape.
//!
//! A node is given as plain data ([`PlanNode`]: name, type, category, ports as written,
//! children), since the page draws trees it is editing and that no blueprint holds yet.
//! Each box comes at two levels of detail: [`Detail::Full`], the SVG's box with its type and
//! ports; and [`Detail::Compact`], the name alone, a long one wrapped onto two lines, for a
//! whole tree at a glance. A layout ([`plan_layout`]) is asked for in an orientation,
//! top-down as the SVG or left to right, at a level of detail and with some subtrees folded.
//!
//! ```
//! use neurotree::render::plan::{plan_boxes, plan_layout, Detail, Orientation, PlanNode};
//!
//! let nodes = vec![
//!     PlanNode::new("root", "Sequence", "control").with_children(vec![1, 2]),
//!     PlanNode::new("a", "AlwaysSuccess", "action"),
//!     PlanNode::new("b", "AlwaysFailure", "action"),
//! ];
//! let boxes = plan_boxes(&nodes);
//! assert_eq!(boxes[0].glyph, Some("→"));
//! let placed = plan_layout(&nodes, &boxes, Orientation::TopDown, Detail::Full, &[]);
//! let [root, a, b] = [placed.nodes[0].unwrap(), placed.nodes[1].unwrap(), placed.nodes[2].unwrap()];
//! assert_eq!(root.x, (a.x + b.x) / 2.0);
//! // Folded, the root's children are not placed.
//! let folded = plan_layout(&nodes, &boxes, Orientation::TopDown, Detail::Full, &[0]);
//! assert!(folded.nodes[1].is_none());
//! ```

use std::collections::BTreeMap;

use neurotree_core::{Blueprint, PortDirection};
use serde::Serialize;

use super::layout::{tidy, Size, Spacing};
use super::node_box::{
    box_size, direction_mark, direction_name, node_ports, port_line, MIN_WIDTH, NAME_SIZE,
};
use super::node_box::{GLYPH_WIDTH, PADDING, SLANT};
use super::style::{printable, NodeView, Shape};
use super::text_width::{text_width, thousandths};

/// The widest a compact box's name line is drawn before the name is wrapped.
pub const COMPACT_WRAP: f64 = 118.0;
/// The height of a compact box of one line.
pub const COMPACT_HEIGHT: f64 = 26.0;
/// The height of a compact box of two lines.
pub const COMPACT_TALL: f64 = 40.0;
/// The gaps of a compact layout: the boxes are small, so are the gaps.
pub const COMPACT_SPACING: Spacing = Spacing {
    sibling: 8.0,
    cousin: 14.0,
    level: 26.0,
};

/// One node as written: what a drawing of it needs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlanNode {
    /// Its name (the type's when it has none).
    pub name: String,
    /// Its type as the file names it.
    pub type_name: String,
    /// Its category: `control`, `decorator`, `condition`, `action` or `subtree`.
    pub category: String,
    /// Its ports as written, `(name, text)`, `{key}` for a blackboard entry.
    pub ports: Vec<(String, String)>,
    /// Which way each port carries data, by port name, when its type declares it.
    pub directions: BTreeMap<String, PortDirection>,
    /// Its children's indices, left to right; node 0 is the root.
    pub children: Vec<usize>,
}

impl PlanNode {
    /// A node of `name`, `type_name` and `category`, with no ports and no children.
    pub fn new(name: &str, type_name: &str, category: &str) -> Self {
        Self {
            name: name.to_string(),
            type_name: type_name.to_string(),
            category: category.to_string(),
            ..Self::default()
        }
    }

    /// The node with these children.
    pub fn with_children(mut self, children: Vec<usize>) -> Self {
        self.children = children;
        self
    }
}

/// One port line as a full box draws it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlannedPort {
    /// The port's name, made printable; shortened with the value when the line is too wide.
    pub name: String,
    /// The value as drawn, shortened with `…` when too wide.
    pub value: String,
    /// Whether the value is cut on the node (whole in `whole`).
    pub cut: bool,
    /// Bound to a blackboard entry rather than literal text.
    pub binding: bool,
    /// `input`, `output` or `inout` when the node's type declares the port.
    pub direction: Option<&'static str>,
    /// What the line starts with: `in `, `out `, `inout ` or nothing.
    pub mark: &'static str,
    /// The line whole, for titles and panels.
    pub whole: String,
}

/// A node's box at both levels of detail.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlannedBox {
    /// The drawn family: `sequential`, `alternative`, `concurrent`, `control`, `decorator`,
    /// `condition`, `action` or `subtree`.
    pub shape: &'static str,
    /// The family as a class name: the three marked controls are `control`.
    pub family: &'static str,
    /// The mark of a well-known control (`→`, `?`, `⇉`).
    pub glyph: Option<&'static str>,
    /// The name, made printable.
    pub label: String,
    /// The type under the name, when it differs from the name.
    pub type_label: Option<String>,
    /// The port lines.
    pub ports: Vec<PlannedPort>,
    /// The full box's width.
    pub width: f64,
    /// The full box's height.
    pub height: f64,
    /// The compact box: the name on one or two lines.
    pub compact: CompactBox,
}

/// A node's box at [`Detail::Compact`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CompactBox {
    /// The name's lines: one, or two for a long name.
    pub lines: Vec<String>,
    /// Width.
    pub width: f64,
    /// Height.
    pub height: f64,
}

/// How much a box shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Detail {
    /// As the SVG draws it: name, type, ports.
    Full,
    /// The name alone, wrapped onto two lines when long.
    Compact,
}

/// Which way the tree grows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Orientation {
    /// Root at the top, rows below it, as the SVG.
    TopDown,
    /// Root at the left, columns to its right.
    LeftRight,
}

/// Where one node goes: its box's horizontal centre and top edge.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PlannedPlace {
    /// The horizontal centre.
    pub x: f64,
    /// The top edge.
    pub y: f64,
    /// Where its row (top-down) or column (left to right) ends, for the lines to its
    /// children, which bend halfway to the next.
    pub end: f64,
}

/// A planned layout: each node's place (`None` under a folded node) and the extent.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlannedLayout {
    /// By node index.
    pub nodes: Vec<Option<PlannedPlace>>,
    /// From the leftmost edge (at 0) to the rightmost.
    pub width: f64,
    /// From the top edge (at 0) to the bottom.
    pub height: f64,
    /// The gap between one row (column) and the next, which the lines to the children
    /// cross.
    pub level: f64,
}

/// A blueprint's nodes as a page that read its file gives them: to plan the drawing of a
/// tree already built.
pub fn plan_nodes<C>(bp: &Blueprint<C>) -> Vec<PlanNode> {
    bp.ids()
        .map(|id| PlanNode {
            name: bp.name(id).to_string(),
            type_name: bp.type_id(id).to_string(),
            category: bp.kind(id).category().as_str().to_string(),
            ports: node_ports(bp, id),
            directions: node_ports(bp, id)
                .into_iter()
                .filter_map(|(p, _)| Some((p.clone(), bp.port_direction(id, &p)?)))
                .collect(),
            children: bp.children(id).iter().map(|c| c.index()).collect(),
        })
        .collect()
}

/// Each node's box, as the SVG draws it in full and in compact.
pub fn plan_boxes(nodes: &[PlanNode]) -> Vec<PlannedBox> {
    nodes.iter().map(plan_box).collect()
}

fn plan_box(node: &PlanNode) -> PlannedBox {
    let shape = Shape::of_type(&node.type_name, &node.category);
    let name = printable(&node.name);
    let view = NodeView {
        id: neurotree_core::NodeId(0),
        shape,
        name: name.clone(),
        type_name: (!node.type_name.is_empty() && node.type_name != node.name)
            .then(|| printable(&node.type_name)),
        status: None,
    };
    let lines: Vec<_> = node
        .ports
        .iter()
        .map(|(port, text)| port_line(port, text, node.directions.get(port).copied()))
        .collect();
    let size = box_size(&view, &lines, None);
    let ports = lines
        .into_iter()
        .map(|p| {
            let mark = direction_mark(p.direction);
            PlannedPort {
                cut: p.whole != p.text(),
                mark,
                direction: p.direction.map(direction_name),
                name: p.name,
                value: p.value,
                binding: p.binding,
                whole: p.whole,
            }
        })
        .collect();
    PlannedBox {
        shape: shape.word(),
        family: shape.family(),
        glyph: shape.glyph(),
        compact: compact_box(shape, &name),
        label: name.into_owned(),
        type_label: view.type_name.map(|t| t.into_owned()),
        ports,
        width: size.width,
        height: size.height,
    }
}

/// The name on one line, or on two split where the name breaks best (after `_`, `-`, a
/// space, `/` or `.`, or between a lower-case letter and a capital or a digit) when it is
/// wider than [`COMPACT_WRAP`].
fn compact_box(shape: Shape, name: &str) -> CompactBox {
    let width = |s: &str| text_width(s, NAME_SIZE, true);
    let mut lines = vec![name.to_string()];
    if let Some(at) = (width(name) > COMPACT_WRAP)
        .then(|| best_break(name))
        .flatten()
    {
        let (a, b) = name.split_at(at);
        lines = vec![a.trim_end().to_string(), b.trim_start().to_string()];
    }
    let text = lines.iter().map(|l| width(l)).fold(0.0, f64::max);
    let extra = match shape {
        Shape::Sequential | Shape::Alternative | Shape::Concurrent => GLYPH_WIDTH,
        Shape::Decorator => 2.0 * SLANT,
        Shape::Condition => COMPACT_HEIGHT / 2.0,
        Shape::SubTree => 6.0,
        Shape::Control | Shape::Action => 0.0,
    };
    let height = if lines.len() > 1 {
        COMPACT_TALL
    } else {
        COMPACT_HEIGHT
    };
    CompactBox {
        width: (text + 2.0 * PADDING + extra).max(MIN_WIDTH).ceil(),
        height,
        lines,
    }
}

/// The byte offset where `name` breaks best: of the places it may break, the one whose
/// wider line is narrowest, the first of equals. Each line's width comes from sums along
/// the name, so that a name of megabytes costs its length rather than its square.
fn best_break(name: &str) -> Option<usize> {
    let chars: Vec<(usize, char)> = name.char_indices().collect();
    let n = chars.len();
    // `before[i]`: the width of the first `i` characters.
    let mut before = Vec::with_capacity(n + 1);
    before.push(0u64);
    for &(_, c) in &chars {
        before.push(before[before.len() - 1] + thousandths(c, true));
    }
    // Where the line ending before `i` ends once trimmed, and where the one starting at
    // `i` starts.
    let mut end = vec![0usize; n + 1];
    for i in 0..=n {
        end[i] = if i > 0 && chars[i - 1].1.is_whitespace() {
            end[i - 1]
        } else {
            i
        };
    }
    let mut start = vec![n; n + 1];
    for i in (0..n).rev() {
        start[i] = if chars[i].1.is_whitespace() {
            start[i + 1]
        } else {
            i
        };
    }
    (1..n)
        .filter(|&i| breaks_at(chars[i - 1].1, chars[i].1))
        .map(|i| (before[end[i]].max(before[n] - before[start[i]]), i))
        .min_by_key(|&(wider, _)| wider)
        .map(|(_, i)| chars[i].0)
}

fn breaks_at(a: char, b: char) -> bool {
    matches!(a, '_' | '-' | ' ' | '/' | '.')
        || (a.is_lowercase() && (b.is_uppercase() || b.is_ascii_digit()))
}

/// Where each node goes in `orientation` at `detail`, the nodes under those in `folded`
/// left out, by [`tidy`]: top-down at full detail, exactly where
/// `render_svg` puts them (less its margin). A child list naming a node out of range or
/// twice, which no tree written in a file gives, places nothing.
pub fn plan_layout(
    nodes: &[PlanNode],
    boxes: &[PlannedBox],
    orientation: Orientation,
    detail: Detail,
    folded: &[usize],
) -> PlannedLayout {
    let n = nodes.len();
    let spacing = match detail {
        Detail::Full => Spacing::default(),
        Detail::Compact => COMPACT_SPACING,
    };
    let empty = PlannedLayout {
        nodes: vec![None; n],
        width: 0.0,
        height: 0.0,
        level: spacing.level,
    };
    if n == 0 || boxes.len() != n {
        return empty;
    }
    let mut is_folded = vec![false; n];
    for &f in folded {
        if let Some(slot) = is_folded.get_mut(f) {
            *slot = true;
        }
    }
    // The visible nodes, renumbered in pre-order.
    let mut shown = Vec::new();
    let mut number = vec![usize::MAX; n];
    let mut stack = vec![0];
    let mut seen = vec![false; n];
    while let Some(v) = stack.pop() {
        if v >= n || seen[v] {
            return empty;
        }
        seen[v] = true;
        number[v] = shown.len();
        shown.push(v);
        if !is_folded[v] {
            stack.extend(nodes[v].children.iter().rev());
        }
    }
    let lr = orientation == Orientation::LeftRight;
    let children: Vec<Vec<usize>> = shown
        .iter()
        .map(|&v| {
            if is_folded[v] {
                Vec::new()
            } else {
                nodes[v].children.iter().map(|&c| number[c]).collect()
            }
        })
        .collect();
    let sizes: Vec<Size> = shown
        .iter()
        .map(|&v| {
            let (w, h) = match detail {
                Detail::Full => (boxes[v].width, boxes[v].height),
                Detail::Compact => (boxes[v].compact.width, boxes[v].compact.height),
            };
            if lr {
                Size::new(h, w)
            } else {
                Size::new(w, h)
            }
        })
        .collect();
    let Ok(layout) = tidy(&children, &sizes, spacing) else {
        return empty;
    };
    // Each row's end: the bottom (right) of its deepest box. Pre-order puts a parent
    // before its children.
    let mut depth = vec![0usize; shown.len()];
    for (i, kids) in children.iter().enumerate() {
        for &c in kids {
            depth[c] = depth[i] + 1;
        }
    }
    let rows = depth.iter().max().map_or(0, |d| d + 1);
    let mut end = vec![0.0f64; rows];
    for (p, &d) in layout.nodes.iter().zip(&depth) {
        end[d] = end[d].max(p.bottom());
    }
    let mut placed = vec![None; n];
    for (i, p) in layout.nodes.iter().enumerate() {
        let e = end[depth[i]];
        placed[shown[i]] = Some(if lr {
            PlannedPlace {
                x: p.middle(),
                y: p.x - p.size.width / 2.0,
                end: e,
            }
        } else {
            PlannedPlace {
                x: p.x,
                y: p.y,
                end: e,
            }
        });
    }
    let (width, height) = if lr {
        (layout.height, layout.width)
    } else {
        (layout.width, layout.height)
    };
    PlannedLayout {
        nodes: placed,
        width,
        height,
        level: spacing.level,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(xml: &str) -> Blueprint<()> {
        let registry = crate::Registry::<()>::new();
        let mut loader = crate::XmlLoader::new(&registry).mock_unknown(true);
        loader.load_str(xml, "t.xml").unwrap();
        loader.build_main().unwrap()
    }

    const TREE: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <ReactiveSequence name="main">
      <Script name="setup" code="wait := 500; speed := 0.25; label := 'long enough to be cut on the node'"/>
      <Fallback>
        <Inverter><AlwaysFailure name="no"/></Inverter>
        <Sleep name="pause" msec="{wait}"/>
        <Parallel success_count="1" failure_count="1">
          <ComputePathToPoseWithAVeryLongName goal="{goal}"/>
          <AlwaysSuccess/>
        </Parallel>
      </Fallback>
    </ReactiveSequence>
  </BehaviorTree>
</root>"#;

    #[test]
    fn top_down_at_full_detail_the_plan_places_every_box_where_the_svg_does() {
        let bp = load(TREE);
        let nodes = plan_nodes(&bp);
        let boxes = plan_boxes(&nodes);
        let placed = plan_layout(&nodes, &boxes, Orientation::TopDown, Detail::Full, &[]);
        let svg = super::super::render_svg(&bp, None);
        for (i, (p, b)) in placed.nodes.iter().zip(&boxes).enumerate() {
            let p = p.expect("nothing folded");
            let start = svg.find(&format!("<g id=\"n{i}\"")).unwrap();
            let node = &svg[start..start + svg[start..].find("</g>").unwrap()];
            let top = format!(" y=\"{}\"", super::super::svg::num(p.y + 16.0));
            assert!(
                node.contains(&top) || b.shape == "decorator",
                "{i}: {top} in {node}"
            );
            let left = super::super::svg::num(p.x - b.width / 2.0 + 16.0);
            assert!(
                node.contains(&format!("x=\"{left}\""))
                    || node.contains(&format!("points=\"{left},")),
                "{i}: {left} in {node}"
            );
            assert!(node.contains(&format!("width=\"{}\"", b.width)) || b.shape == "decorator");
        }
        let [script, fallback, inverter] = [&boxes[1], &boxes[2], &boxes[3]];
        assert!(script.ports[0].cut && script.ports[0].whole.ends_with("on the node'"));
        assert_eq!((boxes[0].glyph, fallback.glyph), (Some("→"), Some("?")));
        assert_eq!((inverter.shape, boxes[0].family), ("decorator", "control"));
    }

    #[test]
    fn left_to_right_turns_the_layout_and_folding_hides_the_subtree() {
        let bp = load(TREE);
        let nodes = plan_nodes(&bp);
        let boxes = plan_boxes(&nodes);
        let td = plan_layout(&nodes, &boxes, Orientation::TopDown, Detail::Compact, &[]);
        let lr = plan_layout(&nodes, &boxes, Orientation::LeftRight, Detail::Compact, &[]);
        let root = lr.nodes[0].unwrap();
        // The children's column starts past the root's, a level's gap on: the wider child
        // fills it, the other is centred in it.
        let left = |i: usize| lr.nodes[i].unwrap().x - boxes[i].compact.width / 2.0;
        assert_eq!(left(1).min(left(2)), root.end + COMPACT_SPACING.level);
        assert!(left(1).max(left(2)) > root.end + COMPACT_SPACING.level);
        // The root at the left edge, in the middle of its column; top-down at the top.
        assert_eq!(root.x - boxes[0].compact.width / 2.0, 0.0);
        assert_eq!(td.nodes[0].unwrap().y, 0.0);
        let right = (0..nodes.len()).map(|i| lr.nodes[i].unwrap().x + boxes[i].compact.width / 2.0);
        assert_eq!(right.fold(0.0, f64::max), lr.width);
        let folded = plan_layout(&nodes, &boxes, Orientation::TopDown, Detail::Full, &[2]);
        assert_eq!(folded.nodes.iter().filter(|p| p.is_some()).count(), 3);
        assert!(folded.nodes[2].is_some() && folded.nodes[3].is_none());
    }

    /// Every place the name may break tried, each line measured whole: where
    /// [`best_break`] must break it.
    fn best_break_by_hand(name: &str) -> Option<usize> {
        let width = |s: &str| text_width(s, NAME_SIZE, true);
        let chars: Vec<(usize, char)> = name.char_indices().collect();
        (1..chars.len())
            .filter(|&i| breaks_at(chars[i - 1].1, chars[i].1))
            .map(|i| {
                let (a, b) = name.split_at(chars[i].0);
                (width(a.trim_end()).max(width(b.trim_start())), chars[i].0)
            })
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .map(|(_, at)| at)
    }

    proptest::proptest! {
        #[test]
        fn a_name_breaks_where_trying_every_break_breaks_it(name in "[a-zA-Z0-9_./ \t\u{3000}界é-]{0,40}") {
            proptest::prop_assert_eq!(best_break(&name), best_break_by_hand(&name));
        }
    }

    #[test]
    fn a_name_of_megabytes_is_wrapped_in_one_pass() {
        // Each break measured whole, this took hours: a page may send such a name.
        let name = "aB_".repeat(1 << 19);
        let compact = compact_box(Shape::Action, &name);
        assert_eq!(compact.lines.len(), 2);
        let (a, b) = (&compact.lines[0], &compact.lines[1]);
        assert!(
            a.len().abs_diff(b.len()) <= 3,
            "{} and {}",
            a.len(),
            b.len()
        );
        assert_eq!(format!("{a}{b}"), name);
    }

    #[test]
    fn a_long_name_wraps_where_it_breaks_best_and_a_short_one_keeps_one_line() {
        let long = compact_box(Shape::Action, "ComputePathThroughPoses");
        assert_eq!(long.lines, ["ComputePath", "ThroughPoses"]);
        assert_eq!(long.height, COMPACT_TALL);
        let short = compact_box(Shape::Sequential, "Wait");
        assert_eq!((short.lines.len(), short.height), (1, COMPACT_HEIGHT));
        assert!(short.width < long.width);
        let dashed = compact_box(Shape::Action, "ClearLocalCostmap-Context");
        assert_eq!(dashed.lines, ["ClearLocal", "Costmap-Context"]);
    }

    #[test]
    fn a_built_in_known_by_name_has_the_shape_its_node_has() {
        for decl in neurotree_core::nodes::BUILT_INS {
            let name = decl.name;
            let children = match decl.arity {
                neurotree_core::Arity::Leaf => String::new(),
                neurotree_core::Arity::One => "<AlwaysSuccess/>".to_string(),
                _ => "<AlwaysSuccess/><AlwaysSuccess/>".to_string(),
            };
            let ports: String = decl
                .ports
                .iter()
                .filter(|p| p.default.is_none())
                .map(|p| format!(r#" {}="1""#, p.name))
                .collect();
            let xml = format!(
                r#"<root BTCPP_format="4" main_tree_to_execute="M"><BehaviorTree ID="M">
                <{name}{ports}>{children}</{name}></BehaviorTree></root>"#
            );
            let bp = load(&xml);
            assert_eq!(
                Shape::of_type(name, "action"),
                Shape::of(bp.kind(neurotree_core::NodeId(0))),
                "{name}"
            );
        }
        assert_eq!(Shape::of_type("Sequence", "control"), Shape::Sequential);
        assert_eq!(Shape::of_type("SequenceStar", "control"), Shape::Sequential);
        assert_eq!(Shape::of_type("ReactiveFallback", ""), Shape::Alternative);
        assert_eq!(Shape::of_type("ParallelAll", ""), Shape::Concurrent);
        assert_eq!(Shape::of_type("Inverter", "Decorator"), Shape::Decorator);
        assert_eq!(Shape::of_type("MoveBase", "Condition"), Shape::Condition);
        assert_eq!(Shape::of_type("Unknown", ""), Shape::Action);
    }
}
