//! The text drawings: one line per node, indented with tree-drawing characters.

use std::fmt::Write as _;

use neurotree_core::{Blueprint, NodeId, NodeStatus, Tree};

/// Draws `tree`'s stored statuses with ascii characters (`+--`, `\--`, `|`, `[S]`, `[F]`).
pub fn render_ascii<C>(tree: &Tree<C>) -> String {
    render_statuses(tree.blueprint(), tree.statuses(), false)
}

/// Draws `tree`'s stored statuses with unicode characters (`├──`, `└──`, `│`, `[✓]`, `[✗]`).
pub fn render_unicode<C>(tree: &Tree<C>) -> String {
    render_statuses(tree.blueprint(), tree.statuses(), true)
}

/// Draws the nodes of `bp` with the given statuses, indexed by
/// [`NodeId`](neurotree_core::NodeId) (nodes beyond the end of `statuses` are drawn Idle).
/// `unicode` picks the character set; every line, the last included, ends with `\n`.
pub fn render_statuses<C>(bp: &Blueprint<C>, statuses: &[NodeStatus], unicode: bool) -> String {
    render_statuses_noted(bp, statuses, &[], unicode)
}

/// Draws as [`render_statuses`] does, with `notes[id]`, where there is one and it is not
/// empty, after the node's label as ` -- NOTE` (as `neurotree show --trace` marks the
/// path that failed).
///
/// ```
/// use neurotree::render::render_statuses_noted;
/// use neurotree::{Blueprint, NodeStatus};
///
/// let bp = Blueprint::<()>::builder().always_failure("no").build().unwrap();
/// let notes = ["failed".to_string()];
/// assert_eq!(
///     render_statuses_noted(&bp, &[NodeStatus::Failure], &notes, false),
///     "[F] no (AlwaysFailure) -- failed\n"
/// );
/// ```
pub fn render_statuses_noted<C>(
    bp: &Blueprint<C>,
    statuses: &[NodeStatus],
    notes: &[String],
    unicode: bool,
) -> String {
    let glyphs = if unicode { &UNICODE } else { &ASCII };
    draw_lines(
        bp,
        unicode,
        |id, out| {
            let status = statuses.get(id.index()).copied().unwrap_or_default();
            out.push_str(glyphs.marker(status));
        },
        |id, out| {
            if let Some(note) = notes.get(id.index()).filter(|n| !n.is_empty()) {
                out.push_str(" -- ");
                out.push_str(note);
            }
        },
    )
}

/// The text drawing of `bp`, each line's marker written by `marker` before the label and
/// `note` after it; [`render_statuses`] and the coverage drawing share it.
pub(crate) fn draw_lines<C>(
    bp: &Blueprint<C>,
    unicode: bool,
    mut marker: impl FnMut(NodeId, &mut String),
    mut note: impl FnMut(NodeId, &mut String),
) -> String {
    let glyphs = if unicode { &UNICODE } else { &ASCII };
    let mut out = String::new();
    // For each ancestor below the root, on the path to the current node: whether it has a
    // later sibling, so that its column carries on with a vertical bar.
    let mut open_columns: Vec<bool> = Vec::new();
    // Ids are in pre-order, so a node's ancestors have all been visited just before it.
    for id in bp.ids() {
        let depth = bp.depth(id) as usize;
        if let Some(parent) = bp.parent(id) {
            open_columns.truncate(depth - 2);
            for &open in &open_columns {
                out.push_str(if open { glyphs.pipe } else { glyphs.blank });
            }
            let is_last = bp.children(parent).last() == Some(&id);
            out.push_str(if is_last { glyphs.last } else { glyphs.branch });
            open_columns.push(!is_last);
        }
        marker(id, &mut out);
        out.push(' ');
        let name = bp.name(id);
        out.push_str(name);
        let type_name = type_label(bp, id);
        if type_name != name {
            // Writing into a String cannot fail.
            let _ = write!(out, " ({type_name})");
        }
        note(id, &mut out);
        out.push('\n');
    }
    out
}

/// What a node's label shows after its name: its registered type (`MoveTo`) when the name
/// is something else, else its kind (`Condition`, `SubTree`), so that a node named after its
/// type still says what it is.
pub(crate) fn type_label<C>(bp: &Blueprint<C>, id: NodeId) -> &str {
    let type_id = bp.type_id(id);
    if type_id != bp.name(id) {
        type_id
    } else {
        bp.kind(id).type_name()
    }
}

