//! Liveness: loops that cannot end (NT0301, NT0302) and roots that never finish (NT0303).

use super::node::shown;
use super::outcomes::{Outcomes, Statuses};
use super::{Diagnostic, Site};
use crate::xml::Element;
use neurotree_core::nodes::Order;

/// Reports the endless loops of the tree `id` (`<BehaviorTree>` element `tree`), and its
/// root if it can only ever run.
///
/// A loop is a node whose declared order ticks a child again after one of some statuses
/// (a Repeat after SUCCESS, a retry after FAILURE): it never ends when its children can end
/// but, given what they return, it can only return RUNNING. NT0301 for a loop that goes
/// again after a failure, NT0302 for the others.
pub(crate) fn check_tree<C: 'static>(
    statuses: &mut Outcomes<'_, '_, C>,
    id: &str,
    tree: Element<'_>,
    found: &mut Vec<Diagnostic>,
) {
    let site = |el| Site {
        tree: id,
        root: tree,
        el,
    };
    for el in tree.descendants() {
        let Order::Again { again_after, .. } = statuses.semantics(el).order else {
            continue;
        };
        if again_after == Statuses::ANY || el.child_count() == 0 {
            continue;
        }
        let children: Vec<_> = el.children().map(|c| (c, statuses.of(c))).collect();
        if statuses.of(el).can_end() || !children.iter().any(|(_, s)| s.can_end()) {
            continue;
        }
        let (code, wanted) = if again_after == Statuses::FAILURE {
            ("NT0301", "never succeeds")
        } else {
            ("NT0302", "never fails")
        };
        let (child, returns) = children[0];
        let message = format!(
            "{} never ends: its child `{}` {wanted} (it returns {returns}), so it ticks it \
             again and again",
            shown(el),
            shown(child)
        );
        found.push(site(el).diagnostic(code, message));
    }
    if let Some(root) = tree.children().next() {
        let root_statuses = statuses.of(root);
        if !root_statuses.can_end() {
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

#[cfg(test)]
mod tests {
    use super::super::findings;

    fn tree(body: &str) -> String {
        format!(
            "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\">\n\
             <BehaviorTree ID=\"Main\">\n{body}\n</BehaviorTree>\n</root>"
        )
    }

    #[test]
    fn an_endless_retry_of_a_child_that_never_succeeds_is_found() {
        let xml = tree("<Fallback>\n<RetryUntilSuccessful num_attempts=\"-1\">\n<AlwaysFailure/>\n</RetryUntilSuccessful>\n<Check/>\n</Fallback>");
        // It only ever runs, so the Fallback never reaches its second child, and never ends.
        assert_eq!(
            findings(&xml),
            [("NT0303", 3), ("NT0301", 4), ("NT0201", 7)]
        );
        assert_eq!(findings(&xml.replace("\"-1\"", "\"3\"")), []);
        // It can end now, but only with a success: the Fallback's second child stays out.
        assert_eq!(
            findings(&xml.replace("AlwaysFailure", "Check")),
            [("NT0201", 7)]
        );
    }

    #[test]
    fn an_endless_repeat_of_a_child_that_never_fails_is_found() {
        let xml = tree("<Fallback>\n<Repeat num_cycles=\"-1\">\n<ForceSuccess><Check/></ForceSuccess>\n</Repeat>\n<Check/>\n</Fallback>");
        assert_eq!(
            findings(&xml),
            [("NT0303", 3), ("NT0302", 4), ("NT0201", 7)]
        );
        assert_eq!(findings(&xml.replace("ForceSuccess", "Inverter")), []);
        let keep = tree("<Fallback>\n<KeepRunningUntilFailure>\n<AlwaysSuccess/>\n</KeepRunningUntilFailure>\n<Check/>\n</Fallback>");
        assert_eq!(
            findings(&keep),
            [("NT0303", 3), ("NT0302", 4), ("NT0201", 7)]
        );
    }

    #[test]
    fn a_retry_of_no_attempts_fails_at_once_and_ends_the_loop_above() {
        let xml = tree(
            "<KeepRunningUntilFailure>\n<RetryUntilSuccessful num_attempts=\"0\">\n\
             <AlwaysSuccess/>\n</RetryUntilSuccessful>\n</KeepRunningUntilFailure>",
        );
        assert_eq!(findings(&xml), []);
        // One attempt of a child that always succeeds: the loop above never ends.
        assert_eq!(
            findings(&xml.replace("\"0\"", "\"1\"")),
            [("NT0302", 3), ("NT0303", 3)]
        );
    }

    #[test]
    fn a_root_that_can_only_run_is_found() {
        let xml = tree("<Sequence>\n<AlwaysSuccess/>\n<KeepRunningUntilFailure><Sleep msec=\"10\"/></KeepRunningUntilFailure>\n</Sequence>");
        assert_eq!(findings(&xml), [("NT0303", 3), ("NT0302", 5)]);
        // With a way out, it can finish.
        let xml = tree("<Sequence>\n<AlwaysSuccess/>\n<KeepRunningUntilFailure><Check/></KeepRunningUntilFailure>\n</Sequence>");
        assert_eq!(findings(&xml), []);
    }
}
