//! Switch2 … Switch6: pick a child by the value of a variable.
//!
//! Ports `variable`, `case_1..N`; the last child is the default. Every tick, the variable is
//! compared with each case in turn and the first match's child is ticked (the default if
//! none matches, or if `variable` cannot be read); a change of match halts the previous
//! branch. A Skipped child makes the node Skipped; a completed one is reset.
//!
//! Comparison is BehaviorTree.CPP's `details::CheckStringEquality` (`switch_node.cpp`), on
//! the text of both values:
//!
//! 1. equal text matches;
//! 2. else, if both are a registered enum name or a whole `int` (as `std::from_chars` reads
//!    one: an optional `-`, decimal digits, within `i32`; no `+`, no spaces, no `0x`), equal
//!    values match;
//! 3. else, if both are an enum name or a whole real (`std::from_chars` again: `1e3`, `.5`,
//!    `inf`, `nan`; no `+`, no spaces), values at most `f32::EPSILON` apart (absolute) match.
//!
//! `variable` and the cases are literal text or blackboard entries. An entry is read as text
//! as BehaviorTree.CPP's `getInput<std::string>` does: a `String` as it is, integers and
//! booleans as `std::to_string` writes an integer (`true` is `1`), reals as it writes a
//! double, with six decimals (`3.5` is `3.500000`, `4e-7` is `0.000000`). An entry of any
//! other type reads as nothing: for `variable`, the default; for a case, no match.
//! Comparing allocates nothing: numbers are written into a buffer on the stack.

use std::fmt::{self, Write as _};
use std::sync::Arc;

use neurotree_core::{
    Arity, Blackboard, Category, CustomNode, CustomSpec, NodeCtx, NodeDecl, NodeKind, NodeStatus,
    Port, PortDecl, PortValue, ScopeId,
};

use crate::registry::Registry;
use crate::script::Enums;
use neurotree_core::nodes::semantics::{union, Order, Semantics, Statuses};

/// A value's text, when it had to be written (a number entry): room for any `f64` with six
/// decimals (at most 309 integer digits, a sign, a point and six decimals).
struct TextBuf {
    bytes: [u8; 320],
    len: usize,
}

impl TextBuf {
    fn new() -> Self {
        Self {
            bytes: [0; 320],
            len: 0,
        }
    }

    fn as_str(&self) -> &str {
        // Only `write_str` fills the buffer, with whole `&str`s.
        std::str::from_utf8(&self.bytes[..self.len]).unwrap_or("")
    }
}

impl fmt::Write for TextBuf {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let end = self.len + s.len();
        let dst = self.bytes.get_mut(self.len..end).ok_or(fmt::Error)?;
        dst.copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

/// `text` as `std::from_chars` reads an `int`: the whole text, no leading `+`.
fn from_chars_int(text: &str) -> Option<i64> {
    if text.starts_with('+') {
        return None;
    }
    text.parse::<i32>().ok().map(i64::from)
}

/// `text` as `std::from_chars` reads a `double`: the whole text, no leading `+`.
fn from_chars_real(text: &str) -> Option<f64> {
    if text.starts_with('+') {
        return None;
    }
    text.parse::<f64>().ok()
}

/// BehaviorTree.CPP's `details::CheckStringEquality` (see the [module docs](self)).
pub(crate) fn check_string_equality(a: &str, b: &str, enums: &Enums) -> bool {
    if a == b {
        return true;
    }
    let int = |t: &str| enums.get(t).or_else(|| from_chars_int(t));
    if let (Some(x), Some(y)) = (int(a), int(b))
        && x == y
    {
        return true;
    }
    // Enum values are integers, exact as reals.
    let real = |t: &str| {
        enums
            .get(t)
            .map(|v| v as f64)
            .or_else(|| from_chars_real(t))
    };
    matches!((real(a), real(b)), (Some(x), Some(y)) if (x - y).abs() <= f64::from(f32::EPSILON))
}

/// Where a value comes from.
#[derive(Clone)]
enum Source {
    Literal(String),
    Entry(String),
}

impl Source {
    /// The value's text, as `getInput<std::string>` gives it (see the [module docs](self));
    /// `None` if there is no entry or it holds no text or number.
    fn read<'a>(
        &'a self,
        bb: &'a Blackboard,
        scope: ScopeId,
        buf: &'a mut TextBuf,
    ) -> Option<&'a str> {
        let key = match self {
            Source::Literal(text) => return Some(text),
            Source::Entry(key) => key,
        };
        let any = bb.get_any_in(scope, key)?;
        if let Some(s) = any.downcast_ref::<String>() {
            return Some(s);
        }
        buf.len = 0;
        macro_rules! integer {
            ($($t:ty),*) => {$(
                if let Some(v) = any.downcast_ref::<$t>() {
                    write!(buf, "{v}").ok()?;
                    return Some(buf.as_str());
                }
            )*};
        }
        integer!(i64, i32, u64, u32, i16, u16, i8, u8, isize, usize);
        let real = if let Some(v) = any.downcast_ref::<f64>() {
            *v
        } else if let Some(v) = any.downcast_ref::<f32>() {
            f64::from(*v)
        } else {
            let b = any.downcast_ref::<bool>()?;
            return Some(if *b { "1" } else { "0" });
        };
        // std::to_string(double) is printf's "%f".
        if real.is_nan() {
            return Some(if real.is_sign_negative() {
                "-nan"
            } else {
                "nan"
            });
        }
        write!(buf, "{real:.6}").ok()?;
        Some(buf.as_str())
    }
}

