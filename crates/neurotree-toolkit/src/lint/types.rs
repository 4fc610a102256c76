//! Which declared port types an entry can pass between, as BehaviorTree.CPP's `Any`
//! converts: numbers and `bool` among themselves and from text, any type to an untyped
//! port, and another type only to itself. A Script's number (a `bool` is 1 or 0 there)
//! is read as a whole number only when it is one that fits, and never as a type of its own.
//!
//! A port's type is the one its Rust declaration gives or, for a node type only a
//! `TreeNodesModel` declares (Nav2's leaves), the one the model names: `double` is a
//! number, `nav_msgs::msg::Path` a type of its own, known by its last name (`Path`), so
//! that a Rust `Path` and a model's are the same. A generic type (`vector<...>`) or a
//! duration (`chrono::milliseconds`, which BehaviorTree.CPP reads from numbers and text) is
//! not followed: lint then says nothing rather than something false.

use neurotree_core::PortType;

use super::{Diagnostic, LintOptions};
use crate::registry::PortSpec;
use crate::script::ast::{Expr, ExprKind, UnOp};
use crate::xml::{LoadError, LoadErrorKind, XmlLoader};

/// The errors of [`Registry::set_strict_types`](crate::Registry::set_strict_types) for the
/// tree `id`: lint's NT0102 findings, each at its reading port, as load errors.
pub(crate) fn strict_errors<C: 'static>(loader: &XmlLoader<'_, C>, id: &str) -> Vec<LoadError> {
    let mut found: Vec<Diagnostic> = Vec::new();
    super::dataflow::check_root(loader, id, &LintOptions::default(), &mut found);
    found
        .into_iter()
        .filter(|d| d.code == "NT0102")
        .map(|d| {
            LoadError::new(
                LoadErrorKind::BadValue,
                d.file,
                d.line,
                d.col,
                format!(
                    "{} (types are strict: the file is refused, as BehaviorTree.CPP refuses it)",
                    d.message
                ),
            )
        })
        .collect()
}

/// What a port writes into an entry or reads it as, as far as its declaration tells.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Held {
    /// Untyped, or a type not followed.
    Any,
    /// A number or `bool`, by its name (`f64`).
    Number(String),
    /// Text.
    Text,
    /// A type of its own, by its last name (`Path`).
    Named(String),
}

impl Held {
    /// What `spec` carries.
    pub(crate) fn of(spec: &PortSpec) -> Held {
        let declared = spec.port_type();
        if !declared.is_any() {
            return if is_text(declared) {
                Held::Text
            } else if declared.reads_as::<f64>() {
                Held::Number(spec.type_name.to_string())
            } else {
                named(spec.type_name)
            };
        }
        match (spec.type_name, spec.model_type.as_deref()) {
            ("f64" | "i64" | "u64" | "bool", _) => Held::Number(spec.type_name.to_string()),
            ("String", _) => Held::Text,
            (_, Some(model)) => named(model),
            _ => Held::Any,
        }
    }

    /// In words, after "writes": `a Path`, `a number (f64)`.
    fn words(&self) -> String {
        match self {
            Held::Number(name) => format!("a number ({name})"),
            Held::Named(name) => format!("a {name}"),
            Held::Text => "text".to_string(),
            Held::Any => "a value of any type".to_string(),
        }
    }
}

/// The type `spec` reads an entry as, for messages: `f64`, `Path`.
pub(crate) fn read_as(spec: &PortSpec) -> String {
    match Held::of(spec) {
        Held::Named(name) => name,
        _ => spec.type_name.to_string(),
    }
}

/// A type of its own by its last name, unless it is generic or a duration.
fn named(type_name: &str) -> Held {
    let last = type_name.rsplit("::").next().unwrap_or(type_name).trim();
    let duration = ["milliseconds", "seconds", "Duration", "duration"];
    if type_name.contains('<') || last.is_empty() || duration.iter().any(|d| last.contains(d)) {
        Held::Any
    } else {
        Held::Named(last.to_string())
    }
}

/// Why a value `writer` writes into an entry cannot be read through `reader`, in words
/// ("writes a Path into it"), or `None` when it can or when the types say too little.
pub(crate) fn entry_mismatch(writer: &PortSpec, reader: &PortSpec) -> Option<String> {
    let (written, read) = (Held::of(writer), Held::of(reader));
    let typed = |p: &PortSpec| !p.port_type().is_any();
    let clash = if typed(writer) && typed(reader) {
        // Both declared in Rust: their types themselves are compared.
        incompatible(writer.port_type(), reader.port_type())
    } else {
        match (&written, &read) {
            (Held::Any, _) | (_, Held::Any) | (Held::Text, _) | (_, Held::Text) => false,
            (Held::Number(_), Held::Number(_)) => false,
            // Nav2's Rust types are not ROS's messages (a `Pose2D` stands for a
            // `PoseStamped`): two names are compared only when models gave both.
            (Held::Named(a), Held::Named(b)) => !typed(writer) && !typed(reader) && a != b,
            _ => true,
        }
    };
    let words = match written {
        Held::Any => format!("a {}", writer.type_name),
        held => held.words(),
    };
    clash.then(|| format!("writes {words} into it"))
}

