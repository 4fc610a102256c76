//! Reachability: children no tick can reach (NT0201), Switch cases no value can match
//! (NT0202), trees of a file that its main tree never uses (NT0203).

use super::node::{line, shown};
use super::outcomes::{Outcomes, Statuses};
use super::{Diagnostic, Site};
use crate::nodes::switch::check_string_equality;
use crate::nodes::switch::{SWITCH2, SWITCH3, SWITCH4, SWITCH5, SWITCH6};
use crate::xml::{binding, Element, XmlLoader};
use neurotree_core::PortValue;

/// Reports the unreachable children and Switch cases of the tree `id`, whose
/// `<BehaviorTree>` element is `tree`.
pub(crate) fn check_tree<C: 'static>(
    loader: &XmlLoader<'_, C>,
    statuses: &mut Outcomes<'_, '_, C>,
    id: &str,
    tree: Element<'_>,
    found: &mut Vec<Diagnostic>,
) {
    for el in tree.descendants() {
        let Some(node) = statuses.node(el) else {
            continue;
        };
        let site = |el| Site {
            tree: id,
            root: tree,
            el,
        };
        cut_off(statuses, el, node.name, &site, found);
        if SWITCHES.iter().any(|d| d.name == node.name) {
            let enums = loader.registry().enums();
            for (case, why) in unmatched_cases(el, |a, b| check_string_equality(a, b, enums)) {
                found.push(site(el).diagnostic("NT0202", format!("`{case}` {why}")));
            }
        }
    }
}

/// Switch2 … Switch6.
const SWITCHES: [neurotree_core::nodes::NodeDecl; 5] =
    [SWITCH2, SWITCH3, SWITCH4, SWITCH5, SWITCH6];

/// Reports the first child of `el` (of type `parent`) that comes after a child that never
/// returns what its declared order needs to tick the next one (a Sequence's SUCCESS or
/// SKIPPED, a Fallback's FAILURE or SKIPPED).
fn cut_off<'d, C: 'static>(
    statuses: &mut Outcomes<'_, '_, C>,
    el: Element<'d>,
    parent: &str,
    site: &dyn Fn(Element<'d>) -> Site<'d>,
    found: &mut Vec<Diagnostic>,
) {
    let next_after = statuses.semantics(el).order.next_after();
    if next_after == Statuses::ANY {
        return;
    }
    let mut children = el.children();
    while let Some(c) = children.next() {
        if statuses.of(c).meets(next_after) {
            continue;
        }
        let never = match next_after.without(Statuses::SKIPPED) {
            s if s == Statuses::SUCCESS => "never succeeds".to_string(),
            s if s == Statuses::FAILURE => "never fails".to_string(),
            s => format!("never returns {s}"),
        };
        if let Some(next) = children.next() {
            found.push(site(next).diagnostic(
                "NT0201",
                format!(
                    "this child is never ticked: the {parent}'s child `{}` at line {} {never}",
                    shown(c),
                    line(c)
                ),
            ));
        }
        return;
    }
}

/// The cases of the Switch `el` that can never be chosen, each with why: one equal to an
/// earlier case, or, with a literal `variable`, one that differs from it. `equal` compares
/// two values as the Switch does.
fn unmatched_cases<'d>(
    el: Element<'d>,
    equal: impl Fn(&str, &str) -> bool,
) -> Vec<(&'d str, String)> {
    let literal = |name: &str| match el.attr(name) {
        Some(text) => match binding(name, text) {
            PortValue::Literal(_) => Some(text),
            PortValue::Entry(_) => None,
        },
        None => None,
    };
    let variable = literal("variable");
    let mut earlier: Vec<(&str, &str)> = Vec::new();
    let mut chosen: Option<&str> = None;
    let mut unmatched = Vec::new();
    for (name, _) in el.attrs().filter(|(k, _)| k.starts_with("case_")) {
        let Some(value) = literal(name) else {
            continue;
        };
        if let Some((first, _)) = earlier.iter().find(|(_, v)| *v == value) {
            let why = format!("is `{value}`, as `{first}` before it is, so it is never chosen");
            unmatched.push((name, why));
        } else if let (Some(variable), Some(first)) = (variable, chosen) {
            let why = format!(
                "is never chosen: `{first}` already matches the literal variable `{variable}`"
            );
            unmatched.push((name, why));
        } else if let Some(variable) = variable {
            if equal(variable, value) {
                chosen = Some(name);
            } else {
                let why = format!(
                    "is `{value}`, which the literal variable `{variable}` never equals; bind \
                     `variable` to an entry (`{{key}}`)"
                );
                unmatched.push((name, why));
            }
        }
        earlier.push((name, value));
    }
    unmatched
}

