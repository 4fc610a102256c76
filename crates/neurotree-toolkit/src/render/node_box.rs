//! The box of a node in a picture: the lines it carries (its name, its type, one line per
//! port, the reason it failed) and the size they need.
//!
//! A port is drawn as `name: value`, the value either literal text or a `{key}` binding to
//! a blackboard entry (drawn apart, in another colour); a Script's code is its `code` port.
//! The line starts with `in`, `out` or `inout` when the node's type declares which way the
//! port carries data ([`Blueprint::port_direction`]).
//! A line wider than [`PORT_WIDTH`] is shortened with `…` on the node and kept whole in the
//! node's title, which viewers show on hover.
//!
//! The studio's page draws the same boxes: it is served [`DrawingMetrics`], these sizes
//! and the font-width tables, rather than keeping a copy of its own.

use std::borrow::Cow;

use neurotree_core::{Blueprint, NodeId, NodeKind, PortDirection, PortValue};
use serde::Serialize;

use super::layout::{Size, Spacing};
use super::style::{printable, NodeView, Shape};
use super::text_width::{scaled, text_width, thousandths, BOLD, OTHER, REGULAR, WIDE, WIDE_RANGES};
use crate::registry::built_in_ports;

/// The height of a node with one or two lines.
pub(crate) const NODE_HEIGHT: f64 = 40.0;
pub(crate) const NAME_SIZE: f64 = 12.0;
pub(crate) const TYPE_SIZE: f64 = 10.0;
pub(crate) const PORT_SIZE: f64 = 10.0;
/// From the top of a box with more than one line to the first line's baseline.
pub(crate) const FIRST_BASELINE: f64 = 17.0;
/// From one label line's baseline to the next.
pub(crate) const LINE_STEP: f64 = 14.0;
/// Width of the compartment holding a control's glyph.
pub(crate) const GLYPH_WIDTH: f64 = 22.0;
pub(crate) const PADDING: f64 = 10.0;
/// How far a decorator's points reach beyond its text.
pub(crate) const SLANT: f64 = 10.0;
pub(crate) const MIN_WIDTH: f64 = 44.0;
/// The widest a port line is drawn: a longer one is shortened, so that one long Script
/// does not make its row of the tree as wide as the code.
pub(crate) const PORT_WIDTH: f64 = 220.0;
const ELLIPSIS: char = '…';
/// What a port line starts with, by the way the port carries data.
const DIRECTION_MARKS: [(&str, &str); 3] =
    [("input", "in "), ("output", "out "), ("inout", "inout ")];

/// One port as a node shows it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct PortLine {
    /// The port's name, made printable; with the value, shortened to fit.
    pub(crate) name: String,
    /// The value as drawn: literal text, or the entry's key in braces; shortened to fit.
    pub(crate) value: String,
    /// Bound to a blackboard entry rather than to literal text.
    pub(crate) binding: bool,
    /// Which way it carries data, if its node's type declares the port.
    pub(crate) direction: Option<PortDirection>,
    /// `name: value` whole, for the title.
    pub(crate) whole: String,
}

/// The ports of node `id` as a file writes them, `(name, text)` with `{key}` for an entry:
/// a built-in's parameters (Repeat's `num_cycles`, Delay's `delay_msec`, which the engine
/// keeps in the node's kind), a SubTree's remapping, any other node's bound ports.
///
/// ```
/// use neurotree::render::node_ports;
/// use neurotree::{Blueprint, Port};
///
/// let bp = Blueprint::<()>::builder()
///     .repeat("again", 3, |r| r.always_success("ok"))
///     .build()
///     .unwrap();
/// assert_eq!(node_ports(&bp, neurotree::NodeId(0)), [("num_cycles".to_string(), "3".to_string())]);
/// ```
pub fn node_ports<C>(bp: &Blueprint<C>, id: NodeId) -> Vec<(String, String)> {
    let kind = bp.kind(id);
    let mut ports = Vec::new();
    if let NodeKind::SubTree(scope) = kind {
        for (child, parent) in &scope.remap {
            ports.push((child.clone(), format!("{{{parent}}}")));
        }
        for (child, text) in &scope.values {
            ports.push((child.clone(), text.clone()));
        }
        return ports;
    }
    if bp.ports(id).is_empty() && bp.type_id(id) == kind.type_name() {
        for (port, value) in built_in_ports(kind, bp.children(id).len()) {
            ports.push((port.to_string(), value));
        }
    }
    for port in bp.ports(id) {
        let value = match &port.value {
            PortValue::Literal(text) => text.clone(),
            PortValue::Entry(key) => format!("{{{key}}}"),
        };
        ports.push((port.name.clone(), value));
    }
    ports
}

