//! Entities and characters, as BehaviorTree.CPP's parser takes them: a bare `&` is text,
//! a short name between `&` and `;` is an entity.

/// If `&` at the start of `rest` is followed by what BehaviorTree.CPP's parser takes for an
/// entity (a short alphanumeric name, or `#` and one, then `;`), that name; `None` for a bare
/// `&`, kept as written.
pub(super) fn entity_name(rest: &[u8]) -> Option<&[u8]> {
    let n = rest.iter().take(12).position(|&c| c == b';')?;
    let name = &rest[..n];
    let is_entity = n > 0
        && (name.iter().all(u8::is_ascii_alphanumeric)
            || (name[0] == b'#' && name[1..].iter().all(u8::is_ascii_alphanumeric)));
    is_entity.then_some(name)
}

/// Whether XML allows `c` in text.
pub(super) fn is_xml_char(c: char) -> bool {
    match c {
        '\t' | '\n' | '\r' => true,
        '\u{FFFE}' | '\u{FFFF}' => false,
        c => c >= ' ',
    }
}

/// The character an entity name (from [`entity_name`]) stands for; `None` for an unknown or
/// malformed one, which the complete reader reports.
pub(super) fn decode_entity(name: &[u8]) -> Option<char> {
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
