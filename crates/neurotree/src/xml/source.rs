//! Reading XML text into elements that remember where they came from.
//!
//! BehaviorTree.CPP's parser accepts a bare `&` inside an attribute (scripts write
//! `a && b`), which strict XML forbids. The text is made strict first, escaping such `&`s,
//! and positions are mapped back to the original text so that errors point where the user
//! looks.

use std::sync::Arc;

use super::LoadError;

/// An XML element with its attributes, children and position.
#[derive(Debug, Clone)]
pub(crate) struct Element {
    pub(crate) tag: String,
    /// The element's own text (a port description in a model).
    pub(crate) text: String,
    pub(crate) attrs: Vec<(String, String)>,
    pub(crate) children: Vec<Element>,
    pub(crate) file: Arc<str>,
    pub(crate) line: u32,
    pub(crate) col: u32,
}

impl Element {
    /// The value of attribute `name`.
    pub(crate) fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// An error located at this element.
    pub(crate) fn error(&self, message: impl Into<String>) -> LoadError {
        LoadError {
            file: self.file.to_string(),
            line: self.line,
            col: self.col,
            message: message.into(),
        }
    }
}

/// Escapes every `&` that does not start an entity; returns the strict text and the offsets
/// (in the strict text) where four bytes were inserted.
fn make_strict(text: &str) -> (String, Vec<usize>) {
    let bytes = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut inserted = Vec::new();
    let mut last = 0;
    for (i, _) in text.match_indices('&') {
        let rest = &bytes[i + 1..];
        let entity_len = rest.iter().take(12).position(|&c| c == b';');
        let is_entity = entity_len.is_some_and(|n| {
            let name = &rest[..n];
            n > 0
                && (name.iter().all(u8::is_ascii_alphanumeric)
                    || (name[0] == b'#' && name[1..].iter().all(u8::is_ascii_alphanumeric)))
        });
        if !is_entity {
            out.push_str(&text[last..=i]);
            inserted.push(out.len());
            out.push_str("amp;");
            last = i + 1;
        }
    }
    out.push_str(&text[last..]);
    (out, inserted)
}

/// Finds lines and columns of byte offsets in one text, in logarithmic time per query.
struct Lines<'a> {
    text: &'a str,
    /// Byte offset of the start of each line.
    starts: Vec<usize>,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Self {
        let starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Self { text, starts }
    }

    /// Line and column (1-based, the column in characters) of byte `offset`.
    fn line_col(&self, offset: usize) -> (u32, u32) {
        let offset = offset.min(self.text.len());
        let line = self.starts.partition_point(|&s| s <= offset) - 1;
        let col = self.text[self.starts[line]..offset].chars().count();
        (line as u32 + 1, col as u32 + 1)
    }
}

/// The deepest element nesting read: far beyond any tree's depth limit, and low enough that
/// the element tree can be dropped (recursively) on any thread's stack.
const MAX_NESTING: usize = 1024;

/// Parses `text` (from `file`) into its root element.
pub(crate) fn parse(text: &str, file: &str) -> Result<Element, LoadError> {
    let (strict, inserted) = make_strict(text);
    let lines = Lines::new(text);
    // A strict-text offset, back in the original text (`inserted` is sorted).
    let original = |offset: usize| offset - 4 * inserted.partition_point(|&i| i < offset);
    let file: Arc<str> = Arc::from(file);
    let options = roxmltree::ParsingOptions {
        allow_dtd: false,
        ..roxmltree::ParsingOptions::default()
    };
    let doc = roxmltree::Document::parse_with_options(&strict, options).map_err(|e| {
        let pos = e.pos();
        // Positions of syntax errors are in the strict text; map through a byte offset.
        let offset = strict
            .split_inclusive('\n')
            .take(pos.row.saturating_sub(1) as usize)
            .map(str::len)
            .sum::<usize>()
            + strict
                .lines()
                .nth(pos.row.saturating_sub(1) as usize)
                .map_or(0, |l| {
                    l.char_indices()
                        .nth(pos.col.saturating_sub(1) as usize)
                        .map_or(l.len(), |(b, _)| b)
                });
        let (line, col) = lines.line_col(original(offset));
        LoadError {
            file: file.to_string(),
            line,
            col,
            message: format!("malformed XML: {e}"),
        }
    })?;
    // Iterative conversion: the document may be deep, and building must not recurse on it.
    let root = doc.root_element();
    let convert = |node: roxmltree::Node<'_, '_>| {
        let (line, col) = lines.line_col(original(node.range().start));
        Element {
            tag: node.tag_name().name().to_string(),
            text: node.text().map(str::trim).unwrap_or_default().to_string(),
            attrs: node
                .attributes()
                .map(|a| (a.name().to_string(), a.value().to_string()))
                .collect(),
            children: Vec::new(),
            file: Arc::clone(&file),
            line,
            col,
        }
    };
    // A stack of (node, its element, index of next child to visit).
    let mut stack: Vec<(roxmltree::Node<'_, '_>, Element)> = vec![(root, convert(root))];
    let mut pending: Vec<std::vec::IntoIter<roxmltree::Node<'_, '_>>> = vec![root
        .children()
        .filter(|n| n.is_element())
        .collect::<Vec<_>>()
        .into_iter()];
    loop {
        let next = pending.last_mut().and_then(Iterator::next);
        match next {
            Some(child) => {
                if stack.len() >= MAX_NESTING {
                    let (line, col) = lines.line_col(original(child.range().start));
                    return Err(LoadError {
                        file: file.to_string(),
                        line,
                        col,
                        message: format!(
                            "elements nest deeper than {MAX_NESTING} levels; no behavior tree is that deep"
                        ),
                    });
                }
                pending.push(
                    child
                        .children()
                        .filter(|n| n.is_element())
                        .collect::<Vec<_>>()
                        .into_iter(),
                );
                stack.push((child, convert(child)));
            }
            None => {
                pending.pop();
                let (_, done) = stack.pop().expect("one element per pending list");
                match stack.last_mut() {
                    Some((_, parent)) => parent.children.push(done),
                    None => return Ok(done),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bare_ampersands_are_accepted_and_entities_kept() {
        let (strict, inserted) = make_strict(r#"<S code="a && b &amp; c &#38; d"/>"#);
        assert_eq!(strict, r#"<S code="a &amp;&amp; b &amp; c &#38; d"/>"#);
        assert_eq!(inserted.len(), 2);
        let el = parse(r#"<S code="a && b"/>"#, "t.xml").unwrap();
        assert_eq!(el.attr("code"), Some("a && b"));
    }

    #[test]
    fn positions_are_in_the_original_text() {
        let text = "<root>\n  <A x=\"&&\"/>\n  <B/>\n</root>";
        let el = parse(text, "t.xml").unwrap();
        assert_eq!((el.children[0].line, el.children[0].col), (2, 3));
        assert_eq!((el.children[1].line, el.children[1].col), (3, 3));
    }

    #[test]
    fn syntax_errors_name_file_line_and_column() {
        let e = parse("<root>\n  <A x=\"&&\">\n</root>", "bad.xml").unwrap_err();
        assert_eq!(e.file, "bad.xml");
        assert_eq!(e.line, 3);
        assert!(e.message.starts_with("malformed XML"), "{}", e.message);
        assert!(e.to_string().starts_with("bad.xml:3:"), "{e}");
    }
}
