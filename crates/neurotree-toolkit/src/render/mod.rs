//! Pictures of a tree, with or without the statuses of its nodes.
//!
//! | format | function | for |
//! |---|---|---|
//! | ascii, unicode | [`render_statuses`], [`render_ascii`], [`render_unicode`] | terminals, logs |
//! | Graphviz DOT | [`render_dot`] | `dot -Tpng`, other Graphviz tools |
//! | Mermaid | [`render_mermaid`] | Markdown on GitHub and GitLab, documentation sites |
//! | SVG | [`render_svg`] | browsers, documents; drawn here, no external tool |
//!
//! [`Format::render_failed_path`] draws, in any format, the statuses of a tick with the path
//! that failed in it ([`FailedPath`], from [`Tree::last_failure`](neurotree_core::Tree::last_failure)
//! or a trace) marked: the text formats note each node on it ` -- failed: REASON`; the
//! picture formats draw its nodes and the edges between them red and wide, and write each
//! reason in the label of the node that gave it.
//!
//! [`render_coverage`] draws, in any format, what a run covered
//! ([`CoverageReport`](crate::observe::CoverageReport)), the nodes never reached set apart.
//!
//! [`Format`] names them for a command line or a configuration file. The picture formats
//! share one look: a shape per family of node and a colour per status,
//!
//! | family | shape | | status | colour |
//! |---|---|---|---|---|
//! | Sequence | box with `→` | | success | green |
//! | Fallback | box with `?` | | failure | red |
//! | Parallel | box with `⇉` | | running | amber |
//! | other control | box | | idle | grey |
//! | decorator | hexagon | | skipped | light grey, dashed |
//! | condition | ellipse | | | |
//! | action | rounded box | | | |
//! | subtree | double box | | | |
//!
//! and the SVG is laid out by [`layout::tidy`], a tidy-tree layout usable on its own. In the
//! SVG each node also draws its ports under its name, `name: value`, a `{key}` binding in
//! blue apart from literal text, long values shortened with `…` and whole in the node's
//! title; [`drawing_metrics`] gives its sizes and font widths to other drawings of the
//! same boxes (the studio's page).
//!
//! ## Text
//!
//! One line per node in pre-order, indented by depth with tree-drawing characters, each
//! line a status marker, the node's name, and its kind's type name when that differs from
//! the name:
//!
//! ```text
//! [R] robot (ReactiveSequence)
//! ├── [✓] battery_ok (Condition)
//! └── [R] patrol (Sequence)
//!     ├── [✓] Inverter
//!     │   └── [✗] stuck (Condition)
//!     └── [R] move (StatefulAction)
//! ```
//!
//! | status | ascii | unicode |
//! |---|---|---|
//! | Idle | `[ ]` | `[ ]` |
//! | Running | `[R]` | `[R]` |
//! | Success | `[S]` | `[✓]` |
//! | Failure | `[F]` | `[✗]` |
//! | Skipped | `[-]` | `[-]` |
//!
//! The ascii form draws branches with `+--`, `\--` and `|`; the unicode form with `├──`,
//! `└──` and `│`.
//!
//! A tree's *stored* statuses ([`render_ascii`], [`render_unicode`]) show where a run
//! stands between ticks, but a root that completes resets every node to Idle, so after a
//! tick that finished the tree they are all blank. To see what happened *during* a tick,
//! attach a [`LastTickStatuses`] observer and draw what it recorded with
//! [`render_statuses`]:
//!
//! ```
//! use neurotree::render::{render_statuses, LastTickStatuses};
//! use neurotree::{Blueprint, ManualClock, Status, Tree};
//!
//! let blueprint = Blueprint::<u32>::builder()
//!     .fallback("find", |f| {
//!         f.condition("is_zero", |n: &u32| *n == 0)
//!             .action("decrement", |n: &mut u32| { *n -= 1; Status::Success })
//!     })
//!     .build_shared()
//!     .unwrap();
//! let mut tree = Tree::with_clock(blueprint, ManualClock::new());
//! let seen = LastTickStatuses::new();
//! tree.set_observer(seen.clone());
//!
//! assert_eq!(tree.tick_once(&mut 3), Ok(Status::Success));
//! // Completed, so every stored status is Idle again...
//! assert!(neurotree::render::render_ascii(&tree).starts_with("[ ] find"));
//! // ...but the observer kept what each node did.
//! assert_eq!(
//!     render_statuses(tree.blueprint(), &seen.statuses(), false),
//!     "[S] find (Fallback)\n\
//!      +-- [F] is_zero (Condition)\n\
//!      \\-- [S] decrement (Action)\n"
//! );
//! ```

