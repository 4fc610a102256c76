//! Pictures of what a run covered ([`CoverageReport`]): the nodes never reached stand out.
//!
//! The text formats mark each node and say what it lacks:
//!
//! | node | ascii | unicode | after the label |
//! |---|---|---|---|
//! | every possible outcome seen | `[+]` | `[✓]` | |
//! | reached, some outcome not seen | `[~]` | `[~]` | `-- not seen: failure, halted` |
//! | never reached | `[!]` | `[!]` | `-- never reached` |
//!
//! The picture formats colour each node as a status would be: covered as success (green),
//! reached with outcomes not seen as running (amber), never reached as skipped (light grey,
//! dashed); the SVG's legend says so.

use std::fmt::Write as _;

use neurotree_core::{Blueprint, NodeStatus};

use super::{render_dot, render_mermaid, svg, text, FailedPath, Format};
use crate::observe::{CoverageReport, NodeCoverage};

/// Draws `bp` in `format` with what `report` (made for `bp`) says each node covered:
/// covered, outcomes not seen, never reached (see [`Coverage`](crate::observe::Coverage)
/// for what counts).
///
/// ```
/// use neurotree::observe::Coverage;
/// use neurotree::render::{render_coverage, Format};
/// use neurotree::{Blueprint, ManualClock, Status, Tree};
///
/// let blueprint = Blueprint::<bool>::builder()
///     .fallback("find", |f| {
///         f.condition("near", |near: &bool| *near)
///             .action("walk", |_: &mut bool| Status::Success)
///     })
///     .build_shared()
///     .unwrap();
/// let mut tree = Tree::with_clock(blueprint.clone(), ManualClock::new());
/// let coverage = Coverage::new(&blueprint);
/// tree.set_observer(coverage.clone());
/// tree.tick_once(&mut true).unwrap();
/// tree.tick_once(&mut false).unwrap();
///
/// assert_eq!(
///     render_coverage(&blueprint, &coverage.report(&blueprint), Format::Ascii),
///     "[~] find (Fallback) -- not seen: failure\n\
///      +-- [+] near (Condition)\n\
///      \\-- [~] walk (Action) -- not seen: failure\n"
/// );
/// ```
pub fn render_coverage<C>(bp: &Blueprint<C>, report: &CoverageReport, format: Format) -> String {
    let nodes = report.nodes();
    match format {
        Format::Ascii | Format::Unicode => {
            let covered = if format == Format::Unicode {
                "[✓]"
            } else {
                "[+]"
            };
            text::draw_lines(
                bp,
                format == Format::Unicode,
                |id, out| {
                    out.push_str(match nodes.get(id.index()) {
                        Some(n) if n.is_covered() => covered,
                        Some(n) if n.reached => "[~]",
                        _ => "[!]",
                    });
                },
                |id, out| match nodes.get(id.index()) {
                    Some(n) if n.is_covered() => {}
                    // Writing into a String cannot fail.
                    Some(n) if n.reached => {
                        let _ = write!(out, " -- not seen: {}", n.missing());
                    }
                    _ => out.push_str(" -- never reached"),
                },
            )
        }
        Format::Dot | Format::Mermaid | Format::Svg => {
            let statuses: Vec<NodeStatus> = bp
                .ids()
                .map(|id| status_of(nodes.get(id.index())))
                .collect();
            match format {
                Format::Dot => render_dot(bp, Some(&statuses)),
                Format::Mermaid => render_mermaid(bp, Some(&statuses)),
                _ => svg::render_svg_with_legend(bp, Some(&statuses), &LEGEND, &FailedPath::new()),
            }
        }
    }
}

/// The legend of a coverage picture: the status whose colours stand for each case.
const LEGEND: [(NodeStatus, &str); 3] = [
    (NodeStatus::Success, "covered"),
    (NodeStatus::Running, "outcomes not seen"),
    (NodeStatus::Skipped, "never reached"),
];

/// The status whose colours a node is drawn with.
fn status_of(node: Option<&NodeCoverage>) -> NodeStatus {
    match node {
        Some(n) if n.is_covered() => NodeStatus::Success,
        Some(n) if n.reached => NodeStatus::Running,
        _ => NodeStatus::Skipped,
    }
}
