//! Which declared port types an entry can pass between, as BehaviorTree.CPP's `Any`
//! converts: numbers and `bool` among themselves and from text, any type to an untyped
//! port, and another type only to itself.

use neurotree_core::PortType;

/// Whether `port` is declared as text (`String`), which reads what converts to text.
fn is_text(port: PortType) -> bool {
    !port.is_any() && !port.writes_as::<f64>() && port.writes_as::<String>()
}

/// Whether a value written through a port of type `written` fails to be read through a
/// port of type `read`. Text on either side is let through: a text port reads a number,
/// and a number port parses text (the literals are checked on their own).
pub(crate) fn incompatible(written: PortType, read: PortType) -> bool {
    let exact = |p: PortType| !p.is_any() && !p.reads_as::<f64>();
    !written.is_any()
        && !read.is_any()
        && !is_text(written)
        && !is_text(read)
        && (exact(written) || exact(read))
        && written != read
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_type_of_its_own_against_another_is_incompatible() {
        let pose = PortType::of::<(f64, f64)>();
        let path = PortType::of::<Vec<(f64, f64)>>();
        let number = PortType::of::<i64>();
        let text = PortType::of::<String>();
        assert!(incompatible(pose, path));
        assert!(incompatible(pose, number));
        assert!(incompatible(number, pose));
        assert!(!incompatible(pose, pose));
        assert!(!incompatible(number, PortType::of::<bool>()));
        assert!(!incompatible(pose, text));
        assert!(!incompatible(text, number));
        assert!(!incompatible(pose, PortType::ANY));
        assert!(!incompatible(
            PortType::named("i32"),
            PortType::named("f64")
        ));
    }
}
