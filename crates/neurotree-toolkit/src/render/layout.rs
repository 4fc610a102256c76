//! Tidy drawing of trees: where each node's box goes in a picture.
//!
//! The layout is the one of Reingold and Tilford as generalised by Walker, computed in
//! linear time as Buchheim, Jünger and Leipert describe ("Improving Walker's Algorithm to
//! Run in Linear Time", 2002), with boxes of different widths:
//!
//! - nodes of one depth share a row; rows are stacked with a fixed gap;
//! - children keep their order, left to right;
//! - a parent is centred over its leftmost and rightmost children;
//! - subtrees are pushed apart until no two boxes of a row are closer than the gap (one gap
//!   between siblings, a wider one between cousins), and no further: the drawing is as
//!   narrow as these rules allow, and the smaller subtrees caught between two that had to
//!   be separated are spread evenly between them.
//!
//! The module knows nothing of behavior trees: it lays out any tree given as child lists,
//! so the pictures and the property tests share it.
//!
//! ```
//! use neurotree::render::layout::{tidy, Size, Spacing};
//!
//! // A root with two leaves.
//! let children = vec![vec![1, 2], vec![], vec![]];
//! let sizes = vec![Size::new(40.0, 20.0); 3];
//! let layout = tidy(&children, &sizes, Spacing::default()).unwrap();
//! let [root, left, right] = [layout.nodes[0], layout.nodes[1], layout.nodes[2]];
//! assert_eq!(root.x, (left.x + right.x) / 2.0);
//! assert_eq!(right.left() - left.right(), Spacing::default().sibling);
//! ```

/// The size of a node's box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Size {
    /// Horizontal extent.
    pub width: f64,
    /// Vertical extent.
    pub height: f64,
}

impl Size {
    /// A box `width` wide and `height` high.
    pub const fn new(width: f64, height: f64) -> Self {
        Self { width, height }
    }
}

/// The gaps the layout keeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spacing {
    /// Between the boxes of two children of one parent.
    pub sibling: f64,
    /// Between neighbouring boxes of a row that have different parents.
    pub cousin: f64,
    /// Between one row and the next.
    pub level: f64,
}

impl Default for Spacing {
    fn default() -> Self {
        Self {
            sibling: 14.0,
            cousin: 24.0,
            level: 36.0,
        }
    }
}

/// Where one node's box goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placed {
    /// The horizontal centre.
    pub x: f64,
    /// The top edge.
    pub y: f64,
    /// The box's size.
    pub size: Size,
}

impl Placed {
    /// The left edge.
    pub fn left(&self) -> f64 {
        self.x - self.size.width / 2.0
    }

    /// The right edge.
    pub fn right(&self) -> f64 {
        self.x + self.size.width / 2.0
    }

    /// The bottom edge.
    pub fn bottom(&self) -> f64 {
        self.y + self.size.height
    }

    /// The vertical centre.
    pub fn middle(&self) -> f64 {
        self.y + self.size.height / 2.0
    }
}

/// A laid-out tree: each node's box (by index), and the extent of the whole.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// The boxes, indexed like the input; the leftmost edge is at 0, the top row at 0.
    pub nodes: Vec<Placed>,
    /// From the leftmost edge to the rightmost one.
    pub width: f64,
    /// From the top of the first row to the bottom of the last.
    pub height: f64,
}

/// Why a tree could not be laid out.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum LayoutError {
    /// The child lists and the sizes describe different numbers of nodes.
    #[error("{children} child lists but {sizes} sizes; give one of each per node")]
    LengthMismatch {
        /// Number of child lists.
        children: usize,
        /// Number of sizes.
        sizes: usize,
    },
    /// A child list names a node that does not exist.
    #[error("node {parent} lists child {child}, but there are only {len} nodes")]
    OutOfRange {
        /// The node whose list is wrong.
        parent: usize,
        /// The child it names.
        child: usize,
        /// How many nodes there are.
        len: usize,
    },
    /// A node is listed as a child twice, or the root (node 0) is listed as a child.
    #[error(
        "node {0} is listed as a child more than once, or is the root; a tree node has one parent"
    )]
    SharedChild(usize),
    /// A node cannot be reached from the root (node 0).
    #[error("node {0} cannot be reached from the root (node 0)")]
    Unreachable(usize),
    /// A size is negative, infinite or not a number.
    #[error("node {0} has a negative or non-finite size")]
    BadSize(usize),
}