/// The characters of one style of drawing.
struct Glyphs {
    branch: &'static str,
    last: &'static str,
    pipe: &'static str,
    blank: &'static str,
    markers: [&'static str; 5],
}

impl Glyphs {
    fn marker(&self, status: NodeStatus) -> &'static str {
        self.markers[match status {
            NodeStatus::Idle => 0,
            NodeStatus::Running => 1,
            NodeStatus::Success => 2,
            NodeStatus::Failure => 3,
            NodeStatus::Skipped => 4,
        }]
    }
}

const ASCII: Glyphs = Glyphs {
    branch: "+-- ",
    last: "\\-- ",
    pipe: "|   ",
    blank: "    ",
    markers: ["[ ]", "[R]", "[S]", "[F]", "[-]"],
};

const UNICODE: Glyphs = Glyphs {
    branch: "├── ",
    last: "└── ",
    pipe: "│   ",
    blank: "    ",
    markers: ["[ ]", "[R]", "[✓]", "[✗]", "[-]"],
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::fixtures::Work;
    use neurotree_core::{Builder, ManualClock, Status};

    fn sample() -> std::sync::Arc<Blueprint<u32>> {
        Builder::<u32>::new()
            .sequence("root", |s| {
                s.fallback("choose", |f| {
                    f.condition("big", |n: &u32| *n > 10)
                        .inverter("", |i| i.condition("odd", |n: &u32| n % 2 == 1))
                })
                .always_success("")
                .action("done", |_: &mut u32| Status::Success)
            })
            .build_shared()
            .unwrap()
    }

    #[test]
    fn ascii_drawing_of_stored_statuses() {
        let bp = sample();
        let statuses = [
            NodeStatus::Running,
            NodeStatus::Success,
            NodeStatus::Failure,
            NodeStatus::Success,
            NodeStatus::Failure,
            NodeStatus::Skipped,
        ];
        assert_eq!(
            render_statuses(&bp, &statuses, false),
            "[R] root (Sequence)\n\
             +-- [S] choose (Fallback)\n\
             |   +-- [F] big (Condition)\n\
             |   \\-- [S] Inverter\n\
             |       \\-- [F] odd (Condition)\n\
             +-- [-] AlwaysSuccess\n\
             \\-- [ ] done (Action)\n"
        );
    }

    #[test]
    fn unicode_drawing_of_stored_statuses() {
        let bp = sample();
        let statuses = [
            NodeStatus::Running,
            NodeStatus::Success,
            NodeStatus::Failure,
            NodeStatus::Success,
            NodeStatus::Failure,
        ];
        assert_eq!(
            render_statuses(&bp, &statuses, true),
            "[R] root (Sequence)\n\
             ├── [✓] choose (Fallback)\n\
             │   ├── [✗] big (Condition)\n\
             │   └── [✓] Inverter\n\
             │       └── [✗] odd (Condition)\n\
             ├── [ ] AlwaysSuccess\n\
             └── [ ] done (Action)\n"
        );
    }

    #[test]
    fn single_node_and_last_branch_columns_stay_blank() {
        let bp = Builder::<()>::new().always_failure("only").build().unwrap();
        assert_eq!(
            render_statuses(&bp, &[NodeStatus::Failure], true),
            "[✗] only (AlwaysFailure)\n"
        );
        let bp = Builder::<()>::new()
            .sequence("a", |s| {
                s.sequence("b", |s| s.sequence("c", |s| s.always_success("d")))
                    .always_success("e")
            })
            .build()
            .unwrap();
        assert_eq!(
            render_statuses(&bp, &[], false),
            "[ ] a (Sequence)\n\
             +-- [ ] b (Sequence)\n\
             |   \\-- [ ] c (Sequence)\n\
             |       \\-- [ ] d (AlwaysSuccess)\n\
             \\-- [ ] e (AlwaysSuccess)\n"
        );
    }

    #[test]
    fn tree_renderers_show_what_is_stored() {
        let bp = Builder::<u32>::new()
            .sequence("job", |s| {
                s.always_success("prepare")
                    .stateful("work", || Work { left: 0, n: 1 })
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut n = 0;
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Running));
        assert_eq!(
            render_unicode(&tree),
            "[R] job (Sequence)\n\
             ├── [✓] prepare (AlwaysSuccess)\n\
             └── [R] work (StatefulAction)\n"
        );
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Success));
        assert_eq!(
            render_ascii(&tree),
            "[ ] job (Sequence)\n\
             +-- [ ] prepare (AlwaysSuccess)\n\
             \\-- [ ] work (StatefulAction)\n"
        );
    }
}
