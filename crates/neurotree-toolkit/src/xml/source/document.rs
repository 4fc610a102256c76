//! The document both readers fill: the text kept once, elements in a flat arena of byte
//! ranges into it, and what the loader asks of an element.

use super::super::{LoadError, LoadErrorKind, LoadWarning};

/// A range of bytes of [`Document::buf`], or of indices into one of its arrays.
///
/// In 32 bits: [`parse`](super::parse) refuses a text of more than
/// [`MAX_TEXT_BYTES`](super::MAX_TEXT_BYTES), so every offset and count fits, and the
/// elements of a large tree take half the memory.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Span {
    start: u32,
    end: u32,
}

impl Span {
    pub(super) fn new(start: usize, end: usize) -> Self {
        Self {
            start: small(start),
            end: small(end),
        }
    }

    /// The range it stands for.
    pub(super) fn range(self) -> core::ops::Range<usize> {
        self.start as usize..self.end as usize
    }

    /// Whether it is empty.
    pub(super) fn is_empty(self) -> bool {
        self.start >= self.end
    }
}

/// An offset or count of a document, in the 32 bits [`Span`] and [`Node`] keep.
pub(super) fn small(n: usize) -> u32 {
    debug_assert!(n <= u32::MAX as usize);
    // `parse` refused texts whose offsets and counts could not fit.
    n as u32
}

/// One element of a [`Document`].
#[derive(Debug)]
pub(super) struct Node {
    pub(super) tag: Span,
    /// The element's own text, trimmed (a port description in a model).
    pub(super) text: Span,
    /// Its attributes, in [`Document::attrs`].
    pub(super) attrs: Span,
    /// One past its last descendant: its next sibling, if it has one (elements are stored in
    /// document order, so its descendants follow it).
    pub(super) end: u32,
    /// How many child elements it has.
    pub(super) children: u32,
    /// Byte offset of its `<` in the text.
    pub(super) offset: u32,
}

/// One XML text read: the text itself and its elements, in document order (the root first).
#[derive(Debug)]
pub(crate) struct Document {
    /// The file name that errors show.
    pub(super) file: String,
    /// The text as given, then the values that decoding changed; spans point into both.
    pub(super) buf: String,
    /// Length of the text as given: positions are counted in `buf[..text_len]`.
    pub(super) text_len: usize,
    pub(super) nodes: Vec<Node>,
    /// Name and value of every attribute, element by element.
    pub(super) attrs: Vec<(Span, Span)>,
}

impl Document {
    pub(super) fn new(text: &str, file: &str, nodes: usize, attrs: usize) -> Self {
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

    pub(super) fn str(&self, span: Span) -> &str {
        &self.buf[span.range()]
    }

    /// Appends `s` to the buffer and returns where it is.
    pub(super) fn push(&mut self, s: &str) -> Span {
        let start = self.buf.len();
        self.buf.push_str(s);
        Span::new(start, self.buf.len())
    }

    /// Line and column (1-based, the column in characters) of byte `offset` of the text.
    pub(super) fn line_col(&self, offset: usize) -> (u32, u32) {
        let text = &self.buf[..self.text_len];
        let before = &text[..offset.min(text.len())];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let line = before.bytes().filter(|&c| c == b'\n').count();
        let col = before[line_start..].chars().count();
        (line as u32 + 1, col as u32 + 1)
    }

    pub(super) fn error_at(
        &self,
        offset: usize,
        kind: LoadErrorKind,
        message: String,
    ) -> LoadError {
        let (line, col) = self.line_col(offset);
        LoadError::new(kind, self.file.clone(), line, col, message)
    }
}

/// An element of a [`Document`], with its attributes, children and position.
#[derive(Clone, Copy)]
pub(crate) struct Element<'d> {
    pub(super) doc: &'d Document,
    pub(super) id: usize,
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
    pub(crate) fn attrs(&self) -> impl Iterator<Item = (&'d str, &'d str)> + use<'d> {
        let doc = self.doc;
        let span = self.node().attrs;
        doc.attrs[span.range()]
            .iter()
            .map(move |&(k, v)| (doc.str(k), doc.str(v)))
    }

    /// Whether it has attributes.
    pub(crate) fn has_attrs(&self) -> bool {
        !self.node().attrs.is_empty()
    }

    /// The value of attribute `name`.
    pub(crate) fn attr(&self, name: &str) -> Option<&'d str> {
        self.attrs().find(|(k, _)| *k == name).map(|(_, v)| v)
    }

    /// How many child elements it has.
    pub(crate) fn child_count(&self) -> usize {
        self.node().children as usize
    }

    /// Its child elements, in document order.
    pub(crate) fn children(&self) -> Children<'d> {
        Children {
            doc: self.doc,
            next: self.id + 1,
            end: self.node().end as usize,
        }
    }

    /// One past its last descendant: the number of the element after it and everything
    /// inside it.
    pub(crate) fn subtree_end(&self) -> usize {
        self.node().end as usize
    }

    /// The element numbered `id` of the same document.
    pub(crate) fn sibling_or_descendant(&self, id: usize) -> Element<'d> {
        self.doc.element(id)
    }

    /// Every element inside it, in document order.
    pub(crate) fn descendants(&self) -> impl Iterator<Item = Element<'d>> + use<'d> {
        let doc = self.doc;
        // Elements are stored in document order: its descendants are the ones up to `end`.
        (self.id + 1..self.node().end as usize).map(move |id| doc.element(id))
    }

    /// Which document it is in, told apart from the others the loader holds while they
    /// stay in place (no file is loaded meanwhile).
    pub(crate) fn document_key(&self) -> usize {
        std::ptr::from_ref(self.doc) as usize
    }

    /// The file it was read from, as errors show it.
    pub(crate) fn file(&self) -> &'d str {
        &self.doc.file
    }

    /// Its line and column (1-based, the column in characters).
    pub(crate) fn line_col(&self) -> (u32, u32) {
        self.doc.line_col(self.node().offset as usize)
    }

    /// An error of `kind` located at this element.
    pub(crate) fn error(&self, kind: LoadErrorKind, message: impl Into<String>) -> LoadError {
        self.doc
            .error_at(self.node().offset as usize, kind, message.into())
    }

    /// A warning located at this element.
    pub(crate) fn warning(&self, message: impl Into<String>) -> LoadWarning {
        let (line, col) = self.doc.line_col(self.node().offset as usize);
        LoadWarning {
            file: self.doc.file.clone(),
            line,
            col,
            message: message.into(),
        }
    }
}

/// The child elements of an element.
pub(crate) struct Children<'d> {
    pub(super) doc: &'d Document,
    pub(super) next: usize,
    pub(super) end: usize,
}

impl<'d> Iterator for Children<'d> {
    type Item = Element<'d>;

    fn next(&mut self) -> Option<Element<'d>> {
        if self.next >= self.end {
            return None;
        }
        let child = self.doc.element(self.next);
        // Its descendants come next; its next sibling after them.
        self.next = self.doc.nodes[self.next].end as usize;
        Some(child)
    }
}
