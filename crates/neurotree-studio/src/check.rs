//! Checking the text the editor holds, as `neurotree check` checks a file (then linting
//! it, as `neurotree lint` does), and locating each error and finding's node so that the
//! page can show it there.

use std::path::Path;

use neurotree_toolkit::lint::{lint, LintOptions};
use neurotree_toolkit::{LoadError, Registry, XmlLoader};
use serde::Serialize;

/// The most errors reported for one text, as `neurotree check` reports.
pub const LIMIT: usize = neurotree_toolkit::xml::MAX_ERRORS;

/// What an unknown node type's error advises, as the studio is started from the command
/// line ([`StudioOptions::unknown_type_advice`](crate::StudioOptions::unknown_type_advice)
/// by default): its node types come from the flags it was started with.
pub const UNKNOWN_TYPE_ADVICE: &str = "start the studio with --model FILE, a TreeNodesModel \
     that declares it, or with --nav2 if it is one of Nav2's";

/// What the loader says of a text (PROTOCOL.md, "Check").
#[derive(Clone, Debug, Default, Serialize)]
pub struct Check {
    /// Every tree loads and validates.
    pub ok: bool,
    /// The tree `main_tree_to_execute` names, or the only one.
    pub main: Option<String>,
    /// The `<BehaviorTree>` IDs of the text, in order.
    pub trees: Vec<String>,
    /// Up to 20 errors, as `neurotree check` reports.
    pub errors: Vec<Diagnostic>,
    /// The loader's warnings (deprecated or misspelt names).
    pub warnings: Vec<Diagnostic>,
    /// What `neurotree lint` finds in a text that loads: `kind` is the rule's code.
    pub lint: Vec<Diagnostic>,
}

/// One error or warning, with the node it is at.
#[derive(Clone, Debug, Serialize)]
pub struct Diagnostic {
    /// 1-based line in the text.
    pub line: u32,
    /// 1-based column.
    pub column: u32,
    /// The error's kind (`UnknownPort`, …); `Warning` for warnings; a lint rule's code.
    pub kind: String,
    /// `error`, `warning` or `note`.
    pub severity: &'static str,
    /// As `neurotree check` prints it: `file:line:col: error: …`.
    pub message: String,
    /// The `<BehaviorTree>` the node is in.
    pub tree: Option<String>,
    /// Indices of element children from that tree down to the node.
    pub element: Option<Vec<usize>>,
}

/// Checks `text` as the file `shown` (includes resolve beside `path`), with `registry`
/// (which gets the text's own `TreeNodesModel`); an unknown node type's error ends with
/// `advice`.
pub fn check_text(
    mut registry: Registry<()>,
    path: &Path,
    shown: &str,
    text: &str,
    max_nodes: usize,
    advice: &'static str,
) -> Check {
    let places = Places::new(text);
    let mut check = Check::default();
    if let Err(e) = registry.add_model_str(text, shown) {
        check.errors.push(places.diagnostic(&e));
        return check;
    }
    let mut loader = XmlLoader::new(&registry)
        .max_nodes(max_nodes)
        .unknown_type_advice(advice);
    if let Some(dir) = path.parent() {
        loader = loader.base_dir(dir);
    }
    let loaded = loader.load_str(text, shown);
    check.warnings = loader
        .warnings()
        .iter()
        .map(|w| places.locate(w.line, w.col, "Warning", "warning", w.to_string()))
        .collect();
    if let Err(e) = loaded {
        check.errors.push(places.diagnostic(&e));
        return check;
    }
    check.trees = loader.tree_ids().map(String::from).collect();
    check.main = loader.main_tree().map(String::from);
    if let Err(errors) = loader.validate_trees(check.trees.iter().map(String::as_str)) {
        check.errors = errors.iter().map(|e| places.diagnostic(e)).collect();
    }
    check.ok = check.errors.is_empty();
    if check.ok {
        check.lint = lint(&loader, &lint_options(&registry))
            .iter()
            .take(LIMIT)
            .map(|d| {
                let severity = match d.severity {
                    neurotree_toolkit::lint::Severity::Error => "error",
                    neurotree_toolkit::lint::Severity::Warning => "warning",
                    neurotree_toolkit::lint::Severity::Note => "note",
                };
                places.locate(d.line, d.col, d.code, severity, d.to_string())
            })
            .collect();
    }
    check
}