/// Why what a write puts into an entry (a `literal` text, the `number` a script assigns,
/// or a value of the type of `port`) cannot be read through `reader`, in words, or `None`
/// when it can or when lint cannot tell.
pub(crate) fn write_mismatch(
    literal: Option<&str>,
    number: Option<f64>,
    port: Option<&PortSpec>,
    reader: &PortSpec,
) -> Option<String> {
    match (literal, number, port) {
        (Some(text), ..) => (!reader.accepts(text))
            .then(|| format!("writes `{text}` into it, which does not convert")),
        (_, Some(n), _) => number_mismatch(n, reader),
        (_, _, Some(port)) => entry_mismatch(port, reader),
        _ => None,
    }
}

/// The number a script's assigned `value` certainly is, as BehaviorTree.CPP's script holds
/// it: a number literal, negated or not, or `true`/`false` (1 and 0); `None` when it is
/// text or an expression whose value lint does not work out.
pub(crate) fn assigned_number(value: &Expr) -> Option<f64> {
    match &value.kind {
        ExprKind::Int(n) => Some(*n as f64),
        ExprKind::Real(x) => Some(*x),
        ExprKind::Bool(b) => Some(f64::from(u8::from(*b))),
        ExprKind::Unary(UnOp::Neg, _, e) => assigned_number(e).map(|n| -n),
        _ => None,
    }
}

/// Why the number `n` a script assigns to an entry cannot be read through `reader`, in
/// words, or `None` when it can or the types say too little. As BehaviorTree.CPP's `Any`
/// converts: a number is read as any number it fits without truncation (text and untyped
/// ports take it as well), never as a type of its own (a `Path`). A `bool` port is let
/// through, as the script's `true` is a double that converts.
pub(crate) fn number_mismatch(n: f64, reader: &PortSpec) -> Option<String> {
    let shown = if n.fract() == 0.0 && n.abs() < 1e15 {
        format!("{n:.0}")
    } else {
        n.to_string()
    };
    match Held::of(reader) {
        Held::Named(name) => Some(format!("assigns the number {shown} into it, not a {name}")),
        Held::Number(_) => {
            // An integer port: its literal check takes `1` and neither `0.5` nor `true`.
            let integer = reader.accepts("1") && !reader.accepts("0.5") && !reader.accepts("true");
            let fits = n.is_finite() && n.fract() == 0.0 && reader.accepts(&format!("{n:.0}"));
            (integer && !fits).then(|| {
                format!("assigns the number {shown} into it, which does not convert without loss")
            })
        }
        Held::Any | Held::Text => None,
    }
}

/// Whether `port` is declared as text (`String`), which reads what converts to text.
fn is_text(port: PortType) -> bool {
    !port.is_any() && !port.writes_as::<f64>() && port.writes_as::<String>()
}

