//! Reading XML text into a [`Document`]: the text kept once, its elements in a flat arena of
//! byte ranges into it, lines and columns worked out only when an error is reported.
//!
//! BehaviorTree.CPP's parser accepts a bare `&` inside an attribute (scripts write
//! `a && b`), which strict XML forbids: such an `&` is kept as written, while entities
//! (`&amp;`, `&#38;`, ...) are decoded.
//!
//! Two readers fill the arena. The quick one reads, straight from the text and with no
//! allocation per element or attribute, the XML that tree files are made of: elements,
//! attributes, comments, an XML declaration, the predefined entities and character
//! references. On anything else (a DTD, CDATA, processing instructions, namespaces,
//! non-ASCII names, nesting deeper than [`MAX_NESTING`], and every malformed document) it
//! gives up, and the complete reader (roxmltree, on a copy of the text whose bare `&`s are
//! escaped) reads the text instead. So what loads, and every error with its message and
//! position, are the complete reader's; the quick one only has to agree with it on the
//! documents it accepts, which a property test checks.

use super::{LoadError, LoadWarning};

/// A range of bytes of [`Document::buf`], or of indices into one of its arrays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Span {
    start: usize,
    end: usize,
}

impl Span {
    fn new(start: usize, end: usize) -> Self {
        Self { start, end }
    }
}

/// One element of a [`Document`].
#[derive(Debug)]
struct Node {
    tag: Span,
    /// The element's own text, trimmed (a port description in a model).
    text: Span,
    /// Its attributes, in [`Document::attrs`].
    attrs: Span,
    /// One past its last descendant: its next sibling, if it has one (elements are stored in
    /// document order, so its descendants follow it).
    end: usize,
    /// How many child elements it has.
    children: usize,
    /// Byte offset of its `<` in the text.
    offset: usize,
}

/// One XML text read: the text itself and its elements, in document order (the root first).
#[derive(Debug)]
pub(crate) struct Document {
    /// The file name that errors show.
    file: String,
    /// The text as given, then the values that decoding changed; spans point into both.
    buf: String,
    /// Length of the text as given: positions are counted in `buf[..text_len]`.
    text_len: usize,
    nodes: Vec<Node>,
    /// Name and value of every attribute, element by element.
    attrs: Vec<(Span, Span)>,
}

impl Document {
    fn new(text: &str, file: &str, nodes: usize, attrs: usize) -> Self {
        Self {
            file: file.to_string(),
            buf: text.to_string(),
            text_len: text.len(),
            nodes: Vec::with_capacity(nodes),
            attrs: Vec::with_capacity(attrs),
        }
    }

    /// The document element.
    pub(crate) fn root(&self) -> Element<'_> {
        self.element(0)
    }

    /// The element numbered `id` (as [`Element::id`] returned).
    pub(crate) fn element(&self, id: usize) -> Element<'_> {
        Element { doc: self, id }
    }

    fn str(&self, span: Span) -> &str {
        &self.buf[span.start..span.end]
    }

    /// Appends `s` to the buffer and returns where it is.
    fn push(&mut self, s: &str) -> Span {
        let start = self.buf.len();
        self.buf.push_str(s);
        Span::new(start, self.buf.len())
    }

    /// Line and column (1-based, the column in characters) of byte `offset` of the text.
    fn line_col(&self, offset: usize) -> (u32, u32) {
        let text = &self.buf[..self.text_len];
        let before = &text[..offset.min(text.len())];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let line = before.bytes().filter(|&c| c == b'\n').count();
        let col = before[line_start..].chars().count();
        (line as u32 + 1, col as u32 + 1)
    }

    fn error_at(&self, offset: usize, message: String) -> LoadError {
        let (line, col) = self.line_col(offset);
        LoadError {
            file: self.file.clone(),
            line,
            col,
            message,
        }
    }
}

/// An element of a [`Document`], with its attributes, children and position.
#[derive(Clone, Copy)]
pub(crate) struct Element<'d> {
    doc: &'d Document,
    id: usize,
}

