//! Splits a script into tokens.

use super::error::{Located, ScriptErrorKind};

/// One token: what it is and the byte range it spans.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Token {
    pub(crate) kind: Tok,
    pub(crate) start: usize,
    pub(crate) end: usize,
}

/// The kinds of token.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Tok {
    /// An integer literal's magnitude; `9223372036854775808` (2^63) is kept so that
    /// `-9223372036854775808` can be `i64::MIN`.
    Int(u64),
    Real(f64),
    /// A string literal; the text is the token's range without the quotes.
    Str,
    Ident,
    True,
    False,
    ColonAssign,
    Assign,
    PlusAssign,
    MinusAssign,
    StarAssign,
    SlashAssign,
    Question,
    Colon,
    OrOr,
    AndAnd,
    EqEq,
    NotEq,
    Lt,
    Le,
    Gt,
    Ge,
    Pipe,
    Caret,
    Amp,
    Plus,
    Minus,
    DotDot,
    Star,
    Slash,
    Tilde,
    Bang,
    LParen,
    RParen,
    Semi,
    Eof,
}

impl Tok {
    /// How error messages name the token.
    pub(crate) fn describe(self) -> &'static str {
        match self {
            Tok::Int(_) | Tok::Real(_) => "a number",
            Tok::Str => "a string",
            Tok::Ident => "a name",
            Tok::True => "`true`",
            Tok::False => "`false`",
            Tok::ColonAssign => "`:=`",
            Tok::Assign => "`=`",
            Tok::PlusAssign => "`+=`",
            Tok::MinusAssign => "`-=`",
            Tok::StarAssign => "`*=`",
            Tok::SlashAssign => "`/=`",
            Tok::Question => "`?`",
            Tok::Colon => "`:`",
            Tok::OrOr => "`||`",
            Tok::AndAnd => "`&&`",
            Tok::EqEq => "`==`",
            Tok::NotEq => "`!=`",
            Tok::Lt => "`<`",
            Tok::Le => "`<=`",
            Tok::Gt => "`>`",
            Tok::Ge => "`>=`",
            Tok::Pipe => "`|`",
            Tok::Caret => "`^`",
            Tok::Amp => "`&`",
            Tok::Plus => "`+`",
            Tok::Minus => "`-`",
            Tok::DotDot => "`..`",
            Tok::Star => "`*`",
            Tok::Slash => "`/`",
            Tok::Tilde => "`~`",
            Tok::Bang => "`!`",
            Tok::LParen => "`(`",
            Tok::RParen => "`)`",
            Tok::Semi => "`;`",
            Tok::Eof => "end of script",
        }
    }
}

fn is_ident_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_'
}