mod coverage;
mod dot;
mod failed;
mod last_tick;
pub mod layout;
mod mermaid;
mod node_box;
pub mod plan;
mod style;
mod svg;
mod text;
mod text_width;

use std::fmt;
use std::str::FromStr;

use neurotree_core::{Blueprint, NodeStatus};

pub use coverage::render_coverage;
pub use dot::render_dot;
pub use failed::FailedPath;
pub use last_tick::LastTickStatuses;
pub use mermaid::render_mermaid;
pub use node_box::{direction_name, drawing_metrics, node_ports, DrawingMetrics};
pub use svg::render_svg;
pub use text::{render_ascii, render_statuses, render_statuses_noted, render_unicode};

/// A picture format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Text with ascii characters only ([`render_statuses`] with `unicode` false).
    Ascii,
    /// Text with box-drawing characters ([`render_statuses`] with `unicode` true).
    Unicode,
    /// Graphviz DOT ([`render_dot`]).
    Dot,
    /// A Mermaid flowchart ([`render_mermaid`]).
    Mermaid,
    /// A standalone SVG document ([`render_svg`]).
    Svg,
}

impl Format {
    /// Every format, in the order help texts list them.
    pub const ALL: [Format; 5] = [
        Format::Ascii,
        Format::Unicode,
        Format::Dot,
        Format::Mermaid,
        Format::Svg,
    ];