impl<'d> Element<'d> {
    fn node(&self) -> &'d Node {
        &self.doc.nodes[self.id]
    }

    /// Its number in its document, to find it again with [`Document::element`].
    pub(crate) fn id(&self) -> usize {
        self.id
    }

    /// Its tag name.
    pub(crate) fn tag(&self) -> &'d str {
        self.doc.str(self.node().tag)
    }

    /// Its own text, trimmed (a port description in a model).
    pub(crate) fn text(&self) -> &'d str {
        self.doc.str(self.node().text)
    }

    /// Its attributes, as names and values, in document order.
    pub(crate) fn attrs(&self) -> impl Iterator<Item = (&'d str, &'d str)> + 'd {
        let doc = self.doc;
        let span = self.node().attrs;
        doc.attrs[span.start..span.end]
            .iter()
            .map(move |&(k, v)| (doc.str(k), doc.str(v)))
    }

    /// Whether it has attributes.
    pub(crate) fn has_attrs(&self) -> bool {
        let span = self.node().attrs;
        span.start < span.end
    }

    /// The value of attribute `name`.
    pub(crate) fn attr(&self, name: &str) -> Option<&'d str> {
        self.attrs().find(|(k, _)| *k == name).map(|(_, v)| v)
    }

    /// How many child elements it has.
    pub(crate) fn child_count(&self) -> usize {
        self.node().children
    }

    /// Its child elements, in document order.
    pub(crate) fn children(&self) -> Children<'d> {
        Children {
            doc: self.doc,
            next: self.id + 1,
            end: self.node().end,
        }
    }

    /// Every element inside it, in document order.
    pub(crate) fn descendants(&self) -> impl Iterator<Item = Element<'d>> + 'd {
        let doc = self.doc;
        // Elements are stored in document order: its descendants are the ones up to `end`.
        (self.id + 1..self.node().end).map(move |id| doc.element(id))
    }

    /// Its line and column (1-based, the column in characters).
    #[cfg(test)]
    pub(crate) fn line_col(&self) -> (u32, u32) {
        self.doc.line_col(self.node().offset)
    }

    /// An error located at this element.
    pub(crate) fn error(&self, message: impl Into<String>) -> LoadError {
        self.doc.error_at(self.node().offset, message.into())
    }

    /// A warning located at this element.
    pub(crate) fn warning(&self, message: impl Into<String>) -> LoadWarning {
        let e = self.error(message);
        LoadWarning {
            file: e.file,
            line: e.line,
            col: e.col,
            message: e.message,
        }
    }
}

/// The child elements of an element.
pub(crate) struct Children<'d> {
    doc: &'d Document,
    next: usize,
    end: usize,
}

impl<'d> Iterator for Children<'d> {
    type Item = Element<'d>;

    fn next(&mut self) -> Option<Element<'d>> {
        if self.next >= self.end {
            return None;
        }
        let child = self.doc.element(self.next);
        // Its descendants come next; its next sibling after them.
        self.next = self.doc.nodes[self.next].end;
        Some(child)
    }
}

/// The deepest element nesting read: far beyond any tree's depth limit, and low enough that
/// no reader needs a deep stack.
const MAX_NESTING: usize = 1024;

/// Parses `text` (from `file`) into a document.
pub(crate) fn parse(text: &str, file: &str) -> Result<Document, LoadError> {
    match quick(text, file) {
        Some(doc) => Ok(doc),
        None => complete(text, file),
    }
}

/// If `&` at the start of `rest` is followed by what BehaviorTree.CPP's parser takes for an
/// entity (a short alphanumeric name, or `#` and one, then `;`), that name; `None` for a bare
/// `&`, kept as written.
fn entity_name(rest: &[u8]) -> Option<&[u8]> {
    let n = rest.iter().take(12).position(|&c| c == b';')?;
    let name = &rest[..n];
    let is_entity = n > 0
        && (name.iter().all(u8::is_ascii_alphanumeric)
            || (name[0] == b'#' && name[1..].iter().all(u8::is_ascii_alphanumeric)));
    is_entity.then_some(name)
}

/// Whether XML allows `c` in text.
fn is_xml_char(c: char) -> bool {
    match c {
        '\t' | '\n' | '\r' => true,
        '\u{FFFE}' | '\u{FFFF}' => false,
        c => c >= ' ',
    }
}

/// The character an entity name (from [`entity_name`]) stands for; `None` for an unknown or
/// malformed one, which the complete reader reports.
fn decode_entity(name: &[u8]) -> Option<char> {
    let (digits, radix) = match name {
        b"amp" => return Some('&'),
        b"lt" => return Some('<'),
        b"gt" => return Some('>'),
        b"quot" => return Some('"'),
        b"apos" => return Some('\''),
        [b'#', b'x', hex @ ..] => (hex, 16),
        [b'#', decimal @ ..] => (decimal, 10),
        _ => return None,
    };
    // `from_str_radix` would take a sign; an entity name has none (it is alphanumeric).
    let digits = std::str::from_utf8(digits).ok()?;
    let c = char::from_u32(u32::from_str_radix(digits, radix).ok()?)?;
    is_xml_char(c).then_some(c)
}

