//! Reachability: children no tick can reach (NT0201), Switch cases no value can match
//! (NT0202), trees of a file that its main tree never uses (NT0203).

use super::node::{line, shown};
use super::outcomes::{Outcomes, Statuses};
use super::{Diagnostic, Site};
use crate::nodes::switch::check_string_equality;
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
        let site = |el| Site { tree: id, root: tree, el };
        match node.name {
            "Sequence" | "SequenceWithMemory" | "ReactiveSequence" | "AsyncSequence" => {
                cut_off(statuses, el, true, &site, found)
            }
            "Fallback" | "ReactiveFallback" | "AsyncFallback" => {
                cut_off(statuses, el, false, &site, found)
            }
            name if name.starts_with("Switch") => {
                let enums = loader.registry().enums();
                for (case, why) in unmatched_cases(el, |a, b| check_string_equality(a, b, enums)) {
                    found.push(site(el).diagnostic("NT0202", format!("`{case}` {why}")));
                }
            }
            _ => {}
        }
    }
}

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
        (Statuses::SUCCESS, "Sequence", "never succeeds")
    } else {
        (Statuses::FAILURE, "Fallback", "never fails")
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
    let mut unmatched = Vec::new();
    for (name, _) in el.attrs().filter(|(k, _)| k.starts_with("case_")) {
        let Some(value) = literal(name) else {
            continue;
        };
        if let Some((first, _)) = earlier.iter().find(|(_, v)| *v == value) {
            unmatched.push((name, format!("is `{value}`, as `{first}` before it is, so it is never chosen")));
        } else if let Some(variable) = variable.filter(|v| !equal(v, value)) {
            unmatched.push((
                name,
                format!(
                    "is `{value}`, which the literal variable `{variable}` never equals; bind \
                     `variable` to an entry (`{{key}}`)"
                ),
            ));
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
        let Some(tree) = loader.tree(id) else { continue };
        if tree.file() != main_el.file() {
            continue;
        }
        let site = Site { tree: id, root: tree, el: tree };
        found.push(site.diagnostic(
            "NT0203",
            format!("tree `{id}` is never used: the main tree `{main}` does not reach it through any SubTree"),
        ));
    }
}
