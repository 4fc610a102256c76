//! The quick reader: straight from the text, with no allocation per element or attribute,
//! the XML that tree files are made of; `None` on anything else.

use super::bytes::*;
use super::document::{small, Node, Span};
use super::entities::{decode_entity, entity_name};
use super::{Document, MAX_NESTING};

/// Reads `text` if it is made only of what tree files use; `None` leaves it (and any error
/// in it) to [`complete`](super::complete::complete).
pub(super) fn quick(text: &str, file: &str) -> Option<Document> {
    let b = text.as_bytes();
    let (tags, attrs) = markup_count(b)?;
    let mut r = Quick {
        text,
        b,
        doc: Document::new(text, file, tags, attrs),
        open: Vec::new(),
    };
    // A UTF-8 byte order mark, which the complete reader skips too.
    let mut pos = if b.starts_with(&[0xEF, 0xBB, 0xBF]) {
        3
    } else {
        0
    };
    if b[pos..].starts_with(b"<?xml ") {
        pos = declaration(b, pos + 6)?;
    }
    pos = misc(b, pos)?;
    if b.get(pos) != Some(&b'<') {
        return None;
    }
    pos = r.content(pos)?;
    pos = misc(b, pos)?;
    (pos == b.len()).then_some(r.doc)
}

/// The quick reader's state.
struct Quick<'t> {
    text: &'t str,
    /// `text`, as bytes.
    b: &'t [u8],
    doc: Document,
    /// The open elements, outermost first.
    open: Vec<usize>,
}

impl<'t> Quick<'t> {
    /// Reads the document element at `pos` and everything in it; returns the end.
    fn content(&mut self, mut pos: usize) -> Option<usize> {
        let b = self.b;
        loop {
            // The element whose first content comes next: its own text, if any.
            let mut fresh = None;
            match *b.get(pos + 1)? {
                b'/' => {
                    pos = self.close(pos)?;
                    if self.open.is_empty() {
                        return Some(pos);
                    }
                }
                b'!' if b[pos..].starts_with(b"<!--") => pos = comment(b, pos)?,
                b'!' | b'?' => return None,
                _ => {
                    let (end, opened) = self.start(pos)?;
                    pos = end;
                    if self.open.is_empty() {
                        // A document element without content.
                        return Some(pos);
                    }
                    if opened {
                        fresh = Some(self.doc.nodes.len() - 1);
                    }
                }
            }
            let start = pos;
            let marks;
            (pos, marks) = text_end(b, pos)?;
            if pos > start {
                let text = &b[start..pos];
                // XML forbids `]]>` in text.
                if marks && text.windows(3).any(|w| w == b"]]>") {
                    return None;
                }
                match fresh {
                    Some(id) => self.doc.nodes[id].text = self.element_text(start, pos)?,
                    // Not kept, but an unknown entity in it is an error all the same.
                    None if marks => {
                        let mut rest = text;
                        while let Some(amp) = rest.iter().position(|&c| c == b'&') {
                            rest = &rest[amp + 1..];
                            if let Some(name) = entity_name(rest) {
                                decode_entity(name)?;
                            }
                        }
                    }
                    None => {}
                }
            }
        }
    }

    /// Reads the start tag at `at`; returns its end and whether the element has content.
    fn start(&mut self, at: usize) -> Option<(usize, bool)> {
        let b = self.b;
        let tag_end = name_end(b, at + 1)?;
        if self.open.len() >= MAX_NESTING {
            return None;
        }
        let first_attr = self.doc.attrs.len();
        let mut pos = tag_end;
        let opened = loop {
            let spaced = skip_spaces(b, &mut pos);
            match *b.get(pos)? {
                b'>' => break true,
                b'/' if b.get(pos + 1) == Some(&b'>') => {
                    pos += 1;
                    break false;
                }
                // Attributes are separated by white space.
                _ if !spaced => return None,
                _ => pos = self.attribute(pos, first_attr)?,
            }
        };
        let id = self.doc.nodes.len();
        if let Some(&parent) = self.open.last() {
            self.doc.nodes[parent].children += 1;
        }
        self.doc.nodes.push(Node {
            tag: Span::new(at + 1, tag_end),
            text: Span::default(),
            attrs: Span::new(first_attr, self.doc.attrs.len()),
            end: small(id + 1),
            children: 0,
            offset: small(at),
        });
        if opened {
            self.open.push(id);
        }
        Some((pos + 1, opened))
    }

