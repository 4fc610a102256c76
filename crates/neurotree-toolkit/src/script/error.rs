//! Why a script failed to parse or to run, and where.

use std::fmt::Write as _;

use neurotree_core::BlackboardError;

/// What went wrong in a script; [`ScriptError`] adds where.
///
/// The first group of variants comes from [`Script::parse`](super::Script::parse), the
/// second from [`Script::eval`](super::Script::eval).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ScriptErrorKind {
    // ----- parse errors -----
    /// A character that starts no token.
    #[error("unexpected character `{0}`")]
    UnexpectedChar(char),
    /// A token (or the end of the script) where something else was needed.
    #[error("expected {expected}, found {found}")]
    Expected {
        /// What the parser needed, such as "`)`" or "an expression".
        expected: &'static str,
        /// What it found, such as "`;`" or "end of script".
        found: String,
    },
    /// A string literal without its closing quote.
    #[error("unterminated string: a string started here lacks its closing `{0}`")]
    UnterminatedString(char),
    /// A number literal that is malformed or out of range.
    #[error("bad number `{text}`: {reason}")]
    BadNumber {
        /// The literal as written.
        text: String,
        /// Why it is not a number.
        reason: &'static str,
    },
    /// The left side of an assignment is not a blackboard key.
    #[error("the left side of `{op}` must be a blackboard key, not an expression")]
    InvalidAssignTarget {
        /// The assignment operator.
        op: &'static str,
    },
    /// The expression nests deeper than the parser allows (to keep the stack bounded).
    #[error("expression nested too deeply (more than {0} levels)")]
    TooDeep(usize),
    /// A script without a statement (blank, or only `;`): BehaviorTree.CPP refuses it
    /// ("Empty Script") rather than run nothing.
    #[error("empty script: write at least one statement, or remove the script")]
    Empty,

    // ----- runtime errors -----
    /// A key read (or assigned with `=` or a compound operator) that has no entry.
    #[error("no blackboard entry `{key}`: write it first, or create it with `{key} := value`")]
    UnknownKey {
        /// The key as written in the script.
        key: String,
    },
    /// A blackboard entry whose type scripts cannot read or write.
    #[error(
        "blackboard entry `{key}` holds a `{type_name}`, which scripts cannot use (they use \
         integers, f64, f32, bool and String)"
    )]
    UnsupportedEntryType {
        /// The key as written in the script.
        key: String,
        /// The entry's Rust type.
        type_name: &'static str,
    },
    /// An assignment whose value has the wrong type for the existing entry.
    #[error(
        "blackboard entry `{key}` has type `{entry}` and cannot hold a value of type \
         {value}: an entry's type is fixed by its first write"
    )]
    WrongEntryType {
        /// The key as written in the script.
        key: String,
        /// The entry's Rust type.
        entry: &'static str,
        /// The script type of the value (`int`, `real`, `bool`, `string`).
        value: &'static str,
    },
    /// An assignment whose value does not fit the existing entry's type.
    #[error("value {value} does not fit blackboard entry `{key}` of type `{entry}`")]
    OutOfRange {
        /// The key as written in the script.
        key: String,
        /// The entry's Rust type.
        entry: &'static str,
        /// The value, printed.
        value: String,
    },
    /// A binary operator applied to operands it does not accept.
    #[error("cannot apply `{op}` to {left} and {right}{hint}")]
    BinaryType {
        /// The operator.
        op: &'static str,
        /// Script type of the left operand.
        left: &'static str,
        /// Script type of the right operand.
        right: &'static str,
        /// Extra advice, empty or starting with `: `.
        hint: &'static str,
    },
    /// A unary operator applied to an operand it does not accept.
    #[error("cannot apply `{op}` to {operand}")]
    UnaryType {
        /// The operator.
        op: &'static str,
        /// Script type of the operand.
        operand: &'static str,
    },
    /// A string compared with a number does not parse as a number.
    #[error("cannot compare the string '{text}' with a number: it is not a number")]
    NotANumber {
        /// The string.
        text: String,
    },
    /// Integer arithmetic overflowed `i64`.
    #[error("integer overflow in `{0}`")]
    Overflow(&'static str),
    /// A string would grow past the environment's limit
    /// ([`ScriptEnv::max_string_len`](super::ScriptEnv::max_string_len)).
    #[error("a string of {len} bytes is longer than the {max} bytes a script string may hold")]
    StringTooLong {
        /// The length the string would have had.
        len: usize,
        /// The limit.
        max: usize,
    },
    /// An assignment to a name that the enum table defines.
    #[error("`{0}` is an enum value and cannot be assigned")]
    AssignToEnum(String),
    /// The blackboard refused an access (for example an unknown scope).
    #[error(transparent)]
    Blackboard(#[from] BlackboardError),
}

/// A [`ScriptErrorKind`] and its position in the script's source.
///
/// `Display` prints `line:column: message`; [`render`](Self::render) also shows the line
/// with a caret under the position.
#[derive(Clone, PartialEq, thiserror::Error)]
#[error("{line}:{column}: {kind}")]
pub struct ScriptError {
    /// What went wrong.
    pub kind: ScriptErrorKind,
    /// Byte offset in the source (equal to the source's length for "at the end").
    pub offset: usize,
    /// Line, from 1.
    pub line: u32,
    /// Column in characters, from 1.
    pub column: u32,
}

neurotree_core::debug_shows_message!(struct ScriptError { kind, offset, line, column });

impl ScriptError {
    /// The error `kind` at byte `offset` of `source`, with its line and column.
    pub fn new(kind: ScriptErrorKind, offset: usize, source: &str) -> Self {
        let offset = clamp_to_char(source, offset);
        let before = &source[..offset];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let line = before.matches('\n').count() + 1;
        let column = before[line_start..].chars().count() + 1;
        Self {
            kind,
            offset,
            line: u32::try_from(line).unwrap_or(u32::MAX),
            column: u32::try_from(column).unwrap_or(u32::MAX),
        }
    }

    /// The message, the source line it points into and a caret under the position:
    ///
    /// ```text
    /// 1:12: expected `)`, found end of script
    ///   |
    /// 1 | a := (1 + 2
    ///   |            ^
    /// ```
    ///
    /// `source` should be the script's source; any other text is rendered without panicking.
    pub fn render(&self, source: &str) -> String {
        let offset = clamp_to_char(source, self.offset);
        let line_start = source[..offset].rfind('\n').map_or(0, |i| i + 1);
        let line_end = source[offset..]
            .find('\n')
            .map_or(source.len(), |i| offset + i);
        let line = source[line_start..line_end].trim_end_matches('\r');
        let text = excerpt(line, offset - line_start);
        // Characters of the line the excerpt leaves out before the error (its `…` takes one
        // column, which the caret line gives back below).
        let cut = window(line, offset - line_start).0;
        let number = self.line.to_string();
        let pad = " ".repeat(number.len());
        let mut caret = String::from(if cut > 0 { " " } else { "" });
        // Keep tabs so that the caret lines up with the text above it.
        for c in source[line_start..offset].chars().skip(cut) {
            caret.push(if c == '\t' { '\t' } else { ' ' });
        }
        caret.push('^');
        let mut out = String::new();
        let _ = write!(out, "{self}\n{pad} |\n{number} | {text}\n{pad} | {caret}");
        out
    }
}

impl ScriptError {
    /// The part of `source` to quote in a message about this error: the whole script when
    /// it is short, else [`EXCERPT_CHARS`] characters around the error, with `…` where
    /// text was left out, so that a long script does not fill the message.
    pub fn excerpt<'s>(&self, source: &'s str) -> std::borrow::Cow<'s, str> {
        excerpt(source, self.offset)
    }
}

