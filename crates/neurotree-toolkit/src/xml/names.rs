//! The names BehaviorTree.CPP 4.10 refuses: tree and node type names
//! (`validateModelName` in `xml_parsing.cpp`), the port names of a SubTree's model
//! (`validatePortName`) and of a registered node (`IsAllowedPortName`, which `CreatePort`
//! checks). A file BehaviorTree.CPP refuses for a name is refused here with the same rule.

/// The characters `findForbiddenChar` (`basic_types.cpp`) refuses in a name: they break XML
/// serialization, Groot2's paths or file names. Control characters are refused too.
const FORBIDDEN: [char; 16] = [
    ' ', '\t', '\n', '\r', '<', '>', '&', '"', '\'', '/', '\\', ':', '*', '?', '|', '.',
];

/// The attributes BehaviorTree.CPP keeps for itself (`IsReservedAttribute`): no port may be
/// named so.
const RESERVED: [&str; 11] = [
    "_failureIf",
    "_successIf",
    "_skipIf",
    "_while",
    "_onHalted",
    "_onFailure",
    "_onSuccess",
    "_post",
    "name",
    "ID",
    "_autoremap",
];

/// [`FORBIDDEN`] and the ASCII control characters, as a table of bytes: `true` for a
/// forbidden byte (all below 128).
static FORBIDDEN_BYTES: [bool; 256] = {
    let mut table = [false; 256];
    let mut b = 0;
    while b < 128 {
        table[b] = (b as u8).is_ascii_control();
        b += 1;
    }
    let mut i = 0;
    while i < FORBIDDEN.len() {
        table[FORBIDDEN[i] as usize] = true;
        i += 1;
    }
    table
};

/// The first character of `name` that BehaviorTree.CPP forbids in a name, if any.
fn forbidden_char(name: &str) -> Option<char> {
    // Multibyte UTF-8 is allowed, as BehaviorTree.CPP skips bytes with the high bit set; an
    // ASCII character is one byte below 128, and no byte of a multibyte one is.
    name.bytes()
        .find(|&b| FORBIDDEN_BYTES[usize::from(b)])
        .map(char::from)
}

/// How a forbidden character is named in a message.
fn shown(c: char) -> String {
    if c.is_ascii_control() {
        format!("control character (ASCII {})", c as u32)
    } else {
        format!("'{c}'")
    }
}

/// Checks a tree ID, a SubTree's ID or a node type name written as an element, as
/// BehaviorTree.CPP's `validateModelName` does; the error says what is wrong and what to do.
pub(crate) fn check_model_name(name: &str, what: &str) -> Result<(), String> {
    if name.is_empty() {
        return Err(format!(
            "{what} is empty; BehaviorTree.CPP refuses an empty name: give it one"
        ));
    }
    if name == "Root" || name == "root" {
        return Err(format!(
            "{what} `{name}`: `Root` is a reserved name in BehaviorTree.CPP; rename it"
        ));
    }
    if let Some(c) = forbidden_char(name) {
        return Err(format!(
            "{what} `{name}` contains the forbidden character {}; BehaviorTree.CPP refuses \
             spaces, control characters and < > & \" ' / \\ : * ? | . in names: rename it",
            shown(c)
        ));
    }
    Ok(())
}

/// Checks a port name that a `TreeNodesModel` declares for a SubTree, as
/// BehaviorTree.CPP's `validatePortName` does.
pub(crate) fn check_subtree_port_name(name: &str) -> Result<(), String> {
    if name.is_empty() {
        return Err("a port name cannot be empty; name the port".to_string());
    }
    if name.starts_with(|c: char| c.is_ascii_digit()) {
        return Err(format!(
            "port name `{name}` starts with a digit, which BehaviorTree.CPP refuses; rename it"
        ));
    }
    if let Some(c) = forbidden_char(name) {
        return Err(format!(
            "port name `{name}` contains the forbidden character {}, which BehaviorTree.CPP \
             refuses in names; rename it",
            shown(c)
        ));
    }
    if RESERVED.contains(&name) {
        return Err(format!(
            "port name `{name}` is a reserved attribute name in BehaviorTree.CPP ({}); \
             rename it",
            RESERVED.join(", ")
        ));
    }
    Ok(())
}

/// Checks the port name of a node type (registered, or declared by a model), as
/// BehaviorTree.CPP's `CreatePort` does with `IsAllowedPortName`: it must start with a
/// letter and be neither reserved nor hold a forbidden character.
pub(crate) fn check_port_name(name: &str) -> Result<(), String> {
    check_subtree_port_name(name)?;
    if !name.starts_with(|c: char| c.is_ascii_alphabetic()) {
        return Err(format!(
            "port name `{name}` must start with a letter, as BehaviorTree.CPP requires \
             (`_` starts the names it reserves); rename it"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_byte_set_forbids_what_the_list_and_control_characters_forbid() {
        for c in (0..=0x10ffu32).filter_map(char::from_u32) {
            let by_rule = c.is_ascii() && (c.is_ascii_control() || FORBIDDEN.contains(&c));
            let name = format!("a{c}b");
            assert_eq!(forbidden_char(&name), by_rule.then_some(c), "{c:?}");
        }
    }

    #[test]
    fn names_as_behaviortree_cpp_checks_them() {
        assert!(check_model_name("Main", "tree ID").is_ok());
        assert!(check_model_name("Bäume", "tree ID").is_ok());
        assert!(check_model_name("", "tree ID").is_err());
        assert!(check_model_name("root", "tree ID").is_err());
        assert!(check_model_name("my tree", "tree ID").is_err());
        assert!(check_model_name("a.b", "tree ID").is_err());
        assert!(check_model_name("a\u{7f}", "tree ID")
            .unwrap_err()
            .contains("ASCII 127"));
        assert!(check_subtree_port_name("_private").is_ok());
        assert!(check_port_name("_private").is_err());
        assert!(check_port_name("goal").is_ok());
        assert!(check_port_name("2goal").is_err());
        assert!(check_port_name("name").is_err());
        assert!(check_port_name("go:al").is_err());
    }
}