/// Whether a port's text binds it to a blackboard entry.
fn is_binding(text: &str) -> bool {
    text.len() >= 2 && text.starts_with('{') && text.ends_with('}')
}

/// The ports of node `id` as lines, in the order a file writes them.
pub(crate) fn port_lines<C>(bp: &Blueprint<C>, id: NodeId) -> Vec<PortLine> {
    node_ports(bp, id)
        .into_iter()
        .map(|(name, text)| {
            let direction = bp.port_direction(id, &name);
            port_line(&name, &text, direction)
        })
        .collect()
}

/// One port written `name="text"` as a line, carrying data `direction` when its node's
/// type declares the port.
pub(crate) fn port_line(name: &str, text: &str, direction: Option<PortDirection>) -> PortLine {
    let binding = is_binding(text);
    let value = printable(text).into_owned();
    let name = printable(name).into_owned();
    let mark = direction_mark(direction);
    let whole = format!("{mark}{name}: {value}");
    let (name, value) = shorten(mark, &name, &value);
    PortLine {
        name,
        value,
        binding,
        direction,
        whole,
    }
}

/// The name pictures and pages give a port's direction: `input`, `output` or `inout`.
pub fn direction_name(direction: PortDirection) -> &'static str {
    match direction {
        PortDirection::Input => DIRECTION_MARKS[0].0,
        PortDirection::Output => DIRECTION_MARKS[1].0,
        PortDirection::InOut => DIRECTION_MARKS[2].0,
    }
}

/// What a port's line starts with: `in `, `out `, `inout `, or nothing when undeclared.
pub(crate) fn direction_mark(direction: Option<PortDirection>) -> &'static str {
    let name = direction.map(direction_name);
    DIRECTION_MARKS
        .iter()
        .find(|(n, _)| Some(*n) == name)
        .map_or("", |(_, mark)| mark)
}

impl PortLine {
    /// The line as drawn: its direction's mark, `name: value`.
    pub(crate) fn text(&self) -> String {
        format!(
            "{}{}: {}",
            direction_mark(self.direction),
            self.name,
            self.value
        )
    }
}

/// `name` and `value` cut so that `{mark}name: value` fits [`PORT_WIDTH`], the cut marked
/// `…`: the value is cut first, then the name.
fn shorten(mark: &str, name: &str, value: &str) -> (String, String) {
    // Widths are summed along the text rather than measured again for each cut, so that a
    // value of megabytes costs its length, not its square.
    let width = |s: &str| s.chars().map(|c| thousandths(c, false)).sum::<u64>();
    let fits = |w: u64| scaled(w, PORT_SIZE) <= PORT_WIDTH;
    let ellipsis = thousandths(ELLIPSIS, false);
    let head = width(mark) + width(name) + width(": ");
    if fits(head + width(value)) {
        return (name.to_string(), value.to_string());
    }
    // The byte length of the longest prefix of `text` that fits after `fixed` with the
    // ellipsis after it; `whole`: the whole text may be that prefix.
    let longest = |text: &str, fixed: u64, whole: bool| {
        let mut used = fixed + ellipsis;
        let mut cut = None;
        let mut chars = text.char_indices().peekable();
        loop {
            let at = chars.peek().map_or(text.len(), |&(at, _)| at);
            if !fits(used) || (!whole && at == text.len()) {
                return cut;
            }
            cut = Some(at);
            let Some((_, c)) = chars.next() else {
                return cut;
            };
            used += thousandths(c, false);
        }
    };
    if let Some(at) = longest(value, head, false) {
        return (name.to_string(), format!("{}{ELLIPSIS}", &value[..at]));
    }
    let at = longest(name, width(mark) + width(": "), true).unwrap_or(0);
    (format!("{}{ELLIPSIS}", &name[..at]), String::new())
}

