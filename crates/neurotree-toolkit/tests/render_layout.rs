//! The tidy layout's promises, on random trees: no two boxes overlap, sibling subtrees keep
//! apart row by row, children stay in order, and every parent is centred over its children.

use neurotree::render::layout::{tidy, Layout, Size, Spacing};
use proptest::prelude::*;

const EPS: f64 = 1e-6;

/// A random tree: node `i > 0` hangs under a node before it, so node 0 is the root; every
/// node has its own box size.
fn tree() -> impl Strategy<Value = (Vec<Vec<usize>>, Vec<Size>)> {
    (1usize..70).prop_flat_map(|n| {
        let parents: Vec<BoxedStrategy<usize>> = (1..n).map(|i| (0..i).boxed()).collect();
        let sizes = prop::collection::vec((1.0f64..220.0, 8.0f64..60.0), n);
        (parents, sizes).prop_map(move |(parents, sizes)| {
            let mut children = vec![Vec::new(); n];
            for (i, p) in parents.into_iter().enumerate() {
                children[p].push(i + 1);
            }
            let sizes = sizes.into_iter().map(|(w, h)| Size::new(w, h)).collect();
            (children, sizes)
        })
    })
}

fn spacing() -> impl Strategy<Value = Spacing> {
    (0.0f64..30.0, 0.0f64..30.0, 1.0f64..50.0).prop_map(|(sibling, extra, level)| Spacing {
        sibling,
        cousin: sibling + extra,
        level,
    })
}

/// Each node's depth and the nodes of its subtree (itself included).
fn depths_and_subtrees(children: &[Vec<usize>]) -> (Vec<usize>, Vec<Vec<usize>>) {
    let n = children.len();
    let mut depth = vec![0; n];
    let mut order = vec![0];
    let mut i = 0;
    while i < order.len() {
        let v = order[i];
        for &c in &children[v] {
            depth[c] = depth[v] + 1;
            order.push(c);
        }
        i += 1;
    }
    let mut subtree: Vec<Vec<usize>> = (0..n).map(|v| vec![v]).collect();
    // Breadth-first order reversed: every child is complete before its parent takes it.
    for &v in order.iter().rev() {
        for &c in &children[v] {
            let below = subtree[c].clone();
            subtree[v].extend(below);
        }
    }
    (depth, subtree)
}