fn is_ident_continue(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

/// The tokens of `src`, ending with [`Tok::Eof`].
pub(crate) fn tokenize(src: &str) -> Result<Vec<Token>, Located> {
    let bytes = src.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if b.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        let next = bytes.get(i + 1).copied();
        let (kind, len) = match b {
            b'0'..=b'9' => {
                let (kind, end) = number(src, start)?;
                (kind, end - start)
            }
            b'\'' | b'"' => match src[start + 1..].find(b as char) {
                Some(close) => (Tok::Str, close + 2),
                None => return Err((ScriptErrorKind::UnterminatedString(b as char), start)),
            },
            b'@' => {
                if !next.is_some_and(is_ident_start) {
                    return Err((
                        ScriptErrorKind::Expected {
                            expected: "a name after `@`",
                            found: describe_at(src, i + 1),
                        },
                        i + 1,
                    ));
                }
                (Tok::Ident, ident_len(bytes, i + 1) + 1)
            }
            _ if is_ident_start(b) => {
                let len = ident_len(bytes, i);
                let kind = match &src[i..i + len] {
                    "true" => Tok::True,
                    "false" => Tok::False,
                    _ => Tok::Ident,
                };
                (kind, len)
            }
            _ => match (b, next) {
                (b':', Some(b'=')) => (Tok::ColonAssign, 2),
                (b'+', Some(b'=')) => (Tok::PlusAssign, 2),
                (b'-', Some(b'=')) => (Tok::MinusAssign, 2),
                (b'*', Some(b'=')) => (Tok::StarAssign, 2),
                (b'/', Some(b'=')) => (Tok::SlashAssign, 2),
                (b'=', Some(b'=')) => (Tok::EqEq, 2),
                (b'!', Some(b'=')) => (Tok::NotEq, 2),
                (b'<', Some(b'=')) => (Tok::Le, 2),
                (b'>', Some(b'=')) => (Tok::Ge, 2),
                (b'|', Some(b'|')) => (Tok::OrOr, 2),
                (b'&', Some(b'&')) => (Tok::AndAnd, 2),
                (b'.', Some(b'.')) => (Tok::DotDot, 2),
                (b':', _) => (Tok::Colon, 1),
                (b'=', _) => (Tok::Assign, 1),
                (b'?', _) => (Tok::Question, 1),
                (b'<', _) => (Tok::Lt, 1),
                (b'>', _) => (Tok::Gt, 1),
                (b'|', _) => (Tok::Pipe, 1),
                (b'^', _) => (Tok::Caret, 1),
                (b'&', _) => (Tok::Amp, 1),
                (b'+', _) => (Tok::Plus, 1),
                (b'-', _) => (Tok::Minus, 1),
                (b'*', _) => (Tok::Star, 1),
                (b'/', _) => (Tok::Slash, 1),
                (b'~', _) => (Tok::Tilde, 1),
                (b'!', _) => (Tok::Bang, 1),
                (b'(', _) => (Tok::LParen, 1),
                (b')', _) => (Tok::RParen, 1),
                (b';', _) => (Tok::Semi, 1),
                _ => {
                    let c = src[i..].chars().next().unwrap_or('\u{fffd}');
                    return Err((ScriptErrorKind::UnexpectedChar(c), i));
                }
            },
        };
        tokens.push(Token {
            kind,
            start,
            end: start + len,
        });
        i = start + len;
    }
    tokens.push(Token {
        kind: Tok::Eof,
        start: src.len(),
        end: src.len(),
    });
    Ok(tokens)
}

/// The length of the identifier continuation starting at `i`.
fn ident_len(bytes: &[u8], i: usize) -> usize {
    bytes[i..]
        .iter()
        .take_while(|&&b| is_ident_continue(b))
        .count()
}

/// What is at `i`, for an error message.
fn describe_at(src: &str, i: usize) -> String {
    match src.get(i..).and_then(|s| s.chars().next()) {
        Some(c) => format!("`{c}`"),
        None => "end of script".into(),
    }
}