/// The box a node needs for its lines (with the reason it gave, on the path that failed)
/// and shape.
pub(crate) fn box_size(view: &NodeView<'_>, ports: &[PortLine], reason: Option<&str>) -> Size {
    let name = text_width(&view.name, NAME_SIZE, true);
    let type_name = view
        .type_name
        .as_deref()
        .map_or(0.0, |t| text_width(t, TYPE_SIZE, false));
    let reason_width = reason.map_or(0.0, |r| text_width(&printable(r), TYPE_SIZE, true));
    let port_width = ports
        .iter()
        .map(|p| text_width(&p.text(), PORT_SIZE, false))
        .fold(0.0, f64::max);
    let mut width = name.max(type_name).max(reason_width).max(port_width) + 2.0 * PADDING;
    width += match view.shape {
        Shape::Sequential | Shape::Alternative | Shape::Concurrent => GLYPH_WIDTH,
        Shape::Decorator => 2.0 * SLANT,
        Shape::Condition => NODE_HEIGHT / 2.0,
        Shape::SubTree => 6.0,
        Shape::Control | Shape::Action => 0.0,
    };
    let lines =
        1 + usize::from(view.type_name.is_some()) + ports.len() + usize::from(reason.is_some());
    Size::new(width.max(MIN_WIDTH).ceil(), box_height(lines))
}

/// Two lines fit the usual height; each further line needs one more step.
pub(crate) fn box_height(lines: usize) -> f64 {
    NODE_HEIGHT + LINE_STEP * lines.saturating_sub(2) as f64
}

/// The sizes the pictures draw with and the font-width tables they measure text with, as
/// the studio's page reads them (served as JSON), so that its boxes are the command's.
///
/// ```
/// let m = neurotree::render::drawing_metrics();
/// assert_eq!(m.regular.len(), 95);
/// assert!(m.port_width > m.min_width);
/// ```
#[derive(Clone, Debug, Serialize)]
pub struct DrawingMetrics {
    /// The height of a node with one or two lines.
    pub node_height: f64,
    /// The name's font size, bold.
    pub name_size: f64,
    /// The type's font size.
    pub type_size: f64,
    /// A port line's font size.
    pub port_size: f64,
    /// From the top of a box with two or more lines to the first baseline.
    pub first_baseline: f64,
    /// From one line's baseline to the next.
    pub line_step: f64,
    /// The width of a control's glyph compartment.
    pub glyph_width: f64,
    /// Space left and right of the widest line.
    pub padding: f64,
    /// How far a decorator's points reach beyond its text.
    pub slant: f64,
    /// The narrowest box.
    pub min_width: f64,
    /// The widest port line before it is shortened with `…`.
    pub port_width: f64,
    /// What a port's line starts with, by its direction (`input`, `output`, `inout`); a
    /// port whose node's type does not declare it has no mark.
    pub direction_marks: [(&'static str, &'static str); 3],
    /// The gaps of the tidy layout.
    pub sibling: f64,
    /// Between neighbouring boxes with different parents.
    pub cousin: f64,
    /// Between one row and the next.
    pub level: f64,
    /// Advance widths of ASCII from space to `~`, in thousandths of the font size.
    pub regular: &'static [u16],
    /// The same, bold.
    pub bold: &'static [u16],
    /// Inclusive ranges of code points drawn a full em wide.
    pub wide_ranges: &'static [[u32; 2]],
    /// The width of those, in thousandths.
    pub wide: u16,
    /// The width of any other character, in thousandths.
    pub other: u16,
}

/// The metrics the pictures use (see [`DrawingMetrics`]).
pub fn drawing_metrics() -> DrawingMetrics {
    let spacing = Spacing::default();
    DrawingMetrics {
        node_height: NODE_HEIGHT,
        name_size: NAME_SIZE,
        type_size: TYPE_SIZE,
        port_size: PORT_SIZE,
        first_baseline: FIRST_BASELINE,
        line_step: LINE_STEP,
        glyph_width: GLYPH_WIDTH,
        padding: PADDING,
        slant: SLANT,
        min_width: MIN_WIDTH,
        port_width: PORT_WIDTH,
        direction_marks: DIRECTION_MARKS,
        sibling: spacing.sibling,
        cousin: spacing.cousin,
        level: spacing.level,
        regular: &REGULAR,
        bold: &BOLD,
        wide_ranges: &WIDE_RANGES,
        wide: WIDE,
        other: OTHER,
    }
}