/// What the linter is told of the trees' surroundings: with Nav2's node types known, the
/// entries Nav2's navigators write and read.
fn lint_options(registry: &Registry<()>) -> LintOptions {
    if registry.get("ComputePathToPose").is_some() {
        LintOptions::nav2()
    } else {
        LintOptions::default()
    }
}

/// How the studio parses XML it was given: no DTD (so no entity expansion), and a bound
/// on the nodes a document may have.
pub(crate) fn xml_options<'i>() -> roxmltree::ParsingOptions<'i> {
    roxmltree::ParsingOptions {
        allow_dtd: false,
        nodes_limit: 1_000_000,
        ..Default::default()
    }
}

/// The elements of a text with where they start and end, to find the node an error's
/// line and column fall in.
struct Places<'a> {
    text: &'a str,
    line_starts: Vec<usize>,
    doc: Option<roxmltree::Document<'a>>,
}

impl<'a> Places<'a> {
    fn new(text: &'a str) -> Self {
        let mut line_starts = vec![0];
        line_starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        let options = crate::check::xml_options();
        Self {
            text,
            line_starts,
            doc: roxmltree::Document::parse_with_options(text, options).ok(),
        }
    }

    fn diagnostic(&self, e: &LoadError) -> Diagnostic {
        self.locate(
            e.line,
            e.col,
            &format!("{:?}", e.kind()),
            "error",
            e.to_string(),
        )
    }

    fn locate(
        &self,
        line: u32,
        column: u32,
        kind: &str,
        severity: &'static str,
        message: String,
    ) -> Diagnostic {
        let (tree, element) = match self.offset(line, column) {
            Some(at) => self.element_at(at),
            None => (None, None),
        };
        Diagnostic {
            line,
            column,
            kind: kind.to_string(),
            severity,
            message,
            tree,
            element,
        }
    }

    /// The byte offset of a 1-based line and (character) column.
    fn offset(&self, line: u32, column: u32) -> Option<usize> {
        let start = *self.line_starts.get((line as usize).checked_sub(1)?)?;
        let rest = &self.text[start..];
        let col = (column as usize).saturating_sub(1);
        Some(start + rest.char_indices().nth(col).map_or(rest.len(), |(i, _)| i))
    }