/// A number literal starting at `start` (a digit): its token and end.
///
/// Decimal and `0x` hexadecimal integers, and reals with a fraction (`1.5`), an exponent
/// (`1e3`, `2.5E-2`) or both. A `.` after the digits starts a fraction only when a digit
/// follows, so that `1..2` is `1`, `..`, `2`. Letters right after a number are an error.
fn number(src: &str, start: usize) -> Result<(Tok, usize), Located> {
    let bytes = src.as_bytes();
    let digits = |from: usize, hex: bool| {
        bytes[from..]
            .iter()
            .take_while(|b| {
                if hex {
                    b.is_ascii_hexdigit()
                } else {
                    b.is_ascii_digit()
                }
            })
            .count()
    };
    let bad = |end: usize, reason: &'static str| {
        (
            ScriptErrorKind::BadNumber {
                text: src[start..end].into(),
                reason,
            },
            start,
        )
    };
    let suffix_end = |end: usize| end + ident_len(bytes, end);
    let check_suffix = |end: usize| {
        if bytes.get(end).is_some_and(|&b| is_ident_continue(b)) {
            Err(bad(suffix_end(end), "letters may not follow a number"))
        } else {
            Ok(())
        }
    };

    if bytes[start] == b'0' && matches!(bytes.get(start + 1), Some(b'x' | b'X')) {
        let n = digits(start + 2, true);
        let end = start + 2 + n;
        if n == 0 {
            return Err(bad(suffix_end(start + 2), "`0x` needs hexadecimal digits"));
        }
        check_suffix(end)?;
        let value = i64::from_str_radix(&src[start + 2..end], 16)
            .map_err(|_| bad(end, "larger than the largest integer (i64)"))?;
        return Ok((Tok::Int(value as u64), end));
    }

    let mut end = start + digits(start, false);
    let mut real = false;
    if bytes.get(end) == Some(&b'.') && bytes.get(end + 1).is_some_and(u8::is_ascii_digit) {
        end += 1 + digits(end + 1, false);
        real = true;
    }
    if matches!(bytes.get(end), Some(b'e' | b'E')) {
        let mut e = end + 1;
        if matches!(bytes.get(e), Some(b'+' | b'-')) {
            e += 1;
        }
        let n = digits(e, false);
        if n == 0 {
            return Err(bad(suffix_end(end), "the exponent needs digits"));
        }
        end = e + n;
        real = true;
    }
    check_suffix(end)?;
    let text = &src[start..end];
    if real {
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok((Tok::Real(v), end)),
            _ => Err(bad(end, "out of the range of a real (f64)")),
        }
    } else {
        match text.parse::<u64>() {
            Ok(v) if v <= 1 << 63 => Ok((Tok::Int(v), end)),
            _ => Err(bad(end, "larger than the largest integer (i64)")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(src: &str) -> Vec<Tok> {
        tokenize(src).unwrap().into_iter().map(|t| t.kind).collect()
    }

    #[test]
    fn operators_take_the_longest_match() {
        assert_eq!(
            kinds("a:=b==c!=d<=e>=f||g&&h..i+=1"),
            [
                Tok::Ident,
                Tok::ColonAssign,
                Tok::Ident,
                Tok::EqEq,
                Tok::Ident,
                Tok::NotEq,
                Tok::Ident,
                Tok::Le,
                Tok::Ident,
                Tok::Ge,
                Tok::Ident,
                Tok::OrOr,
                Tok::Ident,
                Tok::AndAnd,
                Tok::Ident,
                Tok::DotDot,
                Tok::Ident,
                Tok::PlusAssign,
                Tok::Int(1),
                Tok::Eof
            ]
        );
    }

    #[test]
    fn numbers() {
        assert_eq!(kinds("0x1F"), [Tok::Int(31), Tok::Eof]);
        assert_eq!(kinds("1.5"), [Tok::Real(1.5), Tok::Eof]);
        assert_eq!(kinds("1e3"), [Tok::Real(1000.0), Tok::Eof]);
        assert_eq!(kinds("2.5E-1"), [Tok::Real(0.25), Tok::Eof]);
        assert_eq!(
            kinds("1..2"),
            [Tok::Int(1), Tok::DotDot, Tok::Int(2), Tok::Eof]
        );
        assert_eq!(kinds("9223372036854775808"), [Tok::Int(1 << 63), Tok::Eof]);
        for bad in [
            "12abc",
            "0x",
            "0xZ",
            "1e",
            "1e+",
            "9223372036854775809",
            "1e999",
            "0x8000000000000000",
        ] {
            let err = tokenize(bad).unwrap_err();
            assert!(
                matches!(err.0, ScriptErrorKind::BadNumber { .. }),
                "{bad}: {err:?}"
            );
            assert_eq!(err.1, 0);
        }
    }

    #[test]
    fn strings_and_names() {
        let t = tokenize("@x := 'a b' .. \"c\"").unwrap();
        assert_eq!((t[0].kind, t[0].start, t[0].end), (Tok::Ident, 0, 2));
        assert_eq!((t[2].kind, t[2].start, t[2].end), (Tok::Str, 6, 11));
        assert_eq!((t[4].kind, t[4].start, t[4].end), (Tok::Str, 15, 18));
        assert_eq!(
            tokenize("x := 'abc").unwrap_err(),
            (ScriptErrorKind::UnterminatedString('\''), 5)
        );
        assert_eq!(
            tokenize("1 # 2").unwrap_err(),
            (ScriptErrorKind::UnexpectedChar('#'), 2)
        );
        assert_eq!(
            tokenize("é").unwrap_err(),
            (ScriptErrorKind::UnexpectedChar('é'), 0)
        );
        assert!(matches!(
            tokenize("@ x").unwrap_err(),
            (ScriptErrorKind::Expected { .. }, 1)
        ));
    }
}