/// The title line of a port list: each port whole, one per line.
pub(crate) fn ports_title(ports: &[PortLine]) -> Cow<'static, str> {
    if ports.is_empty() {
        return Cow::Borrowed("");
    }
    let mut title = String::new();
    for p in ports {
        title.push('\n');
        title.push_str(&p.whole);
    }
    Cow::Owned(title)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_lines_are_kept_and_long_ones_cut_with_an_ellipsis_to_fit() {
        assert_eq!(
            shorten("", "goal", "{goal}"),
            ("goal".into(), "{goal}".into())
        );
        let code = "x := 1; ".repeat(30);
        let (name, value) = shorten("", "code", &code);
        assert_eq!(name, "code");
        assert!(value.ends_with('…'), "{value}");
        assert!(value.len() < code.len());
        let width = text_width(&format!("{name}: {value}"), PORT_SIZE, false);
        assert!(width <= PORT_WIDTH, "{width}");
        // One more character would not have fitted.
        let longer: String = code
            .chars()
            .take(value.chars().count())
            .chain(['…'])
            .collect();
        assert!(text_width(&format!("code: {longer}"), PORT_SIZE, false) > PORT_WIDTH);
        // A name too long by itself is cut too, and the value dropped.
        // The mark counts: the value is cut shorter, so that the whole line fits.
        let (_, marked) = shorten("inout ", "code", &code);
        assert!(marked.chars().count() < value.chars().count());
        assert!(text_width(&format!("inout code: {marked}"), PORT_SIZE, false) <= PORT_WIDTH);
        let (name, value) = shorten("", &"n".repeat(200), "1");
        assert!(name.ends_with('…') && value.is_empty());
    }

    /// Cutting one character at a time and measuring the whole line again, as a person
    /// would: what [`shorten`] must give, at any length.
    fn shorten_by_hand(mark: &str, name: &str, value: &str) -> (String, String) {
        let fits = |n: &str, v: &str| {
            text_width(&format!("{mark}{n}: {v}"), PORT_SIZE, false) <= PORT_WIDTH
        };
        if fits(name, value) {
            return (name.to_string(), value.to_string());
        }
        let value: Vec<char> = value.chars().collect();
        for k in (0..value.len()).rev() {
            let v: String = value[..k].iter().chain([&ELLIPSIS]).collect();
            if fits(name, &v) {
                return (name.to_string(), v);
            }
        }
        let name: Vec<char> = name.chars().collect();
        for k in (0..=name.len()).rev() {
            let n: String = name[..k].iter().chain([&ELLIPSIS]).collect();
            if k == 0 || fits(&n, "") {
                return (n, String::new());
            }
        }
        unreachable!("k == 0 returns")
    }

    proptest::proptest! {
        #[test]
        fn a_line_is_cut_where_cutting_one_character_at_a_time_cuts_it(
            mark in proptest::sample::select(vec!["", "in ", "out ", "inout "]),
            name in "[a-zA-Z_界é ]{0,60}",
            value in "[a-zA-Z0-9{}:; 界é]{0,80}",
        ) {
            proptest::prop_assert_eq!(
                shorten(mark, &name, &value),
                shorten_by_hand(mark, &name, &value)
            );
        }
    }

    #[test]
    fn a_value_of_megabytes_is_cut_as_a_short_one_is() {
        // Measured again at each cut, this took hours: a page may send such a value.
        let value = "x := 1; ".repeat(1 << 18);
        let (name, cut) = shorten("", "code", &value);
        assert_eq!(name, "code");
        assert_eq!(cut, shorten("", "code", &value[..400]).1);
        let name = "n".repeat(1 << 21);
        let (cut, value) = shorten("out ", &name, "1");
        assert_eq!((cut, value), shorten("out ", &name[..400], "1"));
    }

    #[test]
    fn the_svg_draws_each_port_under_the_name_long_ones_cut_and_whole_in_the_title() {
        let code = "wait := 500; speed := 0.25; label := 'long enough to be cut on the node'";
        let xml = format!(
            r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence name="main">
      <Script name="setup" code="{code}"/>
      <Sleep name="pause" msec="{{wait}}"/>
    </Sequence>
  </BehaviorTree>
</root>"#
        );
        let registry = crate::Registry::<()>::new();
        let mut loader = crate::XmlLoader::new(&registry);
        loader.load_str(&xml, "t.xml").unwrap();
        let bp = loader.build_main().unwrap();
        let svg = super::super::render_svg(&bp, None);
        let node = |id: u32| {
            let start = svg.find(&format!("<g id=\"n{id}\"")).unwrap();
            &svg[start..start + svg[start..].find("</g>").unwrap()]
        };
        // The binding in its own colour and class, after the port's name.
        assert!(node(2).contains(
            "<tspan fill=\"#868e96\">msec: </tspan><tspan class=\"binding\" fill=\"#1864ab\">{wait}</tspan>"
        ));
        // The code cut on the node, whole in the title; the box one step taller than two
        // lines.
        let script = node(1);
        assert!(script.contains(&format!(
            "&#10;in code: {}</title>",
            code.replace('\'', "&apos;")
        )));
        assert!(script.contains("<tspan class=\"literal\" fill=\"#212529\">wait := 500;"));
        assert!(script.contains("…</tspan>"));
        assert!(script.contains(&format!("height=\"{}\"", NODE_HEIGHT + LINE_STEP)));
        assert!(
            !node(0).contains("class=\"port\""),
            "the Sequence has no ports"
        );
    }

    #[test]
    fn the_svg_marks_which_way_each_declared_port_carries_data() {
        let xml = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <LoopDouble name="each" queue="1;2" value="{v}">
      <Sleep name="pause" msec="{v}"/>
    </LoopDouble>
  </BehaviorTree>
</root>"#;
        let registry = crate::Registry::<()>::new();
        let mut loader = crate::XmlLoader::new(&registry);
        loader.load_str(xml, "t.xml").unwrap();
        let bp = loader.build_main().unwrap();
        let lines = port_lines(&bp, NodeId(0));
        let marked: Vec<(&str, Option<PortDirection>)> = lines
            .iter()
            .map(|p| (p.name.as_str(), p.direction))
            .collect();
        assert_eq!(
            marked,
            [
                ("queue", Some(PortDirection::InOut)),
                ("value", Some(PortDirection::Output)),
                // Its default, which the loader gives the node.
                ("if_empty", Some(PortDirection::Input))
            ]
        );
        assert_eq!(lines[1].text(), "out value: {v}");
        assert_eq!(port_lines(&bp, NodeId(1))[0].text(), "in msec: {v}");
        let svg = super::super::render_svg(&bp, None);
        let marks = |direction: &str| {
            svg.matches(&format!("data-direction=\"{direction}\""))
                .count()
        };
        assert_eq!((marks("input"), marks("output"), marks("inout")), (2, 1, 1));
        assert!(svg.contains("<text class=\"port\" data-direction=\"output\" x="));
        assert!(svg.contains(
            "<tspan class=\"direction\" fill=\"#5f3dc4\">out </tspan><tspan fill=\"#868e96\">value: </tspan>"
        ));
        assert!(svg.contains(
            "<tspan class=\"direction\" fill=\"#5f3dc4\">in </tspan><tspan fill=\"#868e96\">msec: </tspan>"
        ));
        // A SubTree's remapping is no port its type declares: no mark.
        let sub = r#"<root BTCPP_format="4" main_tree_to_execute="M">
  <BehaviorTree ID="M"><SubTree ID="S" x="{y}"/></BehaviorTree>
  <BehaviorTree ID="S"><AlwaysSuccess/></BehaviorTree>
</root>"#;
        let mut loader = crate::XmlLoader::new(&registry);
        loader.load_str(sub, "m.xml").unwrap();
        let bp = loader.build_main().unwrap();
        assert_eq!(port_lines(&bp, NodeId(0))[0].text(), "x: {y}");
        assert!(!super::super::render_svg(&bp, None).contains("data-direction"));
    }

    #[test]
    fn each_line_past_two_adds_a_step() {
        assert_eq!(box_height(1), NODE_HEIGHT);
        assert_eq!(box_height(2), NODE_HEIGHT);
        assert_eq!(box_height(5), NODE_HEIGHT + 3.0 * LINE_STEP);
    }
}