neurotree_core::debug_shows_message!(enum LayoutError {
    LengthMismatch { children, sizes },
    OutOfRange { parent, child, len },
    SharedChild(source),
    Unreachable(source),
    BadSize(source),
});

/// Lays out the tree whose node `i` has the children `children[i]` (left to right) and the
/// box `sizes[i]`; node 0 is the root.
pub fn tidy(
    children: &[Vec<usize>],
    sizes: &[Size],
    spacing: Spacing,
) -> Result<Layout, LayoutError> {
    let parent = check_tree(children, sizes)?;
    if children.is_empty() {
        return Ok(Layout {
            nodes: Vec::new(),
            width: 0.0,
            height: 0.0,
        });
    }
    let mut walker = Walker::new(children, sizes, parent, spacing);
    walker.first_walk();
    let x = walker.second_walk();
    Ok(place(children, sizes, &x, spacing))
}

/// Each node's parent, once the input is known to be a tree rooted at 0.
fn check_tree(children: &[Vec<usize>], sizes: &[Size]) -> Result<Vec<Option<usize>>, LayoutError> {
    let len = children.len();
    if sizes.len() != len {
        return Err(LayoutError::LengthMismatch {
            children: len,
            sizes: sizes.len(),
        });
    }
    if let Some(i) = sizes.iter().position(|s| {
        !(s.width.is_finite() && s.height.is_finite() && s.width >= 0.0 && s.height >= 0.0)
    }) {
        return Err(LayoutError::BadSize(i));
    }
    let mut parent = vec![None; len];
    for (p, kids) in children.iter().enumerate() {
        for &child in kids {
            if child >= len {
                return Err(LayoutError::OutOfRange {
                    parent: p,
                    child,
                    len,
                });
            }
            if child == 0 || parent[child].is_some() {
                return Err(LayoutError::SharedChild(child));
            }
            parent[child] = Some(p);
        }
    }
    // Every node but the root has one parent; a node that still cannot be reached sits on
    // a cycle away from the root.
    let mut seen = vec![false; len];
    let mut stack = if len > 0 { vec![0] } else { Vec::new() };
    while let Some(v) = stack.pop() {
        seen[v] = true;
        stack.extend(children[v].iter().copied().filter(|c| !seen[*c]));
    }
    match seen.iter().position(|s| !s) {
        Some(i) => Err(LayoutError::Unreachable(i)),
        None => Ok(parent),
    }
}

/// The state of Buchheim's version of Walker's algorithm, one entry per node.
struct Walker<'a> {
    children: &'a [Vec<usize>],
    sizes: &'a [Size],
    spacing: Spacing,
    parent: Vec<Option<usize>>,
    /// 1-based position among its siblings.
    number: Vec<usize>,
    /// Position relative to the parent's, before the modifiers are summed.
    prelim: Vec<f64>,
    /// Shift applied to the whole subtree below, children included.
    modifier: Vec<f64>,
    /// The next node of a contour, for a leaf whose subtree is shallower than a neighbour's.
    thread: Vec<Option<usize>>,
    ancestor: Vec<usize>,
    change: Vec<f64>,
    shift: Vec<f64>,
    /// Per parent, the child `apportion` charges a shift to when no better one is known.
    default_ancestor: Vec<usize>,
}

impl<'a> Walker<'a> {
    fn new(
        children: &'a [Vec<usize>],
        sizes: &'a [Size],
        parent: Vec<Option<usize>>,
        spacing: Spacing,
    ) -> Self {
        let n = children.len();
        let mut number = vec![1; n];
        for kids in children {
            for (i, &c) in kids.iter().enumerate() {
                number[c] = i + 1;
            }
        }
        Self {
            children,
            sizes,
            spacing,
            parent,
            number,
            prelim: vec![0.0; n],
            modifier: vec![0.0; n],
            thread: vec![None; n],
            ancestor: (0..n).collect(),
            change: vec![0.0; n],
            shift: vec![0.0; n],
            default_ancestor: children
                .iter()
                .enumerate()
                .map(|(v, kids)| kids.first().copied().unwrap_or(v))
                .collect(),
        }
    }