fn check(children: &[Vec<usize>], sizes: &[Size], spacing: Spacing, layout: &Layout) {
    let nodes = &layout.nodes;
    let (depth, subtree) = depths_and_subtrees(children);
    // Sizes are kept, and the drawing starts at the origin and holds every box.
    for (p, s) in nodes.iter().zip(sizes) {
        assert_eq!(p.size, *s);
        assert!(p.left() >= -EPS && p.right() <= layout.width + EPS);
        assert!(p.y >= -EPS && p.bottom() <= layout.height + EPS);
    }
    let min_left = nodes.iter().map(|p| p.left()).fold(f64::INFINITY, f64::min);
    assert!(min_left.abs() < EPS, "the leftmost edge is at {min_left}");
    // No two boxes overlap; boxes of one row keep at least the sibling gap.
    for a in 0..nodes.len() {
        for b in a + 1..nodes.len() {
            let (pa, pb) = (nodes[a], nodes[b]);
            let apart_x = pb.left() - pa.right() >= spacing.sibling - EPS
                || pa.left() - pb.right() >= spacing.sibling - EPS;
            let apart_y = pb.y >= pa.bottom() - EPS || pa.y >= pb.bottom() - EPS;
            assert!(
                apart_x || apart_y,
                "boxes {a} and {b} overlap: {pa:?} {pb:?}"
            );
            if depth[a] == depth[b] {
                assert!(apart_x, "boxes {a} and {b} of one row are too close");
            } else {
                assert!(
                    apart_y,
                    "boxes {a} and {b} of different rows share a height"
                );
            }
        }
    }
    for (v, kids) in children.iter().enumerate() {
        let (Some(&first), Some(&last)) = (kids.first(), kids.last()) else {
            continue;
        };
        // Centred over the outer children.
        let centre = (nodes[first].x + nodes[last].x) / 2.0;
        assert!((nodes[v].x - centre).abs() < EPS, "node {v} is not centred");
        // Sibling subtrees in order, each row of a left one entirely left of the right one.
        for pair in kids.windows(2) {
            let (l, r) = (pair[0], pair[1]);
            for row in depth[l]..=depth.iter().copied().max().unwrap_or(0) {
                let right_edge = subtree[l]
                    .iter()
                    .filter(|&&u| depth[u] == row)
                    .map(|&u| nodes[u].right())
                    .fold(f64::NEG_INFINITY, f64::max);
                let left_edge = subtree[r]
                    .iter()
                    .filter(|&&u| depth[u] == row)
                    .map(|&u| nodes[u].left())
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    left_edge - right_edge >= spacing.sibling - EPS,
                    "subtrees of {l} and {r} cross on row {row}"
                );
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn random_trees_are_tidy((children, sizes) in tree(), spacing in spacing()) {
        let layout = tidy(&children, &sizes, spacing).unwrap();
        check(&children, &sizes, spacing, &layout);
    }

    #[test]
    fn the_layout_depends_only_on_the_input((children, sizes) in tree()) {
        let a = tidy(&children, &sizes, Spacing::default()).unwrap();
        let b = tidy(&children, &sizes, Spacing::default()).unwrap();
        prop_assert_eq!(a, b);
    }
}

#[test]
fn a_row_of_leaves_is_exactly_as_wide_as_its_boxes_and_gaps() {
    let children = vec![(1..=5).collect(), vec![], vec![], vec![], vec![], vec![]];
    let mut sizes = vec![Size::new(10.0, 10.0)];
    sizes.extend([30.0, 5.0, 80.0, 12.0, 40.0].map(|w| Size::new(w, 10.0)));
    let spacing = Spacing::default();
    let layout = tidy(&children, &sizes, spacing).unwrap();
    assert_eq!(
        layout.width,
        30.0 + 5.0 + 80.0 + 12.0 + 40.0 + 4.0 * spacing.sibling
    );
    check(&children, &sizes, spacing, &layout);
}

#[test]
fn a_small_subtree_between_two_wide_ones_does_not_widen_the_drawing() {
    // 0 ─ 1 (two wide leaves), 2 (a leaf), 3 (two wide leaves): the lone leaf fits in the
    // space the wide rows below leave, so the top row is no wider than the bottom one.
    let children = vec![
        vec![1, 2, 3],
        vec![4, 5],
        vec![],
        vec![6, 7],
        vec![],
        vec![],
        vec![],
        vec![],
    ];
    let mut sizes = vec![Size::new(20.0, 10.0); 4];
    sizes.extend([Size::new(100.0, 10.0); 4]);
    let spacing = Spacing::default();
    let layout = tidy(&children, &sizes, spacing).unwrap();
    assert_eq!(
        layout.width,
        4.0 * 100.0 + 2.0 * spacing.sibling + spacing.cousin
    );
    check(&children, &sizes, spacing, &layout);
}

#[test]
fn mirrored_trees_give_mirrored_drawings() {
    // The subtrees caught between two separated ones are spread evenly, so drawing a tree
    // and its mirror image gives mirror images.
    let children = vec![
        vec![1, 2, 3, 4],
        vec![5, 6, 7],
        vec![],
        vec![],
        vec![8],
        vec![],
        vec![],
        vec![],
        vec![9, 10],
        vec![],
        vec![],
    ];
    let mirrored: Vec<Vec<usize>> = children
        .iter()
        .map(|kids| kids.iter().rev().copied().collect())
        .collect();
    let sizes = vec![Size::new(30.0, 10.0); children.len()];
    let a = tidy(&children, &sizes, Spacing::default()).unwrap();
    let b = tidy(&mirrored, &sizes, Spacing::default()).unwrap();
    assert_eq!(a.width, b.width);
    for (pa, pb) in a.nodes.iter().zip(&b.nodes) {
        assert!((pa.x - (b.width - pb.x)).abs() < EPS);
    }
}
