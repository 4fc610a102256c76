//! Reachability: children no tick can reach (NT0201), Switch cases no value can match
//! (NT0202), trees of a file that its main tree never uses (NT0203).

use super::node::{is, line, shown, FALLBACKS, SEQUENCES};
use super::outcomes::{Outcomes, Statuses};
use super::{Diagnostic, Site};
use crate::nodes::switch::check_string_equality;
use crate::nodes::switch::{SWITCH2, SWITCH3, SWITCH4, SWITCH5, SWITCH6};
use crate::xml::{binding, Element, XmlLoader};
use neurotree_core::nodes::control::{fallback, sequence};
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
        if is(node.name, &SEQUENCES) {
            cut_off(statuses, el, true, &site, found);
        } else if is(node.name, &FALLBACKS) {
            cut_off(statuses, el, false, &site, found);
        } else if SWITCHES.iter().any(|d| d.name == node.name) {
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

/// Reports the first child of the Sequence (`sequence`) or Fallback `el` that comes after
/// a child that always ends it.
fn cut_off<'d, C: 'static>(
    statuses: &mut Outcomes<'_, '_, C>,
    el: Element<'d>,
    sequence: bool,
    site: &dyn Fn(Element<'d>) -> Site<'d>,
    found: &mut Vec<Diagnostic>,
) {
    let (go_on, parent, never) = if sequence {
        (Statuses::SUCCESS, sequence::SEQUENCE.name, "never succeeds")
    } else {
        (Statuses::FAILURE, fallback::FALLBACK.name, "never fails")
    };
    let mut children = el.children();
    while let Some(c) = children.next() {
        if statuses.of(c).contains(go_on) {
            continue;
        }
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