    /// The format's name, as [`FromStr`] reads it.
    pub const fn name(self) -> &'static str {
        match self {
            Format::Ascii => "ascii",
            Format::Unicode => "unicode",
            Format::Dot => "dot",
            Format::Mermaid => "mermaid",
            Format::Svg => "svg",
        }
    }

    /// The format a file name extension usually stands for: `svg`, `dot` or `gv`, `mmd` or
    /// `mermaid`, `txt` (unicode text).
    pub fn from_extension(extension: &str) -> Option<Format> {
        match extension.to_ascii_lowercase().as_str() {
            "svg" => Some(Format::Svg),
            "dot" | "gv" => Some(Format::Dot),
            "mmd" | "mermaid" => Some(Format::Mermaid),
            "txt" => Some(Format::Unicode),
            _ => None,
        }
    }

    /// Draws `bp` in this format; with `statuses` (by node id, Idle past the end) each node
    /// shows its status. The text formats always show a status, Idle when none is given.
    ///
    /// ```
    /// use neurotree::render::Format;
    /// use neurotree::{Blueprint, NodeStatus};
    ///
    /// let bp = Blueprint::<()>::builder().always_success("ok").build().unwrap();
    /// let format: Format = "ascii".parse().unwrap();
    /// assert_eq!(format.render(&bp, Some(&[NodeStatus::Success])), "[S] ok (AlwaysSuccess)\n");
    /// ```
    pub fn render<C>(self, bp: &Blueprint<C>, statuses: Option<&[NodeStatus]>) -> String {
        match self {
            Format::Ascii => render_statuses(bp, statuses.unwrap_or_default(), false),
            Format::Unicode => render_statuses(bp, statuses.unwrap_or_default(), true),
            Format::Dot => render_dot(bp, statuses),
            Format::Mermaid => render_mermaid(bp, statuses),
            Format::Svg => render_svg(bp, statuses),
        }
    }

    /// Draws `bp` in this format with `statuses` (by node id, Idle past the end) and the
    /// path that `failed` marked: in text, ` -- failed` after each node on it, with
    /// `: REASON` for a node that gave one (as [`render_statuses_noted`] writes notes); in
    /// DOT, Mermaid and SVG, its nodes and the edges between them red and three times as
    /// wide, and each reason as the last line of its node's label (see each format's page).
    /// An empty path draws as [`render`](Self::render) does.
    ///
    /// ```
    /// use neurotree::render::{FailedPath, Format};
    /// use neurotree::{Blueprint, NodeId, NodeStatus};
    ///
    /// let bp = Blueprint::<()>::builder()
    ///     .fallback("find", |f| f.always_failure("near").always_failure("far"))
    ///     .build()
    ///     .unwrap();
    /// let mut path = FailedPath::new();
    /// path.mark(NodeId(0), None);
    /// path.mark(NodeId(2), Some("blocked (error 106)".into()));
    /// let statuses = [NodeStatus::Failure; 3];
    /// assert_eq!(
    ///     Format::Ascii.render_failed_path(&bp, &statuses, &path),
    ///     "[F] find (Fallback) -- failed\n\
    ///      +-- [F] near (AlwaysFailure)\n\
    ///      \\-- [F] far (AlwaysFailure) -- failed: blocked (error 106)\n"
    /// );
    /// assert!(Format::Dot
    ///     .render_failed_path(&bp, &statuses, &path)
    ///     .contains("n0 -> n2 [color=\"#c92a2a\", penwidth=3];"));
    /// ```
    pub fn render_failed_path<C>(
        self,
        bp: &Blueprint<C>,
        statuses: &[NodeStatus],
        failed: &FailedPath,
    ) -> String {
        match self {
            Format::Ascii | Format::Unicode => {
                let notes = failed.notes(bp.len());
                render_statuses_noted(bp, statuses, &notes, self == Format::Unicode)
            }
            Format::Dot => dot::draw(bp, Some(statuses), failed),
            Format::Mermaid => mermaid::draw(bp, Some(statuses), failed),
            Format::Svg => svg::draw(bp, Some(statuses), failed),
        }
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A format name that [`Format`] does not know.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown picture format `{0}`; expected ascii, unicode, dot, mermaid or svg")]
pub struct UnknownFormat(pub String);

neurotree_core::debug_shows_message!(struct UnknownFormat(name));

impl FromStr for Format {
    type Err = UnknownFormat;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Format::ALL
            .into_iter()
            .find(|f| f.name().eq_ignore_ascii_case(text))
            .ok_or_else(|| UnknownFormat(text.to_string()))
    }
}

#[cfg(test)]
mod fixtures {
    use neurotree_core::{Handle, StatefulAction, Status};

    /// Running for `n` ticks, then Success; adds 100 to the context when halted.
    pub(crate) struct Work {
        pub(crate) left: u32,
        pub(crate) n: u32,
    }

    impl StatefulAction<u32> for Work {
        fn on_start(&mut self, h: &mut Handle<'_, u32>) -> Status {
            self.left = self.n;
            self.on_running(h)
        }
        fn on_running(&mut self, _h: &mut Handle<'_, u32>) -> Status {
            if self.left == 0 {
                return Status::Success;
            }
            self.left -= 1;
            Status::Running
        }
        fn on_halted(&mut self, h: &mut Handle<'_, u32>) {
            *h.ctx_mut() += 100;
        }
    }
}

/// The examples of the guide's chapter on the studio's canvas, which draws the boxes of
/// [`render_svg`], compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../guide/studio-canvas.md")]
pub struct StudioCanvasGuide;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_read_their_names_and_extensions() {
        for format in Format::ALL {
            assert_eq!(format.name().parse::<Format>(), Ok(format));
            assert_eq!(format.to_string(), format.name());
        }
        assert_eq!("SVG".parse::<Format>(), Ok(Format::Svg));
        let err = "png".parse::<Format>().unwrap_err();
        assert_eq!(
            err.to_string(),
            "unknown picture format `png`; expected ascii, unicode, dot, mermaid or svg"
        );
        assert_eq!(Format::from_extension("GV"), Some(Format::Dot));
        assert_eq!(Format::from_extension("mmd"), Some(Format::Mermaid));
        assert_eq!(Format::from_extension("txt"), Some(Format::Unicode));
        assert_eq!(Format::from_extension("png"), None);
    }
}
