//! The picture formats' structure, beyond the snapshots: valid XML with every name intact,
//! one entry per node with a stable id, colours that follow the statuses, and the same bytes
//! every time.

use neurotree::render::{render_dot, render_mermaid, render_svg, Format};
use neurotree::{Blueprint, NodeStatus, Status};
use proptest::prelude::*;

/// Names that break each format unless escaped.
const NASTY: [&str; 6] = [
    r#"say "hi""#,
    "a < b && c > d",
    "it's #1 `quoted`",
    "back\\slash \\N",
    "line\nbreak\ttab\u{1}bell",
    "]]> <!-- --> {{x}}",
];

fn nasty_tree() -> Blueprint<()> {
    Blueprint::<()>::builder()
        .sequence(NASTY[0], |s| {
            s.condition(NASTY[1], |_: &()| true)
                .inverter(NASTY[2], |i| {
                    i.action(NASTY[3], |_: &mut ()| Status::Success)
                })
                .fallback(NASTY[4], |f| f.always_failure(NASTY[5]))
        })
        .build()
        .unwrap()
}

/// A status per node of [`nasty_tree`], each status at least once.
fn statuses() -> Vec<NodeStatus> {
    use NodeStatus::*;
    vec![Running, Success, Failure, Success, Idle, Skipped]
}

