//! Byte scanning for the quick reader: counting markup, finding the end of text, names,
//! quoted values, comments and the XML declaration.

/// The numbers of `<` and `=` in `b` (bounds on the numbers of elements and attributes);
/// `None` if `b` holds a character XML forbids (a control character other than a tab or
/// line break, U+FFFE or U+FFFF).
pub(super) fn markup_count(b: &[u8]) -> Option<(usize, usize)> {
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
pub(super) fn zero_bytes(x: u64) -> u64 {
    const LOW: u64 = 0x0101_0101_0101_0101;
    x.wrapping_sub(LOW) & !x & (LOW << 7)
}

/// `c` in every byte.
pub(super) const fn splat(c: u8) -> u64 {
    0x0101_0101_0101_0101 * c as u64
}

/// The end of the text at `pos` (the next `<`), and whether the text may hold a `>` or `&`
/// (never `false` when it does); `None` at the end of the input.
pub(super) fn text_end(b: &[u8], mut pos: usize) -> Option<(usize, bool)> {
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
pub(super) fn skip_spaces(b: &[u8], pos: &mut usize) -> bool {
    let start = *pos;
    while matches!(b.get(*pos), Some(b' ' | b'\t' | b'\n' | b'\r')) {
        *pos += 1;
    }
    *pos > start
}

/// The bytes that go on an ASCII name.
pub(super) const NAME_BYTES: [bool; 256] = {
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
pub(super) fn name_end(b: &[u8], start: usize) -> Option<usize> {
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
pub(super) fn quoted(b: &[u8], pos: usize) -> Option<(usize, usize, usize)> {
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
pub(super) fn declaration(b: &[u8], mut pos: usize) -> Option<usize> {
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
pub(super) fn comment(b: &[u8], pos: usize) -> Option<usize> {
    let body = pos + 4;
    let dashes = body + b[body..].windows(2).position(|w| w == b"--")?;
    (b.get(dashes + 2) == Some(&b'>')).then_some(dashes + 3)
}

/// Skips white space and comments (what may surround the document element).
pub(super) fn misc(b: &[u8], mut pos: usize) -> Option<usize> {
    loop {
        skip_spaces(b, &mut pos);
        if !b[pos..].starts_with(b"<!--") {
            return Some(pos);
        }
        pos = comment(b, pos)?;
    }
}