    /// Post-order, without recursion so that depth is bounded by memory, not the stack:
    /// each node is finished once its children are, and then fitted against its left
    /// siblings, as the recursive formulation does on returning from it.
    fn first_walk(&mut self) {
        let children = self.children;
        let mut stack: Vec<(usize, usize)> = vec![(0, 0)];
        while let Some(top) = stack.last_mut() {
            let (v, next) = *top;
            if let Some(&child) = children[v].get(next) {
                top.1 += 1;
                stack.push((child, 0));
                continue;
            }
            stack.pop();
            self.finish(v);
            if let Some(p) = self.parent[v] {
                self.default_ancestor[p] = self.apportion(v, self.default_ancestor[p]);
            }
        }
    }

    fn finish(&mut self, v: usize) {
        let left = self.left_sibling(v);
        let (Some(&first), Some(&last)) = (self.children[v].first(), self.children[v].last())
        else {
            self.prelim[v] = left.map_or(0.0, |w| self.prelim[w] + self.distance(w, v));
            return;
        };
        self.execute_shifts(v);
        let midpoint = (self.prelim[first] + self.prelim[last]) / 2.0;
        match left {
            Some(w) => {
                self.prelim[v] = self.prelim[w] + self.distance(w, v);
                self.modifier[v] = self.prelim[v] - midpoint;
            }
            None => self.prelim[v] = midpoint,
        }
    }

    /// Pushes `v`'s subtree right until it clears every subtree to its left, row by row,
    /// following the right contour of those and the left contour of `v`'s.
    fn apportion(&mut self, v: usize, default_ancestor: usize) -> usize {
        let Some(w) = self.left_sibling(v) else {
            return default_ancestor;
        };
        let mut default_ancestor = default_ancestor;
        // Inside/outside, right/left contours ("p" for plus, "m" for minus).
        let (mut vip, mut vop, mut vim) = (v, v, w);
        let mut vom = self.leftmost_sibling(v);
        let (mut sip, mut sop) = (self.modifier[vip], self.modifier[vop]);
        let (mut sim, mut som) = (self.modifier[vim], self.modifier[vom]);
        while let (Some(next_im), Some(next_ip)) = (self.next_right(vim), self.next_left(vip)) {
            vim = next_im;
            vip = next_ip;
            // The outer contours are as deep as the inner ones (threads make them so), so
            // they too have a node on this row; the fallback is never taken.
            vom = self.next_left(vom).unwrap_or(vom);
            vop = self.next_right(vop).unwrap_or(vop);
            self.ancestor[vop] = v;
            let shift =
                (self.prelim[vim] + sim) - (self.prelim[vip] + sip) + self.distance(vim, vip);
            if shift > 0.0 {
                let from = self.ancestor_of(vim, v, default_ancestor);
                self.move_subtree(from, v, shift);
                sip += shift;
                sop += shift;
            }
            sim += self.modifier[vim];
            sip += self.modifier[vip];
            som += self.modifier[vom];
            sop += self.modifier[vop];
        }
        if let (Some(next), None) = (self.next_right(vim), self.next_right(vop)) {
            self.thread[vop] = Some(next);
            self.modifier[vop] += sim - sop;
        }
        if let (Some(next), None) = (self.next_left(vip), self.next_left(vom)) {
            self.thread[vom] = Some(next);
            self.modifier[vom] += sip - som;
            default_ancestor = v;
        }
        default_ancestor
    }

    /// Moves the subtree of `wp` right by `shift`, and records that the subtrees between
    /// `wm` and `wp` move by an even share of it (applied by `execute_shifts`).
    fn move_subtree(&mut self, wm: usize, wp: usize, shift: f64) {
        let between = (self.number[wp] - self.number[wm]) as f64;
        self.change[wp] -= shift / between;
        self.shift[wp] += shift;
        self.change[wm] += shift / between;
        self.prelim[wp] += shift;
        self.modifier[wp] += shift;
    }