/// How many characters of a script a message quotes at most.
pub const EXCERPT_CHARS: usize = 60;

/// `source`, or a window of [`EXCERPT_CHARS`] characters of it around byte `offset`.
pub(crate) fn excerpt(source: &str, offset: usize) -> std::borrow::Cow<'_, str> {
    let (start, end) = window(source, offset);
    if start == 0 && end == usize::MAX {
        return source.into();
    }
    let kept: String = source.chars().skip(start).take(EXCERPT_CHARS).collect();
    let before = if start > 0 { "…" } else { "" };
    let after = if end != usize::MAX { "…" } else { "" };
    format!("{before}{kept}{after}").into()
}

/// The characters of `source` an excerpt around byte `offset` keeps: from the first, to
/// the one past the last (`usize::MAX`: to the end).
fn window(source: &str, offset: usize) -> (usize, usize) {
    let total = source.chars().count();
    if total <= EXCERPT_CHARS {
        return (0, usize::MAX);
    }
    let at = source[..clamp_to_char(source, offset)].chars().count();
    let start = at
        .saturating_sub(EXCERPT_CHARS / 2)
        .min(total - EXCERPT_CHARS);
    let end = start + EXCERPT_CHARS;
    (start, if end >= total { usize::MAX } else { end })
}

/// `offset`, moved back to a character boundary and into `source`.
fn clamp_to_char(source: &str, offset: usize) -> usize {
    let mut offset = offset.min(source.len());
    while !source.is_char_boundary(offset) {
        offset -= 1;
    }
    offset
}

/// An error kind and a byte offset, before the line and column are known.
pub(crate) type Located = (ScriptErrorKind, usize);
