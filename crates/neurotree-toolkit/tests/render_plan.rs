//! The plan the studio's page draws from, on random trees loaded from XML: top-down at full
//! detail it places every box where `render_svg` does, with the same size; in any
//! orientation, at either detail, with any nodes folded, it places exactly the nodes no
//! folded node hides, and no two of their boxes overlap.

use neurotree::render::plan::{plan_boxes, plan_layout, plan_nodes, Detail, Orientation};
use neurotree::render::render_svg;
use neurotree::{Blueprint, Registry, XmlLoader};
use proptest::prelude::*;

const NAMES: [&str; 6] = [
    "go",
    "ClearLocalCostmap-Context",
    "ComputePathThroughPoses",
    "a name long enough to be wrapped onto two lines",
    "x",
    "Wait",
];

/// A random tree as XML: node `i > 0` under a node before it; each node's element chosen
/// by its number of children (a leaf, a decorator or a control), named or not.
fn tree_xml() -> impl Strategy<Value = String> {
    (1usize..40).prop_flat_map(|n| {
        let parents: Vec<BoxedStrategy<usize>> = (1..n).map(|i| (0..i).boxed()).collect();
        let picks = prop::collection::vec((0usize..6, 0usize..7), n);
        (parents, picks).prop_map(move |(parents, picks)| {
            let mut children = vec![Vec::new(); n];
            for (i, p) in parents.into_iter().enumerate() {
                children[p].push(i + 1);
            }
            let mut xml = String::from(
                r#"<root BTCPP_format="4" main_tree_to_execute="M"><BehaviorTree ID="M">"#,
            );
            write(0, &children, &picks, &mut xml);
            xml.push_str("</BehaviorTree></root>");
            xml
        })
    })
}