/// Whether a value written through a port of type `written` fails to be read through a
/// port of type `read`. Text on either side is let through: a text port reads a number,
/// and a number port parses text (the literals are checked on their own).
pub(crate) fn incompatible(written: PortType, read: PortType) -> bool {
    let exact = |p: PortType| !p.is_any() && !p.reads_as::<f64>();
    !written.is_any()
        && !read.is_any()
        && !is_text(written)
        && !is_text(read)
        && (exact(written) || exact(read))
        && written != read
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_core::PortDirection;

    /// A port a model declares with type `t`.
    fn modelled(t: &str) -> PortSpec {
        let mut registry = crate::Registry::<()>::new();
        registry
            .add_model_str(
                &format!(
                    r#"<root BTCPP_format="4"><TreeNodesModel><Action ID="A">
                    <output_port name="p" type="{}"/></Action></TreeNodesModel></root>"#,
                    t.replace('<', "&lt;").replace('>', "&gt;")
                ),
                "model.xml",
            )
            .unwrap();
        registry.get("A").unwrap().ports[0].clone()
    }

    #[test]
    fn types_named_by_models_and_by_rust_are_followed_through_entries() {
        struct Path;
        let path = modelled("nav_msgs::msg::Path");
        let double = modelled("double");
        assert_eq!(Held::of(&path), Held::Named("Path".into()));
        assert_eq!(
            entry_mismatch(&path, &double).as_deref(),
            Some("writes a Path into it")
        );
        assert_eq!(
            entry_mismatch(&double, &path).as_deref(),
            Some("writes a number (f64) into it")
        );
        // A Rust `Path` is the model's `Path`; another type is not.
        let rust = PortSpec::output::<Path>("path");
        assert_eq!(entry_mismatch(&rust, &path), None);
        // A Rust type against a model's other name says nothing (Nav2's Rust `Pose2D`
        // stands for ROS's `PoseStamped`); two models' names are compared.
        let pose = modelled("geometry_msgs::msg::PoseStamped");
        assert_eq!(entry_mismatch(&rust, &pose), None);
        assert_eq!(
            entry_mismatch(&path, &pose).as_deref(),
            Some("writes a Path into it")
        );
        assert_eq!(read_as(&pose), "PoseStamped");
        // Text, untyped ports, generics and durations say too little.
        for quiet in [
            modelled("string"),
            modelled("vector<geometry_msgs::msg::PoseStamped>"),
            modelled("chrono::milliseconds"),
            PortSpec::untyped("any", PortDirection::Input),
            PortSpec::input::<String>("text"),
        ] {
            assert_eq!(entry_mismatch(&path, &quiet), None, "{quiet:?}");
            assert_eq!(entry_mismatch(&quiet, &path), None, "{quiet:?}");
        }
        assert_eq!(entry_mismatch(&double, &PortSpec::input::<u8>("n")), None);
    }

    #[test]
    fn only_a_type_of_its_own_against_another_is_incompatible() {
        let pose = PortType::of::<(f64, f64)>();
        let path = PortType::of::<Vec<(f64, f64)>>();
        let number = PortType::of::<i64>();
        let text = PortType::of::<String>();
        assert!(incompatible(pose, path));
        assert!(incompatible(pose, number));
        assert!(incompatible(number, pose));
        assert!(!incompatible(pose, pose));
        assert!(!incompatible(number, PortType::of::<bool>()));
        assert!(!incompatible(pose, text));
        assert!(!incompatible(text, number));
        assert!(!incompatible(pose, PortType::ANY));
        assert!(!incompatible(
            PortType::named("i32"),
            PortType::named("f64")
        ));
    }

    /// The NT0102 findings of `main` (lines and messages) over Nav2's models, and the load
    /// errors (lines) of the file with strict types.
    fn scripted(main: &str) -> (Vec<(u32, String)>, Vec<u32>) {
        let mut registry = crate::Registry::<()>::new();
        registry
            .add_model_str(
                r#"<root BTCPP_format="4"><TreeNodesModel>
                  <Action ID="ComputePathToPose">
                    <input_port name="goal" type="geometry_msgs::msg::PoseStamped"/>
                    <output_port name="path" type="nav_msgs::msg::Path"/>
                  </Action>
                  <Action ID="Wait"><input_port name="wait_duration" type="double"/></Action>
                  <Action ID="Spin"><input_port name="turns" type="int"/></Action>
                  <Action ID="Say"><input_port name="text" type="std::string"/></Action>
                </TreeNodesModel></root>"#,
                "nav2.xml",
            )
            .unwrap();
        let mut loader = crate::XmlLoader::new(&registry);
        loader.load_str(main, "main.xml").unwrap();
        let found = super::super::lint(&loader, &Default::default())
            .into_iter()
            .filter(|d| d.code == "NT0102")
            .map(|d| (d.line, d.message))
            .collect();
        registry.set_strict_types(true);
        let mut strict = crate::XmlLoader::new(&registry);
        strict.load_str(main, "main.xml").unwrap();
        let refused = strict.validate_all("Main", 20);
        let refused = refused.into_iter().map(|e| e.line).collect();
        (found, refused)
    }

    #[test]
    fn a_number_a_script_assigns_is_checked_against_the_port_that_reads_it() {
        let main = |code: &str, reader: &str| {
            format!(
                r#"<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="{code}"/>
      {reader}
    </Sequence>
  </BehaviorTree>
</root>"#
            )
        };
        let goal = r#"<ComputePathToPose goal="{p}" path="{path}"/>"#;
        let (found, refused) = scripted(&main("p := 3.5", goal));
        assert_eq!(
            found,
            [(
                5,
                "port `goal` of ComputePathToPose reads the entry `p` as PoseStamped, but the \
                 script `code` of Script at line 4 assigns the number 3.5 into it, not a \
                 PoseStamped"
                    .to_string()
            )]
        );
        assert_eq!(refused, [5]);
        // `true` is a number to BehaviorTree.CPP's script, and no pose either.
        assert_eq!(scripted(&main("p := true", goal)).1, [5]);
        // An integer port takes a whole number in its range, and no fraction.
        let spin = r#"<Spin turns="{p}"/>"#;
        for whole in ["p := 3", "p := -2.0", "p = 7", "p := true"] {
            assert_eq!(scripted(&main(whole, spin)), (vec![], vec![]), "{whole}");
        }
        for lossy in ["p := 3.5", "p := -0.25", "p := 1e20"] {
            let (found, refused) = scripted(&main(lossy, spin));
            assert_eq!(found.len(), 1, "{lossy}");
            assert!(
                found[0].1.ends_with("which does not convert without loss"),
                "{found:?}"
            );
            assert_eq!(refused, [5], "{lossy}");
        }
        // A number port, a text port, and what lint cannot work out say nothing.
        for quiet in [
            main("p := 3.5", r#"<Wait wait_duration="{p}"/>"#),
            main("p := 3.5", r#"<Say text="{p}"/>"#),
            main("p := 3.5 * 2", spin),
            main("p := 1; p += 0.5", spin),
            main("p := 'text'", r#"<Say text="{p}"/>"#),
        ] {
            assert_eq!(scripted(&quiet), (vec![], vec![]), "{quiet}");
        }
        // Text that converts is read; text that does not is refused.
        let wait = r#"<Wait wait_duration="{p}"/>"#;
        assert_eq!(scripted(&main("p := '2.5'", wait)), (vec![], vec![]));
        assert_eq!(scripted(&main("p := 'soon'", wait)).1, [5]);
    }

    #[test]
    fn a_script_value_is_a_number_only_when_it_is_a_literal() {
        let value = |code: &str| {
            let script = crate::script::Script::parse(code).unwrap();
            match &script.program()[0].kind {
                ExprKind::Assign(_, _, _, _, value) => assigned_number(value),
                other => panic!("{other:?}"),
            }
        };
        assert_eq!(value("p := 3"), Some(3.0));
        assert_eq!(value("p := -3.5"), Some(-3.5));
        assert_eq!(value("p := false"), Some(0.0));
        assert_eq!(value("p := 'three'"), None);
        assert_eq!(value("p := q"), None);
        assert_eq!(value("p := 1 + 2"), None);
        let int = PortSpec::input::<i32>("n");
        assert_eq!(number_mismatch(2.0, &int), None);
        assert!(number_mismatch(2.5, &int).is_some());
        assert!(number_mismatch(3e9, &int).is_some());
        assert!(number_mismatch(-1.0, &PortSpec::input::<u64>("n")).is_some());
        assert_eq!(number_mismatch(2.5, &PortSpec::input::<f64>("x")), None);
        assert_eq!(number_mismatch(2.5, &PortSpec::input::<bool>("b")), None);
        assert_eq!(number_mismatch(2.5, &PortSpec::input::<String>("s")), None);
    }

    #[test]
    fn an_entry_written_as_a_path_and_read_as_a_number_is_an_error_where_it_is_read() {
        let mut registry = crate::Registry::<()>::new();
        registry
            .add_model_str(
                r#"<root BTCPP_format="4"><TreeNodesModel>
                  <Action ID="ComputePathToPose">
                    <input_port name="goal" type="geometry_msgs::msg::PoseStamped"/>
                    <output_port name="path" type="nav_msgs::msg::Path"/>
                  </Action>
                  <Action ID="Wait"><input_port name="wait_duration" type="double"/></Action>
                </TreeNodesModel></root>"#,
                "nav2.xml",
            )
            .unwrap();
        const MAIN: &str = r#"<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Sequence>
      <ComputePathToPose goal="{goal}" path="{p}"/>
      <Wait wait_duration="{p}"/>
    </Sequence>
  </BehaviorTree>
</root>"#;
        let mut loader = crate::XmlLoader::new(&registry);
        loader.load_str(MAIN, "main.xml").unwrap();
        let options = super::super::LintOptions {
            written: vec!["goal".into()],
            ..Default::default()
        };
        let found: Vec<_> = super::super::lint(&loader, &options)
            .into_iter()
            .filter(|d| d.code == "NT0102")
            .collect();
        assert_eq!(found.len(), 1, "{found:?}");
        // By default the file loads; with strict types, loading refuses it there.
        assert_eq!(loader.validate("Main"), Ok(()));
        registry.set_strict_types(true);
        let mut strict = crate::XmlLoader::new(&registry);
        strict.load_str(MAIN, "main.xml").unwrap();
        let refused = strict.validate("Main").unwrap_err();
        assert_eq!((refused.line, refused.col), (5, 7));
        assert!(refused.message.starts_with(&found[0].message), "{refused}");
        assert_eq!(strict.validate_all("Main", 20), [refused]);
        assert_eq!(found[0].severity, super::super::Severity::Error);
        assert_eq!((found[0].line, found[0].col), (5, 7));
        assert_eq!(
            found[0].message,
            "port `wait_duration` of Wait reads the entry `p` as f64, but port `path` of \
             ComputePathToPose at line 4 writes a Path into it"
        );
    }
}
