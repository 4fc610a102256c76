//! What the picture formats agree on: the shape of each family of node, the colours of
//! each status (both tabled in [`render`](super)), and the label of each node. Keeping them
//! here means a picture in one format reads like one in another.

use std::borrow::Cow;

use neurotree_core::blueprint::PortBinding;
use neurotree_core::nodes::built_in::Family;
use neurotree_core::nodes::BUILT_INS;
use neurotree_core::{Blueprint, Category, NodeId, NodeKind, NodeStatus};

/// The drawn family of a node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Shape {
    Sequential,
    Alternative,
    Concurrent,
    Control,
    Decorator,
    Condition,
    Action,
    SubTree,
}

impl Shape {
    pub(crate) fn of<C>(kind: &NodeKind<C>) -> Self {
        match kind.built_in().and_then(|node| node.family()) {
            Some(Family::Sequential) => Shape::Sequential,
            Some(Family::Alternative) => Shape::Alternative,
            Some(Family::Concurrent) => Shape::Concurrent,
            None => match kind.category() {
                Category::Control => Shape::Control,
                Category::Decorator => Shape::Decorator,
                Category::Condition => Shape::Condition,
                Category::Action => Shape::Action,
                Category::SubTree => Shape::SubTree,
            },
        }
    }

    /// The shape of a node known by its type's name and category (`control`, `decorator`,
    /// `condition`, `action`, `subtree`) alone, as a file being edited gives it: a built-in
    /// (or an alias of one) as its own declaration makes it, any other by category (an
    /// action when the category is unknown).
    pub(crate) fn of_type(type_name: &str, category: &str) -> Self {
        let name = crate::registry::aliases::ALIASES
            .iter()
            .find(|alias| alias.name == type_name)
            .map_or(type_name, |alias| alias.target);
        // Every port read from the blackboard, so that no literal can refuse the node.
        let built_in = BUILT_INS
            .iter()
            .find(|decl| decl.name == name)
            .and_then(|decl| NodeKind::<()>::from_declared(decl, &|_| PortBinding::Entry))
            .and_then(Result::ok);
        if let Some(kind) = built_in {
            return Shape::of(&kind);
        }
        match category.to_ascii_lowercase().as_str() {
            "control" => Shape::Control,
            "decorator" => Shape::Decorator,
            "condition" => Shape::Condition,
            "subtree" => Shape::SubTree,
            _ => Shape::Action,
        }
    }

    /// The shape as a lower-case word, for pages.
    pub(crate) fn word(self) -> &'static str {
        match self {
            Shape::Sequential => "sequential",
            Shape::Alternative => "alternative",
            Shape::Concurrent => "concurrent",
            other => other.family(),
        }
    }

    /// The mark drawn before the name of the well-known controls.
    pub(crate) fn glyph(self) -> Option<&'static str> {
        match self {
            Shape::Sequential => Some("→"),
            Shape::Alternative => Some("?"),
            Shape::Concurrent => Some("⇉"),
            _ => None,
        }
    }

    /// The family as a lower-case word, for class names.
    pub(crate) fn family(self) -> &'static str {
        match self {
            Shape::Sequential | Shape::Alternative | Shape::Concurrent | Shape::Control => {
                "control"
            }
            Shape::Decorator => "decorator",
            Shape::Condition => "condition",
            Shape::Action => "action",
            Shape::SubTree => "subtree",
        }
    }
}

/// The colours of a node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Paint {
    pub(crate) fill: &'static str,
    pub(crate) stroke: &'static str,
    pub(crate) dashed: bool,
}

/// Every status in the order legends list them.
pub(crate) const STATUSES: [NodeStatus; 5] = [
    NodeStatus::Success,
    NodeStatus::Failure,
    NodeStatus::Running,
    NodeStatus::Idle,
    NodeStatus::Skipped,
];

/// The colours for a status, or for a picture drawn without statuses.
pub(crate) fn paint(status: Option<NodeStatus>) -> Paint {
    let (fill, stroke, dashed) = match status {
        None => ("#ffffff", "#495057", false),
        Some(NodeStatus::Success) => ("#d3f9d8", "#2b8a3e", false),
        Some(NodeStatus::Failure) => ("#ffe3e3", "#c92a2a", false),
        Some(NodeStatus::Running) => ("#fff3bf", "#e67700", false),
        Some(NodeStatus::Idle) => ("#f1f3f5", "#868e96", false),
        Some(NodeStatus::Skipped) => ("#f8f9fa", "#adb5bd", true),
    };
    Paint {
        fill,
        stroke,
        dashed,
    }
}