    /// Reads the attribute at `pos` of the element whose attributes start at `first`;
    /// returns its end.
    fn attribute(&mut self, pos: usize, first: usize) -> Option<usize> {
        let b = self.b;
        let name_end = name_end(b, pos)?;
        let name = &b[pos..name_end];
        // A default namespace: the complete reader knows namespaces.
        if name == b"xmlns" {
            return None;
        }
        let mut at = name_end;
        skip_spaces(b, &mut at);
        if b.get(at) != Some(&b'=') {
            return None;
        }
        at += 1;
        skip_spaces(b, &mut at);
        let (end, start, stop) = quoted(b, at)?;
        let raw = &b[start..stop];
        let value = if raw
            .iter()
            .any(|&c| matches!(c, b'&' | b'\t' | b'\n' | b'\r'))
        {
            self.attribute_value(start, stop)?
        } else {
            Span::new(start, stop)
        };
        // Names point into the text, which `b` is.
        if self.doc.attrs[first..]
            .iter()
            .any(|(k, _)| &b[k.range()] == name)
        {
            return None;
        }
        self.doc.attrs.push((Span::new(pos, name_end), value));
        Some(end)
    }

    /// Decodes the attribute value at `start..stop` of the text into the buffer: entities
    /// decoded, bare `&`s kept, tabs and line breaks turned into spaces (a `\r\n` into one).
    fn attribute_value(&mut self, start: usize, stop: usize) -> Option<Span> {
        let b = self.b;
        let from = self.doc.buf.len();
        let mut run = start;
        let mut i = start;
        while i < stop {
            let replacement = match b[i] {
                b'&' => match entity_name(&b[i + 1..stop]) {
                    Some(name) => Some((decode_entity(name)?, name.len() + 2)),
                    None => None,
                },
                b'\r' if b.get(i + 1) == Some(&b'\n') && i + 1 < stop => Some(('\0', 1)),
                b'\t' | b'\n' | b'\r' => Some((' ', 1)),
                _ => None,
            };
            match replacement {
                Some((c, len)) => {
                    self.doc.buf.push_str(self.text(run, i));
                    if c != '\0' {
                        self.doc.buf.push(c);
                    }
                    i += len;
                    run = i;
                }
                None => i += 1,
            }
        }
        self.doc.buf.push_str(self.text(run, stop));
        Some(Span::new(from, self.doc.buf.len()))
    }

    /// The element text at `start..stop` of the text, decoded and trimmed.
    fn element_text(&mut self, start: usize, stop: usize) -> Option<Span> {
        // Most element texts are indentation: a byte test, where `trim` decodes characters.
        if self.b[start..stop]
            .iter()
            .all(|c| matches!(c, b' ' | b'\t' | b'\n' | b'\r'))
        {
            return Some(Span::default());
        }
        let raw = self.text(start, stop);
        if raw.trim().is_empty() {
            return Some(Span::default());
        }
        let has_entity = raw.contains('&');
        let has_cr = raw.contains('\r');
        let decoded = match (has_entity, has_cr) {
            (false, false) => {
                let from = start + (raw.len() - raw.trim_start().len());
                let to = start + raw.trim_end().len();
                return Some(Span::new(from, to));
            }
            // Rare, and decoded with quirks of its own: left to the complete reader.
            (true, true) => return None,
            (false, true) => raw.replace("\r\n", "\n").replace('\r', "\n"),
            (true, false) => {
                let b = raw.as_bytes();
                let mut out = String::with_capacity(raw.len());
                let mut run = 0;
                let mut i = 0;
                while i < b.len() {
                    if b[i] == b'&'
                        && let Some(name) = entity_name(&b[i + 1..])
                    {
                        out.push_str(&raw[run..i]);
                        out.push(decode_entity(name)?);
                        i += name.len() + 2;
                        run = i;
                        continue;
                    }
                    i += 1;
                }
                out.push_str(&raw[run..]);
                out
            }
        };
        Some(self.doc.push(decoded.trim()))
    }

    /// `text[start..stop]`, for offsets at ASCII delimiters.
    fn text(&self, start: usize, stop: usize) -> &'t str {
        &self.text[start..stop]
    }

    /// Reads the end tag at `at`, which must close the innermost open element.
    fn close(&mut self, at: usize) -> Option<usize> {
        let b = self.b;
        let name_end = name_end(b, at + 2)?;
        let mut pos = name_end;
        skip_spaces(b, &mut pos);
        if b.get(pos) != Some(&b'>') {
            return None;
        }
        let id = self.open.pop()?;
        let tag = self.doc.nodes[id].tag;
        if b[tag.range()] != b[at + 2..name_end] {
            return None;
        }
        self.doc.nodes[id].end = small(self.doc.nodes.len());
        Some(pos + 1)
    }
}
