//! The complete reader: roxmltree on a copy of the text whose bare `&`s are escaped, for
//! every document the quick reader leaves, with every error and its position.

use super::super::{LoadError, LoadErrorKind};
use super::document::{small, Node, Span};
use super::entities::entity_name;
use super::{Document, MAX_NESTING};

/// Escapes every `&` that does not start an entity; returns the strict text and the offsets
/// (in the strict text) where four bytes were inserted.
pub(super) fn make_strict(text: &str) -> (String, Vec<usize>) {
    let bytes = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut inserted = Vec::new();
    let mut last = 0;
    for (i, _) in text.match_indices('&') {
        if entity_name(&bytes[i + 1..]).is_none() {
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

/// Reads `text` with roxmltree: every document, and every error with its position.
pub(super) fn complete(text: &str, file: &str) -> Result<Document, LoadError> {
    let (strict, inserted) = make_strict(text);
    let lines = Lines::new(text);
    // A strict-text offset, back in the original text (`inserted` is sorted).
    let original = |offset: usize| offset - 4 * inserted.partition_point(|&i| i < offset);
    let options = roxmltree::ParsingOptions {
        allow_dtd: false,
        ..roxmltree::ParsingOptions::default()
    };
    let error = |offset: usize, kind: LoadErrorKind, message: String| {
        let (line, col) = lines.line_col(offset);
        LoadError::new(kind, file, line, col, message)
    };
    let parsed = roxmltree::Document::parse_with_options(&strict, options).map_err(|e| {
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
        error(
            original(offset),
            LoadErrorKind::Syntax,
            format!("malformed XML: {e}"),
        )
    })?;
    let mut doc = Document::new(text, file, 0, 0);
    // The open elements, outermost first: the new element's ancestors once the elements it
    // does not descend from are closed. Iterative: the document may be deep.
    let mut open: Vec<(roxmltree::NodeId, usize)> = Vec::new();
    for node in parsed.root_element().descendants() {
        if !node.is_element() {
            continue;
        }
        let parent = node.parent().map(|p| p.id());
        while let Some(&(id, index)) = open.last() {
            if Some(id) == parent {
                break;
            }
            doc.nodes[index].end = small(doc.nodes.len());
            open.pop();
        }
        let offset = original(node.range().start);
        if open.len() >= MAX_NESTING {
            return Err(error(
                offset,
                LoadErrorKind::TooDeep,
                format!(
                    "elements nest deeper than {MAX_NESTING} levels; no behavior tree is that deep"
                ),
            ));
        }
        if let Some(&(_, index)) = open.last() {
            doc.nodes[index].children += 1;
        }
        let tag = doc.push(node.tag_name().name());
        let text = doc.push(node.text().map(str::trim).unwrap_or_default());
        let first_attr = doc.attrs.len();
        for a in node.attributes() {
            let name = doc.push(a.name());
            let value = doc.push(a.value());
            doc.attrs.push((name, value));
        }
        let index = doc.nodes.len();
        doc.nodes.push(Node {
            tag,
            text,
            attrs: Span::new(first_attr, doc.attrs.len()),
            end: small(index + 1),
            children: 0,
            offset: small(offset),
        });
        open.push((node.id(), index));
    }
    for (_, index) in open {
        doc.nodes[index].end = small(doc.nodes.len());
    }
    Ok(doc)
}