struct Switch {
    variable: Option<Source>,
    cases: Vec<Option<Source>>,
    enums: Arc<Enums>,
    running: Option<usize>,
}

impl Switch {
    /// The index of the first matching case, else the default (the last child).
    fn choose(&self, bb: &Blackboard, scope: ScopeId) -> usize {
        let default = self.cases.len();
        let mut var_buf = TextBuf::new();
        let Some(variable) = self
            .variable
            .as_ref()
            .and_then(|v| v.read(bb, scope, &mut var_buf))
        else {
            return default;
        };
        let mut case_buf = TextBuf::new();
        self.cases
            .iter()
            .position(|case| {
                case.as_ref()
                    .and_then(|c| c.read(bb, scope, &mut case_buf))
                    .is_some_and(|value| check_string_equality(variable, value, &self.enums))
            })
            .unwrap_or(default)
    }
}

impl<C> CustomNode<C> for Switch {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(self.running,)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(running,)| {
                self.running = running;
            })
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let scope = node.scope();
        let chosen = self.choose(node.blackboard(), scope);
        if let Some(previous) = self.running.filter(|&p| p != chosen) {
            node.halt_child(previous);
        }
        let status = node.tick_child(chosen);
        match status {
            NodeStatus::Running => self.running = Some(chosen),
            NodeStatus::Skipped => self.running = None,
            _ => {
                node.reset_children();
                self.running = None;
            }
        }
        status
    }

    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {
        self.running = None;
    }
}

fn source(ports: &[Port], name: &str) -> Option<Source> {
    ports
        .iter()
        .find(|p| p.name == name)
        .map(|p| match &p.value {
            PortValue::Literal(text) => Source::Literal(text.clone()),
            PortValue::Entry(key) => Source::Entry(key.clone()),
        })
}

/// Switch's ports: `variable`, then `case_1` … `case_6`; SwitchN takes the first N cases.
const SWITCH_PORTS: &[PortDecl] = &[
    PortDecl::input(
        "variable",
        "String",
        "The value compared with the cases: an entry `{key}`, or a literal.",
    ),
    PortDecl::input("case_1", "String", "The value that selects child 1."),
    PortDecl::input("case_2", "String", "The value that selects child 2."),
    PortDecl::input("case_3", "String", "The value that selects child 3."),
    PortDecl::input("case_4", "String", "The value that selects child 4."),
    PortDecl::input("case_5", "String", "The value that selects child 5."),
    PortDecl::input("case_6", "String", "The value that selects child 6."),
];

/// SwitchN's declaration: `cases` cases and the default, so `cases + 1` children, and the
/// first `cases + 1` of [`SWITCH_PORTS`].
const fn switch_decl(name: &'static str, cases: u32) -> NodeDecl {
    NodeDecl {
        name,
        category: Category::Control,
        arity: Arity::Range {
            min: cases + 1,
            max: cases + 1,
        },
        ports: SWITCH_PORTS.split_at(cases as usize + 1).0,
        summary: "Ticks the child whose case matches `variable`; none matches: the last child.",
        // The chosen child may change from tick to tick: no order between them is declared.
        semantics: Semantics::new(Order::AllAtOnce, |_, c| union(c).or(Statuses::FAILURE)),
    }
}

/// Switch2's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const SWITCH2: NodeDecl = switch_decl("Switch2", 2);
/// Switch3's declaration.
pub const SWITCH3: NodeDecl = switch_decl("Switch3", 3);
/// Switch4's declaration.
pub const SWITCH4: NodeDecl = switch_decl("Switch4", 4);
/// Switch5's declaration.
pub const SWITCH5: NodeDecl = switch_decl("Switch5", 5);
/// Switch6's declaration.
pub const SWITCH6: NodeDecl = switch_decl("Switch6", 6);