    fn execute_shifts(&mut self, v: usize) {
        let (mut shift, mut change) = (0.0, 0.0);
        for &w in self.children[v].iter().rev() {
            self.prelim[w] += shift;
            self.modifier[w] += shift;
            change += self.change[w];
            shift += self.shift[w] + change;
        }
    }

    /// The sibling of `v` whose subtree holds `vim`, if recorded; else the default.
    fn ancestor_of(&self, vim: usize, v: usize, default_ancestor: usize) -> usize {
        let a = self.ancestor[vim];
        if self.parent[a] == self.parent[v] {
            a
        } else {
            default_ancestor
        }
    }

    /// Absolute centres: each node's preliminary place plus its ancestors' modifiers.
    fn second_walk(&self) -> Vec<f64> {
        let mut x = vec![0.0; self.children.len()];
        let mut stack = vec![(0, 0.0)];
        while let Some((v, m)) = stack.pop() {
            x[v] = self.prelim[v] + m;
            for &c in &self.children[v] {
                stack.push((c, m + self.modifier[v]));
            }
        }
        x
    }

    fn distance(&self, a: usize, b: usize) -> f64 {
        let gap = if self.parent[a] == self.parent[b] {
            self.spacing.sibling
        } else {
            self.spacing.cousin
        };
        (self.sizes[a].width + self.sizes[b].width) / 2.0 + gap
    }

    fn left_sibling(&self, v: usize) -> Option<usize> {
        let p = self.parent[v]?;
        let i = self.number[v];
        (i > 1).then(|| self.children[p][i - 2])
    }

    fn leftmost_sibling(&self, v: usize) -> usize {
        self.parent[v].map_or(v, |p| self.children[p][0])
    }

    fn next_left(&self, v: usize) -> Option<usize> {
        self.children[v].first().copied().or(self.thread[v])
    }

    fn next_right(&self, v: usize) -> Option<usize> {
        self.children[v].last().copied().or(self.thread[v])
    }
}