#[test]
fn svg_is_valid_xml_with_one_group_per_node_and_every_name_intact() {
    let bp = nasty_tree();
    let svg = render_svg(&bp, Some(&statuses()));
    let doc = roxmltree::Document::parse(&svg).expect("the SVG is well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    assert_eq!(
        root.tag_name().namespace(),
        Some("http://www.w3.org/2000/svg")
    );
    let groups: Vec<_> = root
        .descendants()
        .filter(|n| n.attribute("class").is_some_and(|c| c.starts_with("node ")))
        .collect();
    assert_eq!(groups.len(), bp.len());
    for (i, g) in groups.iter().enumerate() {
        assert_eq!(g.attribute("id"), Some(format!("n{i}").as_str()));
    }
    let texts: Vec<&str> = root
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .collect();
    for name in &NASTY[..4] {
        assert!(texts.contains(name), "{name:?} is not drawn as is");
    }
    // Control characters cannot be carried by XML: breaks become spaces, others U+FFFD.
    assert!(texts.contains(&"line break tab\u{FFFD}bell"));
    assert!(texts.contains(&"]]> <!-- --> {{x}}"));
    // Each node's tooltip names its path, type and status.
    let first_title = groups[1]
        .children()
        .find(|n| n.has_tag_name("title"))
        .unwrap();
    assert_eq!(
        first_title.text(),
        Some(r#"say "hi"/a < b && c > d (Condition): SUCCESS"#)
    );
}

#[test]
fn svg_classes_and_colours_follow_the_statuses() {
    let bp = nasty_tree();
    let svg = render_svg(&bp, Some(&statuses()));
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let class_of = |id: &str| {
        doc.descendants()
            .find(|n| n.attribute("id") == Some(id))
            .and_then(|n| n.attribute("class"))
            .unwrap()
            .to_string()
    };
    assert_eq!(class_of("n0"), "node control running");
    assert_eq!(class_of("n1"), "node condition success");
    assert_eq!(class_of("n2"), "node decorator failure");
    assert_eq!(class_of("n3"), "node action success");
    assert_eq!(class_of("n4"), "node control idle");
    assert_eq!(class_of("n5"), "node action skipped");
    let fill_of = |id: &str| {
        let group = doc
            .descendants()
            .find(|n| n.attribute("id") == Some(id))
            .unwrap();
        let shape = group
            .children()
            .find(|n| n.has_tag_name("rect") || n.has_tag_name("polygon"))
            .unwrap();
        shape.attribute("fill").unwrap().to_string()
    };
    assert_eq!(fill_of("n1"), "#d3f9d8", "success is green");
    assert_eq!(fill_of("n2"), "#ffe3e3", "failure is red");
    assert_eq!(fill_of("n0"), "#fff3bf", "running is amber");
    assert_eq!(fill_of("n4"), "#f1f3f5", "idle is grey");
    // A legend comes with statuses; without them, neither legend nor status classes.
    assert!(svg.contains("<g class=\"legend\">"));
    let plain = render_svg(&bp, None);
    assert!(!plain.contains("legend"));
    assert!(!plain.contains("success"));
    roxmltree::Document::parse(&plain).unwrap();
}

#[test]
fn dot_has_one_statement_per_node_and_edge_with_quotes_escaped() {
    let bp = nasty_tree();
    let dot = render_dot(&bp, Some(&statuses()));
    let node_lines: Vec<&str> = dot.lines().filter(|l| l.contains(" [label=")).collect();
    assert_eq!(node_lines.len(), bp.len());
    let edges: Vec<&str> = dot.lines().filter(|l| l.contains(" -> ")).collect();
    assert_eq!(
        edges,
        [
            "  n0 -> n1;",
            "  n0 -> n2;",
            "  n2 -> n3;",
            "  n0 -> n4;",
            "  n4 -> n5;"
        ]
    );
    assert!(node_lines[0]
        .starts_with(r##"  n0 [label="→ say \"hi\"\nSequence", shape=box, fillcolor="#fff3bf""##));
    assert!(node_lines[3].contains(r#"label="back\\slash \\N\nAction""#));
    // Inside the quotes nothing but escaped quotes: every label is one DOT string.
    for line in &node_lines {
        let label = line.split("label=\"").nth(1).unwrap();
        let end = label.find("\", shape=").unwrap();
        let inner = &label[..end];
        assert!(
            !inner.replace("\\\\", "").replace("\\\"", "").contains('"'),
            "{line}"
        );
    }
}

#[test]
fn mermaid_labels_carry_no_raw_markup() {
    let bp = nasty_tree();
    let chart = render_mermaid(&bp, Some(&statuses()));
    let node_lines: Vec<&str> = chart.lines().skip(1).take(bp.len()).collect();
    for (i, line) in node_lines.iter().enumerate() {
        assert!(line.starts_with(&format!("    n{i}")), "{line}");
        let label = line.split('"').nth(1).unwrap();
        let without_tags = label
            .replace("<br/>", "")
            .replace("<i>", "")
            .replace("</i>", "");
        assert!(
            !without_tags.contains(['<', '>', '&', '`']),
            "raw markup in {line}"
        );
        assert_eq!(line.matches('"').count(), 2, "{line}");
    }
    assert_eq!(
        node_lines[1],
        "    n1([\"a #lt; b #amp;#amp; c #gt; d<br/><i>Condition</i>\"])"
    );
    assert!(chart.contains("    class n1,n3 success;\n"));
    assert!(chart.contains("    class n5 skipped;\n"));
    assert_eq!(chart.matches(" --> ").count(), bp.len() - 1);
}

#[test]
fn every_format_is_deterministic_and_reachable_by_name() {
    for format in Format::ALL {
        let a = format.render(&nasty_tree(), Some(&statuses()));
        let b = format.render(&nasty_tree(), Some(&statuses()));
        assert_eq!(a, b, "{format} differs between two drawings");
        assert!(a.ends_with('\n'));
    }
    let bp = nasty_tree();
    assert_eq!(Format::Svg.render(&bp, None), render_svg(&bp, None));
    assert_eq!(Format::Dot.render(&bp, None), render_dot(&bp, None));
    assert_eq!(Format::Mermaid.render(&bp, None), render_mermaid(&bp, None));
}

/// A random blueprint: a Sequence root over nested Fallbacks and Inverters of leaves, the
/// shape given as a list of (depth change, kind) steps.
fn blueprint(steps: &[(u8, u8)], names: &[String]) -> Blueprint<()> {
    fn grow(
        b: neurotree::Builder<()>,
        steps: &[(u8, u8)],
        names: &[String],
        at: &mut usize,
        depth: u32,
    ) -> neurotree::Builder<()> {
        let mut b = b;
        while *at < steps.len() {
            let (kind, down) = steps[*at];
            let name = &names[*at % names.len()];
            *at += 1;
            b = match kind % 3 {
                0 if depth < 6 && down % 2 == 0 => b.fallback(name, |f| {
                    grow(f.always_failure("x"), steps, names, at, depth + 1)
                }),
                1 if depth < 6 => b.inverter(name, |i| i.condition(name, |_: &()| true)),
                _ => b.action(name, |_: &mut ()| Status::Success),
            };
            if down % 5 == 4 && depth > 0 {
                break;
            }
        }
        b
    }
    let mut at = 0;
    Blueprint::<()>::builder()
        .sequence("root", |s| {
            grow(s.always_success("first"), steps, names, &mut at, 0)
        })
        .build()
        .unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn any_tree_with_any_names_gives_valid_svg(
        steps in prop::collection::vec((any::<u8>(), any::<u8>()), 0..40),
        names in prop::collection::vec(".{0,12}", 1..6),
        raw_statuses in prop::collection::vec(0u8..5, 0..80),
    ) {
        let bp = blueprint(&steps, &names);
        let statuses: Vec<NodeStatus> = raw_statuses
            .iter()
            .map(|s| [NodeStatus::Idle, NodeStatus::Running, NodeStatus::Success, NodeStatus::Failure, NodeStatus::Skipped][*s as usize])
            .collect();
        let svg = render_svg(&bp, Some(&statuses));
        let doc = roxmltree::Document::parse(&svg);
        prop_assert!(doc.is_ok(), "{:?}", doc.err());
        let doc = doc.unwrap();
        let rects = doc
            .descendants()
            .filter(|n| n.attribute("class").is_some_and(|c| c.starts_with("node ")))
            .count();
        prop_assert_eq!(rects, bp.len());
    }
}
