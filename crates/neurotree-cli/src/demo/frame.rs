//! One frame of the demo as plain text: a few status lines, the map, the tree with its
//! statuses, and what happened in the tick.

use std::fmt::Write as _;

/// Where a frame puts the tree.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Layout {
    /// Below the map: narrow (about 75 columns) and tall, for pipes and small terminals.
    #[default]
    Stacked,
    /// Right of the map: wide (about 115 columns) and short enough for a terminal of 45
    /// lines.
    SideBySide,
}

/// The pieces of a frame.
pub(super) struct Parts<'a> {
    /// Status lines, each at most as wide as the map.
    pub(super) head: &'a [String],
    /// The map, one line per row.
    pub(super) map: &'a str,
    /// The tree with its statuses.
    pub(super) tree: &'a str,
    /// What happened in the tick.
    pub(super) notes: &'a [String],
}

/// Columns between the map and the tree side by side.
const GAP: usize = 3;

impl Parts<'_> {
    pub(super) fn compose(&self, layout: Layout) -> String {
        let left: Vec<&str> = self
            .head
            .iter()
            .map(String::as_str)
            .chain([""])
            .chain(self.map.lines())
            .collect();
        let mut out = String::new();
        match layout {
            Layout::Stacked => {
                for line in &left {
                    out.push_str(line);
                    out.push('\n');
                }
                self.write_notes(&mut out);
                out.push('\n');
                out.push_str(self.tree);
            }
            Layout::SideBySide => {
                let width = left.iter().map(|l| columns(l)).max().unwrap_or(0) + GAP;
                let tree: Vec<&str> = self.tree.lines().collect();
                for i in 0..left.len().max(tree.len()) {
                    let l = left.get(i).copied().unwrap_or("");
                    match tree.get(i) {
                        Some(t) => {
                            let pad = width.saturating_sub(columns(l));
                            // Writing to a String cannot fail.
                            let _ = writeln!(out, "{l}{:pad$}{t}", "");
                        }
                        None => {
                            out.push_str(l);
                            out.push('\n');
                        }
                    }
                }
                self.write_notes(&mut out);
            }
        }
        out
    }

    fn write_notes(&self, out: &mut String) {
        for note in self.notes {
            out.push_str("  > ");
            out.push_str(note);
            out.push('\n');
        }
    }
}

/// Terminal columns `line` takes: one per character (the map and the tree's marks and box
/// lines are all single-width).
fn columns(line: &str) -> usize {
    line.chars().count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stacked_and_side_by_side() {
        let head = ["tick 1".to_string()];
        let notes = ["planned".to_string()];
        let parts = Parts {
            head: &head,
            map: "#R.#\n####\n",
            tree: "[R] a\n└── [R] b\n",
            notes: &notes,
        };
        assert_eq!(
            parts.compose(Layout::Stacked),
            "tick 1\n\n#R.#\n####\n  > planned\n\n[R] a\n└── [R] b\n"
        );
        assert_eq!(
            parts.compose(Layout::SideBySide),
            "tick 1   [R] a\n         └── [R] b\n#R.#\n####\n  > planned\n"
        );
    }
}