/// Boxes from centres: rows as high as their highest box, everything moved so that the
/// leftmost edge is at 0.
fn place(children: &[Vec<usize>], sizes: &[Size], x: &[f64], spacing: Spacing) -> Layout {
    let n = children.len();
    let mut depth = vec![0usize; n];
    let mut stack = vec![0];
    while let Some(v) = stack.pop() {
        for &c in &children[v] {
            depth[c] = depth[v] + 1;
            stack.push(c);
        }
    }
    let rows = depth.iter().max().map_or(0, |d| d + 1);
    let mut row_height = vec![0.0f64; rows];
    for (v, &d) in depth.iter().enumerate() {
        row_height[d] = row_height[d].max(sizes[v].height);
    }
    let mut row_top = Vec::with_capacity(rows);
    let mut top = 0.0;
    for h in &row_height {
        row_top.push(top);
        top += h + spacing.level;
    }
    let height = (top - spacing.level).max(0.0);
    let min_left = (0..n)
        .map(|v| x[v] - sizes[v].width / 2.0)
        .fold(f64::INFINITY, f64::min);
    let nodes: Vec<Placed> = (0..n)
        .map(|v| Placed {
            x: x[v] - min_left,
            y: row_top[depth[v]] + (row_height[depth[v]] - sizes[v].height) / 2.0,
            size: sizes[v],
        })
        .collect();
    let width = nodes.iter().map(Placed::right).fold(0.0, f64::max);
    Layout {
        nodes,
        width,
        height,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sizes(widths: &[f64]) -> Vec<Size> {
        widths.iter().map(|w| Size::new(*w, 20.0)).collect()
    }

    #[test]
    fn leaves_of_one_parent_sit_side_by_side_with_the_parent_centred() {
        let children = vec![vec![1, 2, 3], vec![], vec![], vec![]];
        let layout = tidy(
            &children,
            &sizes(&[10.0, 30.0, 50.0, 70.0]),
            Spacing::default(),
        )
        .unwrap();
        let n = &layout.nodes;
        assert_eq!(n[1].left(), 0.0);
        assert_eq!(n[2].left(), 30.0 + 14.0);
        assert_eq!(n[3].left(), 30.0 + 14.0 + 50.0 + 14.0);
        assert_eq!(layout.width, 30.0 + 50.0 + 70.0 + 2.0 * 14.0);
        assert_eq!(n[0].x, (n[1].x + n[3].x) / 2.0);
        assert_eq!(n[0].y, 0.0);
        assert_eq!(n[1].y, 20.0 + 36.0);
        assert_eq!(layout.height, 20.0 + 36.0 + 20.0);
    }

    #[test]
    fn cousins_keep_the_wider_gap_and_a_small_subtree_between_big_ones_is_centred() {
        // 0 has children 1, 2, 3; 1 and 3 have two wide leaves each, 2 is a lone leaf.
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
        let w = [20.0, 20.0, 20.0, 20.0, 100.0, 100.0, 100.0, 100.0];
        let layout = tidy(&children, &sizes(&w), Spacing::default()).unwrap();
        let n = &layout.nodes;
        // Leaf 5 (under 1) and leaf 6 (under 3) are cousins: the cousin gap, exactly.
        assert_eq!(n[6].left() - n[5].right(), 24.0);
        // The lone leaf 2 is spread evenly between its siblings.
        assert!((n[2].x - (n[1].x + n[3].x) / 2.0).abs() < 1e-9);
    }

    #[test]
    fn a_single_child_is_straight_below_and_an_empty_tree_is_empty() {
        let layout = tidy(
            &[vec![1], vec![]],
            &sizes(&[80.0, 20.0]),
            Spacing::default(),
        )
        .unwrap();
        assert_eq!(layout.nodes[0].x, layout.nodes[1].x);
        assert_eq!(layout.nodes[0].left(), 0.0);
        assert_eq!(layout.width, 80.0);
        let empty = tidy(&[], &[], Spacing::default()).unwrap();
        assert!(empty.nodes.is_empty());
        assert_eq!((empty.width, empty.height), (0.0, 0.0));
    }

    #[test]
    fn input_that_is_not_a_tree_is_an_error() {
        let s = sizes(&[1.0, 1.0, 1.0]);
        let spacing = Spacing::default();
        assert_eq!(
            tidy(&[vec![1], vec![]], &s, spacing),
            Err(LayoutError::LengthMismatch {
                children: 2,
                sizes: 3
            })
        );
        assert_eq!(
            tidy(&[vec![5], vec![], vec![]], &s, spacing),
            Err(LayoutError::OutOfRange {
                parent: 0,
                child: 5,
                len: 3
            })
        );
        assert_eq!(
            tidy(&[vec![1, 2], vec![2], vec![]], &s, spacing),
            Err(LayoutError::SharedChild(2))
        );
        assert_eq!(
            tidy(&[vec![1], vec![0], vec![]], &s, spacing),
            Err(LayoutError::SharedChild(0))
        );
        assert_eq!(
            tidy(&[vec![], vec![2], vec![1]], &s, spacing),
            Err(LayoutError::Unreachable(1))
        );
        let bad = [Size::new(1.0, 1.0), Size::new(f64::NAN, 1.0)];
        assert_eq!(
            tidy(&[vec![1], vec![]], &bad, spacing),
            Err(LayoutError::BadSize(1))
        );
    }

    #[test]
    fn a_deep_chain_lays_out_without_recursion() {
        let n = 100_000;
        let children: Vec<Vec<usize>> = (0..n)
            .map(|i| if i + 1 < n { vec![i + 1] } else { vec![] })
            .collect();
        let layout = tidy(
            &children,
            &vec![Size::new(10.0, 10.0); n],
            Spacing::default(),
        )
        .unwrap();
        assert!(layout.nodes.iter().all(|p| p.x == 5.0));
        assert_eq!(layout.nodes[n - 1].y, (n - 1) as f64 * 46.0);
    }
}
