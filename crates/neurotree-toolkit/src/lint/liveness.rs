//! Liveness: loops that cannot end (NT0301, NT0302) and roots that never finish (NT0303).

use super::node::shown;
use super::outcomes::{literal_count, Outcomes};
use super::{Diagnostic, Site};
use crate::xml::Element;

/// Reports the endless loops of the tree `id` (`<BehaviorTree>` element `tree`), and its
/// root if it can only ever run.
pub(crate) fn check_tree<C: 'static>(
    statuses: &mut Outcomes<'_, '_, C>,
    id: &str,
    tree: Element<'_>,
    found: &mut Vec<Diagnostic>,
) {
    let site = |el| Site { tree: id, root: tree, el };
    for el in tree.descendants() {
        let Some(node) = statuses.node(el) else {
            continue;
        };
        let Some(child) = el.children().next() else {
            continue;
        };
        let child_statuses = statuses.of(child);
        match node.name {
            "RetryUntilSuccessful"
                if literal_count(el, "num_attempts") == Some(-1)
                    && !child_statuses.can_succeed() =>
            {
                found.push(site(el).diagnostic(
                    "NT0301",
                    format!(
                        "RetryUntilSuccessful num_attempts=\"-1\" never ends: its child `{}` \
                         never succeeds; give a number of attempts",
                        shown(child)
                    ),
                ));
            }
            "Repeat" if literal_count(el, "num_cycles") == Some(-1) && !child_statuses.can_fail() => {
                found.push(site(el).diagnostic(
                    "NT0302",
                    format!(
                        "Repeat num_cycles=\"-1\" never ends: its child `{}` never fails",
                        shown(child)
                    ),
                ));
            }
            "KeepRunningUntilFailure" if !child_statuses.can_fail() => {
                found.push(site(el).diagnostic(
                    "NT0302",
                    format!(
                        "KeepRunningUntilFailure never ends: its child `{}` never fails",
                        shown(child)
                    ),
                ));
            }
            _ => {}
        }
    }
    if let Some(root) = tree.children().next() {
        let root_statuses = statuses.of(root);
        if !root_statuses.can_succeed() && !root_statuses.can_fail() {
            found.push(site(root).diagnostic(
                "NT0303",
                format!(
                    "the tree `{id}` never finishes: its root `{}` can only return RUNNING",
                    shown(root)
                ),
            ));
        }
    }
}