/// Escapes every `&` that does not start an entity; returns the strict text and the offsets
/// (in the strict text) where four bytes were inserted.
fn make_strict(text: &str) -> (String, Vec<usize>) {
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
fn complete(text: &str, file: &str) -> Result<Document, LoadError> {
    let (strict, inserted) = make_strict(text);
    let lines = Lines::new(text);
    // A strict-text offset, back in the original text (`inserted` is sorted).
    let original = |offset: usize| offset - 4 * inserted.partition_point(|&i| i < offset);
    let options = roxmltree::ParsingOptions {
        allow_dtd: false,
        ..roxmltree::ParsingOptions::default()
    };
    let error = |offset: usize, message: String| {
        let (line, col) = lines.line_col(offset);
        LoadError {
            file: file.to_string(),
            line,
            col,
            message,
        }
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
        error(original(offset), format!("malformed XML: {e}"))
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
            doc.nodes[index].end = doc.nodes.len();
            open.pop();
        }
        let offset = original(node.range().start);
        if open.len() >= MAX_NESTING {
            return Err(error(
                offset,
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
            end: index + 1,
            children: 0,
            offset,
        });
        open.push((node.id(), index));
    }
    for (_, index) in open {
        doc.nodes[index].end = doc.nodes.len();
    }
    Ok(doc)
}

/// Reads `text` if it is made only of what tree files use; `None` leaves it (and any error
/// in it) to [`complete`].
fn quick(text: &str, file: &str) -> Option<Document> {
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

/// The numbers of `<` and `=` in `b` (bounds on the numbers of elements and attributes);
/// `None` if `b` holds a character XML forbids (a control character other than a tab or
/// line break, U+FFFE or U+FFFF).
fn markup_count(b: &[u8]) -> Option<(usize, usize)> {
    let mut tags = 0;
    let mut equals = 0;
    let mut ef = false;
    // In chunks small enough for byte counters, with neither branches nor early exits
    // inside, so that the loop is vectorized.
    for chunk in b.chunks(128) {
        let (mut lt, mut eq, mut control, mut high) = (0u8, 0u8, 0u8, 0u8);
        for &c in chunk {
            lt += u8::from(c == b'<');
            eq += u8::from(c == b'=');
            control |= u8::from(c < 0x20)
                & u8::from(c != b'\t')
                & u8::from(c != b'\n')
                & u8::from(c != b'\r');
            high |= u8::from(c == 0xEF);
        }
        if control != 0 {
            return None;
        }
        tags += usize::from(lt);
        equals += usize::from(eq);
        ef |= high != 0;
    }
    // U+FFFE and U+FFFF are EF BF BE and EF BF BF.
    let non_char = ef
        && b.windows(3)
            .any(|w| w[0] == 0xEF && w[1] == 0xBF && w[2] >= 0xBE);
    (!non_char).then_some((tags, equals))
}

/// The bytes of `x` that are zero, as their top bits (exact up to the lowest zero byte,
/// which is all the callers use).
fn zero_bytes(x: u64) -> u64 {
    const LOW: u64 = 0x0101_0101_0101_0101;
    x.wrapping_sub(LOW) & !x & (LOW << 7)
}

/// `c` in every byte.
const fn splat(c: u8) -> u64 {
    0x0101_0101_0101_0101 * c as u64
}

/// The end of the text at `pos` (the next `<`), and whether the text may hold a `>` or `&`
/// (never `false` when it does); `None` at the end of the input.
fn text_end(b: &[u8], mut pos: usize) -> Option<(usize, bool)> {
    let mut marks = false;
    // Eight bytes at a time: text between tags is mostly indentation.
    while let Some(chunk) = b.get(pos..pos + 8) {
        let mut word = [0; 8];
        word.copy_from_slice(chunk);
        let x = u64::from_le_bytes(word);
        let lt = zero_bytes(x ^ splat(b'<'));
        let other = zero_bytes(x ^ splat(b'>')) | zero_bytes(x ^ splat(b'&'));
        if lt != 0 {
            let at = (lt.trailing_zeros() / 8) as usize;
            // Only the lowest bit of each mask is exact; any bit below the `<` means a real
            // `>` or `&` before it.
            marks |= other & ((1u64 << (at * 8)) - 1) != 0;
            return Some((pos + at, marks));
        }
        marks |= other != 0;
        pos += 8;
    }
    loop {
        match *b.get(pos)? {
            b'<' => return Some((pos, marks)),
            c => marks |= c == b'>' || c == b'&',
        }
        pos += 1;
    }
}

/// Skips XML white space; whether there was any.
fn skip_spaces(b: &[u8], pos: &mut usize) -> bool {
    let start = *pos;
    while matches!(b.get(*pos), Some(b' ' | b'\t' | b'\n' | b'\r')) {
        *pos += 1;
    }
    *pos > start
}

/// The bytes that go on an ASCII name.
const NAME_BYTES: [bool; 256] = {
    let mut table = [false; 256];
    let mut i = 0;
    while i < 256 {
        let c = i as u8;
        table[i] = c.is_ascii_alphanumeric() || c == b'_' || c == b'-' || c == b'.';
        i += 1;
    }
    table
};

/// The end of the ASCII name at `start`; `None` if there is none, or if it goes on with a
/// `:` (a namespace prefix) or a non-ASCII character.
fn name_end(b: &[u8], start: usize) -> Option<usize> {
    let first = *b.get(start)?;
    if !(first.is_ascii_alphabetic() || first == b'_') {
        return None;
    }
    let mut pos = start + 1;
    while let Some(&c) = b.get(pos) {
        if NAME_BYTES[usize::from(c)] {
            pos += 1;
        } else if c == b':' || !c.is_ascii() {
            return None;
        } else {
            break;
        }
    }
    Some(pos)
}

/// The end of the quoted value at `pos` (after its closing quote) and its start and end;
/// `None` if a `<` or the end of the text comes first.
fn quoted(b: &[u8], pos: usize) -> Option<(usize, usize, usize)> {
    let quote = *b.get(pos)?;
    if quote != b'"' && quote != b'\'' {
        return None;
    }
    let start = pos + 1;
    let len = b[start..].iter().position(|&c| c == quote || c == b'<')?;
    let end = start + len;
    (b[end] == quote).then_some((end + 1, start, end))
}

/// After `<?xml `: the end of the XML declaration (`version`, then optionally `encoding`
/// and `standalone`, in that order).
fn declaration(b: &[u8], mut pos: usize) -> Option<usize> {
    let mut keys: &[&[u8]] = &[b"version", b"encoding", b"standalone"];
    skip_spaces(b, &mut pos);
    loop {
        if b[pos..].starts_with(b"?>") {
            // `version` is required.
            return (keys.len() < 3).then_some(pos + 2);
        }
        let end = name_end(b, pos)?;
        let at = keys.iter().position(|k| *k == &b[pos..end])?;
        if keys.len() == 3 && at != 0 {
            return None;
        }
        keys = &keys[at + 1..];
        pos = end;
        skip_spaces(b, &mut pos);
        if b.get(pos) != Some(&b'=') {
            return None;
        }
        pos += 1;
        skip_spaces(b, &mut pos);
        pos = quoted(b, pos)?.0;
        if !skip_spaces(b, &mut pos) && !b[pos..].starts_with(b"?>") {
            return None;
        }
    }
}

/// The end of the comment at `pos`; `None` if it is unclosed or holds `--`.
fn comment(b: &[u8], pos: usize) -> Option<usize> {
    let body = pos + 4;
    let dashes = body + b[body..].windows(2).position(|w| w == b"--")?;
    (b.get(dashes + 2) == Some(&b'>')).then_some(dashes + 3)
}

/// Skips white space and comments (what may surround the document element).
fn misc(b: &[u8], mut pos: usize) -> Option<usize> {
    loop {
        skip_spaces(b, &mut pos);
        if !b[pos..].starts_with(b"<!--") {
            return Some(pos);
        }
        pos = comment(b, pos)?;
    }
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
            end: id + 1,
            children: 0,
            offset: at,
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
            .any(|(k, _)| &b[k.start..k.end] == name)
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
                    if b[i] == b'&' {
                        if let Some(name) = entity_name(&b[i + 1..]) {
                            out.push_str(&raw[run..i]);
                            out.push(decode_entity(name)?);
                            i += name.len() + 2;
                            run = i;
                            continue;
                        }
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
        if b[tag.start..tag.end] != b[at + 2..name_end] {
            return None;
        }
        self.doc.nodes[id].end = self.doc.nodes.len();
        Some(pos + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::path::Path;

    #[test]
    fn bare_ampersands_are_accepted_and_entities_kept() {
        let (strict, inserted) = make_strict(r#"<S code="a && b &amp; c &#38; d"/>"#);
        assert_eq!(strict, r#"<S code="a &amp;&amp; b &amp; c &#38; d"/>"#);
        assert_eq!(inserted.len(), 2);
        let doc = parse(r#"<S code="a && b"/>"#, "t.xml").unwrap();
        assert_eq!(doc.root().attr("code"), Some("a && b"));
    }

    #[test]
    fn positions_are_in_the_original_text() {
        let text = "<root>\n  <A x=\"&&\"/>\n  <B/>\n</root>";
        let doc = parse(text, "t.xml").unwrap();
        let children: Vec<Element<'_>> = doc.root().children().collect();
        assert_eq!(children[0].line_col(), (2, 3));
        assert_eq!(children[1].line_col(), (3, 3));
    }

    #[test]
    fn syntax_errors_name_file_line_and_column() {
        let e = parse("<root>\n  <A x=\"&&\">\n</root>", "bad.xml").unwrap_err();
        assert_eq!(e.file, "bad.xml");
        assert_eq!(e.line, 3);
        assert!(e.message.starts_with("malformed XML"), "{}", e.message);
        assert!(e.to_string().starts_with("bad.xml:3:"), "{e}");
    }

    #[test]
    fn text_ends_at_the_first_lt_and_sees_marks_before_it() {
        for (text, expected) in [
            ("<", Some((0, false))),
            ("        <", Some((8, false))),
            ("   &    x<", Some((9, true))),
            ("0123456>89<", Some((10, true))),
            ("0123<567>9abcdef<", Some((4, false))),
            ("0123&<67", Some((5, true))),
            ("0<234567", Some((1, false))),
            ("0123456789ab>", None),
            ("", None),
        ] {
            assert_eq!(text_end(text.as_bytes(), 0), expected, "{text:?}");
        }
    }

    /// Everything a document says, element by element, with positions.
    fn dump(doc: &Document) -> Vec<String> {
        (0..doc.nodes.len())
            .map(|id| {
                let el = doc.element(id);
                let attrs: Vec<_> = el.attrs().collect();
                let children: Vec<usize> = el.children().map(|c| c.id()).collect();
                format!(
                    "{} {:?} {:?} {:?} {} {:?}",
                    el.tag(),
                    el.text(),
                    attrs,
                    children,
                    el.child_count(),
                    el.line_col()
                )
            })
            .collect()
    }

    /// The quick reader accepts only what the complete one accepts, and reads the same.
    fn agree(text: &str) -> bool {
        let Some(quick) = quick(text, "t.xml") else {
            return false;
        };
        match complete(text, "t.xml") {
            Ok(full) => assert_eq!(dump(&quick), dump(&full), "{text:?}"),
            Err(e) => panic!("only the quick reader accepts {text:?}: {e}"),
        }
        true
    }

    #[test]
    fn the_quick_reader_reads_tree_files() {
        let text = "\u{FEFF}<?xml version=\"1.0\" encoding='UTF-8' ?>\r\n<!-- c -->\n\
            <root BTCPP_format=\"4\" >\r\n  <BehaviorTree ID=\"T\">\n\
            <Script code=\"a := 1 &amp;&amp; b &lt; 2;  c && d &#65;&#x42; &foo\tx\r\ny\"/>\n\
            <Sequence name='s'>text &lt; &#x263A; here<A/>tail<!-- c --></Sequence >\n\
            <input_port>\r\n desc\r\nline </input_port><p> a\r\nb\rc </p>\n\
            </BehaviorTree></root><!-- end -->\n";
        assert!(agree(text));
        let doc = quick(text, "t.xml").unwrap();
        let script = doc.element(2);
        assert_eq!(
            script.attr("code"),
            Some("a := 1 && b < 2;  c && d AB &foo x y")
        );
        assert_eq!(doc.element(3).text(), "text < \u{263A} here");
        assert_eq!(doc.element(5).text(), "desc\nline");
        assert_eq!(doc.element(6).text(), "a\nb\nc");
        let tree1111 =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../corpus/bench/tree1111.xml");
        let text = std::fs::read_to_string(&tree1111)
            .unwrap_or_else(|e| panic!("{}: {e}", tree1111.display()));
        assert!(agree(&text));
    }

    #[test]
    fn the_readers_agree_on_the_corpus() {
        fn walk(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
            let entries =
                std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
            for path in entries.flatten().map(|e| e.path()) {
                if path.is_dir() {
                    walk(&path, out);
                } else if path.extension().is_some_and(|e| e == "xml") {
                    out.push(path);
                }
            }
        }
        let mut files = Vec::new();
        walk(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../corpus"),
            &mut files,
        );
        assert!(files.len() >= 60, "only {} corpus files found", files.len());
        // Every corpus file is ordinary enough for the quick reader, and `agree` checks
        // that both readers see the same elements.
        for file in &files {
            let text =
                std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
            assert!(
                agree(&text),
                "the quick reader left {} to the complete one",
                file.display()
            );
        }
    }

    #[test]
    fn the_quick_reader_leaves_the_rest_to_the_complete_one() {
        for text in [
            "<a><![CDATA[x]]></a>",
            "<!DOCTYPE a><a/>",
            "<a><?pi x?></a>",
            "<?xml version='1.0'?><?pi?><a/>",
            "<x:a xmlns:x='u'/>",
            "<a xmlns='u'/>",
            "<a x='1' x='2'/>",
            "<a x='1'y='2'/>",
            "<a>&foo;</a>",
            "<a x='&#0;'/>",
            "<a x='&#xD800;'/>",
            "<a x='a<b'/>",
            "<a>]]></a>",
            "<a><!-- a -- b --></a>",
            "<a><!-- a ---></a>",
            "<a></b>",
            "<a>",
            "<a/><b/>",
            "<a/>x",
            "x<a/>",
            "",
            "<é/>",
            "<a\u{1}/>",
            "<a>\u{FFFE}</a>",
            "<a>&amp;\r</a>",
            "<?xml encoding='x'?><a/>",
            "<?xml version='1'encoding='x'?><a/>",
        ] {
            assert!(!agree(text), "{text:?}");
        }
        let deep = format!(
            "{}{}",
            "<a>".repeat(MAX_NESTING + 1),
            "</a>".repeat(MAX_NESTING + 1)
        );
        assert!(!agree(&deep));
        let e = parse(&deep, "deep.xml").unwrap_err();
        assert!(e.message.contains("nest deeper than 1024 levels"), "{e}");
    }

    /// Text made of the pieces of XML, well-formed or not.
    fn xml_like() -> impl Strategy<Value = String> {
        let piece = prop_oneof![
            Just("<a>".to_string()),
            Just("</a>".to_string()),
            Just("<b x=\"1\" y='&amp;&&#65;'>".to_string()),
            Just("</b>".to_string()),
            Just("<c/>".to_string()),
            Just("<c z=\"\t\r\n&#10;&lt;&gt;&quot;&apos;\"  />".to_string()),
            Just("<!-- x -->".to_string()),
            Just("<?xml version=\"1.0\"?>".to_string()),
            Just("&".to_string()),
            Just("&#x41;".to_string()),
            Just("\r\n".to_string()),
            Just("]]>".to_string()),
            "[a-c<>/=\"' \t\r\n&#;!?x:-]{0,8}",
        ];
        prop::collection::vec(piece, 0..24).prop_map(|parts| parts.concat())
    }

    /// A well-formed element, rendered with random spacing, texts, comments and entities.
    fn element() -> impl Strategy<Value = String> {
        let leaf = ("[a-c]", "[ -~]{0,6}").prop_map(|(tag, attr)| {
            let attr = attr
                .replace('&', "&amp;")
                .replace('<', "&lt;")
                .replace('"', "&quot;");
            format!("<{tag} v=\"{attr} && x\"/>")
        });
        leaf.prop_recursive(6, 64, 6, |inner| {
            (
                "[a-c]",
                prop::collection::vec(inner, 0..6),
                "[ \na-z&;#0-9]{0,6}",
                any::<bool>(),
            )
                .prop_map(|(tag, children, text, comment)| {
                    let text = text.replace('&', "&amp;");
                    let comment = if comment { "<!--c-->" } else { "" };
                    format!(
                        "<{tag} k='1'\r\n>{text}{}{comment}</{tag} >",
                        children.concat()
                    )
                })
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        #[test]
        fn the_readers_agree_on_xml_like_text(text in xml_like()) {
            agree(&text);
        }

        #[test]
        fn the_readers_agree_on_well_formed_text(el in element(), cut in any::<prop::sample::Index>()) {
            prop_assert!(agree(&el), "{el:?}");
            let cut = cut.index(el.len() + 1);
            if el.is_char_boundary(cut) {
                agree(&el[..cut]);
            }
        }
    }
}