/// The status as a lower-case word, for class names and legends.
pub(crate) fn status_word(status: NodeStatus) -> &'static str {
    match status {
        NodeStatus::Idle => "idle",
        NodeStatus::Running => "running",
        NodeStatus::Success => "success",
        NodeStatus::Failure => "failure",
        NodeStatus::Skipped => "skipped",
    }
}

/// One node as the pictures see it.
pub(crate) struct NodeView<'a> {
    pub(crate) id: NodeId,
    pub(crate) shape: Shape,
    /// The node's name, made printable.
    pub(crate) name: Cow<'a, str>,
    /// The kind's type name when it differs from the name, made printable.
    pub(crate) type_name: Option<Cow<'a, str>>,
    /// `None` when the picture is drawn without statuses.
    pub(crate) status: Option<NodeStatus>,
}

impl NodeView<'_> {
    /// The first line of the label: the glyph, if any, and the name.
    pub(crate) fn title(&self) -> String {
        match self.shape.glyph() {
            Some(glyph) => format!("{glyph} {}", self.name),
            None => self.name.to_string(),
        }
    }
}

/// The nodes of `bp` in pre-order, each with its status from `statuses` (by [`NodeId`];
/// Idle past the end) when statuses are given.
pub(crate) fn node_views<'a, C>(
    bp: &'a Blueprint<C>,
    statuses: Option<&[NodeStatus]>,
) -> Vec<NodeView<'a>> {
    bp.ids()
        .map(|id| {
            let name = bp.name(id);
            let type_name = super::text::type_label(bp, id);
            NodeView {
                id,
                shape: Shape::of(bp.kind(id)),
                name: printable(name),
                type_name: (type_name != name).then(|| printable(type_name)),
                status: statuses.map(|s| s.get(id.index()).copied().unwrap_or_default()),
            }
        })
        .collect()
}

/// `text` with control characters replaced: line breaks and tabs by spaces, the others by
/// U+FFFD, since XML 1.0 cannot carry them at all and the other formats would break lines.
pub(crate) fn printable(text: &str) -> Cow<'_, str> {
    if !text.chars().any(char::is_control) {
        return Cow::Borrowed(text);
    }
    Cow::Owned(
        text.chars()
            .map(|c| match c {
                '\n' | '\r' | '\t' => ' ',
                c if c.is_control() => '\u{FFFD}',
                c => c,
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_core::{Builder, Status};

    #[test]
    fn shapes_follow_the_kind() {
        let bp = Builder::<()>::new()
            .reactive_sequence("a", |s| {
                s.fallback("b", |f| f.always_failure("x"))
                    .parallel("c", -1, 1, |p| p.always_success("y"))
                    .if_then_else("d", |i| i.always_success("p").always_success("q"))
                    .inverter("e", |i| i.condition("f", |_: &()| true))
                    .action("g", |_: &mut ()| Status::Success)
            })
            .build()
            .unwrap();
        let views = node_views(&bp, None);
        let shape = |name: &str| views.iter().find(|v| v.name == name).unwrap().shape;
        assert_eq!(shape("a"), Shape::Sequential);
        assert_eq!(shape("b"), Shape::Alternative);
        assert_eq!(shape("c"), Shape::Concurrent);
        assert_eq!(shape("d"), Shape::Control);
        assert_eq!(shape("e"), Shape::Decorator);
        assert_eq!(shape("f"), Shape::Condition);
        assert_eq!(shape("g"), Shape::Action);
        assert_eq!(shape("x"), Shape::Action);
        assert_eq!(views[0].title(), "→ a");
        assert_eq!(views[0].type_name.as_deref(), Some("ReactiveSequence"));
        assert!(views.iter().all(|v| v.status.is_none()));
    }

    #[test]
    fn statuses_past_the_end_are_idle_and_names_equal_to_the_type_are_not_repeated() {
        let bp = Builder::<()>::new()
            .sequence("Sequence", |s| s.always_success("ok"))
            .build()
            .unwrap();
        let views = node_views(&bp, Some(&[NodeStatus::Running]));
        assert_eq!(views[0].type_name, None);
        assert_eq!(views[0].status, Some(NodeStatus::Running));
        assert_eq!(views[1].status, Some(NodeStatus::Idle));
    }

    #[test]
    fn control_characters_are_made_printable() {
        assert!(matches!(printable("plain"), Cow::Borrowed("plain")));
        assert_eq!(printable("a\nb\tc\u{1}d\u{7f}"), "a b c\u{FFFD}d\u{FFFD}");
    }
}