/// Adds Switch2 … Switch6 to `registry`.
pub(crate) fn register<C: 'static>(registry: &mut Registry<C>) {
    for decl in [&SWITCH2, &SWITCH3, &SWITCH4, &SWITCH5, &SWITCH6] {
        let n = decl.ports.len() - 1;
        registry.register_declared(
            decl,
            Arc::new(move |ports, enums| {
                let variable = source(ports, "variable");
                let enums = Arc::clone(enums);
                let cases: Vec<Option<Source>> = (1..=n)
                    .map(|i| source(ports, &format!("case_{i}")))
                    .collect();
                Ok(NodeKind::Custom(Box::new(CustomSpec::new(
                    decl.name,
                    decl.arity,
                    Box::new(move || {
                        Box::new(Switch {
                            variable: variable.clone(),
                            cases: cases.clone(),
                            enums: Arc::clone(&enums),
                            running: None,
                        })
                    }),
                ))))
            }),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    /// Which child a Switch2 ticks for `variable` and `case_1`: 0 (case 1), 1 (case 2,
    /// which nothing matches) or 2 (the default).
    fn chosen(lab: &mut Lab, tree: &mut Tree<Lab>) -> usize {
        let before = lab.ticks.clone();
        assert_eq!(lab.tick(tree), Ok(S));
        (0..3).find(|&i| lab.ticks[i] > before[i]).unwrap()
    }

    fn switch(variable: &str, case: &str) -> String {
        format!(
            r#"<Switch2 variable="{variable}" case_1="{case}" case_2="@never@"><L0/><L1/><L2/></Switch2>"#
        )
    }

    #[test]
    fn literals_compare_as_check_string_equality_does() {
        // (variable, case, matches): equal text; else both whole `int`s (std::from_chars:
        // no `+`, no spaces, no hex) and equal; else both whole reals within float epsilon.
        let table = [
            ("walk", "walk", true),
            ("walk", "Walk", false),
            ("2", "2.0", true),
            ("007", "7", true),
            ("+2", "2", false),
            (" 2", "2", false),
            ("2 ", "2", false),
            ("0x10", "16", false),
            ("1e3", "1000", true),
            (".5", "0.5", true),
            ("5.", "5", true),
            ("1.0000001", "1", true),
            ("1.000001", "1", false),
            ("3000000000", "3000000000.0", true),
            ("inf", "INF", false),
            ("nan", "nan", true),
        ];
        for (variable, case, matches) in table {
            let mut lab = Lab::new(&[&[S], &[S], &[S]]);
            let mut tree = lab.tree(&switch(variable, case));
            let want = if matches { 0 } else { 2 };
            assert_eq!(
                chosen(&mut lab, &mut tree),
                want,
                "{variable:?} vs {case:?}"
            );
            assert_eq!(lab.halts, [0, 0, 0]);
        }
    }

    #[test]
    fn enum_names_compare_by_value() {
        let lab = Lab::new(&[&[S], &[S], &[S]]);
        let mut registry = lab.registry();
        registry.register_enums([("DOCKING", 2)]).unwrap();
        for (variable, case, want) in [
            ("DOCKING", "2", 0),
            ("2", "DOCKING", 0),
            ("DOCKING", "2.0", 0),
            ("DOCKING", "3", 2),
        ] {
            let mut lab = Lab::new(&[&[S], &[S], &[S]]);
            let xml = format!(
                r#"<root BTCPP_format="4"><BehaviorTree ID="T">{}</BehaviorTree></root>"#,
                switch(variable, case)
            );
            let mut tree = lab.load_with(&registry, &xml).unwrap();
            assert_eq!(
                chosen(&mut lab, &mut tree),
                want,
                "{variable:?} vs {case:?}"
            );
        }
    }

    #[test]
    fn entries_compare_as_the_text_bt_cpp_makes_of_them() {
        // Numbers become text as std::to_string does: integers and booleans as integers,
        // reals with six decimals ("0.000000" for 4e-7, which is then 0, not 4e-7).
        let mut lab = Lab::new(&[&[S], &[S], &[S]]);
        let mut tree = lab.tree(&switch("{v}", "{c}"));
        type Write<'a> = &'a dyn Fn(&mut Tree<Lab>);
        let cases: [(Write<'_>, usize); 7] = [
            (&|t| set(t, 3.5_f64, "3.5"), 0),
            (&|t| set(t, 2.0_f64, "2"), 0),
            (&|t| set(t, true, "1"), 0),
            (&|t| set(t, 5_i32, "5.0"), 0),
            (&|t| set(t, -7_i64, "-7"), 0),
            (&|t| set(t, 4e-7_f64, "0.0000004"), 2),
            (&|t| set(t, vec![1_i64], "1"), 2),
        ];
        for (i, (write, want)) in cases.iter().enumerate() {
            write(&mut tree);
            assert_eq!(chosen(&mut lab, &mut tree), *want, "case {i}");
        }
        // No entry: the default.
        tree.blackboard_mut().unset("v");
        assert_eq!(chosen(&mut lab, &mut tree), 2);
    }

    fn set<T: std::any::Any + Send + Sync>(tree: &mut Tree<Lab>, v: T, c: &str) {
        let bb = tree.blackboard_mut();
        bb.replace_in(neurotree_core::ScopeId::ROOT, "v", v, Default::default());
        bb.replace_in(
            neurotree_core::ScopeId::ROOT,
            "c",
            c.to_string(),
            Default::default(),
        );
    }
}
