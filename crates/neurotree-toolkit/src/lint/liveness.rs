//! Liveness: loops that cannot end (NT0301, NT0302) and roots that never finish (NT0303).

use super::node::{is, shown};
use super::outcomes::{literal_count, Outcomes};
use super::{Diagnostic, Site};
use crate::xml::Element;
use neurotree_core::nodes::decorator::{keep_running, repeat, retry};

/// Reports the endless loops of the tree `id` (`<BehaviorTree>` element `tree`), and its
/// root if it can only ever run.
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
        let Some(node) = statuses.node(el) else {
            continue;
        };
        let Some(child) = el.children().next() else {
            continue;
        };
        let child_statuses = statuses.of(child);
        let name = node.name;
        let endless = if is(name, &[&retry::RETRY_UNTIL_SUCCESSFUL])
            && literal_count(el, "num_attempts") == Some(-1)
            && !child_statuses.can_succeed()
        {
            Some((
                "NT0301",
                "num_attempts=\"-1\" never ends: its child",
                "never succeeds; give a number of attempts",
            ))
        } else if is(name, &[&repeat::REPEAT])
            && literal_count(el, "num_cycles") == Some(-1)
            && !child_statuses.can_fail()
        {
            Some((
                "NT0302",
                "num_cycles=\"-1\" never ends: its child",
                "never fails",
            ))
        } else if is(name, &[&keep_running::KEEP_RUNNING_UNTIL_FAILURE])
            && !child_statuses.can_fail()
        {
            Some(("NT0302", "never ends: its child", "never fails"))
        } else {
            None
        };
        if let Some((code, ends, why)) = endless {
            let message = format!("{name} {ends} `{}` {why}", shown(child));
            found.push(site(el).diagnostic(code, message));
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
    fn a_root_that_can_only_run_is_found() {
        let xml = tree("<Sequence>\n<AlwaysSuccess/>\n<KeepRunningUntilFailure><Sleep msec=\"10\"/></KeepRunningUntilFailure>\n</Sequence>");
        assert_eq!(findings(&xml), [("NT0303", 3), ("NT0302", 5)]);
        // With a way out, it can finish.
        let xml = tree("<Sequence>\n<AlwaysSuccess/>\n<KeepRunningUntilFailure><Check/></KeepRunningUntilFailure>\n</Sequence>");
        assert_eq!(findings(&xml), []);
    }
}