fn write(v: usize, children: &[Vec<usize>], picks: &[(usize, usize)], xml: &mut String) {
    let (name, kind) = picks[v];
    let name = if name < NAMES.len() - 1 {
        format!(" name=\"{}\"", NAMES[name])
    } else {
        String::new()
    };
    let (tag, attrs) = match (children[v].len(), kind) {
        (0, 0) => ("AlwaysSuccess", ""),
        (0, 1) => (
            "Script",
            r#" code="wait := 500; speed := 0.25; label := 'long enough to be cut on the node'""#,
        ),
        (0, 2) => ("Sleep", r#" msec="{wait}""#),
        (0, 3) => ("SetBlackboard", r#" value="42" output_key="answer""#),
        (0, _) => ("AlwaysFailure", ""),
        (1, 0) => ("Inverter", ""),
        (1, 1) => ("Repeat", r#" num_cycles="3""#),
        (1, 2) => ("ForceSuccess", ""),
        (_, 0 | 1) => ("Sequence", ""),
        (_, 2) => ("ReactiveFallback", ""),
        (_, 3) => ("Parallel", r#" success_count="1" failure_count="1""#),
        (_, 4) => ("IfThenElse", ""),
        _ => ("Fallback", ""),
    };
    // IfThenElse takes two or three children; any other count is a Sequence.
    let tag = if tag == "IfThenElse" && !(2..=3).contains(&children[v].len()) {
        "Sequence"
    } else {
        tag
    };
    xml.push_str(&format!("<{tag}{name}{attrs}>"));
    for &c in &children[v] {
        write(c, children, picks, xml);
    }
    xml.push_str(&format!("</{tag}>"));
}

fn load(xml: &str) -> Blueprint<()> {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(xml, "random.xml").expect("the tree loads");
    loader.build_main().expect("the tree builds")
}

/// Each node's box in the SVG, by node id: `(left, top, width, height)`.
fn svg_boxes(svg: &str) -> Vec<(f64, f64, f64, f64)> {
    let number = |s: &str| -> f64 { s.parse().expect("a number") };
    let attr = |el: &str, name: &str| -> f64 {
        let at = el.find(&format!(" {name}=\"")).expect("the attribute") + name.len() + 3;
        number(&el[at..at + el[at..].find('"').unwrap()])
    };
    (0..)
        .map_while(|i| {
            let start = svg.find(&format!("<g id=\"n{i}\""))?;
            let node = &svg[start..start + svg[start..].find("</g>").unwrap()];
            let shape = &node[node.find("</title>").unwrap() + 8..];
            Some(if shape.starts_with("<polygon") {
                let at = shape.find("points=\"").unwrap() + 8;
                let points: Vec<(f64, f64)> = shape[at..at + shape[at..].find('"').unwrap()]
                    .split(' ')
                    .map(|p| {
                        let (x, y) = p.split_once(',').unwrap();
                        (number(x), number(y))
                    })
                    .collect();
                let xs = points.iter().map(|p| p.0);
                let ys = points.iter().map(|p| p.1);
                let (l, r) = (
                    xs.clone().fold(f64::INFINITY, f64::min),
                    xs.fold(f64::NEG_INFINITY, f64::max),
                );
                let (t, b) = (
                    ys.clone().fold(f64::INFINITY, f64::min),
                    ys.fold(f64::NEG_INFINITY, f64::max),
                );
                (l, t, r - l, b - t)
            } else {
                (
                    attr(shape, "x"),
                    attr(shape, "y"),
                    attr(shape, "width"),
                    attr(shape, "height"),
                )
            })
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(120))]

    #[test]
    fn top_down_at_full_detail_every_box_is_where_and_as_large_as_the_svg_draws_it(xml in tree_xml()) {
        let bp = load(&xml);
        let nodes = plan_nodes(&bp);
        let boxes = plan_boxes(&nodes);
        let placed = plan_layout(&nodes, &boxes, Orientation::TopDown, Detail::Full, &[]);
        let svg = svg_boxes(&render_svg(&bp, None));
        prop_assert_eq!(svg.len(), nodes.len());
        // The SVG has a margin of 16 and rounds to a tenth.
        for (i, ((l, t, w, h), b)) in svg.iter().zip(&boxes).enumerate() {
            let p = placed.nodes[i].expect("nothing folded");
            prop_assert!((p.x - b.width / 2.0 + 16.0 - l).abs() <= 0.051, "node {}: {:?} against {:?}", i, p, (l, t));
            prop_assert!((p.y + 16.0 - t).abs() <= 0.051, "node {}: {:?} against {:?}", i, p, (l, t));
            prop_assert!((b.width - w).abs() <= 0.051 && (b.height - h).abs() <= 0.051, "node {}: {:?} against {:?}", i, (b.width, b.height), (w, h));
        }
    }

    #[test]
    fn any_orientation_detail_and_folds_place_the_nodes_not_hidden_and_no_two_overlap(
        xml in tree_xml(),
        left_to_right in any::<bool>(),
        compact in any::<bool>(),
        folds in prop::collection::vec(0usize..40, 0..4),
    ) {
        let bp = load(&xml);
        let nodes = plan_nodes(&bp);
        let boxes = plan_boxes(&nodes);
        let orientation = if left_to_right { Orientation::LeftRight } else { Orientation::TopDown };
        let detail = if compact { Detail::Compact } else { Detail::Full };
        let folded: Vec<usize> = folds.into_iter().filter(|&f| f < nodes.len()).collect();
        let placed = plan_layout(&nodes, &boxes, orientation, detail, &folded);
        // Hidden: under a folded node.
        let mut hidden = vec![false; nodes.len()];
        for id in bp.ids() {
            let mut up = bp.parent(id);
            while let Some(p) = up {
                if folded.contains(&p.index()) {
                    hidden[id.index()] = true;
                }
                up = bp.parent(p);
            }
        }
        let size = |i: usize| match detail {
            Detail::Full => (boxes[i].width, boxes[i].height),
            Detail::Compact => (boxes[i].compact.width, boxes[i].compact.height),
        };
        let mut shown = Vec::new();
        for (i, (place, hidden)) in placed.nodes.iter().zip(&hidden).enumerate() {
            prop_assert_eq!(place.is_none(), *hidden, "node {}", i);
            if let Some(p) = place {
                let (w, h) = size(i);
                let (l, t, r, b) = (p.x - w / 2.0, p.y, p.x + w / 2.0, p.y + h);
                prop_assert!(l >= -1e-6 && t >= -1e-6 && r <= placed.width + 1e-6 && b <= placed.height + 1e-6);
                shown.push((i, l, t, r, b));
            }
        }
        for (a, &(i, l1, t1, r1, b1)) in shown.iter().enumerate() {
            for &(j, l2, t2, r2, b2) in &shown[a + 1..] {
                let apart = r1 <= l2 + 1e-6 || r2 <= l1 + 1e-6 || b1 <= t2 + 1e-6 || b2 <= t1 + 1e-6;
                prop_assert!(apart, "nodes {} and {} overlap", i, j);
            }
        }
    }
}

#[test]
fn a_long_name_is_wrapped_in_compact_and_whole_at_full_detail() {
    let bp = load(
        r#"<root BTCPP_format="4" main_tree_to_execute="M"><BehaviorTree ID="M">
        <AlwaysSuccess name="ComputePathThroughPoses"/></BehaviorTree></root>"#,
    );
    let boxes = plan_boxes(&plan_nodes(&bp));
    assert_eq!(boxes[0].label, "ComputePathThroughPoses");
    assert_eq!(boxes[0].compact.lines, ["ComputePath", "ThroughPoses"]);
    assert!(boxes[0].compact.width < boxes[0].width);
    assert_eq!(boxes[0].type_label.as_deref(), Some("AlwaysSuccess"));
}