    /// The tree and element path of the deepest element inside a `<BehaviorTree>` whose
    /// text holds `at`.
    fn element_at(&self, at: usize) -> (Option<String>, Option<Vec<usize>>) {
        let Some(doc) = &self.doc else {
            return (None, None);
        };
        let trees = doc
            .root_element()
            .children()
            .filter(|n| n.is_element() && n.has_tag_name("BehaviorTree"));
        for tree in trees {
            if !tree.range().contains(&at) {
                continue;
            }
            let id = tree.attribute("ID").map(String::from);
            let mut path = Vec::new();
            let mut node = tree;
            'down: loop {
                for (i, child) in node.children().filter(|n| n.is_element()).enumerate() {
                    if child.range().contains(&at) {
                        path.push(i);
                        node = child;
                        continue 'down;
                    }
                }
                break;
            }
            return (id, (!path.is_empty()).then_some(path));
        }
        (None, None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = r#"<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Sequence>
      <!-- a comment is not an element -->
      <AlwaysSuccess/>
      <Repeat num_cycles="many">
        <AlwaysSuccess/>
      </Repeat>
    </Sequence>
  </BehaviorTree>
</root>"#;

    #[test]
    fn an_error_is_located_at_its_node() {
        let check = check_text(
            Registry::new(),
            Path::new("a.xml"),
            "a.xml",
            TEXT,
            100_000,
            UNKNOWN_TYPE_ADVICE,
        );
        assert!(!check.ok);
        assert_eq!(check.trees, ["Main"]);
        assert_eq!(check.errors.len(), 1, "{:?}", check.errors);
        let e = &check.errors[0];
        assert_eq!(e.kind, "BadValue");
        assert!(e.message.starts_with("a.xml:6:"), "{}", e.message);
        assert_eq!(e.tree.as_deref(), Some("Main"));
        // The Sequence is the tree's root; the Repeat its second element child.
        assert_eq!(e.element.as_deref(), Some(&[0, 1][..]));
    }

    #[test]
    fn a_valid_text_is_ok_and_malformed_text_says_where() {
        let good = TEXT.replace("many", "2");
        let check = check_text(
            Registry::new(),
            Path::new("a.xml"),
            "a.xml",
            &good,
            100_000,
            UNKNOWN_TYPE_ADVICE,
        );
        assert!(check.ok, "{:?}", check.errors);
        assert_eq!(check.main.as_deref(), Some("Main"));

        let bad = check_text(
            Registry::new(),
            Path::new("a.xml"),
            "a.xml",
            "<root><BehaviorTree ID=\"M\">",
            100_000,
            UNKNOWN_TYPE_ADVICE,
        );
        assert!(!bad.ok);
        assert_eq!(bad.errors[0].kind, "Syntax");
        assert_eq!(bad.errors[0].element, None);
    }

    #[test]
    fn a_lint_finding_is_located_at_its_node() {
        let text = TEXT.replace("num_cycles=\"many\"", "num_cycles=\"-1\"");
        let check = check_text(
            Registry::new(),
            Path::new("a.xml"),
            "a.xml",
            &text,
            100_000,
            UNKNOWN_TYPE_ADVICE,
        );
        assert!(check.ok, "{:?}", check.errors);
        let found: Vec<(&str, &str, Option<&[usize]>)> = check
            .lint
            .iter()
            .map(|d| (d.kind.as_str(), d.severity, d.element.as_deref()))
            .collect();
        // The Repeat never ends, so neither does the tree.
        assert_eq!(
            found,
            [
                ("NT0303", "warning", Some(&[0][..])),
                ("NT0302", "warning", Some(&[0, 1][..]))
            ]
        );
        assert!(check.lint[1]
            .message
            .starts_with("a.xml:6:7: warning[NT0302]: "));
    }

    #[test]
    fn an_unknown_type_is_advised_as_the_studio_is_started() {
        let text = TEXT
            .replace(
                "<AlwaysSuccess/>\n      <Repeat",
                "<MoveTo/>\n      <Repeat",
            )
            .replace("many", "2");
        let check = check_text(
            Registry::new(),
            Path::new("a.xml"),
            "a.xml",
            &text,
            100_000,
            UNKNOWN_TYPE_ADVICE,
        );
        assert_eq!(check.errors.len(), 1, "{:?}", check.errors);
        let e = &check.errors[0];
        assert_eq!(e.kind, "UnknownNode");
        assert!(e.message.starts_with("a.xml:5:7: error: "), "{}", e.message);
        assert!(e.message.contains("MoveTo"), "{}", e.message);
        assert!(e.message.ends_with(UNKNOWN_TYPE_ADVICE), "{}", e.message);
        assert!(!e.message.contains("Registry"), "{}", e.message);
        assert_eq!(e.element.as_deref(), Some(&[0, 0][..]));
        // A program serving the studio with a registry of its own says how it is extended.
        let own = check_text(
            Registry::new(),
            Path::new("a.xml"),
            "a.xml",
            &text,
            100_000,
            "add it to the program's registry",
        );
        assert!(own.errors[0]
            .message
            .ends_with("add it to the program's registry"));
    }
}