/// Reports each tree of the main tree's file that no SubTree on the way from the main tree
/// uses (nothing is reported for a file that does not name its main tree).
pub(crate) fn unused_trees<C: 'static>(loader: &XmlLoader<'_, C>, found: &mut Vec<Diagnostic>) {
    let Some(main) = loader.main_tree() else {
        return;
    };
    let Some(main_el) = loader.tree(main) else {
        return;
    };
    let used = super::uses(loader, main);
    for id in loader.tree_ids().filter(|id| !used.contains(id)) {
        let Some(tree) = loader.tree(id) else {
            continue;
        };
        if tree.file() != main_el.file() {
            continue;
        }
        let site = Site {
            tree: id,
            root: tree,
            el: tree,
        };
        found.push(site.diagnostic(
            "NT0203",
            format!("tree `{id}` is never used: the main tree `{main}` does not reach it through any SubTree"),
        ));
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
    fn a_child_after_one_that_never_fails_in_a_fallback_is_found() {
        let xml = tree(
            "<Fallback>\n<ForceSuccess><Check/></ForceSuccess>\n<Check/>\n<Check/>\n</Fallback>",
        );
        assert_eq!(findings(&xml), [("NT0201", 5)]);
        assert_eq!(findings(&xml.replace("ForceSuccess", "Inverter")), []);
    }

    #[test]
    fn a_child_after_one_that_never_succeeds_in_a_sequence_is_found() {
        let xml = tree("<Sequence>\n<Inverter><AlwaysSuccess/></Inverter>\n<Check/>\n</Sequence>");
        assert_eq!(findings(&xml), [("NT0201", 5)]);
        // A precondition can end the node with another status.
        let hooked = xml.replace("<Inverter>", "<Inverter _successIf=\"true\">");
        assert_eq!(findings(&hooked), []);
        // An action's outcome is not known.
        let plain = tree("<Sequence>\n<Say message=\"hi\"/>\n<Check/>\n</Sequence>");
        assert_eq!(findings(&plain), []);
    }

    #[test]
    fn a_repeat_of_no_cycles_succeeds_at_once() {
        let xml = tree(
            "<Sequence>\n<Repeat num_cycles=\"0\"><AlwaysFailure/></Repeat>\n\
             <AlwaysSuccess name=\"after\"/>\n</Sequence>",
        );
        assert_eq!(findings(&xml), []);
        // One cycle: the child's failure is the Repeat's, and ends the Sequence.
        assert_eq!(findings(&xml.replace("\"0\"", "\"1\"")), [("NT0201", 5)]);
    }

    #[test]
    fn a_skipped_child_lets_a_fallback_go_on() {
        let xml = tree(
            "<Fallback>\n<ForceSuccess><Precondition if=\"false\" else=\"SKIPPED\">\
             <Check/></Precondition></ForceSuccess>\n<Check/>\n</Fallback>",
        );
        assert_eq!(findings(&xml), []);
        assert_eq!(
            findings(&xml.replace("SKIPPED", "FAILURE")),
            [("NT0201", 5)]
        );
        // A skip attribute does the same.
        let skip = tree(
            "<Fallback>\n<ForceSuccess _skipIf=\"true\"><Check/></ForceSuccess>\n\
             <Check/>\n</Fallback>",
        );
        assert_eq!(findings(&skip), []);
    }

    #[test]
    fn through_a_subtree_the_statuses_of_its_root_count() {
        let xml = "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\">\n\
             <BehaviorTree ID=\"Main\"><Sequence>\n\
             <SubTree ID=\"Fail\"/>\n\
             <Check/>\n\
             </Sequence></BehaviorTree>\n\
             <BehaviorTree ID=\"Fail\"><AlwaysFailure/></BehaviorTree></root>";
        assert_eq!(findings(xml), [("NT0201", 4)]);
    }

    #[test]
    fn switch_cases_no_value_matches_are_found() {
        let duplicate = tree(
            "<Switch3 variable=\"{mode}\" case_1=\"idle\" case_2=\"run\" case_3=\"idle\">\n\
             <Check/><Check/><Check/><Check/></Switch3>",
        );
        assert_eq!(findings(&duplicate), [("NT0101", 3), ("NT0202", 3)]);
        let literal = tree(
            "<Switch2 variable=\"run\" case_1=\"idle\" case_2=\"run\">\n\
             <Check/><Check/><Check/></Switch2>",
        );
        assert_eq!(findings(&literal), [("NT0202", 3)]);
        // Compared as numbers too, as BehaviorTree.CPP compares them: `1` matches `1.0`.
        let numbers = literal
            .replace("\"run\"", "\"1.0\"")
            .replace("\"idle\"", "\"1\"");
        assert_eq!(findings(&numbers), [("NT0202", 3)]);
    }

    #[test]
    fn a_tree_the_main_tree_never_uses_is_found() {
        let xml = "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\">\n\
             <BehaviorTree ID=\"Main\"><SubTree ID=\"Used\"/></BehaviorTree>\n\
             <BehaviorTree ID=\"Used\"><Check/></BehaviorTree>\n\
             <BehaviorTree ID=\"Orphan\"><Check/></BehaviorTree></root>";
        assert_eq!(findings(xml), [("NT0203", 4)]);
        // Without a main tree, every tree may be meant to start from.
        assert_eq!(
            findings(&xml.replace(" main_tree_to_execute=\"Main\"", "")),
            []
        );
    }
}
